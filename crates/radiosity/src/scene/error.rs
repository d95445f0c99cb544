//! Scene loading errors: one line naming the file, the line and column, the key, and the cause.
//!
//! Every stage of loading (parse, validate, build, the OBJ/MTL reader) reports its first problem
//! as a [`SceneError`], whose `Display` is a single line in the compiler style
//!
//! ```text
//! scenes/box.toml:12:15: `objects[2].material`: unknown material `whit` (defined: red, white)
//! ```
//!
//! Parts that do not apply are left out (`FILE: cannot read: No such file or directory`).

use std::fmt;
use std::path::{Path, PathBuf};

/// A position in a source file, 1-based line and column (columns count characters).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Loc {
    /// The file.
    pub file: PathBuf,
    /// 1-based line.
    pub line: usize,
    /// 1-based column.
    pub col: usize,
}

impl fmt::Display for Loc {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file.display(), self.line, self.col)
    }
}

/// A scene that cannot be loaded: where, which key, and why.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub struct SceneError {
    /// The file the problem is in, when there is one.
    pub file: Option<PathBuf>,
    /// 1-based (line, column) inside [`SceneError::file`], when known.
    pub line_col: Option<(usize, usize)>,
    /// The key, as a dotted path (`objects[2].material`) or a bare name.
    pub key: Option<String>,
    /// What is wrong, on one line.
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(file) = &self.file {
            write!(f, "{}", file.display())?;
            if let Some((line, col)) = self.line_col {
                write!(f, ":{line}:{col}")?;
            }
            f.write_str(": ")?;
        }
        if let Some(key) = &self.key {
            write!(f, "`{key}`: ")?;
        }
        f.write_str(&self.message)
    }
}

impl SceneError {
    /// An error with only a message (newlines in it are folded, so `Display` stays one line).
    #[must_use]
    pub fn new(message: impl Into<String>) -> Self {
        Self {
            file: None,
            line_col: None,
            key: None,
            message: one_line(&message.into()),
        }
    }

    /// An error at `loc`.
    #[must_use]
    pub fn at(loc: Loc, message: impl Into<String>) -> Self {
        Self {
            file: Some(loc.file),
            line_col: Some((loc.line, loc.col)),
            ..Self::new(message)
        }
    }

    /// An error about a whole file (e.g. it cannot be read).
    #[must_use]
    pub fn in_file(file: &Path, message: impl Into<String>) -> Self {
        Self {
            file: Some(file.to_path_buf()),
            ..Self::new(message)
        }
    }

    /// The same error, naming `key`.
    #[must_use]
    pub fn with_key(mut self, key: impl Into<String>) -> Self {
        self.key = Some(key.into());
        self
    }

    /// The location, when both the file and the line are known.
    #[must_use]
    pub fn loc(&self) -> Option<Loc> {
        let (line, col) = self.line_col?;
        Some(Loc {
            file: self.file.clone()?,
            line,
            col,
        })
    }
}

/// Folds a multi-line message into one line.
fn one_line(message: &str) -> String {
    message
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_has_every_present_part_on_one_line() {
        let loc = Loc {
            file: PathBuf::from("a.toml"),
            line: 3,
            col: 7,
        };
        let e = SceneError::at(loc.clone(), "bad\nthing").with_key("objects[0].name");
        assert_eq!(e.to_string(), "a.toml:3:7: `objects[0].name`: bad, thing");
        assert_eq!(e.loc(), Some(loc));
        let e = SceneError::in_file(Path::new("x.obj"), "cannot read: gone");
        assert_eq!(e.to_string(), "x.obj: cannot read: gone");
        assert_eq!(SceneError::new("plain").to_string(), "plain");
    }
}
