//! Surfaces of the course: tensor-product patches, surfaces of revolution and sweeps,
//! subdivision surfaces, and their tessellation into planar polygons.
//!
//! Every parametric surface here is a [`NurbsSurface`] — a tensor-product rational B-spline
//!
//! S(u, v) = Σ_i Σ_j N_{i,p}(u) N_{j,q}(v) w_ij P_ij / Σ_i Σ_j N_{i,p}(u) N_{j,q}(v) w_ij,
//!
//! of which the bicubic Bézier patch (p = q = 3, one knot span, all w = 1), the B-spline patch
//! (w = 1) and the surfaces of [`revolve`] (profile × exact NURBS circle) and [`sweep`]
//! (profile + path) are special cases. One evaluator and one tessellator ([`tessellate`])
//! serve them all. [`subdivision`] refines polygon meshes instead (Catmull-Clark, Loop).
//!
//! References: Farin, *Curves and Surfaces for CAGD*, ch. 14–16; Piegl & Tiller, *The NURBS
//! Book*, ch. 3–4 and 8.

pub mod patch;
pub mod revolve;
pub mod subdivision;
pub mod sweep;
pub mod tessellate;

pub use patch::NurbsSurface;
pub use tessellate::{tessellate, TessellationSettings};
