//! Links and their form-factor and visibility estimates.
//!
//! A link (Hanrahan, Salzman & Aupperle 1991) says "receiver r gathers from source s": it
//! stores the form factor F_rs times a visibility estimate V_rs, and the gather adds
//! F_rs·V_rs·B_s to r's irradiance. Receivers and sources are *handles*: a quadtree node of
//! the mesh, or — top bit set — a cluster.
//!
//! - **Face to face**: the unoccluded factor is Lambert's contour integral at a 2 × 2 grid of
//!   quadrature points on the receiver ([`crate::formfactor::analytic::point_to_polygon`]),
//!   exact up to the receiver quadrature at any distance (4 × 4 points in the near field, where
//!   the centres are closer than twice the sum of the bounding radii); V is the kernel-weighted
//!   fraction of 20 stratified shadow rays that arrive, as in [`crate::formfactor::raycast`].
//!   When V < 1 the link's spread is the unoccluded factor, so the oracle refines a partly (or
//!   apparently wholly) hidden link until the light it could carry is below its threshold;
//!   a link found wholly hidden and fine enough is dropped.
//!   The spread of the point values over the quadrature points tells how much F varies over
//!   the receiver (large next to a shared edge), which the oracle also bounds.
//!   Faces of one patch (coplanar) and faces behind each other get no link.
//! - **Cluster involved**: the point-to-point kernel F ≈ A_s c_r c_s / (π d²) between the
//!   bounding-sphere centres d apart, with c = max(0, n·ω) for a face and c = P(ω)/A for a
//!   cluster (its projected area over its area: [`super::cluster`], after the isotropic model
//!   of Smits, Arvo & Greenberg 1994). The estimate is only trusted when the spheres are
//!   disjoint and no face's plane cuts the other side's sphere; otherwise the oracle must open
//!   the cluster ([`Estimate::Open`]). V is sampled with 4 rays between front-facing member
//!   faces.
//!
//! The error of the cluster model is bounded by the oracle: a cluster link survives only if
//! B_s·F·A_r ≤ [`super::refine::VARIATION`]·ε·Φ (its spread is taken as F itself), and the
//! model's projected area is off by at most a factor ~4 (mixed orientations, self-shadowing),
//! so each surviving cluster link misplaces at most ~ε/2 of the emitted power.
//!
//! Rays are jittered by a hash of (receiver, source, ray): node ids never change once made, so
//! a link's value does not depend on the thread count or the order of work.

use glam::{DVec3, Vec3};

use super::cluster::Clusters;
use crate::accel::{Bvh, Ray};
use crate::formfactor::analytic::point_to_polygon;
use crate::formfactor::{facing, Receiver};
use crate::mesh::Mesh;

/// Top bit of a handle: the rest is a cluster index (else a node index into [`Mesh::nodes`]).
pub const CLUSTER: u32 = 1 << 31;

/// Side of the receiver quadrature grid of face-to-face links in the far field.
const QUADRATURE: u32 = 2;

/// Side of the grid in the near field ([`NEAR`]), where the factor varies fast over the
/// receiver (logarithmically at a shared edge) and the midpoint rule on 2 × 2 points
/// underestimates it: by 3 % on the Cornell box's floor after interreflection.
const NEAR_QUADRATURE: u32 = 4;

/// A pair is in the near field when the distance between the centres of the bounding spheres is
/// below this multiple of the sum of their radii.
const NEAR: f32 = 2.0;

/// Shadow rays paired by quadrant between two faces, and the rays of cluster links.
const PILOT: u32 = 4;

/// Stratified shadow rays between two faces besides the quadrant pairs (a 4 × 4 grid).
const RAYS: u32 = 16;

/// A link: 16 bytes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Link {
    /// Receiving handle.
    pub receiver: u32,
    /// Source handle.
    pub source: u32,
    /// Form factor times visibility, F_rs·V_rs.
    pub factor: f32,
    /// How much the factor may be off over the receiver: the spread (max − min) of the
    /// point-to-polygon factors at the quadrature points; the unoccluded factor when shadow
    /// rays found the pair partly or wholly hidden; the factor itself for a cluster link.
    pub spread: f32,
}

