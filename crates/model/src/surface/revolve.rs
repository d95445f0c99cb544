//! Surfaces of revolution: a profile curve C(v) turned about an axis,
//! S(u, v) = O(v) + cos θ(u) r(v) + sin θ(u) (a × r(v)), with O the foot of C on the axis and
//! r = C − O.
//!
//! Exact as a NURBS surface (Piegl & Tiller §8.5, algorithm A8.1): the u direction is the
//! rational quadratic circle, built from ⌈angle/90°⌉ arcs whose middle control points sit at
//! distance r / cos(θ/2) with weight cos(θ/2); each profile control point P_j with weight w_j
//! spawns one such circle, weights multiplied. A profile that runs *up* the axis (in the
//! axis direction) on the side it is revolved from gives outward normals
//! (S_u × S_v points away from the axis).

use glam::DVec3;

use super::NurbsSurface;
use crate::curve::Nurbs;

/// Revolves `profile` by `angle_deg` (0 < angle ≤ 360) about the axis through `origin`
/// along `axis` (non-zero), or `None` for bad input.
#[must_use]
pub fn revolve(
    profile: &Nurbs,
    origin: DVec3,
    axis: DVec3,
    angle_deg: f64,
) -> Option<NurbsSurface> {
    let a = axis.try_normalize()?;
    if !(angle_deg > 0.0 && angle_deg <= 360.0 && origin.is_finite()) {
        return None;
    }
    // Arcs of at most 90° each.
    let arcs = (angle_deg / 90.0).ceil().max(1.0) as usize;
    let dtheta = angle_deg.to_radians() / arcs as f64;
    let mid_weight = (dtheta / 2.0).cos();
    let mut knots_u = vec![0.0; 3];
    for k in 1..arcs {
        let t = k as f64 / arcs as f64;
        knots_u.extend([t, t]);
    }
    knots_u.extend([1.0; 3]);
    // Unit circle control points (cos, sin) and weights for the u direction.
    let mut circle = Vec::with_capacity(2 * arcs + 1);
    for k in 0..=2 * arcs {
        let theta = dtheta * k as f64 / 2.0;
        if k == 2 * arcs && angle_deg == 360.0 {
            // Close the full turn exactly, so the seam's two sides are bit-identical.
            circle.push((1.0, 0.0, 1.0));
        } else if k % 2 == 0 {
            circle.push((theta.cos(), theta.sin(), 1.0));
        } else {
            let r = 1.0 / mid_weight;
            circle.push((r * theta.cos(), r * theta.sin(), mid_weight));
        }
    }
    let profile_points = profile.points();
    let profile_weights = profile.weights();
    let (count_u, count_v) = (circle.len(), profile_points.len());
    let mut points = vec![DVec3::ZERO; count_u * count_v];
    let mut weights = vec![0.0; count_u * count_v];
    for (j, (p, w)) in profile_points.iter().zip(&profile_weights).enumerate() {
        let foot = origin + (*p - origin).dot(a) * a;
        let r = *p - foot;
        let s = a.cross(r);
        for (i, (c, si, cw)) in circle.iter().enumerate() {
            points[i * count_v + j] = foot + *c * r + *si * s;
            weights[i * count_v + j] = cw * w;
        }
    }
    NurbsSurface::new(
        (2, profile.degree()),
        (knots_u, profile.knots().to_vec()),
        (count_u, count_v),
        &points,
        &weights,
    )
}
