//! Tensor-product patches: Bézier, B-spline and NURBS surfaces, S(u, v) = Σ_i Σ_j
//! N_i(u) N_j(v) w_ij P_ij / Σ_i Σ_j N_i(u) N_j(v) w_ij.
//!
//! A tensor-product surface is a curve of curves: for fixed u, the control points
//! Q_j(u) = Σ_i N_i(u) (w_ij P_ij, w_ij) are a homogeneous curve in v. Evaluation therefore
//! runs de Boor's algorithm ([`crate::curve::bspline`]) along u on every column, then once
//! along v, and projects. The partial derivatives come the same way from the derivative
//! curves, and the normal is S_u × S_v: the front of the patch (counter-clockwise in (u, v)
//! seen from the front).

use glam::{DVec3, DVec4};

use crate::curve::bezier::{dehomogenize, homogenize, project, project_derivative, weights_valid};
use crate::curve::bspline::{self, clamped_knots, knots_valid};
use crate::curve::Nurbs;

/// A tensor-product NURBS patch of degree (p, q) with `count_u × count_v` control points.
#[derive(Clone, Debug, PartialEq)]
pub struct NurbsSurface {
    degree_u: usize,
    degree_v: usize,
    knots_u: Vec<f64>,
    knots_v: Vec<f64>,
    count_u: usize,
    count_v: usize,
    /// Homogeneous control points, `[i * count_v + j]` for P_ij (i along u).
    homogeneous: Vec<DVec4>,
}

impl NurbsSurface {
    /// A patch from control points `points[i * count_v + j]` with `weights` (finite, > 0)
    /// and explicit knots, or `None` if anything is inconsistent.
    #[must_use]
    pub fn new(
        (degree_u, degree_v): (usize, usize),
        (knots_u, knots_v): (Vec<f64>, Vec<f64>),
        (count_u, count_v): (usize, usize),
        points: &[DVec3],
        weights: &[f64],
    ) -> Option<Self> {
        let ok = points.len() == count_u * count_v
            && weights.len() == points.len()
            && points.iter().all(|p| p.is_finite())
            && weights_valid(weights)
            && knots_valid(degree_u, &knots_u, count_u)
            && knots_valid(degree_v, &knots_v, count_v);
        ok.then(|| Self {
            degree_u,
            degree_v,
            knots_u,
            knots_v,
            count_u,
            count_v,
            homogeneous: homogenize(points, weights),
        })
    }

    /// A Bézier patch of degree (count_u − 1, count_v − 1) on [0, 1]².
    #[must_use]
    pub fn bezier(count_u: usize, count_v: usize, points: &[DVec3]) -> Option<Self> {
        let (p, q) = (count_u.checked_sub(1)?, count_v.checked_sub(1)?);
        Self::bspline((p, q), (count_u, count_v), points)
    }

    /// A B-spline patch of degree (p, q) with clamped uniform knots on [0, 1]².
    #[must_use]
    pub fn bspline(
        (p, q): (usize, usize),
        (count_u, count_v): (usize, usize),
        points: &[DVec3],
    ) -> Option<Self> {
        let knots = (clamped_knots(p, count_u)?, clamped_knots(q, count_v)?);
        Self::new(
            (p, q),
            knots,
            (count_u, count_v),
            points,
            &vec![1.0; points.len()],
        )
    }

    /// Degrees (p, q).
    #[must_use]
    pub fn degrees(&self) -> (usize, usize) {
        (self.degree_u, self.degree_v)
    }

    /// Control net size (count_u, count_v).
    #[must_use]
    pub fn counts(&self) -> (usize, usize) {
        (self.count_u, self.count_v)
    }

    /// Knot vectors in u and v.
    #[must_use]
    pub fn knots(&self) -> (&[f64], &[f64]) {
        (&self.knots_u, &self.knots_v)
    }

    /// Homogeneous control points (w P, w), `[i * count_v + j]`.
    #[must_use]
    pub fn homogeneous(&self) -> &[DVec4] {
        &self.homogeneous
    }

    /// Parameter domain in u.
    #[must_use]
    pub fn domain_u(&self) -> (f64, f64) {
        bspline::domain(self.degree_u, &self.knots_u, self.count_u)
    }

    /// Parameter domain in v.
    #[must_use]
    pub fn domain_v(&self) -> (f64, f64) {
        bspline::domain(self.degree_v, &self.knots_v, self.count_v)
    }

