//! A quantity checked against its reference ([`Check`]): the rows of `radiosity validate` (closed
//! forms, CIE 171, the Cornell box against Mitsuba 3) and of `cargo xtask suite` (the reference
//! suite), printed as a Markdown table ([`markdown`]) or as JSON rows ([`Check::json`]), as
//! `--format` ([`Format`]) says.
//!
//! The error is relative, |ours − reference| / |reference|, and a check passes when it is at
//! most its tolerance.

use std::fmt::Write;

use clap::ValueEnum;
use radiosity::Rgb;

/// How the checks are printed (`--format`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// A Markdown table.
    Markdown,
    /// A JSON array of rows.
    Json,
}

/// One checked quantity.
#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    /// What was run (the case, and for the suite the scene, solver and form factors).
    pub case: String,
    /// What was measured, with its unit.
    pub quantity: &'static str,
    /// The known answer.
    pub reference: f64,
    /// Our answer.
    pub ours: f64,
    /// Largest accepted relative error.
    pub tolerance: f64,
}

impl Check {
    /// The relative error |ours − reference| / |reference|.
    #[must_use]
    pub fn error(&self) -> f64 {
        (self.ours - self.reference).abs() / self.reference.abs()
    }

    /// Whether the error is within the tolerance.
    #[must_use]
    pub fn pass(&self) -> bool {
        self.error() <= self.tolerance
    }

    /// The JSON row: case, quantity, reference, ours, error, tolerance, pass.
    #[must_use]
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "case": self.case,
            "quantity": self.quantity,
            "reference": self.reference,
            "ours": self.ours,
            "error": self.error(),
            "tolerance": self.tolerance,
            "pass": self.pass(),
        })
    }
}

/// The Markdown table of `checks`: case, quantity, reference, ours, error, pass; one line each,
/// the last without a line break.
#[must_use]
pub fn markdown(checks: &[Check]) -> String {
    let mut table = String::from(
        "| case | quantity | reference | ours | error | pass |\n|---|---|---:|---:|---:|---|",
    );
    for c in checks {
        // Writing to a String cannot fail.
        let _ = write!(
            table,
            "\n| {} | {} | {:.6} | {:.6} | {:.3} % | {} (≤ {:e}) |",
            c.case,
            c.quantity,
            c.reference,
            c.ours,
            100.0 * c.error(),
            if c.pass() { "yes" } else { "NO" },
            c.tolerance
        );
    }
    table
}

/// An RGB triple from a JSON array of three numbers (a reference file's radiosity).
#[must_use]
pub fn rgb(values: &[serde_json::Value]) -> Option<Rgb> {
    match values {
        [r, g, b] => Some(Rgb::new(r.as_f64()?, g.as_f64()?, b.as_f64()?)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(ours: f64) -> Check {
        Check {
            case: "case".into(),
            quantity: "F",
            reference: 0.2,
            ours,
            tolerance: 0.01,
        }
    }

    #[test]
    fn a_check_passes_within_its_relative_tolerance() {
        assert!(check(0.2019).pass());
        assert!(!check(0.2021).pass());
        assert!((check(0.19).error() - 0.05).abs() < 1e-12);
        assert_eq!(check(0.2021).json()["pass"], false);
    }

    #[test]
    fn the_table_has_a_header_and_a_line_per_check() {
        let table = markdown(&[check(0.2), check(0.3)]);
        let lines: Vec<&str> = table.lines().collect();
        assert_eq!(lines.len(), 4);
        assert_eq!(
            lines[2],
            "| case | F | 0.200000 | 0.200000 | 0.000 % | yes (≤ 1e-2) |"
        );
        assert!(
            lines[3].ends_with("| 50.000 % | NO (≤ 1e-2) |"),
            "{}",
            lines[3]
        );
    }

    #[test]
    fn rgb_takes_exactly_three_numbers() {
        let json: serde_json::Value = serde_json::json!([1.0, 2.0, 3.0]);
        assert_eq!(rgb(json.as_array().unwrap()), Some(Rgb::new(1.0, 2.0, 3.0)));
        assert_eq!(rgb(&[serde_json::json!(1.0)]), None);
        let words = serde_json::json!(["a", "b", "c"]);
        assert_eq!(rgb(words.as_array().unwrap()), None);
    }
}