/// What [`View::estimate`] says about a pair.
#[derive(Clone, Copy, Debug)]
pub enum Estimate {
    /// The pair exchanges no light (same patch, facing away, or wholly hidden).
    Nothing,
    /// The cluster estimate cannot be trusted here: a cluster must be opened.
    Open,
    /// A link with its estimate.
    Link(Link),
}

/// The hierarchy as the refinement sees it: mesh quadtrees below, clusters above.
#[derive(Clone, Copy, Debug)]
pub struct View<'a> {
    /// Patches and quadtrees.
    pub mesh: &'a Mesh,
    /// Clusters over the root faces.
    pub clusters: &'a Clusters,
    /// Visibility structure over `mesh.triangles`.
    pub bvh: &'a Bvh,
    /// Shadow-ray offset off the surfaces (10⁻⁴ of the scene's diagonal).
    pub lift: f32,
}

impl<'a> View<'a> {
    /// Bundles the three and derives the shadow-ray offset.
    #[must_use]
    pub fn new(mesh: &'a Mesh, clusters: &'a Clusters, bvh: &'a Bvh) -> Self {
        let b = bvh.bounds();
        let diagonal = (b.max - b.min).length();
        let lift = if diagonal.is_finite() && diagonal > 0.0 {
            1e-4 * diagonal
        } else {
            1e-4
        };
        Self {
            mesh,
            clusters,
            bvh,
            lift,
        }
    }

    /// Surface area of a handle.
    #[must_use]
    pub fn area(&self, h: u32) -> f64 {
        if h & CLUSTER != 0 {
            self.clusters.nodes[(h & !CLUSTER) as usize].area
        } else {
            self.mesh.nodes[h as usize].face.area()
        }
    }

    /// Bounding sphere (centre, radius) of a handle.
    #[must_use]
    pub fn sphere(&self, h: u32) -> (Vec3, f32) {
        if h & CLUSTER != 0 {
            let c = &self.clusters.nodes[(h & !CLUSTER) as usize];
            (c.center, c.radius)
        } else {
            let corners = self.mesh.nodes[h as usize].face.corners();
            let centre = corners.iter().copied().sum::<Vec3>() / corners.len() as f32;
            let radius = corners
                .iter()
                .map(|c| c.distance(centre))
                .fold(0.0, f32::max);
            (centre, radius)
        }
    }

    /// Appends the children of a handle to `out`: two clusters, the faces of a leaf cluster,
    /// the four children of a split face, or nothing for an element.
    pub fn children(&self, h: u32, out: &mut Vec<u32>) {
        if h & CLUSTER != 0 {
            let c = &self.clusters.nodes[(h & !CLUSTER) as usize];
            match c.children {
                Some([a, b]) => out.extend([a | CLUSTER, b | CLUSTER]),
                None => out.extend_from_slice(
                    &self.clusters.faces[c.faces.start as usize..c.faces.end as usize],
                ),
            }
        } else if let Some(c) = self.mesh.nodes[h as usize].children {
            out.extend(c..c + 4);
        }
    }

