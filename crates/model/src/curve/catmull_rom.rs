//! Catmull-Rom splines (Catmull & Rom 1974): the C¹ cubic Hermite spline through P₀ … Pₙ at
//! t = 0, 1, …, n whose tangent at each interior point is the central difference
//!
//! C′(i) = (P_{i+1} − P_{i−1}) / 2,
//!
//! and at the two ends the one-sided difference P₁ − P₀, Pₙ − Pₙ₋₁. Each point moves only
//! the two segments on either side of it (local control).

use glam::DVec3;

use super::HermiteSpline;

/// The uniform Catmull-Rom spline through `points` (at least 2), or `None`.
#[must_use]
pub fn catmull_rom(points: &[DVec3]) -> Option<HermiteSpline> {
    let n = points.len();
    if n < 2 {
        return None;
    }
    let tangents = (0..n)
        .map(|i| match i {
            0 => points[1] - points[0],
            _ if i == n - 1 => points[n - 1] - points[n - 2],
            _ => (points[i + 1] - points[i - 1]) * 0.5,
        })
        .collect();
    HermiteSpline::new(
        (0..n).map(|i| i as f64).collect(),
        points.to_vec(),
        tangents,
    )
}
