//! Visibility acceleration: a bounding-volume hierarchy over triangles.
//!
//! Form factors need visibility V(x, y) between points, and the ray tracer needs the nearest
//! surface along a ray; both ask "what does this ray hit?" of a soup of triangles. A BVH answers
//! in O(log n) expected time by testing nested boxes before triangles.
//!
//! - [`ray`]: [`Ray`], [`Hit`] and the Möller–Trumbore ray–triangle test.
//! - [`Bvh`]: the hierarchy, built with the binned surface-area heuristic
//!   (MacDonald & Booth 1990; Wald 2007), collapsed to 8-wide nodes, traversed in order
//!   (nearest child first for closest hits, largest first for occlusion).
//! - [`bench`]: the ray-throughput benchmark measured against Intel Embree
//!   (`benches/README.md`).
//!
//! Measured choice of node: 8 children with their boxes in structure-of-arrays form, faster
//! here than binary (Aila & Laine 2009) and 4-wide nodes; see `benches/README.md`.

pub mod bench;
mod build;
pub mod bvh;
pub mod ray;

pub use bvh::{Aabb, Bvh};
pub use ray::{Hit, Ray};
