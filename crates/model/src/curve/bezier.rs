//! Bézier curves: C(t) = Σ_{i=0}^{n} B_i^n(t) P_i with the Bernstein polynomials
//! B_i^n(t) = C(n, i) tᶦ (1 − t)ⁿ⁻ⁱ, t ∈ [0, 1].
//!
//! - **de Casteljau** (1959): repeated linear interpolation P_i^{r} = (1 − t) P_i^{r−1} +
//!   t P_{i+1}^{r−1}; the apex P_0^n is C(t). [`Bezier::de_casteljau`] returns the whole
//!   pyramid — the lecture's geometric construction.
//! - **Subdivision**: the left edge P_0^0 … P_0^n and the right edge P_0^n … P_n^0 of the
//!   pyramid are the control polygons of C on [0, t] and [t, 1] ([`Bezier::split`]).
//! - **Derivative**: C′(t) = n Σ B_i^{n−1}(t) (P_{i+1} − P_i), so C′(0) = n (P₁ − P₀).
//! - **Degree elevation**: Q_i = (i/(n+1)) P_{i−1} + (1 − i/(n+1)) P_i, the same curve with one
//!   more control point ([`Bezier::elevate`]).
//! - **Rational Bézier** ([`RationalBezier`]): weights w_i, evaluated as a Bézier curve of
//!   homogeneous points (w_i P_i, w_i) then projected; a quadratic with w₁ = cos(θ/2)
//!   is an exact circular arc of angle θ, and any conic is a quadratic rational Bézier
//!   (Farin ch. 12).

use glam::{DVec3, DVec4};

use super::{clamp_param, Curve};

/// A polynomial Bézier curve of degree `points.len() − 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct Bezier {
    points: Vec<DVec3>,
}

impl Bezier {
    /// The curve with control points `points` (at least one), or `None`.
    #[must_use]
    pub fn new(points: Vec<DVec3>) -> Option<Self> {
        (!points.is_empty()).then_some(Self { points })
    }

    /// The control points P_0 … P_n.
    #[must_use]
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }

    /// The degree n.
    #[must_use]
    pub fn degree(&self) -> usize {
        self.points.len() - 1
    }

    /// The de Casteljau pyramid at `t`: level r holds P_0^r … P_{n−r}^r, so level 0 is the
    /// control polygon and the last level is the single point C(t).
    #[must_use]
    pub fn de_casteljau(&self, t: f64) -> Vec<Vec<DVec3>> {
        let mut levels = vec![self.points.clone()];
        while levels[levels.len() - 1].len() > 1 {
            let prev = &levels[levels.len() - 1];
            let next = prev.windows(2).map(|w| w[0].lerp(w[1], t)).collect();
            levels.push(next);
        }
        levels
    }

    /// The two halves of the curve at `t` ∈ [0, 1]: control polygons of C on [0, t] and on
    /// [t, 1], each reparameterised to [0, 1].
    #[must_use]
    pub fn split(&self, t: f64) -> (Self, Self) {
        let t = clamp_param(t, (0.0, 1.0));
        let pyramid = self.de_casteljau(t);
        let left = pyramid.iter().map(|l| l[0]).collect();
        let right = pyramid.iter().rev().map(|l| l[l.len() - 1]).collect();
        (Self { points: left }, Self { points: right })
    }

    /// The same curve with degree n + 1.
    #[must_use]
    pub fn elevate(&self) -> Self {
        let n1 = self.points.len() as f64; // n + 1
        let p = &self.points;
        let mut q = Vec::with_capacity(p.len() + 1);
        q.push(p[0]);
        for i in 1..p.len() {
            let a = i as f64 / n1;
            q.push(a * p[i - 1] + (1.0 - a) * p[i]);
        }
        q.push(p[p.len() - 1]);
        Self { points: q }
    }

    /// The hodograph C′ as a Bézier curve of degree n − 1 (a point curve at the origin for
    /// degree 0).
    #[must_use]
    pub fn hodograph(&self) -> Self {
        let n = self.degree() as f64;
        let points = if self.points.len() == 1 {
            vec![DVec3::ZERO]
        } else {
            self.points.windows(2).map(|w| n * (w[1] - w[0])).collect()
        };
        Self { points }
    }
}

impl Curve for Bezier {
    fn point(&self, t: f64) -> DVec3 {
        let t = clamp_param(t, (0.0, 1.0));
        let mut p = self.points.clone();
        for r in 1..p.len() {
            for i in 0..p.len() - r {
                p[i] = p[i].lerp(p[i + 1], t);
            }
        }
        p[0]
    }

    fn derivative(&self, t: f64) -> DVec3 {
        self.hodograph().point(t)
    }

