//! Render modes: the ways to picture a solved scene, one enum over the renderers of this
//! module, each variant holding its renderer's settings, and their registry [`ModeKind`] (the
//! names the command line parses). `Mode::render` dispatches on it, so every front end (the
//! command line's `render` and `compare`) draws the same picture from the same mode.
//!
//! Adding a mode is a renderer with its settings struct, and here: its line in [`ModeKind`]
//! (its doc comment is its help on the command line), its variant of [`Mode`] and the arms the
//! compiler then asks for in this file.
//!
//! | mode | renderer | settings | reads |
//! |---|---|---|---|
//! | [`Mode::Radiosity`] | the z-buffer rasterizer ([`super::raster`]) | none beyond [`super::RasterSettings`] | the lit mesh |
//! | [`Mode::Local`] | local illumination ([`super::local`]) | [`LocalSettings`] | geometry and emitters |
//! | [`Mode::Raytrace`] | the Whitted ray tracer ([`super::raytrace`]) | [`RaytraceSettings`] | the lit mesh |
//! | [`Mode::Final`] | the solution evaluated at each visible point ([`super::evaluated`]) | [`RaytraceSettings`] | the element radiosity |

use super::evaluated;
use super::local::{self, LocalSettings};
use super::raytrace::{self, RaytraceSettings};
use super::{Image, RasterSettings, Watch};
use crate::mesh::{LitMesh, Mesh};
use crate::registry::registry;
use crate::scene::Camera;
use crate::solve::Solution;
use crate::Scene;

/// How to picture a solved scene (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mode {
    /// Diffuse global illumination from the radiosity solution: the lit mesh rasterised.
    Radiosity,
    /// Direct light plus a constant ambient term, for comparison.
    Local(LocalSettings),
    /// Whitted ray tracing over the radiosity solution.
    Raytrace(RaytraceSettings),
    /// The radiosity solution evaluated at each visible point: direct light from the emitters
    /// exactly, indirect light from the solution; mirrors and glass traced.
    Final(RaytraceSettings),
}

registry! {
    /// The render modes by name, without their settings: the registry of the family.
    pub enum ModeKind {
        /// Diffuse global illumination from the radiosity solution.
        Radiosity = "radiosity",
        /// Direct light plus a constant ambient term, for comparison.
        Local = "local",
        /// Whitted ray tracing over the radiosity solution.
        Raytrace = "raytrace",
        /// The radiosity solution evaluated at each visible point: direct light from the emitters
        /// exactly (Lambert's formula, shadow rays in penumbrae), indirect light from the
        /// solution; mirrors and glass traced.
        Final = "final",
    }
    /// An unknown render mode name.
    pub struct UnknownMode = "unknown render mode";
}

/// Antialiasing samples per pixel by default (`local`, `raytrace`, and a quick picture).
pub const DEFAULT_SAMPLES: u32 = 4;

/// With `final`: the first pass of the coverage (`render/raytrace/coverage.rs`). The
/// evaluation runs once per pixel and surface; a pixel whose samples, or its neighbours' next
/// to it, meet more than one surface is sampled again on a 16 × 16 grid refined to 64 × 64
/// where the surface changes, so the samples only have to find the edges (Cornell box 256²
/// against Mitsuba 3: 0.68 % block error at 4 samples, 0.67 % at 16 and at 64; the render
/// stage grows by a few tenths of a second from 16 to 64).
const FINAL_SAMPLES: u32 = 16;

/// With `radiosity` the rasterizer's samples cost next to nothing (256²: 0.01 s at 4, 0.05 s
/// at 64) and buy box-filtered edges (8.3 % at 4, 3.7 % at 64 with the averaged lit mesh,
/// 2.5 % with the refined one).
const RASTER_SAMPLES: u32 = 64;

impl ModeKind {
    /// Antialiasing samples per pixel when none are asked for.
    #[must_use]
    pub fn default_samples(self) -> u32 {
        match self {
            ModeKind::Final => FINAL_SAMPLES,
            ModeKind::Radiosity => RASTER_SAMPLES,
            ModeKind::Local | ModeKind::Raytrace => DEFAULT_SAMPLES,
        }
    }
}

/// The settings of every renderer: a mode takes those of its own.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Settings {
    /// Of local illumination.
    pub local: LocalSettings,
    /// Of the ray tracer (`raytrace` and `final`).
    pub raytrace: RaytraceSettings,
}

impl Mode {
    /// The mode `kind` with its renderer's `settings`.
    #[must_use]
    pub fn of(kind: ModeKind, settings: &Settings) -> Self {
        match kind {
            ModeKind::Radiosity => Mode::Radiosity,
            ModeKind::Local => Mode::Local(settings.local),
            ModeKind::Raytrace => Mode::Raytrace(settings.raytrace),
            ModeKind::Final => Mode::Final(settings.raytrace),
        }
    }

    /// Which mode this is.
    #[must_use]
    pub fn kind(&self) -> ModeKind {
        match self {
            Mode::Radiosity => ModeKind::Radiosity,
            Mode::Local(_) => ModeKind::Local,
            Mode::Raytrace(_) => ModeKind::Raytrace,
            Mode::Final(_) => ModeKind::Final,
        }
    }

    /// The picture of the solved `scene` — its `mesh`, `lit` mesh and `solution` — seen by
    /// `camera`; `None` when `watch` stops it.
    // The solved scene in its parts, as the renderers take them: this module sits below the
    // pipeline and does not know its `Solved`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn render(
        &self,
        scene: &Scene,
        mesh: &Mesh,
        lit: &LitMesh,
        solution: &Solution,
        camera: &Camera,
        raster: &RasterSettings,
        watch: &Watch,
    ) -> Option<Image> {
        match self {
            Mode::Radiosity => super::render_watched(lit, camera, raster, watch),
            Mode::Local(settings) => {
                local::render(scene, mesh, lit, camera, raster, settings, watch)
            }
            Mode::Raytrace(settings) => {
                raytrace::render(scene, mesh, lit, camera, raster, settings, watch)
            }
            Mode::Final(settings) => {
                evaluated::render(scene, mesh, solution, camera, raster, settings, watch)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_mode_is_named_parsed_and_built() {
        let err = "cartoon".parse::<ModeKind>().unwrap_err().to_string();
        assert!(err.starts_with("unknown render mode `cartoon` (choose "));
        for kind in ModeKind::ALL {
            assert_eq!(kind.name().parse::<ModeKind>(), Ok(kind));
            assert!(err.contains(kind.name()), "{err}");
            assert_eq!(Mode::of(kind, &Settings::default()).kind(), kind);
            assert!(kind.default_samples() >= 1);
        }
    }
}
