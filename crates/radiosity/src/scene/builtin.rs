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
        "cornell-spheres",
        "the Cornell box with a mirror sphere and a glass sphere (for --mode raytrace, compare)",
    ),
    (
        "furnace",
        "a closed unit cube, reflectance 0.5, ceiling emitting radiance 1 (furnace test)",
    ),
    (
        "teapot",
        "the Utah teapot (32 bicubic Bézier patches) in a lit room with coloured walls",
    ),
    (
        "solids",
        "a CSG part, a metaball blob and a torus with instances, in a lit room (solid modeling)",
    ),
];

/// (path for messages, TOML text), in the order of [`NAMES`].
const SOURCES: &[(&str, &str)] = &[
    (
        "scenes/cornell/scene.toml",
        include_str!("../../../../scenes/cornell/scene.toml"),
    ),
    (
        "scenes/cornell-spheres/scene.toml",
        include_str!("../../../../scenes/cornell-spheres/scene.toml"),
    ),
    (
        "scenes/furnace/scene.toml",
        include_str!("../../../../scenes/furnace/scene.toml"),
    ),
    (
        "scenes/teapot/scene.toml",
        include_str!("../../../../scenes/teapot/scene.toml"),
    ),
    (
        "scenes/solids/scene.toml",
        include_str!("../../../../scenes/solids/scene.toml"),
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
