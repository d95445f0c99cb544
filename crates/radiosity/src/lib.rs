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
//! Beside the pipeline, [`photometry`] reads luminaires' photometric files (IES LM-63,
//! EULUMDAT) into intensity distributions.
//!
//! [`pipeline`] strings them together and [`stats`] reports what happened.
//!
//! ## The library road: scene → solve → image
//!
//! ```
//! use radiosity::mesh::Subdivision;
//! use radiosity::pipeline::{self, Settings};
//! use radiosity::progress::Silent;
//! use radiosity::render::{self, RasterSettings};
//! use radiosity::Scene;
//!
//! // A built-in scene by name, or a file (.toml, .obj, .gltf, .glb, Mitsuba .xml): here the
//! // furnace, a closed unit cube of reflectance 0.5 whose ceiling emits radiance 1.
//! let scene = Scene::resolve("furnace")?;
//!
//! // Solve: light at equilibrium, whatever the camera.
//! let settings = Settings {
//!     subdivision: Subdivision::Elements(96),
//!     ..Settings::default()
//! };
//! let solved = pipeline::solve(scene, &settings, &Silent)?;
//!
//! // A closed scene of uniform ρ keeps its energy: Σ A B = Σ A E / (1 − ρ) = π / 0.5.
//! let power: f64 = (0..solved.mesh.element_count())
//!     .map(|e| solved.mesh.element(e).area() * solved.solution.radiosity[e].x)
//!     .sum();
//! assert!((power - 2.0 * std::f64::consts::PI).abs() < 1e-2 * power);
//!
//! // Render the lit mesh from the scene's camera: radiance per pixel.
//! let camera = &solved.scene.cameras[0];
//! let image = render::render(&solved.lit, camera, &RasterSettings::default());
//! assert_eq!(image.pixels.len(), (image.width * image.height) as usize);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! `radiosity render` does the same from the command line, and then evaluates the solution at
//! every visible point (`render::evaluated`) for the default picture.
// `unsafe` only in `accel::isa` (run-time instruction-set dispatch, a cache prefetch and a
// `movmskps` hit mask) and `accel::pages` (one `madvise` for transparent huge pages).
#![deny(unsafe_code)]

pub mod accel;
pub mod bake;
pub mod color;
pub mod formfactor;
pub mod grids;
pub mod hash;
pub mod io;
pub mod mesh;
pub mod photometry;
pub mod pipeline;
pub mod plot;
pub mod progress;
mod registry;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod solve;
pub mod stats;
// Scenes built in code for tests, benchmarks and `radiosity validate`'s closed-form cases: used
// across the workspace, but not part of the engine's documented interface.
#[doc(hidden)]
pub mod testing;

pub use color::Rgb;
pub use scene::Scene;
