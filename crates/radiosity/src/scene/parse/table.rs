//! A TOML table being read key by key, the analogue of serde's `deny_unknown_fields`.

use std::ops::Range;

use super::source::Source;
use super::value::{Key, Kind, Value};
use crate::scene::description::Field;
use crate::scene::SceneError;

/// A table being read: keys are taken one by one; leftovers are unknown keys.
pub(super) struct Table<'s> {
    pub(super) src: &'s Source<'s>,
    pub(super) path: String,
    pub(super) span: Range<usize>,
    pub(super) entries: Vec<(Key, Value)>,
}

impl<'s> Table<'s> {
    pub(super) fn new(src: &'s Source<'s>, path: String, v: Value) -> Result<Self, SceneError> {
        match v.kind {
            Kind::Table(entries) => Ok(Self {
                src,
                path,
                span: v.span,
                entries,
            }),
            _ => Err(src.wrong_type(&path, &v, "a table")),
        }
    }

    pub(super) fn child_path(&self, name: &str) -> String {
        if self.path.is_empty() {
            name.to_string()
        } else {
            format!("{}.{name}", self.path)
        }
    }

    /// Fails on the first key (in file order) not in `allowed`.
    pub(super) fn check_keys(&self, allowed: &[&str]) -> Result<(), SceneError> {
        match self
            .entries
            .iter()
            .find(|(k, _)| !allowed.contains(&k.name.as_str()))
        {
            Some((k, _)) => Err(self.src.error(
                &k.span,
                &self.child_path(&k.name),
                format!("unknown key (expected one of: {})", allowed.join(", ")),
            )),
            None => Ok(()),
        }
    }

    pub(super) fn take(&mut self, name: &str) -> Option<(Key, Value)> {
        let i = self.entries.iter().position(|(k, _)| k.name == name)?;
        Some(self.entries.remove(i))
    }

    /// An optional key without a default.
    pub(super) fn optional<T>(
        &mut self,
        name: &str,
        read: impl FnOnce(&str, Value) -> Result<Field<T>, SceneError>,
    ) -> Result<Option<Field<T>>, SceneError> {
        let key = self.child_path(name);
        self.take(name).map(|(_, v)| read(&key, v)).transpose()
    }

    pub(super) fn optional_with<T>(
        &mut self,
        name: &str,
        default: T,
        read: impl FnOnce(&str, Value) -> Result<Field<T>, SceneError>,
    ) -> Result<Field<T>, SceneError> {
        let key = self.child_path(name);
        match self.take(name) {
            Some((_, v)) => read(&key, v),
            None => Ok(Field {
                value: default,
                pos: self.src.pos(self.span.start),
                key,
            }),
        }
    }

    pub(super) fn required_with<T>(
        &mut self,
        name: &str,
        read: impl FnOnce(&str, Value) -> Result<Field<T>, SceneError>,
    ) -> Result<Field<T>, SceneError> {
        let key = self.child_path(name);
        match self.take(name) {
            Some((_, v)) => read(&key, v),
            None => Err(self.src.error(&self.span, &key, "missing required key")),
        }
    }

    pub(super) fn default_field<T>(&self, value: T) -> Field<T> {
        Field {
            value,
            pos: self.src.pos(self.span.start),
            key: self.path.clone(),
        }
    }
}
