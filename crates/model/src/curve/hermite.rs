//! Cubic Hermite interpolation: a cubic segment fixed by its end points and end tangents,
//!
//! H(s) = h₀₀(s) P₀ + h₁₀(s) M₀ + h₀₁(s) P₁ + h₁₁(s) M₁,  s ∈ [0, 1],
//!
//! with h₀₀ = 2s³ − 3s² + 1, h₁₀ = s³ − 2s² + s, h₀₁ = −2s³ + 3s², h₁₁ = s³ − s². Chaining
//! segments that share points and tangents gives a C¹ [`HermiteSpline`]; Catmull-Rom and
//! Bessel-Overhauser splines are Hermite splines whose tangents are estimated from the points.

use glam::DVec3;

use super::{clamp_param, Curve};

/// One cubic Hermite segment on s ∈ [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hermite {
    /// Start point P₀.
    pub p0: DVec3,
    /// Start tangent M₀ = H′(0).
    pub m0: DVec3,
    /// End point P₁.
    pub p1: DVec3,
    /// End tangent M₁ = H′(1).
    pub m1: DVec3,
}

impl Curve for Hermite {
    fn point(&self, s: f64) -> DVec3 {
        let s = clamp_param(s, (0.0, 1.0));
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * self.p0
            + (s3 - 2.0 * s2 + s) * self.m0
            + (-2.0 * s3 + 3.0 * s2) * self.p1
            + (s3 - s2) * self.m1
    }

    fn derivative(&self, s: f64) -> DVec3 {
        let s = clamp_param(s, (0.0, 1.0));
        let s2 = s * s;
        (6.0 * s2 - 6.0 * s) * self.p0
            + (3.0 * s2 - 4.0 * s + 1.0) * self.m0
            + (-6.0 * s2 + 6.0 * s) * self.p1
            + (3.0 * s2 - 2.0 * s) * self.m1
    }

    fn domain(&self) -> (f64, f64) {
        (0.0, 1.0)
    }
}

/// A C¹ piecewise cubic through `points` at increasing `params` with the given `tangents`
/// (C′(t_i) = tangents\[i\]).
#[derive(Clone, Debug, PartialEq)]
pub struct HermiteSpline {
    params: Vec<f64>,
    points: Vec<DVec3>,
    tangents: Vec<DVec3>,
}

impl HermiteSpline {
    /// `None` unless the three lists have the same length ≥ 2 and the parameters are finite
    /// and strictly increasing.
    #[must_use]
    pub fn new(params: Vec<f64>, points: Vec<DVec3>, tangents: Vec<DVec3>) -> Option<Self> {
        let ok = points.len() >= 2
            && params.len() == points.len()
            && tangents.len() == points.len()
            && params.iter().all(|t| t.is_finite())
            && params.windows(2).all(|w| w[0] < w[1]);
        ok.then_some(Self {
            params,
            points,
            tangents,
        })
    }

    /// The interpolated points.
    #[must_use]
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }

    /// The knots t_i at which the points are reached.
    #[must_use]
    pub fn params(&self) -> &[f64] {
        &self.params
    }

    /// The tangent C′(t_i) at each point.
    #[must_use]
    pub fn tangents(&self) -> &[DVec3] {
        &self.tangents
    }

    /// Segment index, local parameter s ∈ [0, 1] and segment length for `t`.
    fn locate(&self, t: f64) -> (usize, f64, f64) {
        let t = clamp_param(t, self.domain());
        let i = self
            .params
            .partition_point(|&x| x <= t)
            .saturating_sub(1)
            .min(self.params.len() - 2);
        let h = self.params[i + 1] - self.params[i];
        (i, (t - self.params[i]) / h, h)
    }

    /// Segment `i` in its local parameter (tangents scaled by the segment length).
    fn segment(&self, i: usize, h: f64) -> Hermite {
        Hermite {
            p0: self.points[i],
            m0: self.tangents[i] * h,
            p1: self.points[i + 1],
            m1: self.tangents[i + 1] * h,
        }
    }
}

impl Curve for HermiteSpline {
    fn point(&self, t: f64) -> DVec3 {
        let (i, s, h) = self.locate(t);
        self.segment(i, h).point(s)
    }

    fn derivative(&self, t: f64) -> DVec3 {
        let (i, s, h) = self.locate(t);
        self.segment(i, h).derivative(s) / h
    }

    fn domain(&self) -> (f64, f64) {
        (self.params[0], self.params[self.params.len() - 1])
    }
}
