//! Where a figure is in a measurement's JSON, and how the values found become one.
//!
//! A path is a JSON Pointer (RFC 6901: `/0/error`, `~1` for a `/` inside a segment, `~0` for a
//! `~`) with two more kinds of segment, so that a figure can name a row by what it is rather
//! than where it happens to stand:
//!
//! | segment | keeps |
//! |---|---|
//! | `name`, `3` | the member `name` of each object, the element 3 of each array |
//! | `*` | every element of each array |
//! | `?key=text` | the elements of each array (or the objects) whose member `key` is `text` (a string, or a number so written) |
//! | `?key^=text` | the same, whose `key` starts with `text` |
//! | `?key*=text` | the same, whose `key` contains `text` |
//!
//! `/?case^=Cornell/error` is the `error` of every row whose `case` starts with `Cornell`, in
//! an array of rows; `/?quantity^=B/?case*=box/error` of those that also have `box` in `case`.
//! [`reduce`] turns what a path selects into the figure's text.

use anyhow::{bail, ensure, Context};
use serde_json::Value;

use super::manifest::{Reduce, Unit};

/// The values `path` selects in `root`, in document order.
///
/// # Errors
/// The path does not start with `/`, or a member or element it names is missing.
pub fn select<'a>(root: &'a Value, path: &str) -> anyhow::Result<Vec<&'a Value>> {
    let rest = path
        .strip_prefix('/')
        .with_context(|| format!("{path:?}: a path starts with /"))?;
    let mut current = vec![root];
    for raw in rest.split('/') {
        let segment = raw.replace("~1", "/").replace("~0", "~");
        current = step(current, &segment).with_context(|| format!("{path:?} at {segment:?}"))?;
    }
    Ok(current)
}

/// One segment applied to every value selected so far.
fn step<'a>(current: Vec<&'a Value>, segment: &str) -> anyhow::Result<Vec<&'a Value>> {
    if segment == "*" {
        let mut next = Vec::new();
        for v in current {
            next.extend(v.as_array().context("not an array")?);
        }
        return Ok(next);
    }
    if let Some(filter) = segment.strip_prefix('?') {
        let keep = Filter::parse(filter)?;
        let candidates = current.into_iter().flat_map(|v| match v {
            Value::Array(items) => items.iter().collect(),
            _ => vec![v],
        });
        return Ok(candidates.filter(|v| keep.matches(v)).collect());
    }
    current
        .into_iter()
        .map(|v| match v {
            Value::Array(items) => segment
                .parse::<usize>()
                .ok()
                .and_then(|i| items.get(i))
                .context("no such element"),
            _ => v.get(segment).context("no such member"),
        })
        .collect()
}

/// A `?key<op>text` segment.
struct Filter<'s> {
    key: &'s str,
    op: Op,
    text: &'s str,
}

/// How a filter compares a string with its text.
#[derive(Clone, Copy)]
enum Op {
    Equals,
    StartsWith,
    Contains,
}

impl<'s> Filter<'s> {
    fn parse(filter: &'s str) -> anyhow::Result<Self> {
        let (left, text) = filter.split_once('=').with_context(|| {
            format!("{filter:?}: a filter is ?key=text, ?key^=text or ?key*=text")
        })?;
        let (key, op) = if let Some(key) = left.strip_suffix('^') {
            (key, Op::StartsWith)
        } else if let Some(key) = left.strip_suffix('*') {
            (key, Op::Contains)
        } else {
            (left, Op::Equals)
        };
        Ok(Self { key, op, text })
    }

    fn matches(&self, value: &Value) -> bool {
        let s = match value.get(self.key) {
            Some(Value::String(s)) => s.clone(),
            Some(Value::Number(n)) => n.to_string(),
            _ => return false,
        };
        match self.op {
            Op::Equals => s == self.text,
            Op::StartsWith => s.starts_with(self.text),
            Op::Contains => s.contains(self.text),
        }
    }
}

