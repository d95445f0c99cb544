//! Lagrange interpolation: the unique polynomial of degree ≤ n through n + 1 points
//! P_i at distinct parameters t_i,
//!
//! L(t) = Σ_i P_i ℓ_i(t),  ℓ_i(t) = Π_{j≠i} (t − t_j)/(t_i − t_j),
//!
//! evaluated with Neville's scheme (repeated linear interpolation, the same pyramid as de
//! Casteljau's but with parameter-dependent ratios). High degrees oscillate between the nodes
//! (Runge's phenomenon), which is why the course moves on to splines.

use glam::DVec3;

use super::{clamp_param, Curve};

/// The interpolating polynomial through `points` at strictly increasing `params`.
#[derive(Clone, Debug, PartialEq)]
pub struct Lagrange {
    params: Vec<f64>,
    points: Vec<DVec3>,
}

impl Lagrange {
    /// Through `points` at `params`; `None` unless both have the same length ≥ 1 and the
    /// parameters are finite and strictly increasing.
    #[must_use]
    pub fn new(params: Vec<f64>, points: Vec<DVec3>) -> Option<Self> {
        let ok = !points.is_empty()
            && params.len() == points.len()
            && params.iter().all(|t| t.is_finite())
            && params.windows(2).all(|w| w[0] < w[1]);
        ok.then_some(Self { params, points })
    }

    /// Through `points` at t = 0, 1, …, n.
    #[must_use]
    pub fn uniform(points: Vec<DVec3>) -> Option<Self> {
        Self::new((0..points.len()).map(|i| i as f64).collect(), points)
    }

    /// Neville's pyramid for the value and the derivative together.
    fn neville(&self, t: f64) -> (DVec3, DVec3) {
        let t = clamp_param(t, self.domain());
        let mut p = self.points.clone();
        let mut d = vec![DVec3::ZERO; p.len()];
        let n = p.len();
        for level in 1..n {
            for i in 0..n - level {
                let (ti, tj) = (self.params[i], self.params[i + level]);
                let h = tj - ti;
                // p_{i..j}(t) = ((tj − t) p_{i..j−1} + (t − ti) p_{i+1..j}) / (tj − ti)
                d[i] = ((tj - t) * d[i] - p[i] + (t - ti) * d[i + 1] + p[i + 1]) / h;
                p[i] = ((tj - t) * p[i] + (t - ti) * p[i + 1]) / h;
            }
        }
        (p[0], d[0])
    }
}

impl Curve for Lagrange {
    fn point(&self, t: f64) -> DVec3 {
        self.neville(t).0
    }

    fn derivative(&self, t: f64) -> DVec3 {
        self.neville(t).1
    }

    fn domain(&self) -> (f64, f64) {
        (self.params[0], self.params[self.params.len() - 1])
    }
}
