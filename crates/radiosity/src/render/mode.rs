//! Render modes: the ways to picture a solved scene, one enum over the renderers of this
//! module, each variant holding its renderer's settings. [`crate::pipeline::Solved::render`]
//! dispatches on it, so every front end (the command line's `render` and `compare`) draws the
//! same picture from the same mode.
//!
//! | mode | renderer | settings | reads |
//! |---|---|---|---|
//! | [`Mode::Radiosity`] | the z-buffer rasterizer ([`super::raster`]) | none beyond [`super::RasterSettings`] | the lit mesh |
//! | [`Mode::Local`] | local illumination ([`super::local`]) | [`LocalSettings`] | geometry and emitters |
//! | [`Mode::Raytrace`] | the Whitted ray tracer ([`super::raytrace`]) | [`RaytraceSettings`] | the lit mesh |
//! | [`Mode::Final`] | the solution evaluated at each visible point ([`super::raytrace::evaluate`]) | [`RaytraceSettings`] | the element radiosity |

use super::local::LocalSettings;
use super::raytrace::RaytraceSettings;

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
