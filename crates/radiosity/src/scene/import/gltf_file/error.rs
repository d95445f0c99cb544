//! glTF errors as scene errors: positions of JSON errors, JSON paths of validation errors.

use std::path::Path;

use crate::scene::{Loc, SceneError};

/// A `gltf` error as a [`SceneError`]: a JSON syntax or type error at its line and column (of
/// the file for `.gltf`; of the JSON chunk, in the message, for `.glb`), a validation error
/// under the JSON path of its first problem (`accessors[0].bufferView`).
pub(super) fn gltf_error(e: gltf::Error, bytes: &[u8], file: &Path) -> SceneError {
    match e {
        gltf::Error::Deserialize(e) if e.line() > 0 => {
            // `serde_json` appends the position to its message and counts columns in bytes.
            let text = e.to_string();
            let suffix = format!(" at line {} column {}", e.line(), e.column());
            let cause = text.strip_suffix(&suffix).unwrap_or(&text);
            if bytes.starts_with(b"glTF") {
                let col = gltf::Glb::from_slice(bytes).map_or(e.column(), |glb| {
                    char_column(&glb.json, e.line(), e.column())
                });
                SceneError::in_file(
                    file,
                    format!(
                        "invalid glTF: JSON chunk line {} col {col}: {cause}",
                        e.line()
                    ),
                )
            } else {
                let loc = Loc {
                    file: file.to_path_buf(),
                    line: e.line(),
                    col: char_column(bytes, e.line(), e.column()),
                };
                SceneError::at(loc, format!("invalid glTF: {cause}"))
            }
        }
        gltf::Error::Validation(problems) if !problems.is_empty() => {
            let (path, problem) = &problems[0];
            let more = match problems.len() - 1 {
                0 => String::new(),
                n => format!(" (and {n} more problem(s))"),
            };
            let problem = problem.to_string().to_lowercase();
            SceneError::in_file(file, format!("invalid glTF: {problem}{more}"))
                .with_key(path.as_str().replace("[\"", ".").replace("\"]", ""))
        }
        e => SceneError::in_file(file, format!("invalid glTF: {e}")),
    }
}

/// The 1-based character column of the character that ends at byte column `byte_col` (1-based,
/// as `serde_json` counts) of 1-based line `line` of `text` (at least 1).
pub(super) fn char_column(text: &[u8], line: usize, byte_col: usize) -> usize {
    let line = text
        .split(|&b| b == b'\n')
        .nth(line.saturating_sub(1))
        .unwrap_or_default();
    // UTF-8 continuation bytes are 0b10xx_xxxx; every other byte starts a character.
    let starts = line[..byte_col.min(line.len())]
        .iter()
        .filter(|&&b| b & 0xC0 != 0x80)
        .count();
    starts.max(1)
}
