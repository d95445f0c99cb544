//! The scene's warnings as a run prints them: alike ones once.
//!
//! A Mitsuba file of hundreds of shapes can give the same warning for each of them ("skipped 6
//! degenerate face(s)" at every `<shape>` line), which buries the few that matter (BSDFs
//! approximated, shapes left out). Warnings that differ only in their numbers (lines, counts)
//! are alike: the first of a run of more than [`SHOWN`] is printed with how many more there
//! are, at the place of the first. `radiosity info` still lists every one.

use std::collections::HashMap;

/// The most alike warnings printed one by one.
pub(crate) const SHOWN: usize = 3;

/// The warnings to print, in the order of their first occurrence.
pub(crate) fn summarise(warnings: &[String]) -> Vec<String> {
    let patterns: Vec<String> = warnings.iter().map(|w| pattern(w)).collect();
    let mut count: HashMap<&str, usize> = HashMap::new();
    for p in &patterns {
        *count.entry(p).or_default() += 1;
    }
    let mut printed: HashMap<&str, usize> = HashMap::new();
    let mut out = Vec::new();
    for (w, p) in warnings.iter().zip(&patterns) {
        let total = count[p.as_str()];
        let seen = printed.entry(p).or_default();
        *seen += 1;
        if total <= SHOWN {
            out.push(w.clone());
        } else if *seen == 1 {
            out.push(format!(
                "{w} (and {} more like it; `radiosity info` lists them all)",
                total - 1
            ));
        }
    }
    out
}

/// The warning with every run of digits replaced by `#`.
fn pattern(warning: &str) -> String {
    let mut out = String::with_capacity(warning.len());
    let mut in_number = false;
    for c in warning.chars() {
        if c.is_ascii_digit() {
            if !in_number {
                out.push('#');
            }
            in_number = true;
        } else {
            out.push(c);
            in_number = false;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alike_warnings_beyond_a_few_are_printed_once_with_their_count() {
        let mut warnings: Vec<String> = (0..50)
            .map(|i| {
                format!(
                    "s.xml:{}: shape type=\"obj\": skipped {} degenerate face(s)",
                    10 + i,
                    i % 7 + 1
                )
            })
            .collect();
        warnings.insert(3, "BSDFs approximated as diffuse: conductor (2)".to_owned());
        warnings.push("s.xml: 3 transparent shape(s) left out".to_owned());
        let out = summarise(&warnings);
        assert_eq!(
            out,
            [
                "s.xml:10: shape type=\"obj\": skipped 1 degenerate face(s) (and 49 more like \
                 it; `radiosity info` lists them all)",
                "BSDFs approximated as diffuse: conductor (2)",
                "s.xml: 3 transparent shape(s) left out",
            ]
        );
        // A few alike ones are printed as they are.
        let few = &warnings[..SHOWN];
        assert_eq!(summarise(few), few);
    }
}
