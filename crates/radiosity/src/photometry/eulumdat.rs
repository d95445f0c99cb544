//! # EULUMDAT: the European photometric file
//!
//! EULUMDAT (`.ldt`; A. W. Stockmar, *EULUMDAT — ein Leuchtendatenformat für den europäischen
//! Beleuchtungsplaner*, Licht '90, and *EULUMDAT/2*, CIBSE 1998) is a text file of fixed lines,
//! one field each:
//!
//! | line | field |
//! |---|---|
//! | 1 | company identification, data bank, version |
//! | 2 | Ityp: type indicator (0 point source without symmetry, 1 symmetric about the vertical axis, 2 linear, 3 other point source) |
//! | 3 | Isym: symmetry indicator, 0–4 (below) |
//! | 4, 5 | Mc: number of C planes in 0°–360°; Dc: their spacing (0 if uneven) |
//! | 6, 7 | Ng: number of γ angles per plane; Dg: their spacing (0 if uneven) |
//! | 8–12 | measurement report, luminaire name, luminaire number, file name, date/user |
//! | 13–15 | luminaire length (or diameter), width (0: round), height, mm |
//! | 16–21 | luminous area length (or diameter), width b1 (0: round), height at C0, C90, C180, C270, mm |
//! | 22–25 | downward flux fraction DFF %, light output ratio LORL %, conversion factor for the intensities, tilt during measurement ° |
//! | 26 | n: number of lamp sets |
//! | 26a–f | n lines each: number of lamps, lamp type, total luminous flux (lm), colour temperature, colour rendering, wattage with ballast (W) |
//! | +10 | direct ratios for the room indices k = 0.6 … 5 |
//! | +Mc | the C angles, one per line |
//! | +Ng | the γ angles, one per line |
//! | rest | luminous intensities in cd/klm, plane by plane (Ng values each) |
//!
//! **Symmetry.** Isym says which planes are stored (indices into the Mc C angles, 0-based):
//! 0 — all; 1 — one (rotational symmetry); 2 — planes 0 to Mc/2 (C0–C180; symmetric about that
//! plane); 3 — planes 3Mc/4 to 3Mc/4 + Mc/2, wrapping past Mc (C270 through C0 to C90;
//! symmetric about the C90–C270 plane); 4 — planes 0 to Mc/4 (C0–C90; symmetric about both).
//! The reader checks that the stored planes' angles are the ones the symmetry needs.
//!
//! **Values.** The intensities are given per 1000 lm of lamp flux: in candela they are
//! I = I_file · Φ_lamps / 1000 · (conversion factor), where Φ_lamps is the sum of the total
//! flux of the lamp sets (a file whose sets are alternative equipments should carry one). The
//! luminaire's declared flux is then Φ_lamps · LORL / 100.
//!
//! Numbers may carry a decimal comma (`0,85`), as some European writers produce.

use std::path::Path;

use super::distribution::{Distribution, Symmetry};
use super::text::Tokens;
use super::{ErrorKind, Format, Opening, ParseError, PhotometricFile};

/// The most C planes or γ angles the reader accepts: 1/100° steps over a full circle.
const MAX_ANGLES: i64 = 36_001;
/// The most lamp sets the reader accepts.
const MAX_LAMP_SETS: i64 = 1000;

/// The fixed lines of the file.
struct Fields<'a> {
    file: &'a Path,
    lines: Vec<&'a str>,
}

impl Fields<'_> {
    fn error(&self, line: usize, kind: ErrorKind) -> ParseError {
        ParseError {
            file: self.file.to_path_buf(),
            line: Some(line.min(self.lines.len()).max(1)),
            kind,
        }
    }

    /// Line `n` (1-based), trimmed.
    fn text(&self, n: usize, what: &str) -> Result<&str, ParseError> {
        self.lines.get(n - 1).map(|l| l.trim()).ok_or_else(|| {
            self.error(
                n,
                ErrorKind::Expected {
                    what: format!("{what} on line {n}"),
                    found: "the end of the file".into(),
                },
            )
        })
    }

    /// Line `n` as a finite number.
    fn number(&self, n: usize, what: &str) -> Result<f64, ParseError> {
        let t = self.text(n, what)?;
        t.replace(',', ".")
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                self.error(
                    n,
                    ErrorKind::Expected {
                        what: what.to_string(),
                        found: if t.is_empty() {
                            "an empty line".into()
                        } else {
                            format!("`{t}`")
                        },
                    },
                )
            })
    }

    /// Line `n` as a whole number in `lo..=hi`.
    fn integer(&self, n: usize, what: &str, lo: i64, hi: i64) -> Result<i64, ParseError> {
        let v = self.number(n, what)?;
        if v.fract() != 0.0 || v < lo as f64 || v > hi as f64 {
            return Err(self.error(
                n,
                ErrorKind::Expected {
                    what: format!("{what} (a whole number from {lo} to {hi})"),
                    found: format!("`{v}`"),
                },
            ));
        }
        Ok(v as i64)
    }
}