    /// The form factor and visibility of receiver `r` from source `s` (see the module
    /// documentation).
    #[must_use]
    pub fn estimate(&self, r: u32, s: u32) -> Estimate {
        if r & CLUSTER == 0 && s & CLUSTER == 0 {
            return self.face_to_face(r, s);
        }
        let ((cr, rr), (cs, rs)) = (self.sphere(r), self.sphere(s));
        let d = cs - cr;
        let distance = d.length();
        // Overlapping spheres (or NaN geometry): the kernel cannot be trusted.
        if distance.is_nan() || distance <= rr + rs {
            return Estimate::Open;
        }
        let w = d / distance;
        // The cosine factor of each side; a face whose plane cuts the other sphere is refused.
        let side = |h: u32, toward: Vec3, other: Vec3, other_radius: f32| -> Option<f64> {
            if h & CLUSTER != 0 {
                let c = (h & !CLUSTER) as usize;
                let area = self.clusters.nodes[c].area;
                let p = self.clusters.projected_area(c, toward.as_dvec3());
                return Some(if area > 0.0 { p / area } else { 0.0 });
            }
            let node = &self.mesh.nodes[h as usize];
            let n = self.mesh.patches[node.patch as usize].normal;
            let height = n.dot(other - node.face.corners()[0]);
            if height.abs() <= other_radius {
                return None;
            }
            Some(f64::from(n.dot(toward)).max(0.0))
        };
        let (Some(c_r), Some(c_s)) = (side(r, w, cs, rs), side(s, -w, cr, rr)) else {
            return Estimate::Open;
        };
        let f = self.area(s) * c_r * c_s / (std::f64::consts::PI * f64::from(distance).powi(2));
        if f <= 0.0 {
            return Estimate::Nothing;
        }
        let v = self.cluster_visibility(r, s);
        if v <= 0.0 {
            // Four rays are too few to drop a whole group of surfaces: look closer.
            return Estimate::Open;
        }
        let factor = (f.min(1.0) * v) as f32;
        Estimate::Link(Link {
            receiver: r,
            source: s,
            factor,
            spread: factor,
        })
    }

    /// Lambert's unoccluded factor times the ray-cast visibility, for two faces.
    fn face_to_face(&self, r: u32, s: u32) -> Estimate {
        let (nr, ns) = (&self.mesh.nodes[r as usize], &self.mesh.nodes[s as usize]);
        if nr.patch == ns.patch {
            return Estimate::Nothing;
        }
        let normal = |p: u32| self.mesh.patches[p as usize].normal;
        if !facing(&nr.face, normal(nr.patch), &ns.face, normal(ns.patch)) {
            return Estimate::Nothing;
        }
        let ((cr, rr), (cs, rs)) = (self.sphere(r), self.sphere(s));
        let near = cr.distance(cs) < NEAR * (rr + rs);
        let mut receiver = Receiver::default();
        receiver.set(&nr.face, if near { NEAR_QUADRATURE } else { QUADRATURE });
        let mut corners = [DVec3::ZERO; 4];
        let cs = ns.face.corners();
        for (o, c) in corners.iter_mut().zip(cs) {
            *o = c.as_dvec3();
        }
        let polygon = &corners[..cs.len()];
        let (mut f, mut lo, mut hi) = (0.0, f64::INFINITY, 0.0f64);
        for &(x, w) in &receiver.points {
            let point = point_to_polygon(x, receiver.normal, polygon);
            f += w * point;
            lo = lo.min(point);
            hi = hi.max(point);
        }
        if f.is_nan() || f <= 0.0 {
            return Estimate::Nothing;
        }
        let v = self.face_visibility(r, s);
        // Visibility known only from shadow rays: the unoccluded factor bounds what the link
        // may be wrong by, so the oracle refines it as long as that is too much to risk.
        let factor = f.min(1.0) * v;
        let spread = if v < 1.0 { f.min(1.0) } else { hi - lo };
        Estimate::Link(Link {
            receiver: r,
            source: s,
            factor: factor as f32,
            spread: spread as f32,
        })
    }

    /// Whether the segment between two lifted points is free.
    fn arrives(&self, from: Vec3, from_normal: Vec3, to: Vec3, to_normal: Vec3) -> bool {
        let origin = from + from_normal * self.lift;
        let target = to + to_normal * self.lift;
        !self.bvh.occluded(&Ray::new(origin, target - origin), 1.0)
    }

