//! # Photometry: luminaires from their photometric files
//!
//! A luminaire manufacturer measures how much light a luminaire sends in each direction with a
//! goniophotometer and publishes the table of **luminous intensities** I (candela, cd = lm/sr)
//! in one of two text formats:
//!
//! - **IES LM-63** (`.ies`, North America; revisions 1991, 1995, 2002 and 2019), read by
//!   [`ies`];
//! - **EULUMDAT** (`.ldt`, Europe; Stockmar 1990, 1998), read by [`eulumdat`].
//!
//! Both describe the distribution in **type C** photometry: a direction is given by the angle γ
//! from the nadir (0° straight down, 90° horizontal, 180° straight up) and the azimuth C of its
//! vertical half-plane (the *C plane*, 0°–360°, counter-clockwise seen from above). Both may
//! store only part of the sphere when the luminaire is symmetric. [`Distribution`] is the one
//! representation of either: the full I(C, γ) in candela with the file's multipliers applied,
//! interpolated bilinearly, integrated to the luminous flux Φ = ∫ I dΩ, and searched for its
//! maximum and its beam and field angles.
//!
//! [`read`] takes a file path, recognises the format by its extension and returns a
//! [`PhotometricFile`]: the distribution and what the file says about itself (names, declared
//! lamp flux, luminous opening). Every malformed input gives a [`ParseError`] naming the file and
//! the line, in the compiler style `lamp.ies:12: expected 37 vertical angles, found 20`, never a
//! panic.
//!
//! ```
//! use glam::DVec3;
//! use radiosity::photometry::{Distribution, Symmetry};
//!
//! // A bare lamp of 100 cd in every direction: one C plane, rotationally symmetric.
//! let d = Distribution::new(Symmetry::Rotational, &[0.0], &[0.0, 180.0], vec![100.0, 100.0])?;
//! assert_eq!(d.intensity(DVec3::new(0.3, -0.2, 0.9)), 100.0);
//! // Φ = 4π I.
//! assert!((d.flux() - 4.0 * std::f64::consts::PI * 100.0).abs() < 1e-9);
//! # Ok::<(), radiosity::photometry::TableError>(())
//! ```

use std::path::{Path, PathBuf};

pub mod distribution;
pub mod eulumdat;
pub mod ies;
mod text;

pub use distribution::{Distribution, Peak, Spread, Symmetry, TableError};
pub use ies::Tilt;

/// The two photometric file formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// IES LM-63 (`.ies`).
    Ies,
    /// EULUMDAT (`.ldt`).
    Eulumdat,
}

impl Format {
    /// The format a file's extension names (`.ies` or `.ldt`, any case), if any.
    #[must_use]
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "ies" => Some(Self::Ies),
            "ldt" => Some(Self::Eulumdat),
            _ => None,
        }
    }
}

/// The luminous opening: the size of the light-emitting part of the luminaire, in metres.
///
/// IES LM-63 measures the length along the C0–C180 axis (+X of the luminaire frame, see
/// [`Distribution::intensity`]) and the width along the C90–C270 axis; EULUMDAT gives the length
/// (or diameter) and width of the luminous area in the same order.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Opening {
    /// Length (or diameter of a round opening), metres.
    pub length: f64,
    /// Width, metres (equal to the length for a round opening).
    pub width: f64,
    /// Height, metres (0 for a flat opening).
    pub height: f64,
    /// Whether the file describes a round (circular or elliptical) opening.
    pub round: bool,
}

