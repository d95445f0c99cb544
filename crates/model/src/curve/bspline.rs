//! B-spline curves: C(t) = Σ_i N_{i,p}(t) P_i over a non-decreasing knot vector
//! U = (u_0, …, u_{n+p+1}), defined on [u_p, u_{n+1}].
//!
//! - **Cox–de Boor recurrence** (de Boor 1972; Cox 1972) for the basis functions:
//!   N_{i,0}(t) = 1 if u_i ≤ t < u_{i+1} else 0,
//!   N_{i,p}(t) = (t − u_i)/(u_{i+p} − u_i) N_{i,p−1}(t) + (u_{i+p+1} − t)/(u_{i+p+1} − u_{i+1}) N_{i+1,p−1}(t)
//!   (0/0 := 0). They are non-negative, sum to one on the domain (partition of unity) and
//!   N_{i,p} vanishes outside [u_i, u_{i+p+1}) (local support), hence the convex-hull and
//!   affine-invariance properties. [`basis`] evaluates one function by the recurrence.
//! - **de Boor's algorithm** evaluates C(t) from the p + 1 control points of t's knot span by
//!   repeated affine combination (the B-spline analogue of de Casteljau).
//! - **Derivative**: C′ is a B-spline of degree p − 1 with control points
//!   p (P_{i+1} − P_i)/(u_{i+p+1} − u_{i+1}).
//! - **Knot insertion** (Boehm 1980): inserting t ∈ [u_k, u_{k+1}) replaces P_{k−p+1} … P_k by
//!   Q_i = (1 − a_i) P_{i−1} + a_i P_i, a_i = (t − u_i)/(u_{i+p} − u_i); the curve is unchanged.
//!
//! Uniform knots (u_i = i) give the classic uniform B-spline that does not reach its end
//! points; clamped knots (p + 1 equal end knots) make it interpolate them like a Bézier curve.
//! Reference: Piegl & Tiller, *The NURBS Book*, ch. 2–5.

use std::ops::{Add, Mul, Sub};

use glam::DVec3;

use super::{clamp_param, Curve};

/// A non-rational B-spline curve of degree `degree` (order degree + 1).
#[derive(Clone, Debug, PartialEq)]
pub struct BSpline {
    degree: usize,
    knots: Vec<f64>,
    points: Vec<DVec3>,
}

impl BSpline {
    /// A B-spline with explicit `knots`, or `None` unless [`knots_valid`] holds.
    #[must_use]
    pub fn new(degree: usize, knots: Vec<f64>, points: Vec<DVec3>) -> Option<Self> {
        knots_valid(degree, &knots, points.len()).then_some(Self {
            degree,
            knots,
            points,
        })
    }

    /// Uniform (unclamped) knots u_i = i: domain [p, n + 1].
    #[must_use]
    pub fn uniform(degree: usize, points: Vec<DVec3>) -> Option<Self> {
        let knots = (0..points.len() + degree + 1).map(|i| i as f64).collect();
        Self::new(degree, knots, points)
    }

    /// Clamped uniform knots (p + 1 zeros, uniform interior, p + 1 ones): domain [0, 1], the
    /// curve starts at the first point and ends at the last.
    #[must_use]
    pub fn clamped(degree: usize, points: Vec<DVec3>) -> Option<Self> {
        let knots = clamped_knots(degree, points.len())?;
        Self::new(degree, knots, points)
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

    /// The control points.
    #[must_use]
    pub fn points(&self) -> &[DVec3] {
        &self.points
    }

    /// The same curve with the knot `t` inserted once (Boehm); `t` is clamped to the domain.
    #[must_use]
    pub fn insert_knot(&self, t: f64) -> Self {
        let t = clamp_param(t, self.domain());
        let (knots, points) = insert_knot(self.degree, &self.knots, &self.points, t);
        Self {
            degree: self.degree,
            knots,
            points,
        }
    }
}

impl Curve for BSpline {
    fn point(&self, t: f64) -> DVec3 {
        de_boor(self.degree, &self.knots, &self.points, t)
    }

    fn derivative(&self, t: f64) -> DVec3 {
        derivative(self.degree, &self.knots, &self.points, t)
    }

