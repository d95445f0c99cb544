//! Geometric and solid modeling for the radiosity renderer.
//!
//! This crate knows nothing about light. It builds shapes — primitives today; curves, surfaces,
//! subdivision surfaces, implicit surfaces and CSG as the course's modeling review is built out —
//! and hands them to the renderer as [`PolyMesh`]es: lists of planar polygons.
//!
//! Conventions: single-precision positions ([`glam::Vec3`]); a polygon's front is where the
//! right-hand rule on its vertex order points (counter-clockwise seen from the front).
#![forbid(unsafe_code)]

pub mod brep;
pub mod csg;
pub mod curve;
pub mod implicit;
pub mod polymesh;
pub mod primitives;
pub mod spatial;
pub mod surface;
pub mod teapot;
pub mod transform;

pub use polymesh::PolyMesh;
pub use transform::Transform;
