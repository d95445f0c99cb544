//! Scene loading errors (in progress).
use std::path::PathBuf;
/// Where in a file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Loc {
    /// File.
    pub file: PathBuf,
    /// 1-based line.
    pub line: usize,
    /// 1-based column.
    pub col: usize,
}
/// A scene loading error.
#[derive(Debug, thiserror::Error)]
#[error("{message}")]
pub struct SceneError {
    /// Message.
    pub message: String,
}
