//! Typed readers: a TOML [`Value`] to a [`Field`] that keeps its position and key.
//!
//! Every reader checks the type (a message names what was expected and what was found), rejects
//! the `nan`/`inf` literals TOML allows, and range-checks integers and single-precision numbers.

use std::ops::Range;
use std::path::Path;

use glam::Vec3;

use super::value::{Kind, Value};
use crate::scene::description::{Field, Pos};
use crate::scene::{Loc, SceneError};
use crate::Rgb;

/// The text being parsed: file name and line starts, to turn byte offsets into positions.
pub(super) struct Source<'a> {
    file: &'a Path,
    text: &'a str,
    line_starts: Vec<usize>,
}

impl<'a> Source<'a> {
    pub(super) fn new(text: &'a str, file: &'a Path) -> Self {
        let line_starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Self {
            file,
            text,
            line_starts,
        }
    }

    /// 1-based line and column (in characters) of a byte offset.
    pub(super) fn pos(&self, offset: usize) -> Pos {
        let offset = offset.min(self.text.len());
        let line = self.line_starts.partition_point(|&s| s <= offset).max(1);
        let start = self.line_starts[line - 1];
        let col = self
            .text
            .get(start..offset)
            .map_or(offset - start, |s| s.chars().count())
            + 1;
        Pos { line, col }
    }

    pub(super) fn loc_of(&self, pos: Pos) -> Loc {
        Loc {
            file: self.file.to_path_buf(),
            line: pos.line,
            col: pos.col,
        }
    }

    pub(super) fn loc(&self, offset: usize) -> Loc {
        self.loc_of(self.pos(offset))
    }

    pub(super) fn error(
        &self,
        span: &Range<usize>,
        key: &str,
        message: impl Into<String>,
    ) -> SceneError {
        let e = SceneError::at(self.loc(span.start), message);
        if key.is_empty() {
            e
        } else {
            e.with_key(key)
        }
    }

    /// An error at the value of `f`, naming its key.
    pub(super) fn error_at<T>(&self, f: &Field<T>, message: impl Into<String>) -> SceneError {
        SceneError::at(self.loc_of(f.pos), message).with_key(f.key.clone())
    }

    pub(super) fn wrong_type(&self, key: &str, v: &Value, expected: &str) -> SceneError {
        self.error(
            &v.span,
            key,
            format!("expected {expected}, found {}", v.kind),
        )
    }

    pub(super) fn field<T>(&self, key: &str, v: &Value, value: T) -> Field<T> {
        Field {
            value,
            pos: self.pos(v.span.start),
            key: key.to_string(),
        }
    }

    pub(super) fn array(&self, v: Value, key: &str) -> Result<Vec<Value>, SceneError> {
        match v.kind {
            Kind::Array(items) => Ok(items),
            _ => Err(self.wrong_type(key, &v, "an array")),
        }
    }

    /// An array whose items are read by `item` (each with its indexed key, `key[i]`).
    pub(super) fn list<T>(
        &self,
        key: &str,
        v: Value,
        item: impl Fn(&str, Value) -> Result<Field<T>, SceneError>,
    ) -> Result<Field<Vec<T>>, SceneError> {
        let at = self.field(key, &v, ());
        let items = self
            .array(v, key)?
            .into_iter()
            .enumerate()
            .map(|(i, x)| Ok(item(&format!("{key}[{i}]"), x)?.value))
            .collect::<Result<Vec<T>, SceneError>>()?;
        Ok(at.map(|()| items))
    }

    /// An array of points.
    pub(super) fn vec3_list(&self, key: &str, v: Value) -> Result<Field<Vec<Vec3>>, SceneError> {
        self.list(key, v, |k, x| self.vec3(k, x))
    }

    /// An array of finite numbers.
    pub(super) fn f64_list(&self, key: &str, v: Value) -> Result<Field<Vec<f64>>, SceneError> {
        self.list(key, v, |k, x| self.f64(k, x))
    }

    pub(super) fn string(&self, key: &str, v: Value) -> Result<Field<String>, SceneError> {
        match &v.kind {
            Kind::Str(s) => Ok(self.field(key, &v, s.clone())),
            _ => Err(self.wrong_type(key, &v, "a string")),
        }
    }

