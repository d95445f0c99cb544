//! Built-in scenes, compiled into the library from `scenes/<name>/scene.toml`, so that
//! `radiosity render cornell` works from any directory.

use std::path::Path;

use super::{Scene, SceneError};

/// Names and one-line descriptions; [`SOURCES`] holds the files in the same order.
const NAMES: &[(&str, &str)] = &[
    (
        "cornell",
        "the measured Cornell box (Cornell Program of Computer Graphics), in millimetres",
    ),
    (
        "furnace",
        "a closed unit cube, reflectance 0.5, ceiling emitting radiance 1 (furnace test)",
    ),
];

/// (path for messages, TOML text), in the order of [`NAMES`].
const SOURCES: &[(&str, &str)] = &[
    (
        "scenes/cornell/scene.toml",
        include_str!("../../../../scenes/cornell/scene.toml"),
    ),
    (
        "scenes/furnace/scene.toml",
        include_str!("../../../../scenes/furnace/scene.toml"),
    ),
];

/// The built-in scenes: (name, one-line description).
#[must_use]
pub fn names() -> &'static [(&'static str, &'static str)] {
    NAMES
}

/// Loads the built-in scene `name`, or `None` if there is none of that name.
#[must_use]
pub fn load(name: &str) -> Option<Result<Scene, SceneError>> {
    let i = NAMES.iter().position(|(n, _)| *n == name)?;
    let (file, text) = SOURCES.get(i)?;
    Some(Scene::from_toml_str(text, Path::new(file)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_built_in_loads_without_warnings() {
        assert_eq!(NAMES.len(), SOURCES.len());
        for (name, _) in names() {
            let scene = load(name).unwrap().unwrap();
            assert_eq!(scene.name, *name);
            assert!(scene.warnings.is_empty(), "{name}: {:?}", scene.warnings);
        }
        assert!(load("nope").is_none());
    }
}
