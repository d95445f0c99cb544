//! Visibility acceleration: a bounding-volume hierarchy over triangles.
//!
//! Form factors need visibility V(x, y) between points, and the ray tracer needs the nearest
//! surface along a ray; both ask "what does this ray hit?" of a soup of triangles. A BVH answers
//! in O(log n) expected time by testing nested boxes before triangles.
//!
//! - [`ray`]: [`Ray`], [`Hit`] and the Möller–Trumbore ray–triangle test.
//! - [`Bvh`]: the hierarchy, built with the binned surface-area heuristic
//!   (MacDonald & Booth 1990; Wald 2007), traversed nearest child first.
//! - [`bench`]: the ray-throughput benchmark measured against Intel Embree
//!   (`benches/README.md`).
//!
//! Measured choice of node: a binary node holding both child boxes in one cache line
//! (Aila & Laine 2009); see `benches/README.md` for the figures.

pub mod bench;
mod build;
pub mod bvh;
pub mod ray;

pub use bvh::{Aabb, Bvh};
pub use ray::{Hit, Ray};
