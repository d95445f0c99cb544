//! # IES LM-63: the North American photometric file
//!
//! ANSI/IES LM-63, *Standard File Format for the Electronic Transfer of Photometric Data*
//! (revisions 1986, 1991, 1995, 2002, 2019), is a text file in this order:
//!
//! ```text
//! IESNA:LM-63-2002                       the revision (IESNA91; IESNA:LM-63-1995; IES:LM-63-2019;
//!                                        none in LM-63-1986)
//! [TEST] 12345                           keyword lines: [MANUFAC], [LUMINAIRE], [LAMP], [LUMCAT],
//! [MANUFAC] Acme                         [ISSUEDATE], ...; [MORE] continues the line before
//! TILT=NONE                              or TILT=INCLUDE (a tilt table follows) or TILT=<file>
//! 1 1000 1 37 5 1 2 0.6 0.6 0            lamps, lumens per lamp (−1: absolute photometry),
//!                                        candela multiplier, # vertical angles, # horizontal
//!                                        angles, photometric type (1 = C, 2 = B, 3 = A), units
//!                                        (1 feet, 2 metres), width, length, height of the
//!                                        luminous opening
//! 1 1 32                                 ballast factor, ballast-lamp factor (1995; "future use"
//!                                        2002; file generation type 2019), input watts
//! 0 2.5 5 ... 90                         the vertical angles γ
//! 0 22.5 45 67.5 90                      the horizontal angles C
//! 1200 1180 ...                          candela: all γ of the first C, then the next C, ...
//! ```
//!
//! From the `TILT=` line on the file is a stream of numbers separated by blanks, commas or line
//! ends, wrapped anywhere; the reader takes it as such.
//!
//! **Tilt.** `TILT=INCLUDE` is followed by the lamp-to-luminaire geometry (1: lamp vertical,
//! base up or down; 2: lamp horizontal, tilting along its axis; 3: lamp horizontal, tilting
//! across it), the number of tilt angles, the angles and one multiplying factor per angle:
//! the factor by which all candela values change when the luminaire is installed tilted by that
//! angle from its photometric position. The reader keeps the table as a [`Tilt`]; the
//! installation, which knows the tilt, applies [`Tilt::factor`]. `TILT=<file>` (the table in
//! another file) is refused with its line.
//!
//! **Photometric type.** Only type C (vertical planes about the luminaire's vertical axis, the
//! photometry of interior and area luminaires) is read; types A and B are refused with their
//! line. The horizontal angles say the symmetry: a single angle — rotational; 0–90 — both
//! principal planes; 0–180 — the C0–C180 plane; 90–270 — the C90–C270 plane (LM-63-1995);
//! 0 to more than 180 — none ([`Symmetry`]).
//!
//! **Values.** The candela values are multiplied by the candela multiplier and the ballast
//! factor (and, in LM-63-1991 and -1995, by the ballast-lamp photometric factor, which later
//! revisions replaced by an unused field). Lengths are converted to metres (1 ft = 0.3048 m);
//! LM-63-2002 writes negative width and length for round openings.

use std::path::Path;

use super::distribution::{Distribution, Symmetry};
use super::text::Tokens;
use super::{ErrorKind, Format, Opening, ParseError, PhotometricFile};

/// The tilt table of `TILT=INCLUDE`: the multiplier of all candela values as a function of the
/// luminaire's tilt from its photometric position.
#[derive(Clone, Debug, PartialEq)]
pub struct Tilt {
    /// The lamp-to-luminaire geometry: 1 lamp vertical, 2 horizontal tilting along its axis,
    /// 3 horizontal tilting across it.
    pub geometry: u8,
    /// Tilt angles, degrees, rising.
    pub angles: Vec<f64>,
    /// The multiplying factor at each angle.
    pub factors: Vec<f64>,
}

impl Tilt {
    /// The multiplying factor at a tilt of `angle` degrees: linear between the table's angles,
    /// the end value beyond them.
    #[must_use]
    pub fn factor(&self, angle: f64) -> f64 {
        let a = &self.angles;
        let k = a.partition_point(|&x| x <= angle);
        if k == 0 {
            return self.factors[0];
        }
        if k == a.len() {
            return self.factors[a.len() - 1];
        }
        let t = (angle - a[k - 1]) / (a[k] - a[k - 1]);
        self.factors[k - 1] * (1.0 - t) + self.factors[k] * t
    }
}

