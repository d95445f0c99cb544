//! Bessel-Overhauser splines (Overhauser 1968; the "Bessel tangent" of Farin §9.2): a C¹ cubic
//! Hermite spline through P₀ … Pₙ with chord-length parameters t_{i+1} − t_i = |P_{i+1} − P_i|,
//! whose tangent at P_i is the derivative of the parabola through P_{i−1}, P_i, P_{i+1}:
//!
//! C′(t_i) = (Δ_i v_{i−½} + Δ_{i−1} v_{i+½}) / (Δ_{i−1} + Δ_i),
//! v_{i+½} = (P_{i+1} − P_i)/Δ_i, Δ_i = t_{i+1} − t_i,
//!
//! so unevenly spaced points do not make the loops and overshoots of uniform Catmull-Rom.
//! At the ends the tangent is the end chord's slope.

use glam::DVec3;

use super::HermiteSpline;

/// The Bessel-Overhauser spline through `points` (at least 2, consecutive points distinct),
/// parameterised by chord length, or `None`.
#[must_use]
pub fn bessel_overhauser(points: &[DVec3]) -> Option<HermiteSpline> {
    let n = points.len();
    if n < 2 {
        return None;
    }
    let mut params = vec![0.0];
    for w in points.windows(2) {
        params.push(params[params.len() - 1] + (w[1] - w[0]).length());
    }
    let slope = |i: usize| (points[i + 1] - points[i]) / (params[i + 1] - params[i]);
    let tangents = (0..n)
        .map(|i| match i {
            0 => slope(0),
            _ if i == n - 1 => slope(n - 2),
            _ => {
                let (a, b) = (params[i] - params[i - 1], params[i + 1] - params[i]);
                (b * slope(i - 1) + a * slope(i)) / (a + b)
            }
        })
        .collect();
    HermiteSpline::new(params, points.to_vec(), tangents)
}
