//! The exports of a solved scene, one arm per format, all with one signature: a path, the
//! [`Solved`] scene and the [`Options`] every format reads what it needs from.
//!
//! - `.ply` ([`super::ply`]): the lit mesh in scene units, radiosity and sRGB colours per
//!   vertex, object names in comments;
//! - `.glb` ([`super::gltf`]): binary glTF in metres, one mesh per object, vertex colours as
//!   `options.colours` asks, the cameras;
//! - `.html` ([`super::html`]): the self-contained WebGL viewer, starting at the exposure of
//!   `options.colours` (the automatic one unless it names stops).
//!
//! Adding a format is a writer in `io/`, a variant here with its extension in
//! [`Format::ALL`], and its arm in [`Format::write`].

use std::io;
use std::path::Path;

use super::gltf::{write_glb, Placement, VertexColours};
use super::{html, ply};
use crate::pipeline::Solved;
use crate::scene::Camera;

/// An export format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Binary PLY.
    Ply,
    /// Binary glTF 2.0.
    Glb,
    /// The HTML viewer.
    Html,
}

/// What the exports take besides the solution.
#[derive(Clone, Copy, Debug)]
pub struct Options<'a> {
    /// The vertex colours of a `.glb`, and the viewer's initial exposure.
    pub colours: VertexColours,
    /// Cameras for the `.glb`, the default first.
    pub cameras: &'a [Camera],
    /// Width over height of the `.glb`'s cameras.
    pub aspect: f32,
}

impl Format {
    /// Every format with its file extension.
    pub const ALL: [(Format, &'static str); 3] = [
        (Format::Ply, "ply"),
        (Format::Glb, "glb"),
        (Format::Html, "html"),
    ];

    /// The format of `path`'s extension (in any case), if it is one.
    #[must_use]
    pub fn of(path: &Path) -> Option<Format> {
        let extension = path.extension()?.to_string_lossy().to_lowercase();
        Self::ALL
            .iter()
            .find(|(_, e)| *e == extension)
            .map(|&(f, _)| f)
    }

    /// Writes `solved` to `path` in this format (atomically).
    ///
    /// # Errors
    /// The writer's I/O error.
    pub fn write(self, path: &Path, solved: &Solved, options: &Options) -> io::Result<()> {
        let names: Vec<String> = solved
            .scene
            .objects
            .iter()
            .map(|o| o.name.clone())
            .collect();
        match self {
            Format::Ply => ply::write_ply(path, &solved.lit, &names),
            Format::Glb => write_glb(
                path,
                &solved.lit,
                &names,
                options.colours,
                &Placement {
                    metres_per_unit: solved.scene.units.metres(),
                    cameras: options.cameras,
                    aspect: options.aspect,
                },
            ),
            Format::Html => {
                let exposure = match options.colours {
                    VertexColours::Exposure(stops) => Some(stops),
                    VertexColours::AutoExposure | VertexColours::Linear => None,
                };
                html::write_solved(path, solved, exposure)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_are_found_by_extension_in_any_case() {
        assert_eq!(Format::of(Path::new("a/lit.GLB")), Some(Format::Glb));
        assert_eq!(Format::of(Path::new("x.ply")), Some(Format::Ply));
        assert_eq!(Format::of(Path::new("x.html")), Some(Format::Html));
        assert_eq!(Format::of(Path::new("x.obj")), None);
        assert_eq!(Format::of(Path::new("glb")), None);
    }
}
