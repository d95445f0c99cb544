//! Visibility acceleration: a bounding-volume hierarchy over triangles.
//!
//! Form factors need visibility V(x, y) between points, and the ray tracer needs the nearest
//! surface along a ray; both ask "what does this ray hit?" of a soup of triangles. A BVH answers
//! in O(log n) expected time by testing nested boxes before triangles.
//!
//! - [`ray`]: [`Ray`], [`Hit`] and the Möller–Trumbore ray–triangle test.
//! - [`Bvh`] (`bvh`): the hierarchy, built with the binned surface-area heuristic
//!   (MacDonald & Booth 1990; Wald 2007, `build`), collapsed to 8-wide nodes with their
//!   children's boxes quantized to 8 bits (`node`) whose leaves hold packets of four
//!   triangles tested together (`packet`).
//! - `traverse`: the closest-hit and occlusion queries, ordered (nearest child first for
//!   closest hits; largest first for long occlusion rays, nearest first for short segments),
//!   one ray at a time or four interleaved so that their cache misses overlap.
//! - [`coherent`]: ray packets, eight coherent rays (a camera's, shadow rays to one light)
//!   walked together, sharing each node's fetch and ordering; `frustum`: the packet's
//!   interval bounds, which rule a child out for all its rays at once.
//! - [`isa`]: the queries compiled for the baseline and for AVX2, chosen at run time.
//! - `pages`: the node and packet arrays on transparent huge pages (`madvise`), so that a
//!   walk through 50 MB of hierarchy does not also miss the TLB at every step.
//! - [`BoxTree`] (`box_tree`): a binary hierarchy over boxes of the caller's choosing, for
//!   overlap queries whose reach differs from item to item (the contact test of
//!   [`crate::mesh`]).
//!
//! Measured choice of node: 8 children with their boxes in structure-of-arrays form, faster
//! here than binary (Aila & Laine 2009) and 4-wide nodes; see `benches/README.md`.

pub mod box_tree;
mod build;
pub mod bvh;
pub mod coherent;
mod frustum;
pub mod isa;
mod node;
mod packet;
mod pages;
pub mod ray;
mod traverse;

pub use box_tree::BoxTree;
pub use bvh::Bvh;
pub use node::{largest_axis, Aabb};
pub use ray::{Hit, Ray};

/// With the `count` feature: nodes and leaves visited by all ray queries so far (`cargo xtask`'s
/// `traversal-counts`).
#[cfg(feature = "count")]
pub static COUNT_STEPS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
/// With the `count` feature: triangle packets tested by all ray queries so far.
#[cfg(feature = "count")]
pub static COUNT_PACKETS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