/// Parses the text of a EULUMDAT file; `path` names it in errors.
///
/// # Errors
/// [`ParseError`] with the line of the first problem.
pub fn parse(text: &str, path: &Path) -> Result<PhotometricFile, ParseError> {
    let f = Fields {
        file: path,
        lines: text.lines().collect(),
    };

    // The header: lines 1–25.
    let company = f.text(1, "the company identification")?.to_string();
    f.integer(2, "the type indicator Ityp", 0, 3)?;
    let isym = f.integer(3, "the symmetry indicator Isym", 0, 4)?;
    let mc = f.integer(4, "the number of C planes Mc", 1, MAX_ANGLES)? as usize;
    f.number(5, "the C plane spacing Dc")?;
    let ng = f.integer(6, "the number of γ angles Ng", 1, MAX_ANGLES)? as usize;
    f.number(7, "the γ angle spacing Dg")?;
    let luminaire = f.text(9, "the luminaire name")?.to_string();
    f.text(12, "the date and user")?;
    for (n, what) in [
        (13, "the luminaire length"),
        (14, "the luminaire width"),
        (15, "the luminaire height"),
    ] {
        f.number(n, what)?;
    }
    let area_length = f.number(16, "the length of the luminous area")?;
    let area_width = f.number(17, "the width of the luminous area")?;
    let mut area_height: f64 = 0.0;
    for (n, plane) in [(18, "C0"), (19, "C90"), (20, "C180"), (21, "C270")] {
        let h = f.number(n, &format!("the height of the luminous area at {plane}"))?;
        area_height = area_height.max(h);
    }
    f.number(22, "the downward flux fraction DFF")?;
    let lorl = f.number(23, "the light output ratio LORL")?;
    let conversion = f.number(24, "the conversion factor for luminous intensities")?;
    if conversion <= 0.0 {
        return Err(f.error(
            24,
            ErrorKind::Invalid(format!(
                "the conversion factor must be positive, not {conversion}"
            )),
        ));
    }
    f.number(25, "the tilt during measurement")?;

    // The lamp sets: n lines of each field, field after field.
    let sets = f.integer(26, "the number of lamp sets n", 1, MAX_LAMP_SETS)? as usize;
    let field = |k: usize, i: usize| 27 + k * sets + i;
    let mut lamp_flux = 0.0;
    let mut lamp = String::new();
    for i in 0..sets {
        f.integer(
            field(0, i),
            "the number of lamps",
            i64::from(i32::MIN),
            i64::from(i32::MAX),
        )?;
        let kind = f.text(field(1, i), "the lamp type")?;
        if i == 0 {
            lamp = kind.to_string();
        }
        let flux_line = field(2, i);
        let flux = f.number(flux_line, "the total luminous flux of the lamps")?;
        if flux < 0.0 {
            return Err(f.error(
                flux_line,
                ErrorKind::Invalid(format!("the lamp flux must not be negative, not {flux}")),
            ));
        }
        lamp_flux += flux;
        f.text(field(3, i), "the colour temperature")?;
        f.text(field(4, i), "the colour rendering index")?;
        f.number(field(5, i), "the wattage")?;
    }
    if lamp_flux <= 0.0 {
        return Err(f.error(
            field(2, 0),
            ErrorKind::Invalid(
                "the lamp sets' flux must be positive: it scales the cd/klm values".into(),
            ),
        ));
    }

    // From here on one number per line, read as a stream.
    let start = field(6, 0);
    let rest = f
        .lines
        .iter()
        .enumerate()
        .skip(start - 1)
        .map(|(i, l)| (i + 1, *l));
    let mut tokens = Tokens::new(path, rest, f.lines.len(), true);
    tokens.list(10, "direct ratios")?;
    let c_line = tokens.line();
    let c_all = tokens.list(mc, "C angles")?;
    let gamma_line = tokens.line();
    let gamma = tokens.list(ng, "γ angles")?;
    let (symmetry, planes) =
        stored_planes(isym, &c_all).map_err(|m| tokens.error_at(c_line, ErrorKind::Invalid(m)))?;
    let values_line = tokens.line();
    let values = tokens.list(planes.len() * ng, "luminous intensities")?;

    // Stored planes by rising angle (Isym 3 wraps through 0°), with their values in candela.
    let scale = lamp_flux / 1000.0 * conversion;
    let mut order: Vec<usize> = (0..planes.len()).collect();
    order.sort_by(|&a, &b| c_all[planes[a]].total_cmp(&c_all[planes[b]]));
    let c: Vec<f64> = order.iter().map(|&k| c_all[planes[k]]).collect();
    let candela = order
        .iter()
        .flat_map(|&k| values[k * ng..(k + 1) * ng].iter().map(|v| v * scale))
        .collect();
    let distribution = Distribution::new(symmetry, &c, &gamma, candela).map_err(|e| {
        let line = match e {
            super::TableError::Gamma(..) => gamma_line,
            super::TableError::C(..) => c_line,
            _ => values_line,
        };
        tokens.error_at(
            line,
            ErrorKind::Invalid(format!("the intensity table: {e}")),
        )
    })?;

    let round = area_width == 0.0;
    Ok(PhotometricFile {
        format: Format::Eulumdat,
        version: "EULUMDAT".into(),
        manufacturer: company,
        luminaire,
        lamp,
        symmetry,
        stored: (planes.len(), ng),
        lamp_flux: Some(lamp_flux),
        output_ratio: Some(lorl / 100.0),
        opening: Opening {
            length: area_length.abs() / 1000.0,
            width: if round {
                area_length.abs()
            } else {
                area_width.abs()
            } / 1000.0,
            height: area_height.abs() / 1000.0,
            round,
        },
        tilt: None,
        distribution,
    })
}

