//! The manifest `benches/figures/figures.toml`: where each figure of the README's table comes
//! from.
//!
//! ```toml
//! [sources.validate]                   # a measurement: one JSON file beside the manifest
//! file = "validate.json"
//! command = "radiosity validate --format json > benches/figures/validate.json"
//! kind = "output"                      # the file is what `command` writes (default)
//!
//! [[figures]]                          # one row of the table
//! label = "`radiosity validate`, Cornell box vs Mitsuba 3, worst object"
//! value = "{worst}"                    # the cell: text with {name} for each value
//! values.worst = { source = "validate", path = "/?case^=Cornell/error", reduce = "max", unit = "percent", digits = 2 }
//! ```
//!
//! A source of `kind = "transcribed"` holds numbers copied from what `command` printed (a
//! Python script driving another renderer, or a run too long to repeat on demand); `cargo
//! xtask figures --measure` reruns only the `output` sources. The path language is
//! [`super::path`]'s; the units are [`Unit`]'s.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::Context;
use serde::Deserialize;

/// The whole manifest.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// The measurements by name.
    pub sources: BTreeMap<String, Source>,
    /// The rows of the table, in order.
    pub figures: Vec<Figure>,
}

/// One measurement: a JSON file and the command that makes it.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Source {
    /// The JSON file, relative to the manifest's folder.
    pub file: String,
    /// The exact command, run from the repository's root.
    pub command: String,
    /// How the file comes from the command.
    #[serde(default)]
    pub kind: Kind,
}

/// How a source's file comes from its command.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Kind {
    /// The command writes the file (`--measure` reruns it).
    #[default]
    Output,
    /// The file holds numbers copied from what the command printed.
    Transcribed,
}

/// One row of the table.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Figure {
    /// What the figure is.
    pub label: String,
    /// The value cell: text in which `{name}` stands for the value `name`.
    pub value: String,
    /// The values by name.
    pub values: BTreeMap<String, Value>,
}

/// One value of a row: a place in a source's JSON and how to print it.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Value {
    /// The source's name.
    pub source: String,
    /// Where the value is in the source's JSON ([`super::path::select`]).
    pub path: String,
    /// How the values the path selects become one.
    #[serde(default)]
    pub reduce: Reduce,
    /// The unit the number is printed in.
    #[serde(default)]
    pub unit: Unit,
    /// Digits after the decimal point.
    #[serde(default = "two")]
    pub digits: usize,
}

fn two() -> usize {
    2
}

/// How the values a path selects become one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Reduce {
    /// The path selects exactly one value.
    #[default]
    One,
    /// The largest number.
    Max,
    /// The smallest number.
    Min,
    /// Booleans: "K of N", the count of `true` among them.
    CountTrue,
}

/// The unit a number is printed in; JSON holds SI base units (fractions, seconds, bytes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Unit {
    /// As it is.
    #[default]
    Number,
    /// A whole number in groups of three digits: "1 039 397".
    Count,
    /// A fraction as a percentage: 0.0075 → "0.75 %".
    Percent,
    /// Seconds: "3.6 s".
    Seconds,
    /// Bytes as gigabytes (10⁹).
    Gigabytes,
    /// Bytes as megabytes (10⁶).
    Megabytes,
    /// Rays per second as millions.
    Mrays,
}

impl Unit {
    /// `number` in this unit with `digits` decimals.
    #[must_use]
    pub fn format(self, number: f64, digits: usize) -> String {
        let (scale, suffix) = match self {
            Unit::Count => return grouped(number),
            Unit::Number => (1.0, ""),
            Unit::Percent => (100.0, " %"),
            Unit::Seconds => (1.0, " s"),
            Unit::Gigabytes => (1e-9, " GB"),
            Unit::Megabytes => (1e-6, " MB"),
            Unit::Mrays => (1e-6, " Mrays/s"),
        };
        format!("{:.digits$}{suffix}", number * scale)
    }
}

/// `number` rounded to a whole number, its digits in groups of three.
fn grouped(number: f64) -> String {
    let digits = format!("{:.0}", number.abs());
    let mut text = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            text.push(' ');
        }
        text.push(c);
    }
    if number < 0.0 && digits != "0" {
        text.insert(0, '-');
    }
    text
}

impl Manifest {
    /// Reads and checks the manifest at `path`: every value names a source of the manifest,
    /// and every `{name}` of a row's text is one of its values and each value is used.
    ///
    /// # Errors
    /// The file is unreadable or malformed, or a row refers to what is not there.
    pub fn read(path: &Path) -> anyhow::Result<Self> {
        let text = std::fs::read_to_string(path).with_context(|| format!("{}", path.display()))?;
        let manifest: Self =
            toml::from_str(&text).with_context(|| format!("{}", path.display()))?;
        for figure in &manifest.figures {
            for (name, value) in &figure.values {
                anyhow::ensure!(
                    manifest.sources.contains_key(&value.source),
                    "{}: figure {:?}: value {name}: no source {:?}",
                    path.display(),
                    figure.label,
                    value.source
                );
                anyhow::ensure!(
                    figure.value.contains(&format!("{{{name}}}")),
                    "{}: figure {:?}: value {name} is not in its text",
                    path.display(),
                    figure.label
                );
            }
        }
        Ok(manifest)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_scale_and_name_the_number() {
        assert_eq!(Unit::Percent.format(0.0075, 2), "0.75 %");
        assert_eq!(Unit::Seconds.format(3.64, 1), "3.6 s");
        assert_eq!(Unit::Gigabytes.format(2.93e9, 2), "2.93 GB");
        assert_eq!(Unit::Mrays.format(17.0e6, 1), "17.0 Mrays/s");
        assert_eq!(Unit::Number.format(1.5, 0), "2");
        assert_eq!(Unit::Count.format(1_039_397.0, 2), "1 039 397");
        assert_eq!(Unit::Count.format(948.0, 0), "948");
        assert_eq!(Unit::Count.format(-48_384.0, 0), "-48 384");
    }

    #[test]
    fn a_row_parses_with_its_defaults() {
        let m: Manifest = toml::from_str(
            "[sources.v]\nfile = \"v.json\"\ncommand = \"radiosity validate\"\n\n\
             [[figures]]\nlabel = \"l\"\nvalue = \"{x}\"\nvalues.x = { source = \"v\", path = \"/0\" }\n",
        )
        .unwrap();
        assert_eq!(m.sources["v"].kind, Kind::Output);
        let x = &m.figures[0].values["x"];
        assert_eq!((x.reduce, x.unit, x.digits), (Reduce::One, Unit::Number, 2));
    }
}
