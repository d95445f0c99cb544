//! # radiosity — global illumination by energy equilibrium
//!
//! A scene is split into patches (its planar polygons) and elements (their quadtree
//! subdivisions); form factors couple them; a solver brings light to equilibrium,
//!
//! B_i = E_i + ρ_i Σ_j F_ij B_j        (Goral et al. 1984),
//!
//! and the viewer-independent result — a lit mesh with radiosity at its vertices — is rendered
//! from any camera and exported. The chapters, in pipeline order:
//!
//! 1. [`scene`]: the scene format (parse → check → build) and built-in scenes.
//! 2. [`mesh`]: patches, element quadtrees and the display mesh.
//! 3. [`accel`]: a bounding-volume hierarchy for visibility.
//! 4. [`formfactor`]: analytic, ray-cast and hemicube form factors.
//! 5. [`solve`]: Jacobi, Gauss-Seidel, progressive refinement and hierarchical radiosity.
//! 6. [`render`]: camera, z-buffer rasterizer, ray tracer, the evaluated picture, tone mapping.
//! 7. [`io`]: mesh files in, images out.
//!
//! [`pipeline`] strings them together and [`stats`] reports what happened.
// `unsafe` only in `accel::isa` (run-time instruction-set dispatch, a cache prefetch and a
// `movmskps` hit mask) and `accel::pages` (one `madvise` for transparent huge pages).
#![deny(unsafe_code)]

pub mod accel;
pub mod color;
pub mod formfactor;
pub mod hash;
pub mod io;
pub mod mesh;
pub mod pipeline;
pub mod plot;
pub mod progress;
mod registry;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod solve;
pub mod stats;
pub mod testing;

pub use color::Rgb;
pub use scene::Scene;
