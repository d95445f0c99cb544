//! Rendering the lit mesh into images of radiance.
//!
//! The solve is viewer independent; this module looks at its product, the
//! [`LitMesh`](crate::mesh::LitMesh), from a [`Camera`](crate::scene::Camera):
//!
//! 1. [`camera`]: the perspective projection, world → camera → clip space → pixels, and the
//!    primary rays of the same camera for ray tracers.
//! 2. [`raster`]: a z-buffer rasterizer with Gouraud (perspective-correct) interpolation of the
//!    vertex radiosity, near-plane clipping and stratified supersampling.
//! 3. [`image`]: the [`Image`] it produces, holding **radiance** L = B/π per channel (linear), so
//!    it compares pixel for pixel with a path tracer's image of the same scene.
//! 4. [`tonemap`]: exposure and the sRGB transfer function, for 8-bit output.
//! 5. [`raytrace`]: a Whitted ray tracer over the lit mesh (two-pass: specular paths on top of
//!    the radiosity solution), with optional final gather.
//! 6. [`evaluated`]: the default picture, the solution evaluated at each visible point (exact
//!    direct light, the near field gathered at the point, the rest interpolated), traced by
//!    [`raytrace`].
//! 7. [`display_refinement`]: the lit mesh with that evaluation at its vertices, split where
//!    interpolation misses: what the exports show.
//! 8. [`surface_points`]: that evaluation at given points of the surfaces: what a baker stores
//!    per texel.
//! 9. [`local`]: the "OpenGL" local illumination model (direct light + constant ambient).
//! 10. [`compare`]: labelled side-by-side images of several modes.
//! 11. [`mode`]: the [`Mode`] enum over these renderers, with the settings of each.
//! 12. [`block_error`]: how far a picture is from a reference picture (block luminance error).
//! 13. [`false_colour`]: illuminance or luminance at the surface seen through each pixel
//!     ([`evaluated::measured`]) on a colour scale with a legend, drawn in [`font`].
pub mod block_error;
pub mod camera;
pub mod compare;
pub mod display_refinement;
pub mod evaluated;
pub mod false_colour;
pub mod font;
pub mod image;
pub mod local;
pub mod mode;
pub mod raster;
pub mod raytrace;
pub mod surface_points;
pub mod tonemap;
pub mod watch;

pub use camera::Projection;
pub use image::Image;
pub use mode::{Mode, ModeKind};
pub use raster::{render, render_watched, RasterSettings};
pub use watch::Watch;
