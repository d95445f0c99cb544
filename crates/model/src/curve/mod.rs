//! Parametric curves of the course: interpolating (Lagrange, Hermite, Catmull-Rom,
//! Bessel-Overhauser) and approximating (Bézier, rational Bézier, B-spline, NURBS).
//!
//! Every curve is a map C: [a, b] → ℝ³ with a derivative C′, exposed through the [`Curve`]
//! trait. Computation is in f64 ([`glam::DVec3`]) so that the identities the tests check
//! (partition of unity, degree elevation, knot insertion) hold to ~1e-12; meshes are converted
//! to f32 only at the end.
//!
//! - [`lagrange`]: the polynomial through n+1 points, Neville's scheme.
//! - [`hermite`]: cubic Hermite segments and piecewise Hermite splines (the base of
//!   [`catmull_rom`] and [`bessel_overhauser`]).
//! - [`bezier`]: Bernstein form, de Casteljau, subdivision, degree elevation, rational form.
//! - [`bspline`]: Cox–de Boor recurrence, de Boor's algorithm, Boehm knot insertion.
//! - [`nurbs`]: rational B-splines, the exact circle and conic arcs.
//!
//! References: Farin, *Curves and Surfaces for CAGD* (5th ed., 2002); Piegl & Tiller, *The
//! NURBS Book* (2nd ed., 1997); Foley et al., *Computer Graphics* §11.

pub mod bessel_overhauser;
pub mod bezier;
pub mod bspline;
pub mod catmull_rom;
pub mod hermite;
pub mod lagrange;
pub mod nurbs;

use glam::DVec3;

pub use bezier::{Bezier, RationalBezier};
pub use bspline::BSpline;
pub use hermite::{Hermite, HermiteSpline};
pub use lagrange::Lagrange;
pub use nurbs::Nurbs;

/// A parametric curve C(t), t in [`Curve::domain`].
pub trait Curve {
    /// The point C(t). Parameters outside the domain are clamped to it.
    #[must_use]
    fn point(&self, t: f64) -> DVec3;

    /// The first derivative C′(t) (clamped like [`Curve::point`]).
    #[must_use]
    fn derivative(&self, t: f64) -> DVec3;

    /// The parameter interval [a, b].
    #[must_use]
    fn domain(&self) -> (f64, f64);

    /// `n + 1` points at equally spaced parameters over the domain (n ≥ 1).
    #[must_use]
    fn polyline(&self, n: usize) -> Vec<DVec3> {
        let (a, b) = self.domain();
        let n = n.max(1);
        (0..=n)
            .map(|i| self.point(a + (b - a) * i as f64 / n as f64))
            .collect()
    }
}

/// Clamps `t` to `[a, b]` (NaN goes to `a`).
pub(crate) fn clamp_param(t: f64, (a, b): (f64, f64)) -> f64 {
    if t.is_nan() {
        a
    } else {
        t.clamp(a, b)
    }
}