    /// Kernel-weighted fraction of the shadow rays between two faces that arrive, as in
    /// [`crate::formfactor::raycast`]: one ray per quadrant pair and 16 more stratified over both
    /// faces, each weighted by cosθ_r cosθ_s / r² at its ends. Always all 20: letting a
    /// unanimous 4-ray pilot decide (as the matrix solvers do per element pair) biased the
    /// Cornell box 3–8 % low here, where one link stands for a whole subtree of pairs.
    fn face_visibility(&self, r: u32, s: u32) -> f64 {
        let (nr, ns) = (&self.mesh.nodes[r as usize], &self.mesh.nodes[s as usize]);
        let normal = |p: u32| self.mesh.patches[p as usize].normal;
        let (n_r, n_s) = (normal(nr.patch), normal(ns.patch));
        let pair = mix(mix(u64::from(r)) ^ u64::from(s));
        let (mut total, mut visible) = (0.0, 0.0);
        let mut cast = |(u, v): (f32, f32), (su, sv): (f32, f32)| {
            let (from, to) = (nr.face.point(u, v), ns.face.point(su, sv));
            let d = (to - from).as_dvec3();
            let weight = (d.dot(n_r.as_dvec3()).max(0.0) * (-d.dot(n_s.as_dvec3())).max(0.0))
                / d.length_squared().powi(2).max(f64::MIN_POSITIVE);
            let arrives = self.arrives(from, n_r, to, n_s);
            total += weight;
            if arrives {
                visible += weight;
            }
            arrives
        };
        let quadrant =
            |q: u32, ju: f32, jv: f32| (((q & 1) as f32 + ju) * 0.5, ((q >> 1) as f32 + jv) * 0.5);
        let mut arrived = 0;
        for k in 0..PILOT {
            let bits = mix(!pair ^ u64::from(k));
            let from = quadrant(k, jitter(bits, 0), jitter(bits, 1));
            let to = quadrant(3 - k, jitter(bits, 2), jitter(bits, 3));
            arrived += u32::from(cast(from, to));
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
        if total > 0.0 {
            visible / total
        } else {
            f64::from(arrived) / f64::from(PILOT + RAYS)
        }
    }

    /// Fraction of [`PILOT`] rays between points of front-facing member faces that arrive
    /// (1 when no front-facing member face is found on a side).
    fn cluster_visibility(&self, r: u32, s: u32) -> f64 {
        let pair = mix(mix(u64::from(r) ^ 0x5EED) ^ u64::from(s));
        let (cr, cs) = (self.sphere(r).0, self.sphere(s).0);
        let mut cast = 0u32;
        let mut visible = 0u32;
        for k in 0..PILOT {
            let bits = mix(pair ^ u64::from(k));
            let from = self.sample(r, cs, bits);
            let to = self.sample(s, cr, mix(bits));
            if let (Some((p, n)), Some((q, m))) = (from, to) {
                cast += 1;
                visible += u32::from(self.arrives(p, n, q, m));
            }
        }
        if cast == 0 {
            1.0
        } else {
            f64::from(visible) / f64::from(cast)
        }
    }

    /// A point (with its normal) on handle `h` whose face looks toward `toward`: on the face
    /// itself, or on one of a few member faces of a cluster drawn by `bits`.
    fn sample(&self, h: u32, toward: Vec3, bits: u64) -> Option<(Vec3, Vec3)> {
        let (u, v) = (jitter(bits, 0), jitter(bits, 1));
        let on = |node: u32| {
            let node = &self.mesh.nodes[node as usize];
            let n = self.mesh.patches[node.patch as usize].normal;
            let p = node.face.point(u, v);
            (n.dot(toward - p) > 0.0).then_some((p, n))
        };
        if h & CLUSTER == 0 {
            return on(h);
        }
        let c = &self.clusters.nodes[(h & !CLUSTER) as usize];
        let faces = &self.clusters.faces[c.faces.start as usize..c.faces.end as usize];
        (0..8u64).find_map(|t| {
            let pick = mix(bits ^ (t << 48)) % faces.len() as u64;
            on(faces[pick as usize])
        })
    }
}

/// Sixteen bits of `bits` as a jitter in (0, 1).
fn jitter(bits: u64, i: u32) -> f32 {
    (((bits >> (16 * i)) & 0xFFFF) as f32 + 0.5) / 65536.0
}

/// SplitMix64's finaliser (Steele, Lea & Flood 2014).
fn mix(z: u64) -> u64 {
    let z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    let z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