/// A parsed photometric file: the distribution and the file's description of the luminaire.
#[derive(Clone, Debug)]
pub struct PhotometricFile {
    /// The format.
    pub format: Format,
    /// The revision as the file declares it (`LM-63-2002`, `LM-63-1986` for a file without a
    /// header line, `EULUMDAT`).
    pub version: String,
    /// The manufacturer (IES `[MANUFAC]`, EULUMDAT line 1), possibly empty.
    pub manufacturer: String,
    /// The luminaire's name (IES `[LUMINAIRE]`, EULUMDAT line 9), possibly empty.
    pub luminaire: String,
    /// The lamps (IES `[LAMP]`, EULUMDAT the first lamp set's type), possibly empty.
    pub lamp: String,
    /// The symmetry the file declares (and the part of the sphere it stores).
    pub symmetry: Symmetry,
    /// The numbers of C planes and γ angles stored in the file.
    pub stored: (usize, usize),
    /// The lamps' rated luminous flux the file declares, lm (`None` for IES absolute
    /// photometry, lumens per lamp = −1).
    pub lamp_flux: Option<f64>,
    /// The light output ratio the file declares (EULUMDAT LORL / 100); the luminaire's flux
    /// is then `lamp_flux × output_ratio`. IES files declare none.
    pub output_ratio: Option<f64>,
    /// The luminous opening.
    pub opening: Opening,
    /// IES `TILT=INCLUDE`: the multiplier of the candela values as the luminaire is tilted.
    pub tilt: Option<Tilt>,
    /// The intensity distribution, in candela.
    pub distribution: Distribution,
}

impl PhotometricFile {
    /// The luminaire's flux the file declares, lm: the lamp flux times the light output ratio
    /// (EULUMDAT), or the lamp flux alone (IES, which states no ratio).
    #[must_use]
    pub fn declared_flux(&self) -> Option<f64> {
        self.lamp_flux.map(|f| f * self.output_ratio.unwrap_or(1.0))
    }
}

/// A photometric file that cannot be read: where and why.
///
/// `Display` is one line, `FILE:LINE: CAUSE` (`FILE: CAUSE` when no line applies).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct ParseError {
    /// The file.
    pub file: PathBuf,
    /// The 1-based line the problem is on, when one applies.
    pub line: Option<usize>,
    /// What is wrong.
    pub kind: ErrorKind,
}

impl std::fmt::Display for ParseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        write!(f, ": {}", self.kind)
    }
}

/// The causes of a [`ParseError`].
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ErrorKind {
    /// The file cannot be read.
    #[error("cannot read: {0}")]
    Read(String),
    /// The file's extension is neither `.ies` nor `.ldt`.
    #[error("not a photometric file (expected the extension .ies or .ldt)")]
    UnknownFormat,
    /// A list ended early: `expected 37 vertical angles, found 20`.
    #[error("expected {expected} {what}, found {found}{after}")]
    Count {
        /// What the list holds.
        what: &'static str,
        /// How many the file announced.
        expected: usize,
        /// How many were there.
        found: usize,
        /// What stopped the list (`` and then `abc` ``, or ` (the file ends)`).
        after: String,
    },
    /// A single value is missing or malformed: `expected the number of lamps, found `x``.
    #[error("expected {what}, found {found}")]
    Expected {
        /// What was expected.
        what: String,
        /// What was there.
        found: String,
    },
    /// A feature of the format that is not read.
    #[error("{what} is not supported; {instead}")]
    Unsupported {
        /// The feature.
        what: String,
        /// What the file could do instead.
        instead: &'static str,
    },
    /// A value out of its range or inconsistent with others.
    #[error("{0}")]
    Invalid(String),
}

/// Reads a photometric file, recognised by its extension (`.ies` or `.ldt`).
///
/// # Errors
/// [`ParseError`] when the file cannot be read, has another extension, or is malformed.
pub fn read(path: &Path) -> Result<PhotometricFile, ParseError> {
    let error = |kind| ParseError {
        file: path.to_path_buf(),
        line: None,
        kind,
    };
    let format = Format::from_path(path).ok_or_else(|| error(ErrorKind::UnknownFormat))?;
    let bytes = std::fs::read(path).map_err(|e| error(ErrorKind::Read(e.to_string())))?;
    // Photometric files are ASCII by their standards; older ones carry Latin-1 names (°, µ,
    // umlauts), which are kept as replacement characters rather than refused.
    let text = String::from_utf8_lossy(&bytes);
    parse(format, &text, path)
}

/// Parses the text of a photometric file of the given format; `path` names it in errors.
///
/// # Errors
/// [`ParseError`] when the text is malformed.
pub fn parse(format: Format, text: &str, path: &Path) -> Result<PhotometricFile, ParseError> {
    match format {
        Format::Ies => ies::parse(text, path),
        Format::Eulumdat => eulumdat::parse(text, path),
    }
}
