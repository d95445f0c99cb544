//! The text of a photometric file as a stream of tokens that remember their line.
//!
//! IES LM-63 lets numbers wrap across lines anywhere and separates them by blanks or commas
//! (LM-63-2002 §3, "delimiter"); EULUMDAT writes one value per line, with a decimal comma in
//! some files. Both readers take their numbers from a [`Tokens`] stream, so a missing or
//! malformed value is reported at its own line.

use std::path::Path;

use super::{ErrorKind, ParseError};

/// Tokens with their 1-based line numbers, read front to back.
pub(super) struct Tokens<'a> {
    file: &'a Path,
    tokens: Vec<(usize, &'a str)>,
    next: usize,
    /// The line reported when the stream has ended: the last line of the file.
    end_line: usize,
    /// Whether `,` is a decimal separator (EULUMDAT) rather than a delimiter (IES).
    decimal_comma: bool,
}

impl<'a> Tokens<'a> {
    /// The tokens of `lines` (1-based line number, text). With `decimal_comma`, tokens are
    /// separated by blanks only and `3,5` reads as 3.5; otherwise commas separate tokens too.
    pub fn new(
        file: &'a Path,
        lines: impl IntoIterator<Item = (usize, &'a str)>,
        end_line: usize,
        decimal_comma: bool,
    ) -> Self {
        let mut tokens = Vec::new();
        for (n, line) in lines {
            let parts = line.split(|c: char| c.is_whitespace() || (!decimal_comma && c == ','));
            tokens.extend(parts.filter(|t| !t.is_empty()).map(|t| (n, t)));
        }
        Self {
            file,
            tokens,
            next: 0,
            end_line,
            decimal_comma,
        }
    }

    /// An error at `line`.
    pub fn error_at(&self, line: usize, kind: ErrorKind) -> ParseError {
        ParseError {
            file: self.file.to_path_buf(),
            line: Some(line),
            kind,
        }
    }

    /// The line of the next token (the file's last line once the stream has ended).
    pub fn line(&self) -> usize {
        self.tokens.get(self.next).map_or(self.end_line, |t| t.0)
    }

    /// The line of the token just read (the first line before any).
    pub fn last_line(&self) -> usize {
        self.next
            .checked_sub(1)
            .and_then(|i| self.tokens.get(i))
            .map_or(1, |t| t.0)
    }

    /// The next token as a finite number, if it is one (the token is consumed only then).
    fn try_number(&mut self) -> Option<f64> {
        let (_, token) = self.tokens.get(self.next)?;
        let value = if self.decimal_comma {
            token.replace(',', ".").parse::<f64>().ok()
        } else {
            token.parse::<f64>().ok()
        };
        let value = value.filter(|v| v.is_finite())?;
        self.next += 1;
        Some(value)
    }

    /// What stands where a number was expected: `` `abc` `` or `the end of the file`.
    fn found(&self) -> String {
        self.tokens.get(self.next).map_or_else(
            || "the end of the file".to_string(),
            |t| format!("`{}`", t.1),
        )
    }

    /// The next number, described as `what` in the error if there is none.
    pub fn number(&mut self, what: &str) -> Result<f64, ParseError> {
        self.try_number().ok_or_else(|| {
            self.error_at(
                self.line(),
                ErrorKind::Expected {
                    what: what.to_string(),
                    found: self.found(),
                },
            )
        })
    }

    /// The next number, which must be a whole number in `lo..=hi`.
    pub fn integer(&mut self, what: &str, lo: i64, hi: i64) -> Result<i64, ParseError> {
        let line = self.line();
        let v = self.number(what)?;
        if v.fract() != 0.0 || v < lo as f64 || v > hi as f64 {
            return Err(self.error_at(
                line,
                ErrorKind::Expected {
                    what: format!("{what} (a whole number from {lo} to {hi})"),
                    found: format!("`{v}`"),
                },
            ));
        }
        Ok(v as i64)
    }

    /// The next `n` numbers: a list of `what`.
    pub fn list(&mut self, n: usize, what: &'static str) -> Result<Vec<f64>, ParseError> {
        // The capacity is bounded by the tokens left, whatever count a broken file announces.
        let mut values = Vec::with_capacity(n.min(self.tokens.len() - self.next));
        while values.len() < n {
            match self.try_number() {
                Some(v) => values.push(v),
                None => {
                    let after = match self.tokens.get(self.next) {
                        Some(t) => format!(" and then `{}`", t.1),
                        None => " (the file ends)".to_string(),
                    };
                    return Err(self.error_at(
                        self.line(),
                        ErrorKind::Count {
                            what,
                            expected: n,
                            found: values.len(),
                            after,
                        },
                    ));
                }
            }
        }
        Ok(values)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_keep_their_lines_and_lists_say_how_far_they_got() {
        let text = "1, 2 3\n\n4,5\nx";
        let lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
        let mut t = Tokens::new(Path::new("a.ies"), lines, 4, false);
        assert_eq!(t.list(3, "angles").unwrap(), vec![1.0, 2.0, 3.0]);
        assert_eq!(t.line(), 3);
        let e = t.list(3, "angles").unwrap_err();
        assert_eq!(
            e.to_string(),
            "a.ies:4: expected 3 angles, found 2 and then `x`"
        );
    }

    #[test]
    fn a_decimal_comma_reads_as_a_point() {
        let lines = [(1, "3,5"), (2, "nan")];
        let mut t = Tokens::new(Path::new("a.ldt"), lines, 2, true);
        assert_eq!(t.number("x").unwrap(), 3.5);
        assert_eq!(
            t.number("the factor").unwrap_err().to_string(),
            "a.ldt:2: expected the factor, found `nan`"
        );
    }
}