    fn domain(&self) -> (f64, f64) {
        domain(self.degree, &self.knots, self.points.len())
    }
}

/// Whether `knots` is a valid knot vector for `count` control points of degree `degree`:
/// `count > degree`, `knots.len() == count + degree + 1`, finite, non-decreasing, and a
/// non-empty domain [u_p, u_n].
#[must_use]
pub fn knots_valid(degree: usize, knots: &[f64], count: usize) -> bool {
    count > degree
        && knots.len() == count + degree + 1
        && knots.iter().all(|k| k.is_finite())
        && knots.windows(2).all(|w| w[0] <= w[1])
        && knots[degree] < knots[count]
}

/// Clamped uniform knots for `count` control points of degree `degree` (`None` if
/// `count ≤ degree`).
#[must_use]
pub fn clamped_knots(degree: usize, count: usize) -> Option<Vec<f64>> {
    if count <= degree {
        return None;
    }
    let spans = count - degree;
    let mut knots = vec![0.0; degree + 1];
    knots.extend((1..spans).map(|i| i as f64 / spans as f64));
    knots.extend(std::iter::repeat_n(1.0, degree + 1));
    Some(knots)
}

/// The basis function N_{i,p}(t) by the Cox–de Boor recurrence. At the right end of the
/// domain the last non-empty interval is taken as closed, so that the basis still sums to 1
/// there.
#[must_use]
pub fn basis(knots: &[f64], degree: usize, i: usize, t: f64) -> f64 {
    if i + degree + 1 >= knots.len() {
        return 0.0;
    }
    if degree == 0 {
        let (a, b) = (knots[i], knots[i + 1]);
        let last = knots[knots.len() - 1];
        // Close the last non-empty interval so the basis sums to 1 at the end of the domain.
        let closes_end = t == b && b == last && a < b;
        return if (a <= t && t < b) || closes_end {
            1.0
        } else {
            0.0
        };
    }
    let ratio = |num: f64, den: f64| if den == 0.0 { 0.0 } else { num / den };
    ratio(t - knots[i], knots[i + degree] - knots[i]) * basis(knots, degree - 1, i, t)
        + ratio(
            knots[i + degree + 1] - t,
            knots[i + degree + 1] - knots[i + 1],
        ) * basis(knots, degree - 1, i + 1, t)
}

/// The domain [u_p, u_n] for `count` control points.
pub(crate) fn domain(degree: usize, knots: &[f64], count: usize) -> (f64, f64) {
    (knots[degree], knots[count])
}

/// The index k of the knot span [u_k, u_{k+1}) holding `t`, with p ≤ k ≤ n − 1 (the end of
/// the domain belongs to the last non-empty span).
pub(crate) fn find_span(degree: usize, knots: &[f64], count: usize, t: f64) -> usize {
    let (a, b) = domain(degree, knots, count);
    let t = clamp_param(t, (a, b));
    if t >= b {
        // The last span with u_k < u_{k+1}.
        let mut k = count - 1;
        while k > degree && knots[k] >= knots[k + 1] {
            k -= 1;
        }
        return k;
    }
    // Largest k with u_k ≤ t.
    (knots.partition_point(|&u| u <= t) - 1).clamp(degree, count - 1)
}

/// de Boor's algorithm, generic over points (3D) and homogeneous points (4D).
pub(crate) fn de_boor<T>(degree: usize, knots: &[f64], points: &[T], t: f64) -> T
where
    T: Copy + Add<Output = T> + Mul<f64, Output = T>,
{
    let t = clamp_param(t, domain(degree, knots, points.len()));
    let k = find_span(degree, knots, points.len(), t);
    let mut d: Vec<T> = (0..=degree).map(|j| points[j + k - degree]).collect();
    for r in 1..=degree {
        for j in (r..=degree).rev() {
            let i = j + k - degree;
            let den = knots[i + degree + 1 - r] - knots[i];
            let a = if den == 0.0 {
                0.0
            } else {
                (t - knots[i]) / den
            };
            d[j] = d[j - 1] * (1.0 - a) + d[j] * a;
        }
    }
    d[degree]
}

/// C′(t) through the derivative curve's control points.
pub(crate) fn derivative<T>(degree: usize, knots: &[f64], points: &[T], t: f64) -> T
where
    T: Copy + Add<Output = T> + Sub<Output = T> + Mul<f64, Output = T>,
{
    if degree == 0 {
        return points[0] * 0.0;
    }
    let q: Vec<T> = (0..points.len() - 1)
        .map(|i| {
            let den = knots[i + degree + 1] - knots[i + 1];
            let s = if den == 0.0 { 0.0 } else { degree as f64 / den };
            (points[i + 1] - points[i]) * s
        })
        .collect();
    let t = clamp_param(t, domain(degree, knots, points.len()));
    de_boor(degree - 1, &knots[1..knots.len() - 1], &q, t)
}

/// Boehm's single knot insertion: the new knots and control points.
pub(crate) fn insert_knot<T>(
    degree: usize,
    knots: &[f64],
    points: &[T],
    t: f64,
) -> (Vec<f64>, Vec<T>)
where
    T: Copy + Add<Output = T> + Mul<f64, Output = T>,
{
    let k = find_span(degree, knots, points.len(), t);
    let mut q = Vec::with_capacity(points.len() + 1);
    for i in 0..=points.len() {
        q.push(if i + degree <= k {
            points[i]
        } else if i > k {
            points[i - 1]
        } else {
            let a = (t - knots[i]) / (knots[i + degree] - knots[i]);
            points[i - 1] * (1.0 - a) + points[i] * a
        });
    }
    let mut u = knots.to_vec();
    u.insert(k + 1, t);
    (u, q)
}