    /// The same surface with its orientation reversed (u runs backwards), so the normal flips.
    #[must_use]
    pub fn flipped(&self) -> Self {
        let (a, b) = self.domain_u();
        let knots_u = self.knots_u.iter().rev().map(|k| a + b - k).collect();
        let mut homogeneous = Vec::with_capacity(self.homogeneous.len());
        for i in (0..self.count_u).rev() {
            homogeneous
                .extend_from_slice(&self.homogeneous[i * self.count_v..(i + 1) * self.count_v]);
        }
        Self {
            knots_u,
            homogeneous,
            ..self.clone()
        }
    }

    /// The same surface with every control point mapped by `f` (weights kept): exact for
    /// affine maps, by the affine invariance of rational B-splines.
    #[must_use]
    pub fn map_points(&self, f: impl Fn(DVec3) -> DVec3) -> Self {
        Self {
            homogeneous: self
                .homogeneous
                .iter()
                .map(|&h| (f(project(h)) * h.w).extend(h.w))
                .collect(),
            ..self.clone()
        }
    }

    /// The boundary curve `edge` as a NURBS curve, oriented counter-clockwise around the
    /// patch: 0 is v = v₀ (u increasing), 1 is u = u₁ (v increasing), 2 is v = v₁ (u
    /// decreasing), 3 is u = u₀ (v decreasing). Exact for clamped knots.
    #[must_use]
    pub fn boundary(&self, edge: usize) -> (Vec<f64>, Vec<DVec4>) {
        let (nu, nv) = (self.count_u, self.count_v);
        let h = &self.homogeneous;
        let (knots, points): (&[f64], Vec<DVec4>) = match edge % 4 {
            0 => (&self.knots_u, (0..nu).map(|i| h[i * nv]).collect()),
            1 => (
                &self.knots_v,
                (0..nv).map(|j| h[(nu - 1) * nv + j]).collect(),
            ),
            2 => (
                &self.knots_u,
                (0..nu).rev().map(|i| h[i * nv + nv - 1]).collect(),
            ),
            _ => (&self.knots_v, (0..nv).rev().map(|j| h[j]).collect()),
        };
        if edge % 4 < 2 {
            (knots.to_vec(), points)
        } else {
            let (a, b) = (knots[0], knots[knots.len() - 1]);
            (knots.iter().rev().map(|k| a + b - k).collect(), points)
        }
    }

    /// The homogeneous curve in v at parameter u (one de Boor run per column), and its
    /// u-derivative.
    fn column_curves(&self, u: f64) -> (Vec<DVec4>, Vec<DVec4>) {
        let (nu, nv) = (self.count_u, self.count_v);
        let mut q = Vec::with_capacity(nv);
        let mut qu = Vec::with_capacity(nv);
        let mut column = Vec::with_capacity(nu);
        for j in 0..nv {
            column.clear();
            column.extend((0..nu).map(|i| self.homogeneous[i * nv + j]));
            q.push(bspline::de_boor(self.degree_u, &self.knots_u, &column, u));
            qu.push(bspline::derivative(
                self.degree_u,
                &self.knots_u,
                &column,
                u,
            ));
        }
        (q, qu)
    }

    /// The point S(u, v) (parameters clamped to the domain).
    #[must_use]
    pub fn point(&self, u: f64, v: f64) -> DVec3 {
        self.evaluate(u, v).0
    }

    /// S(u, v) and the partial derivatives S_u, S_v.
    #[must_use]
    pub fn evaluate(&self, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
        let (q, qu) = self.column_curves(u);
        let h = bspline::de_boor(self.degree_v, &self.knots_v, &q, v);
        let hu = bspline::de_boor(self.degree_v, &self.knots_v, &qu, v);
        let hv = bspline::derivative(self.degree_v, &self.knots_v, &q, v);
        // Quotient rule in each direction: S_x = (A_x − w_x S)/w.
        (
            project(h),
            project_derivative(h, hu),
            project_derivative(h, hv),
        )
    }

    /// The unit normal S_u × S_v / |S_u × S_v|, or zero where the patch is degenerate (a
    /// collapsed edge, as at the teapot's lid knob).
    #[must_use]
    pub fn normal(&self, u: f64, v: f64) -> DVec3 {
        let (_, su, sv) = self.evaluate(u, v);
        su.cross(sv).normalize_or_zero()
    }

    /// The iso-curve u = const as a NURBS curve in v.
    #[must_use]
    pub fn iso_u(&self, u: f64) -> Option<Nurbs> {
        let (q, _) = self.column_curves(u);
        let (points, weights) = dehomogenize(&q);
        Nurbs::new(self.degree_v, self.knots_v.clone(), &points, &weights)
    }
}
