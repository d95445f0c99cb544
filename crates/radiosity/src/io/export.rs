//! The exports of a solved scene, one arm per format, all with one signature: a path, the
//! [`Solved`] scene and the [`Options`] every format reads what it needs from.
//!
//! - `.ply` ([`super::ply`]): the lit mesh in metres, radiosity and sRGB colours per
//!   vertex, object names in comments;
//! - `.glb` ([`super::gltf`]): binary glTF in metres, one mesh per object, vertex colours as
//!   `options.colours` asks, the cameras;
//! - `.html` ([`super::html`]): the self-contained WebGL viewer, starting at the exposure of
//!   `options.colours` (the automatic one unless it names stops).
//!
//! Adding a format is a writer in `io/`, and here its line in the [`Format`] registry (its name
//! is its file extension) with its arm in [`Format::write`].

use std::io;
use std::path::Path;

use super::gltf::{write_glb, Placement, VertexColours};
use super::{html, ply};
use crate::pipeline::Solved;
use crate::registry::registry;
use crate::scene::Camera;

registry! {
    /// The export formats, each named by its file extension: the registry of the family.
    pub enum Format {
        /// Binary PLY.
        Ply = "ply",
        /// Binary glTF 2.0.
        Glb = "glb",
        /// The HTML viewer.
        Html = "html",
    }
    /// An unknown export extension.
    pub struct UnknownFormat = "unknown export format";
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
    /// The format of `path`'s extension (in any case), if it is one.
    #[must_use]
    pub fn of(path: &Path) -> Option<Format> {
        let extension = path.extension()?.to_string_lossy().to_lowercase();
        extension.parse().ok()
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
            Format::Ply => ply::write_ply(path, &solved.lit, &names, solved.scene.units.metres()),
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

    #[test]
    fn every_format_is_found_by_its_name() {
        for format in Format::ALL {
            let path = format!("lit.{format}");
            assert_eq!(Format::of(Path::new(&path)), Some(format));
        }
    }
}