/// The most angles of a list the reader accepts: 1/100° steps over a full circle.
const MAX_ANGLES: i64 = 36_001;

/// Parses the text of an IES LM-63 file; `path` names it in errors.
///
/// # Errors
/// [`ParseError`] with the line of the first problem.
pub fn parse(text: &str, path: &Path) -> Result<PhotometricFile, ParseError> {
    let lines: Vec<&str> = text.lines().collect();
    let error = |line: usize, kind| ParseError {
        file: path.to_path_buf(),
        line: Some(line),
        kind,
    };

    // The revision, from the first line.
    let first = lines.first().map_or("", |l| l.trim());
    let declared = first
        .strip_prefix("IESNA:LM-63-")
        .or_else(|| first.strip_prefix("IES:LM-63-"))
        .map(|year| format!("LM-63-{}", year.trim()))
        .or_else(|| (first == "IESNA91").then(|| "LM-63-1991".to_string()));
    let header_start = usize::from(declared.is_some());
    let version = declared.unwrap_or_else(|| "LM-63-1986".to_string());

    // Keyword lines up to TILT=.
    let mut keywords: Vec<(String, String)> = Vec::new();
    let mut tilt_line = None;
    for (i, line) in lines.iter().enumerate().skip(header_start) {
        let t = line.trim();
        if t.get(..5).is_some_and(|p| p.eq_ignore_ascii_case("TILT=")) {
            tilt_line = Some(i);
            break;
        }
        if let Some(rest) = t.strip_prefix('[') {
            if let Some((key, value)) = rest.split_once(']') {
                let (key, value) = (key.trim().to_ascii_uppercase(), value.trim().to_string());
                match (key.as_str(), keywords.last_mut()) {
                    ("MORE", Some(last)) => {
                        last.1.push(' ');
                        last.1.push_str(&value);
                    }
                    _ => keywords.push((key, value)),
                }
            }
        }
        // Other lines before TILT= are free text (LM-63-1986 has no keywords).
    }
    let Some(tilt_index) = tilt_line else {
        return Err(error(
            lines.len().max(1),
            ErrorKind::Expected {
                what: "a line TILT=NONE, TILT=INCLUDE or TILT=<file>".into(),
                found: "the end of the file".into(),
            },
        ));
    };
    let keyword = |name: &str| {
        keywords
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.clone())
            .unwrap_or_default()
    };

    // Everything after TILT= is a stream of numbers.
    let tilt_value = lines[tilt_index].trim()[5..].trim();
    let rest = lines
        .iter()
        .enumerate()
        .skip(tilt_index + 1)
        .map(|(i, l)| (i + 1, *l));
    let mut tokens = Tokens::new(path, rest, lines.len(), false);
    let tilt = if tilt_value.eq_ignore_ascii_case("NONE") {
        None
    } else if tilt_value.eq_ignore_ascii_case("INCLUDE") {
        Some(read_tilt(&mut tokens)?)
    } else {
        return Err(error(
            tilt_index + 1,
            ErrorKind::Unsupported {
                what: format!("TILT={tilt_value} (a tilt table in another file)"),
                instead: "write the table into this one with TILT=INCLUDE",
            },
        ));
    };

    // The line of counts.
    let lamps = tokens.integer("the number of lamps", 1, i64::from(u32::MAX))?;
    let lumens_line = tokens.line();
    let lumens = tokens.number("the lumens per lamp")?;
    if !(lumens > 0.0 || lumens == -1.0) {
        return Err(error(
            lumens_line,
            ErrorKind::Invalid(format!(
                "the lumens per lamp must be positive (or −1 for absolute photometry), not {lumens}"
            )),
        ));
    }
    let multiplier = positive(&mut tokens, "the candela multiplier")?;
    let vertical = tokens.integer("the number of vertical angles", 1, MAX_ANGLES)? as usize;
    let horizontal = tokens.integer("the number of horizontal angles", 1, MAX_ANGLES)? as usize;
    let type_line = tokens.line();
    let photometric_type = tokens.integer("the photometric type", 1, 3)?;
    if photometric_type != 1 {
        let name = if photometric_type == 2 { "B" } else { "A" };
        return Err(error(
            type_line,
            ErrorKind::Unsupported {
                what: format!("photometric type {photometric_type} (type {name})"),
                instead: "only type C (1) is read",
            },
        ));
    }
    let units = tokens.integer("the units type (1 feet, 2 metres)", 1, 2)?;
    let metres = if units == 1 { 0.3048 } else { 1.0 };
    let width = tokens.number("the width of the luminous opening")?;
    let length = tokens.number("the length of the luminous opening")?;
    let height = tokens.number("the height of the luminous opening")?;

    // The ballast line.
    let ballast = positive(&mut tokens, "the ballast factor")?;
    let ballast_lamp = tokens.number("the ballast-lamp factor (or future use field)")?;
    let _input_watts = tokens.number("the input watts")?;
    let old_factor = matches!(version.as_str(), "LM-63-1991" | "LM-63-1995");
    if old_factor && ballast_lamp <= 0.0 {
        return Err(error(
            tokens.last_line(),
            ErrorKind::Invalid(format!(
                "the ballast-lamp photometric factor must be positive, not {ballast_lamp}"
            )),
        ));
    }
    let factor = multiplier * ballast * if old_factor { ballast_lamp } else { 1.0 };

    // The angles and the candela values.
    let gamma_line = tokens.line();
    let gamma = tokens.list(vertical, "vertical angles")?;
    let c_line = tokens.line();
    let c = tokens.list(horizontal, "horizontal angles")?;
    let candela_line = tokens.line();
    let candela = tokens.list(vertical * horizontal, "candela values")?;
    if let Some(w) = gamma.windows(2).find(|w| w[1] <= w[0]) {
        return Err(error(
            gamma_line,
            ErrorKind::Invalid(format!(
                "the vertical angles must rise, found {} after {}",
                w[1], w[0]
            )),
        ));
    }
    if gamma[0] < 0.0 || gamma[vertical - 1] > 180.0 {
        return Err(error(
            gamma_line,
            ErrorKind::Invalid(format!(
                "type C vertical angles lie in 0–180°, found {}–{}",
                gamma[0],
                gamma[vertical - 1]
            )),
        ));
    }
    let symmetry = lateral_symmetry(&c).map_err(|m| error(c_line, ErrorKind::Invalid(m)))?;
    let scaled = candela.iter().map(|v| v * factor).collect();
    let distribution = Distribution::new(symmetry, &c, &gamma, scaled).map_err(|e| {
        error(
            candela_line,
            ErrorKind::Invalid(format!("the candela table: {e}")),
        )
    })?;

    Ok(PhotometricFile {
        format: Format::Ies,
        version,
        manufacturer: keyword("MANUFAC"),
        luminaire: keyword("LUMINAIRE"),
        lamp: keyword("LAMP"),
        symmetry,
        stored: (horizontal, vertical),
        lamp_flux: (lumens > 0.0).then_some(lamps as f64 * lumens),
        output_ratio: None,
        opening: Opening {
            length: length.abs() * metres,
            width: width.abs() * metres,
            height: height.abs() * metres,
            round: width < 0.0 || length < 0.0,
        },
        tilt,
        distribution,
    })
}