/// The text of the values a path selected: reduced by `reduce`, a number printed in `unit`
/// with `digits` decimals, a string as it is.
///
/// # Errors
/// Nothing was selected, `One` found more than one value, or a value is not of the kind the
/// reduction takes (numbers; booleans for `CountTrue`).
pub fn reduce(
    values: &[&Value],
    reduce: Reduce,
    unit: Unit,
    digits: usize,
) -> anyhow::Result<String> {
    ensure!(!values.is_empty(), "the path selects nothing");
    let numbers = || -> anyhow::Result<Vec<f64>> {
        values
            .iter()
            .map(|v| v.as_f64().with_context(|| format!("{v} is not a number")))
            .collect()
    };
    let number = match reduce {
        Reduce::One => {
            ensure!(
                values.len() == 1,
                "the path selects {} values, not one",
                values.len()
            );
            if let Some(s) = values[0].as_str() {
                return Ok(s.to_string());
            }
            numbers()?[0]
        }
        Reduce::Max => numbers()?.into_iter().fold(f64::NEG_INFINITY, f64::max),
        Reduce::Min => numbers()?.into_iter().fold(f64::INFINITY, f64::min),
        Reduce::CountTrue => {
            let mut yes = 0;
            for v in values {
                match v.as_bool() {
                    Some(b) => yes += usize::from(b),
                    None => bail!("{v} is not a boolean"),
                }
            }
            return Ok(format!("{yes} of {}", values.len()));
        }
    };
    Ok(unit.format(number, digits))
}

#[cfg(test)]
mod tests {
    use serde_json::json;

    use super::*;

    fn rows() -> Value {
        json!([
            { "case": "Cornell box, floor", "quantity": "B", "error": 0.004, "pass": true },
            { "case": "Cornell box, light", "quantity": "B", "error": 0.0063, "pass": true },
            { "case": "furnace a/b", "quantity": "B", "error": 0.01, "pass": false, "n": 7 },
        ])
    }

    fn text(path: &str, r: Reduce, unit: Unit) -> anyhow::Result<String> {
        let rows = rows();
        let values = select(&rows, path)?;
        reduce(&values, r, unit, 2)
    }

    #[test]
    fn filters_pick_rows_by_what_they_are() {
        let max = text("/?case^=Cornell/error", Reduce::Max, Unit::Percent).unwrap();
        assert_eq!(
            max,
            text("/*/?case^=Cornell/error", Reduce::Max, Unit::Percent).unwrap()
        );
        assert_eq!(max, "0.63 %");
        let one = text("/?case=furnace a~1b/error", Reduce::One, Unit::Number).unwrap();
        assert_eq!(one, "0.01");
        let min = text("/?quantity=B/?case*=box/error", Reduce::Min, Unit::Percent).unwrap();
        assert_eq!(min, "0.40 %");
        assert_eq!(
            text("/1/case", Reduce::One, Unit::Number).unwrap(),
            "Cornell box, light"
        );
        assert_eq!(
            text("/?n=7/error", Reduce::One, Unit::Percent).unwrap(),
            "1.00 %"
        );
    }

    #[test]
    fn booleans_are_counted() {
        assert_eq!(
            text("/*/pass", Reduce::CountTrue, Unit::Number).unwrap(),
            "2 of 3"
        );
    }

    #[test]
    fn a_path_that_finds_nothing_or_too_much_is_an_error() {
        assert!(text("/?case^=Sponza/error", Reduce::Max, Unit::Percent).is_err());
        assert!(text("/*/error", Reduce::One, Unit::Percent).is_err());
        assert!(text("/*/missing", Reduce::Max, Unit::Percent).is_err());
        assert!(text("/7", Reduce::One, Unit::Number).is_err());
        assert!(text("0/error", Reduce::One, Unit::Number).is_err());
        assert!(text("/*/case", Reduce::Max, Unit::Number).is_err());
    }
}
