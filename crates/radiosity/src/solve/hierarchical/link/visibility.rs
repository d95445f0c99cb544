//! How much of one handle another sees, by shadow rays: between two faces the quadrant pairs
//! and a stratified grid, kernel-weighted ([`crate::formfactor::visibility`]); where a cluster
//! is at either end, rays between member faces that face the other end. Part of the link
//! estimator ([`super::View`]).

use glam::Vec3;

use super::{End, Handle, Sight, View};
use crate::accel::Ray;
use crate::formfactor::visibility::{jitter, kernel, quadrant, ShadowRays};
use crate::hash::mix;

/// Shadow rays paired by quadrant between two faces.
const PILOT: u32 = 4;

/// Shadow rays between front-facing member faces where a cluster is at either end. Four (until
/// 3 December, sixth session) found a link wholly hidden whenever they all happened to be
/// blocked — a chair's cluster seen through a table's legs, say —, and such a link carries
/// nothing: the furnished room's chairs delivered 0.93 of the light they shine. Sixteen took its
/// worst object from −1.9 % to −0.5 % (chairs) and the bare OBJ room's from +1.9 % to +1.4 %
/// (docs/validation.md, thirteenth round).
const CLUSTER_RAYS: u32 = 16;

/// Stratified shadow rays between two faces besides the quadrant pairs (a 4 × 4 grid).
const RAYS: u32 = 16;

