//! Built-in scenes, compiled into the library from `scenes/<name>/scene.toml` with the files
//! they name ([`bundled`]), so that `radiosity render cornell` works from any directory.

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
    (
        "office",
        "a 6 × 4 × 3 m office: six IES ceiling luminaires, a window under an overcast sky, a work-plane grid",
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
    (
        "scenes/office/scene.toml",
        include_str!("../../../../scenes/office/scene.toml"),
    ),
];

/// The files the built-in scenes name (path as the scene resolves it, text).
const FILES: &[(&str, &str)] = &[(
    "scenes/office/panel.ies",
    include_str!("../../../../scenes/office/panel.ies"),
)];

/// The built-in scenes: (name, one-line description).
#[must_use]
pub fn names() -> &'static [(&'static str, &'static str)] {
    NAMES
}

/// The text of a file a built-in scene names, by the path the scene resolves it to
/// (`scenes/office/panel.ies`), or `None` for any other path.
#[must_use]
pub fn bundled(path: &Path) -> Option<&'static str> {
    FILES
        .iter()
        .find(|(p, _)| Path::new(p) == path)
        .map(|(_, text)| *text)
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
