//! NURBS curves (non-uniform rational B-splines): C(t) = Σ N_{i,p}(t) w_i P_i / Σ N_{i,p}(t) w_i.
//!
//! Evaluated as a B-spline of homogeneous points (w_i P_i, w_i) followed by the central
//! projection — so de Boor's algorithm, its derivative and Boehm's knot insertion all carry
//! over unchanged ([`super::bspline`]). Unlike polynomial curves, NURBS represent conics
//! exactly: [`Nurbs::ellipse`] joins four quadratic rational arcs with corner weights
//! √2/2 (Piegl & Tiller §7.5, the 9-point circle), and [`Nurbs::from_rational_bezier`] wraps
//! any rational Bézier arc (such as [`super::RationalBezier::conic`]).

use glam::{DVec3, DVec4};

use super::bezier::{dehomogenize, homogenize, project, project_derivative, weights_valid};
use super::bspline::{self, clamped_knots, knots_valid};
use super::{Curve, RationalBezier};

/// A rational B-spline curve.
#[derive(Clone, Debug, PartialEq)]
pub struct Nurbs {
    degree: usize,
    knots: Vec<f64>,
    homogeneous: Vec<DVec4>,
}

impl Nurbs {
    /// `points` with `weights` (finite, > 0) over `knots`, or `None` if anything is
    /// inconsistent (see [`bspline::knots_valid`]).
    #[must_use]
    pub fn new(degree: usize, knots: Vec<f64>, points: &[DVec3], weights: &[f64]) -> Option<Self> {
        let ok = points.len() == weights.len()
            && weights_valid(weights)
            && points.iter().all(|p| p.is_finite())
            && knots_valid(degree, &knots, points.len());
        ok.then(|| Self {
            degree,
            knots,
            homogeneous: homogenize(points, weights),
        })
    }

    /// Clamped uniform knots on [0, 1] (see [`bspline::clamped_knots`]).
    #[must_use]
    pub fn clamped(degree: usize, points: &[DVec3], weights: &[f64]) -> Option<Self> {
        Self::new(
            degree,
            clamped_knots(degree, points.len())?,
            points,
            weights,
        )
    }

    /// The full ellipse center + cos φ · `x` + sin φ · `y` (x, y need not be orthogonal or
    /// unit): 9 control points, degree 2, knots {0,0,0,¼,¼,½,½,¾,¾,1,1,1}. With orthonormal
    /// x, y scaled by r it is the exact circle of radius r.
    #[must_use]
    pub fn ellipse(center: DVec3, x: DVec3, y: DVec3) -> Self {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let corners = [
            (1.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (-1.0, 1.0),
            (-1.0, 0.0),
            (-1.0, -1.0),
            (0.0, -1.0),
            (1.0, -1.0),
            (1.0, 0.0),
        ];
        let points: Vec<DVec3> = corners
            .iter()
            .map(|(a, b)| center + *a * x + *b * y)
            .collect();
        let weights: Vec<f64> = (0..9).map(|i| if i % 2 == 0 { 1.0 } else { s }).collect();
        let knots = vec![
            0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
        ];
        Self {
            degree: 2,
            knots,
            homogeneous: homogenize(&points, &weights),
        }
    }

    /// The circle of `radius` about `center` in the plane of the orthonormal `x`, `y`.
    #[must_use]
    pub fn circle(center: DVec3, radius: f64, x: DVec3, y: DVec3) -> Self {
        Self::ellipse(center, radius * x, radius * y)
    }

    /// A rational Bézier arc as a NURBS curve (clamped knots, one span).
    #[must_use]
    pub fn from_rational_bezier(arc: &RationalBezier) -> Self {
        let points = arc.points();
        let degree = points.len() - 1;
        let mut knots = vec![0.0; degree + 1];
        knots.extend(vec![1.0; degree + 1]);
        Self {
            degree,
            knots,
            homogeneous: homogenize(&points, &arc.weights()),
        }
    }

    /// The degree p.
    #[must_use]
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knot vector.
    #[must_use]
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// Homogeneous control points (w P, w).
    #[must_use]
    pub fn homogeneous(&self) -> &[DVec4] {
        &self.homogeneous
    }

    /// The control points P_i.
    #[must_use]
    pub fn points(&self) -> Vec<DVec3> {
        dehomogenize(&self.homogeneous).0
    }

    /// The weights w_i.
    #[must_use]
    pub fn weights(&self) -> Vec<f64> {
        dehomogenize(&self.homogeneous).1
    }

    /// The same curve with knot `t` inserted (Boehm, in homogeneous space).
    #[must_use]
    pub fn insert_knot(&self, t: f64) -> Self {
        let t = super::clamp_param(t, self.domain());
        let (knots, homogeneous) =
            bspline::insert_knot(self.degree, &self.knots, &self.homogeneous, t);
        Self {
            degree: self.degree,
            knots,
            homogeneous,
        }
    }
}

impl Curve for Nurbs {
    fn point(&self, t: f64) -> DVec3 {
        project(bspline::de_boor(
            self.degree,
            &self.knots,
            &self.homogeneous,
            t,
        ))
    }

    fn derivative(&self, t: f64) -> DVec3 {
        let h = bspline::de_boor(self.degree, &self.knots, &self.homogeneous, t);
        let d = bspline::derivative(self.degree, &self.knots, &self.homogeneous, t);
        project_derivative(h, d)
    }

    fn domain(&self) -> (f64, f64) {
        bspline::domain(self.degree, &self.knots, self.homogeneous.len())
    }
}