/// The symmetry of Isym and the indices of the stored planes into the C angles, checked
/// against the angles the symmetry needs.
fn stored_planes(isym: i64, c: &[f64]) -> Result<(Symmetry, Vec<usize>), String> {
    let mc = c.len();
    let quarter = || {
        // (`usize::is_multiple_of` is newer than the workspace's rust-version.)
        if 4 * (mc / 4) == mc {
            Ok(mc / 4)
        } else {
            Err(format!(
                "Isym {isym} needs Mc divisible by 4, found Mc = {mc}"
            ))
        }
    };
    // (symmetry, stored indices, the angles the first and last stored plane must have)
    let (symmetry, planes, ends): (Symmetry, Vec<usize>, Option<(f64, f64)>) = match isym {
        0 => (Symmetry::None, (0..mc).collect(), None),
        1 => (Symmetry::Rotational, vec![0], None),
        2 => {
            if 2 * (mc / 2) != mc {
                return Err(format!("Isym 2 needs an even Mc, found Mc = {mc}"));
            }
            (
                Symmetry::PlaneC0C180,
                (0..=mc / 2).collect(),
                Some((0.0, 180.0)),
            )
        }
        3 => {
            let q = quarter()?;
            let planes = (3 * q..=5 * q).map(|i| i % mc).collect();
            (Symmetry::PlaneC90C270, planes, Some((270.0, 90.0)))
        }
        _ => {
            let q = quarter()?;
            (Symmetry::Quadrant, (0..=q).collect(), Some((0.0, 90.0)))
        }
    };
    if let Some((first, last)) = ends {
        let (a, b) = (c[planes[0]], c[planes[planes.len() - 1]]);
        if (a - first).abs() > 1e-6 || (b - last).abs() > 1e-6 {
            return Err(format!(
                "Isym {isym} stores the planes C{first}° to C{last}°, but the C angles put them at \
                 {a}° and {b}°"
            ));
        }
    }
    Ok((symmetry, planes))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A EULUMDAT file of a rotationally symmetric downlight: 500 cd/klm at the nadir falling
    /// to 0 at 90°, two lamp sets of 600 and 400 lm, conversion factor `cf`.
    fn downlight(cf: &str) -> String {
        let mut lines = vec![
            "Acme Lighting",
            "1",
            "1",
            "4",
            "90",
            "3",
            "45",
            "R-17",
            "Dome 1",
            "D1",
            "dome.ldt",
            "2024-01-01 / test",
            "300",
            "0",
            "100",
            "200",
            "0",
            "10",
            "10",
            "10",
            "10",
            "100",
            "70,5",
            cf,
            "0",
            "2",
            "1",
            "1",
            "LED A",
            "LED B",
            "600",
            "400",
            "3000",
            "4000",
            "90",
            "80",
            "10",
            "8",
        ];
        lines.extend(["0.5"; 10]);
        lines.extend(["0", "90", "180", "270"]);
        lines.extend(["0", "45", "90"]);
        lines.extend(["500", "250,5", "0"]);
        lines.join("\r\n")
    }

    #[test]
    fn the_fixed_lines_are_read() {
        let f = parse(&downlight("1"), Path::new("dome.ldt")).unwrap();
        assert_eq!(f.version, "EULUMDAT");
        assert_eq!(f.manufacturer, "Acme Lighting");
        assert_eq!(f.luminaire, "Dome 1");
        assert_eq!(f.lamp, "LED A");
        assert_eq!(f.symmetry, Symmetry::Rotational);
        assert_eq!(f.stored, (1, 3));
        assert_eq!(f.lamp_flux, Some(1000.0));
        assert_eq!(f.output_ratio, Some(0.705));
        assert!((f.declared_flux().unwrap() - 705.0).abs() < 1e-9);
        // Round (b1 = 0) luminous area 200 mm across, 10 mm high.
        assert_eq!(
            f.opening,
            Opening {
                length: 0.2,
                width: 0.2,
                height: 0.01,
                round: true
            }
        );
        // cd/klm × 1000 lm / 1000 × conversion factor.
        assert_eq!(f.distribution.intensity_at(123.0, 0.0), 500.0);
        assert_eq!(f.distribution.intensity_at(0.0, 45.0), 250.5);
        let f = parse(&downlight("2,5"), Path::new("dome.ldt")).unwrap();
        assert_eq!(f.distribution.intensity_at(0.0, 45.0), 626.25);
    }

    #[test]
    fn errors_name_the_line() {
        let err = |text: &str| parse(text, Path::new("dome.ldt")).unwrap_err().to_string();
        let good = downlight("1");
        let with = |n: usize, value: &str| {
            let mut lines: Vec<&str> = good.lines().collect();
            lines[n - 1] = value;
            lines.join("\n")
        };
        assert_eq!(
            err(&with(3, "7")),
            "dome.ldt:3: expected the symmetry indicator Isym (a whole number from 0 to 4), found `7`"
        );
        assert_eq!(err(&with(24, "")), "dome.ldt:24: expected the conversion factor for luminous intensities, found an empty line");
        assert_eq!(
            err(&with(24, "0")),
            "dome.ldt:24: the conversion factor must be positive, not 0"
        );
        assert_eq!(
            err(&with(3, "2").replace("\n4\n90\n", "\n3\n90\n")),
            "dome.ldt:49: Isym 2 needs an even Mc, found Mc = 3"
        );
        assert_eq!(
            err(&with(3, "2").replace("\n0\n90\n180\n270\n", "\n0\n30\n60\n90\n")),
            "dome.ldt:49: Isym 2 stores the planes C0° to C180°, but the C angles put them at 0° \
             and 60°"
        );
        let lines: Vec<&str> = good.lines().collect();
        assert_eq!(
            err(&lines[..lines.len() - 1].join("\n")),
            "dome.ldt:57: expected 3 luminous intensities, found 2 (the file ends)"
        );
        assert_eq!(
            err("Acme\n1\n"),
            "dome.ldt:2: expected the symmetry indicator Isym on line 3, found the end of the file"
        );
    }
}