/// The next number, which must be positive.
fn positive(tokens: &mut Tokens<'_>, what: &str) -> Result<f64, ParseError> {
    let line = tokens.line();
    let v = tokens.number(what)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(tokens.error_at(
            line,
            ErrorKind::Invalid(format!("{what} must be positive, not {v}")),
        ))
    }
}

/// The tilt table after `TILT=INCLUDE`.
fn read_tilt(tokens: &mut Tokens<'_>) -> Result<Tilt, ParseError> {
    let geometry = tokens.integer("the lamp-to-luminaire geometry (1, 2 or 3)", 1, 3)? as u8;
    let n = tokens.integer("the number of tilt angles", 1, MAX_ANGLES)? as usize;
    let line = tokens.line();
    let angles = tokens.list(n, "tilt angles")?;
    let factors = tokens.list(n, "tilt multiplying factors")?;
    if angles.windows(2).any(|w| w[1] <= w[0]) || factors.iter().any(|f| *f < 0.0) {
        return Err(tokens.error_at(
            line,
            ErrorKind::Invalid(
                "the tilt angles must rise and the tilt factors must not be negative".into(),
            ),
        ));
    }
    Ok(Tilt {
        geometry,
        angles,
        factors,
    })
}

/// The symmetry the horizontal angles of a type C file imply (LM-63-2002 §4, LM-63-1995).
fn lateral_symmetry(c: &[f64]) -> Result<Symmetry, String> {
    let (first, last) = (c[0], c[c.len() - 1]);
    if c.len() == 1 {
        return Ok(Symmetry::Rotational);
    }
    if let Some(w) = c.windows(2).find(|w| w[1] <= w[0]) {
        return Err(format!(
            "the horizontal angles must rise, found {} after {}",
            w[1], w[0]
        ));
    }
    if first == 0.0 && last == 90.0 {
        Ok(Symmetry::Quadrant)
    } else if first == 0.0 && last == 180.0 {
        Ok(Symmetry::PlaneC0C180)
    } else if first == 90.0 && last == 270.0 {
        Ok(Symmetry::PlaneC90C270)
    } else if first == 0.0 && last > 180.0 && last <= 360.0 {
        Ok(Symmetry::None)
    } else {
        Err(format!(
            "type C horizontal angles run 0–90, 0–180, 90–270 or 0–360 (or are a single angle), \
             found {first}–{last}"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small bare lamp, 100 cd everywhere, in a given header and tilt.
    fn lamp(header: &str, tilt: &str) -> String {
        format!(
            "{header}[TEST] T1\n[MANUFAC] Acme\n[LUMINAIRE] Globe\n[MORE] opal\n[LAMP] LED 10 W\n\
             {tilt}\n1 1256.637 1 3 1 1 2 -0.1 -0.1 0.05\n1 1 10\n0 90 180\n0\n100 100 100\n"
        )
    }

    fn parse_str(text: &str) -> Result<PhotometricFile, ParseError> {
        parse(text, Path::new("lamp.ies"))
    }

    #[test]
    fn every_revision_header_is_read() {
        for (header, version) in [
            ("IESNA91\n", "LM-63-1991"),
            ("IESNA:LM-63-1995\n", "LM-63-1995"),
            ("IESNA:LM-63-2002\n", "LM-63-2002"),
            ("IES:LM-63-2019\n", "LM-63-2019"),
            ("", "LM-63-1986"),
        ] {
            let f = parse_str(&lamp(header, "TILT=NONE")).expect(version);
            assert_eq!(f.version, version);
            assert_eq!(f.manufacturer, "Acme");
            assert_eq!(f.luminaire, "Globe opal");
            assert_eq!(f.lamp, "LED 10 W");
            assert_eq!(f.symmetry, Symmetry::Rotational);
            assert_eq!(f.stored, (1, 3));
            assert_eq!(f.lamp_flux, Some(1256.637));
            // A negative width and length: a round opening, 0.1 m across.
            assert_eq!(
                f.opening,
                Opening {
                    length: 0.1,
                    width: 0.1,
                    height: 0.05,
                    round: true
                }
            );
            assert!(f.tilt.is_none());
        }
    }

    #[test]
    fn multipliers_scale_the_candela_values() {
        // Candela multiplier 2, ballast factor 0.5 and (LM-63-1995) ballast-lamp factor 3.
        let text = "IESNA:LM-63-1995\nTILT=NONE\n1 -1 2 2 1 1 1 1 2 0\n0.5 3 10\n0 90\n0\n10 10\n";
        let f = parse_str(text).unwrap();
        assert_eq!(f.distribution.intensity_at(0.0, 45.0), 30.0);
        assert_eq!(
            f.lamp_flux, None,
            "absolute photometry declares no lamp flux"
        );
        // Feet: 2 ft long, 1 ft wide.
        assert!(
            (f.opening.length - 0.6096).abs() < 1e-12 && (f.opening.width - 0.3048).abs() < 1e-12
        );
        // In LM-63-2002 the same field is unused.
        let f = parse_str(&text.replace("1995", "2002")).unwrap();
        assert_eq!(f.distribution.intensity_at(0.0, 45.0), 10.0);
    }

    #[test]
    fn a_tilt_table_is_read_and_interpolated() {
        let f = parse_str(&lamp(
            "IESNA:LM-63-2002\n",
            "TILT=INCLUDE\n1\n3\n0 45 90\n1 0.9\n0.7",
        ))
        .unwrap();
        let t = f.tilt.expect("tilt");
        assert_eq!(t.geometry, 1);
        assert_eq!(t.factor(0.0), 1.0);
        assert!((t.factor(22.5) - 0.95).abs() < 1e-12);
        assert!((t.factor(67.5) - 0.8).abs() < 1e-12);
        assert_eq!(t.factor(120.0), 0.7);
    }

    #[test]
    fn values_wrap_across_lines_and_commas_separate_them() {
        let text = "IESNA:LM-63-2002\nTILT=NONE\n1,1000,1,3,2,1,2,0,0,0\n1 1 10\n0 45\n90 0\n180\n\
                    10,20\n30 11\n21\n31\n";
        let f = parse_str(text).unwrap();
        assert_eq!(f.symmetry, Symmetry::PlaneC0C180);
        assert_eq!(f.distribution.intensity_at(0.0, 90.0), 30.0);
        assert_eq!(f.distribution.intensity_at(180.0, 45.0), 21.0);
    }

    #[test]
    fn errors_name_the_line_and_what_was_expected() {
        let err = |text: &str| parse_str(text).unwrap_err().to_string();
        let tilt_file = lamp("IESNA:LM-63-2002\n", "TILT=lamp.tlt");
        assert_eq!(
            err(&tilt_file),
            "lamp.ies:7: TILT=lamp.tlt (a tilt table in another file) is not supported; write \
             the table into this one with TILT=INCLUDE"
        );
        let type_b = lamp("", "TILT=NONE").replace("1 1 2 -0.1", "1 2 2 -0.1");
        assert_eq!(
            err(&type_b),
            "lamp.ies:7: photometric type 2 (type B) is not supported; only type C (1) is read"
        );
        // 37 vertical angles announced, 20 given before the file ends.
        let angles: Vec<String> = (0..20).map(|k| (k * 5).to_string()).collect();
        let short = format!(
            "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 37 1 1 2 0 0 0\n1 1 10\n{}\n",
            angles.join("\n")
        );
        assert_eq!(
            err(&short),
            "lamp.ies:24: expected 37 vertical angles, found 20 (the file ends)"
        );
        assert_eq!(
            err("IESNA:LM-63-2002\n[TEST] x\n"),
            "lamp.ies:2: expected a line TILT=NONE, TILT=INCLUDE or TILT=<file>, found the end of the file"
        );
        assert_eq!(
            err("TILT=NONE\n1 1000 1 2 x"),
            "lamp.ies:2: expected the number of horizontal angles, found `x`"
        );
        assert_eq!(
            err("TILT=NONE\n1 1000 1 2 2 1 3 0 0 0"),
            "lamp.ies:2: expected the units type (1 feet, 2 metres) (a whole number from 1 to 2), found `3`"
        );
        let sideways = "TILT=NONE\n1 1000 1 2 2 1 2 0 0 0\n1 1 1\n0 90\n0 45\n1 1 1 1\n";
        assert!(err(sideways).starts_with("lamp.ies:5: type C horizontal angles run"));
        let falling = "TILT=NONE\n1 1000 1 2 1 1 2 0 0 0\n1 1 1\n90 0\n0\n1 1\n";
        assert_eq!(
            err(falling),
            "lamp.ies:4: the vertical angles must rise, found 0 after 90"
        );
        let negative = "TILT=NONE\n1 1000 1 2 1 1 2 0 0 0\n1 1 1\n0 90\n0\n1 -1\n";
        assert!(err(negative).starts_with("lamp.ies:6: the candela table: intensities must be"));
    }
}
