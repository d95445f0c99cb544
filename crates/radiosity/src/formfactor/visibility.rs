//! Kernel-weighted visibility between two faces by shadow rays: the estimator the ray-cast
//! form factors ([`super::raycast`]) and the hierarchical solver's links share.
//!
//! The visible fraction of a pair is not the fraction of rays that arrive but the fraction of
//! the kernel they carry: each ray between x on one face and y on the other is weighted by
//! cosθ_x cosθ_y / r², the integrand of the form factor, so that a ray through a wide gap
//! near the faces counts for more than one that grazes them (Wallace, Elmquist & Haines 1989
//! weight their rays the same way). The kernel is taken between the points on the surfaces,
//! the ray between the points lifted off them along their normals: where two faces are closer
//! than twice the lift (an emitter 1 mm in front of a wall), the lifted ends pass each other and
//! their difference points backwards.
//!
//! Where the rays start and end (pilot rays by quadrants, stratified cells, how the pairs are
//! permuted) is each caller's sampling plan; [`jitter`] and [`quadrant`] are their common parts.

use glam::Vec3;

use crate::accel::{Bvh, Ray};
use crate::mesh::Face;

/// Shadow rays between two faces, with their kernel-weighted tally.
pub(crate) struct ShadowRays<'a> {
    bvh: &'a Bvh,
    from: &'a Face,
    to: &'a Face,
    n_from: Vec3,
    n_to: Vec3,
    lift: f32,
    /// Σ kernel over every ray cast, and over those that arrived.
    total: f64,
    visible: f64,
}

impl<'a> ShadowRays<'a> {
    /// Rays from `from` (front normal `n_from`) to `to` (front normal `n_to`), their ends lifted
    /// by `lift`.
    pub fn new(bvh: &'a Bvh, from: (&'a Face, Vec3), to: (&'a Face, Vec3), lift: f32) -> Self {
        Self {
            bvh,
            from: from.0,
            to: to.0,
            n_from: from.1,
            n_to: to.1,
            lift,
            total: 0.0,
            visible: 0.0,
        }
    }

    /// Casts the ray from the point (u, v) of `from` to the point (su, sv) of `to`, adds its
    /// kernel weight to the tally, and says whether it arrived.
    pub fn cast(&mut self, (u, v): (f32, f32), (su, sv): (f32, f32)) -> bool {
        let (x, y) = (self.from.point(u, v), self.to.point(su, sv));
        let origin = x + self.n_from * self.lift;
        let target = y + self.n_to * self.lift;
        let weight = kernel((x, self.n_from), (y, self.n_to));
        let arrives = !self.bvh.occluded(&Ray::new(origin, target - origin), 1.0);
        self.total += weight;
        if arrives {
            self.visible += weight;
        }
        arrives
    }

    /// The kernel-weighted fraction of the rays cast that arrived; `None` when no ray carried
    /// any kernel (every one grazing or behind a face).
    pub fn fraction(&self) -> Option<f64> {
        (self.total > 0.0).then(|| self.visible / self.total)
    }
}

/// The weight of a ray from x (front normal n_x) to y (front normal n_y): cosθ_x cosθ_y / r²
/// over r² (the form factor's integrand, up to π, with the cosines taken of the unnormalised
/// y − x); 0 where either point lies behind the other's face.
pub(crate) fn kernel((x, n_x): (Vec3, Vec3), (y, n_y): (Vec3, Vec3)) -> f64 {
    let d = (y - x).as_dvec3();
    (d.dot(n_x.as_dvec3()).max(0.0) * (-d.dot(n_y.as_dvec3())).max(0.0))
        / d.length_squared().powi(2).max(f64::MIN_POSITIVE)
}

/// Sixteen bits `i` of `bits` (i < 4) as a jitter in (0, 1).
pub(crate) fn jitter(bits: u64, i: u32) -> f32 {
    (((bits >> (16 * i)) & 0xFFFF) as f32 + 0.5) / 65536.0
}

/// The point (ju, jv) of quadrant `q` (0–3) of the unit square.
pub(crate) fn quadrant(q: u32, ju: f32, jv: f32) -> (f32, f32) {
    (((q & 1) as f32 + ju) * 0.5, ((q >> 1) as f32 + jv) * 0.5)
}