    /// A string naming one of `choices`, as its value; any other string is an error at it
    /// with the message `unknown(name)`.
    pub(super) fn keyword<T: Copy>(
        &self,
        key: &str,
        v: Value,
        choices: &[(&str, T)],
        unknown: impl FnOnce(&str) -> String,
    ) -> Result<Field<T>, SceneError> {
        let name = self.string(key, v)?;
        match choices.iter().find(|(n, _)| *n == name.value) {
            Some(&(_, value)) => Ok(name.map(|_| value)),
            None => Err(self.error_at(&name, unknown(&name.value))),
        }
    }

    pub(super) fn boolean(&self, key: &str, v: Value) -> Result<Field<bool>, SceneError> {
        match v.kind {
            Kind::Bool(b) => Ok(self.field(key, &v, b)),
            _ => Err(self.wrong_type(key, &v, "true or false")),
        }
    }

    pub(super) fn u32(&self, key: &str, v: Value) -> Result<Field<u32>, SceneError> {
        match v.kind {
            Kind::Int(i) => match u32::try_from(i) {
                Ok(n) => Ok(self.field(key, &v, n)),
                Err(_) => Err(self.error(
                    &v.span,
                    key,
                    format!("{i} is out of range (0 to {})", u32::MAX),
                )),
            },
            _ => Err(self.wrong_type(key, &v, "a whole number")),
        }
    }

    /// A finite number (integers are accepted).
    pub(super) fn number(&self, key: &str, v: &Value) -> Result<f64, SceneError> {
        let x = match v.kind {
            Kind::Int(i) => i as f64,
            Kind::Float(x) => x,
            _ => return Err(self.wrong_type(key, v, "a number")),
        };
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.error(
                &v.span,
                key,
                format!("`{x}` is not allowed: numbers must be finite"),
            ))
        }
    }

    pub(super) fn f64(&self, key: &str, v: Value) -> Result<Field<f64>, SceneError> {
        let x = self.number(key, &v)?;
        Ok(self.field(key, &v, x))
    }

    pub(super) fn f32(&self, key: &str, v: Value) -> Result<Field<f32>, SceneError> {
        let x = self.number(key, &v)?;
        if (x as f32).is_finite() {
            Ok(self.field(key, &v, x as f32))
        } else {
            Err(self.error(
                &v.span,
                key,
                format!("{x:e} is too large for single precision"),
            ))
        }
    }

    /// Exactly `N` finite numbers.
    pub(super) fn numbers<const N: usize>(
        &self,
        key: &str,
        v: &Value,
    ) -> Result<[f64; N], SceneError> {
        let Kind::Array(items) = &v.kind else {
            return Err(self.wrong_type(key, v, &format!("an array of {N} numbers")));
        };
        if items.len() != N {
            return Err(self.error(
                &v.span,
                key,
                format!("expected {N} numbers, found {}", items.len()),
            ));
        }
        let mut out = [0.0; N];
        for (i, (o, item)) in out.iter_mut().zip(items).enumerate() {
            *o = self.number(&format!("{key}[{i}]"), item)?;
        }
        Ok(out)
    }

    pub(super) fn vec3(&self, key: &str, v: Value) -> Result<Field<Vec3>, SceneError> {
        let [x, y, z] = self.numbers::<3>(key, &v)?;
        let p = Vec3::new(x as f32, y as f32, z as f32);
        if p.is_finite() {
            Ok(self.field(key, &v, p))
        } else {
            Err(self.error(&v.span, key, "a coordinate is too large"))
        }
    }

    /// An RGB triple, or one number for grey.
    pub(super) fn rgb(&self, key: &str, v: Value) -> Result<Field<Rgb>, SceneError> {
        let c = match v.kind {
            Kind::Int(_) | Kind::Float(_) => Rgb::splat(self.number(key, &v)?),
            _ => Rgb::from_array(self.numbers::<3>(key, &v)?),
        };
        Ok(self.field(key, &v, c))
    }
}