impl View<'_> {
    /// The visibility of source `s` from receiver `r` by few rays: the four quadrant pairs of
    /// [`View::estimate`]'s shadow rays between two faces (the gathering solvers' count per
    /// pair, [`crate::formfactor::raycast`]), the `CLUSTER_RAYS` between facing member faces
    /// where a cluster is at either end. For an element under a partly hidden link, and for the
    /// pieces of such a link's source ([`super::super::leaf_rows`], [`super::super::source_pieces`]).
    #[must_use]
    pub fn quick_visibility(&self, r: Handle, s: Handle) -> f64 {
        if r.is_cluster() || s.is_cluster() {
            self.cluster_visibility(r, s)
        } else {
            self.face_visibility(r, s, Sight::Unknown, false)
        }
    }

    /// Whether the segment between two lifted points is free.
    fn arrives(&self, from: Vec3, from_normal: Vec3, to: Vec3, to_normal: Vec3) -> bool {
        let origin = from + from_normal * self.lift;
        let target = to + to_normal * self.lift;
        !self.bvh.occluded(&Ray::new(origin, target - origin), 1.0)
    }

    /// Kernel-weighted fraction of the shadow rays between two faces that arrive, as in
    /// [`crate::formfactor::raycast`]: one ray per quadrant pair and 16 more stratified over both
    /// faces, each weighted by cosθ_r cosθ_s / r² at its ends. All 20 unless the `sight` is
    /// clear (the pair refines one whose 20 rays all arrived) and the 4 quadrant rays arrive
    /// too: then 1.
    /// Letting a unanimous 4-ray pilot decide for a fresh pair (as the matrix solvers did per
    /// element pair until 2 December) biased the Cornell box 3–8 % low here, where one link stands for a whole
    /// subtree of pairs; trusting the parent's 20 rays alone, without the pilot, biased it
    /// 1 % high at ε = 10⁻⁵ (occluders the parent's rays missed). Without `stratified`, the
    /// four quadrant rays alone.
    pub(super) fn face_visibility(
        &self,
        r: Handle,
        s: Handle,
        sight: Sight,
        stratified: bool,
    ) -> f64 {
        let (Some(nr), Some(ns)) = (self.node(r), self.node(s)) else {
            return 0.0;
        };
        let normal = |p: u32| self.mesh.patches[p as usize].normal;
        let (n_r, n_s) = (normal(nr.patch), normal(ns.patch));
        let pair = mix(mix(u64::from(r.to_bits())) ^ u64::from(s.to_bits()));
        let mut rays = ShadowRays::new(self.bvh, (&nr.face, n_r), (&ns.face, n_s), self.lift);
        let mut cast = |from, to| rays.cast(from, to);
        let mut arrived = 0;
        for k in 0..PILOT {
            let bits = mix(!pair ^ u64::from(k));
            let from = quadrant(k, jitter(bits, 0), jitter(bits, 1));
            // Quadrant k with quadrant k + o, o drawn per pair: a fixed pairing (k with 3 − k)
            // never sent a pilot ray between some quadrants, which biased apertures (a door
            // seen from a ceiling) by 4 % low.
            let to = quadrant(
                (k + (pair >> 40) as u32) % 4,
                jitter(bits, 2),
                jitter(bits, 3),
            );
            arrived += u32::from(cast(from, to));
        }
        if sight == Sight::Clear && arrived == PILOT {
            return 1.0;
        }
        if !stratified {
            return rays
                .fraction()
                .unwrap_or(f64::from(arrived) / f64::from(PILOT));
        }
        let offset = (pair % u64::from(RAYS)) as u32;
        let cell =
            |k: u32, ju: f32, jv: f32| (((k % 4) as f32 + ju) * 0.25, ((k / 4) as f32 + jv) * 0.25);
        for k in 0..RAYS {
            let bits = mix(pair ^ u64::from(k));
            let from = cell(k, jitter(bits, 0), jitter(bits, 1));
            // 5 is coprime to 16: a permutation of the source cells.
            let to = cell((5 * k + offset) % RAYS, jitter(bits, 2), jitter(bits, 3));
            arrived += u32::from(cast(from, to));
        }
        rays.fraction()
            .unwrap_or(f64::from(arrived) / f64::from(PILOT + RAYS))
    }

    /// Kernel-weighted fraction of [`CLUSTER_RAYS`] rays between points of front-facing member
    /// faces that arrive; 0 when no member face on a side is found facing the other side's
    /// centre (as for two parts of one convex object, whose centres lie behind all of each
    /// other's faces). The member faces are drawn by count, not by area, so each ray weighs
    /// A_p A_q cosθ_p cosθ_q / r², its share of ∫∫ cosθ cosθ' / (π r²) dA dA' (the same
    /// weights as [`crate::formfactor::raycast`]'s). A plain count weighed every drawn face
    /// alike whatever its size and slant: the furnished room's chairs delivered 0.92–0.93 of
    /// the light they shine (0.96 weighted), its power balance was 0.9970 (now 0.9998;
    /// docs/validation.md, fourteenth round).
    pub(super) fn cluster_visibility(&self, r: Handle, s: Handle) -> f64 {
        let pair = mix(mix(u64::from(r.to_bits()) ^ 0x5EED) ^ u64::from(s.to_bits()));
        let (cr, cs) = (self.sphere(r).0, self.sphere(s).0);
        let (mut cast, mut seen) = (0.0, 0.0);
        for k in 0..CLUSTER_RAYS {
            let bits = mix(pair ^ u64::from(k));
            let from = self.sample(r, cs, bits);
            let to = self.sample(s, cr, mix(bits));
            if let (Some((p, n, a)), Some((q, m, b))) = (from, to) {
                let kernel = kernel((p, n), (q, m)) * a * b;
                cast += kernel;
                if self.arrives(p, n, q, m) {
                    seen += kernel;
                }
            }
        }
        if cast > 0.0 {
            seen / cast
        } else {
            0.0
        }
    }

    /// A point (with its normal and its face's area) on handle `h` whose face looks toward
    /// `toward`: on the face itself, or on one of a few member faces of a cluster drawn by
    /// `bits`.
    fn sample(&self, h: Handle, toward: Vec3, bits: u64) -> Option<(Vec3, Vec3, f64)> {
        let (u, v) = (jitter(bits, 0), jitter(bits, 1));
        let on = |node: u32| {
            let node = &self.mesh.nodes[node as usize];
            let n = self.mesh.patches[node.patch as usize].normal;
            let p = node.face.point(u, v);
            (n.dot(toward - p) > 0.0).then(|| (p, n, node.area()))
        };
        let c = match h.end() {
            End::Node(n) => return on(n as u32),
            End::Cluster(c) => &self.clusters.nodes[c],
        };
        let faces = &self.clusters.faces[c.faces.start as usize..c.faces.end as usize];
        (0..8u64).find_map(|t| {
            let pick = mix(bits ^ (t << 48)) % faces.len() as u64;
            on(faces[pick as usize])
        })
    }
}