    fn domain(&self) -> (f64, f64) {
        (0.0, 1.0)
    }
}

/// The Bernstein polynomial B_i^n(t).
#[must_use]
pub fn bernstein(n: usize, i: usize, t: f64) -> f64 {
    if i > n {
        return 0.0;
    }
    let mut c = 1.0;
    for k in 0..i {
        c = c * (n - k) as f64 / (k + 1) as f64;
    }
    c * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32)
}

/// Whether every weight of a rational curve or surface is finite and positive.
pub(crate) fn weights_valid(weights: &[f64]) -> bool {
    weights.iter().all(|w| w.is_finite() && *w > 0.0)
}

/// The homogeneous points (w P, w) of `points` with `weights` (paired in order).
pub(crate) fn homogenize(points: &[DVec3], weights: &[f64]) -> Vec<DVec4> {
    points
        .iter()
        .zip(weights)
        .map(|(p, &w)| (*p * w).extend(w))
        .collect()
}

/// The points P and weights w of homogeneous points (w P, w).
pub(crate) fn dehomogenize(homogeneous: &[DVec4]) -> (Vec<DVec3>, Vec<f64>) {
    (
        homogeneous.iter().map(|&h| project(h)).collect(),
        homogeneous.iter().map(|h| h.w).collect(),
    )
}

/// The central projection A/w of a homogeneous point (A, w).
pub(crate) fn project(h: DVec4) -> DVec3 {
    h.truncate() / h.w
}

/// The derivative of the projection C = A/w from the homogeneous point `h` = (A, w) and its
/// derivative `d` = (A′, w′): C′ = (A′ − w′ C)/w (the quotient rule).
pub(crate) fn project_derivative(h: DVec4, d: DVec4) -> DVec3 {
    (d.truncate() - d.w * project(h)) / h.w
}

/// A rational Bézier curve: control points with positive weights.
#[derive(Clone, Debug, PartialEq)]
pub struct RationalBezier {
    /// Homogeneous control points (w P, w).
    homogeneous: Vec<DVec4>,
}

impl RationalBezier {
    /// The curve with `points` and `weights` (same length ≥ 1, weights finite and > 0), or
    /// `None`.
    #[must_use]
    pub fn new(points: &[DVec3], weights: &[f64]) -> Option<Self> {
        let ok = !points.is_empty() && points.len() == weights.len() && weights_valid(weights);
        ok.then(|| Self {
            homogeneous: homogenize(points, weights),
        })
    }

    /// The conic arc from `p0` to `p2` with tangents through `p1` and middle weight `w`:
    /// an ellipse arc for w < 1, a parabola for w = 1, a hyperbola for w > 1.
    #[must_use]
    pub fn conic(p0: DVec3, p1: DVec3, p2: DVec3, w: f64) -> Option<Self> {
        Self::new(&[p0, p1, p2], &[1.0, w, 1.0])
    }

    /// The exact circular arc of `angle` radians (0 < angle < π) about `center` in the plane
    /// spanned by the orthonormal `x`, `y`, starting at center + radius·x.
    #[must_use]
    pub fn circular_arc(
        center: DVec3,
        radius: f64,
        x: DVec3,
        y: DVec3,
        angle: f64,
    ) -> Option<Self> {
        if !(angle > 0.0 && angle < std::f64::consts::PI && radius > 0.0) {
            return None;
        }
        let half = angle / 2.0;
        let p0 = center + radius * x;
        let p2 = center + radius * (angle.cos() * x + angle.sin() * y);
        // The tangents at both ends meet at distance r / cos(θ/2) along the bisector.
        let p1 = center + radius / half.cos() * (half.cos() * x + half.sin() * y);
        Self::conic(p0, p1, p2, half.cos())
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

    /// de Casteljau on the homogeneous points: (Σ B_i w_i P_i, Σ B_i w_i) and its derivative.
    fn homogeneous_at(&self, t: f64) -> (DVec4, DVec4) {
        let t = clamp_param(t, (0.0, 1.0));
        let mut p = self.homogeneous.clone();
        let n = p.len();
        let mut d = DVec4::ZERO;
        for r in 1..n {
            if r == n - 1 {
                d = (p[1] - p[0]) * (n - 1) as f64;
            }
            for i in 0..n - r {
                p[i] = p[i].lerp(p[i + 1], t);
            }
        }
        (p[0], d)
    }
}

impl Curve for RationalBezier {
    fn point(&self, t: f64) -> DVec3 {
        project(self.homogeneous_at(t).0)
    }

    fn derivative(&self, t: f64) -> DVec3 {
        let (h, d) = self.homogeneous_at(t);
        project_derivative(h, d)
    }

    fn domain(&self) -> (f64, f64) {
        (0.0, 1.0)
    }
}
