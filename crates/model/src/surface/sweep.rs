//! Translational sweeps and extrusions: S(u, v) = C(u) + D(v) − D(v₀), the profile C moved
//! along the path D without turning.
//!
//! Exact as a tensor product: with control points P_ij = C_i + D_j − D_0 and weights w_i
//! (the profile's), Σ_i Σ_j N_i N_j w_i (C_i + D_j − D_0) / Σ_i Σ_j N_i N_j w_i
//! = C(u) + D(v) − D_0, because the path's basis sums to one (partition of unity). An
//! extrusion is the sweep along a straight segment (degree 1). The front is S_u × S_v:
//! a profile running counter-clockwise seen from the tip of the path gives outward sides.

use glam::DVec3;

use super::NurbsSurface;
use crate::curve::{BSpline, Nurbs};

/// Sweeps `profile` along `path` (a polynomial B-spline), or `None` if degenerate.
#[must_use]
pub fn sweep(profile: &Nurbs, path: &BSpline) -> Option<NurbsSurface> {
    let cp = profile.points();
    let cw = profile.weights();
    let dp = path.points();
    let (count_u, count_v) = (cp.len(), dp.len());
    let mut points = Vec::with_capacity(count_u * count_v);
    let mut weights = Vec::with_capacity(count_u * count_v);
    for (c, w) in cp.iter().zip(&cw) {
        for d in dp {
            points.push(*c + *d - dp[0]);
            weights.push(*w);
        }
    }
    NurbsSurface::new(
        (profile.degree(), path.degree()),
        (profile.knots().to_vec(), path.knots().to_vec()),
        (count_u, count_v),
        &points,
        &weights,
    )
}

/// Extrudes `profile` along `direction` (non-zero), or `None`.
#[must_use]
pub fn extrude(profile: &Nurbs, direction: DVec3) -> Option<NurbsSurface> {
    if direction.length_squared() == 0.0 || !direction.is_finite() {
        return None;
    }
    let path = BSpline::new(1, vec![0.0, 0.0, 1.0, 1.0], vec![DVec3::ZERO, direction])?;
    sweep(profile, &path)
}
