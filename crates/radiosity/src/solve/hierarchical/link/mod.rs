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
//!   a link found wholly hidden carries nothing but stays, to be judged again in later passes.
//!   The spread of the point values over the quadrature points tells how much F varies over
//!   the receiver (large next to a shared edge), which the oracle also bounds.
//!   Faces of one patch (coplanar) and faces behind each other get no link.
//! - **Cluster involved**: the point-to-point kernel F ≈ A_s c_r c_s / (π d²) between the
//!   bounding-sphere centres d apart, with c = max(0, n·ω) for a face and c = P(ω)/A for a
//!   cluster (its projected area over its area, tabulated: [`super::projected`]; Smits, Arvo &
//!   Greenberg 1994 took it isotropic). The estimate is only trusted when the spheres are
//!   disjoint and no face's plane cuts the other side's sphere; otherwise the oracle must open
//!   the cluster ([`Estimate::Open`]). V is sampled with 16 rays ([`visibility`]) between
//!   front-facing member faces.
//!
//! The error of the cluster model is bounded by the oracle: a cluster link survives only if
//! B_s·F·A_r ≤ [`super::refine::VARIATION`]·ε·Φ (its spread is taken as F itself), and the
//! model's projected area is off by at most a factor ~4 (self-shadowing),
//! so each surviving cluster link misplaces at most ~ε/2 of the emitted power.
//!
//! Rays are jittered by a hash of (receiver, source, ray): node ids never change once made, so
//! a link's value does not depend on the thread count or the order of work.

mod unresolved;
mod visibility;

use glam::{DVec3, Vec3};

use super::cluster::{face_plane, same_plane, Clusters};
use crate::accel::Bvh;
use crate::formfactor::analytic::{point_to_polygon, solid_angle};
use crate::formfactor::{facing, Receiver, FAR_FIELD};
use crate::mesh::{Mesh, Node};

pub use super::handle::{End, Handle};

/// Side of the receiver quadrature grid of face-to-face links in the far field.
const QUADRATURE: u32 = 2;

/// Side of the grid in the near field ([`NEAR`]), where the factor varies fast over the
/// receiver (logarithmically at a shared edge) and the midpoint rule on 2 × 2 points
/// underestimates it: by 3 % on the Cornell box's floor after interreflection.
const NEAR_QUADRATURE: u32 = 4;

/// A pair is in the near field when the distance between the centres of the bounding spheres is
/// below this multiple of the sum of their radii.
const NEAR: f32 = 2.0;

/// What is known of the visibility between two faces before their shadow rays are cast.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sight {
    /// Nothing: their rays decide.
    Unknown,
    /// They are parts of faces found wholly visible to each other: 4 rays that all arrive
    /// settle it.
    Clear,
}

/// A link: 16 bytes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Link {
    /// Receiving handle.
    pub receiver: Handle,
    /// Source handle.
    pub source: Handle,
    /// Form factor times visibility, F_rs·V_rs.
    pub factor: f32,
    /// [`Link::spread`] in its magnitude and [`Link::sight`] in its sign bit (negative when
    /// clear), so that a link stays 16 bytes.
    bound: f32,
}

impl Link {
    /// A link; `spread` must be ≥ 0.
    #[must_use]
    pub fn new(receiver: Handle, source: Handle, factor: f32, spread: f32, sight: Sight) -> Self {
        let bound = match sight {
            Sight::Clear => -spread.abs(),
            Sight::Unknown => spread.abs(),
        };
        Self {
            receiver,
            source,
            factor,
            bound,
        }
    }

    /// How much the factor may be off over the receiver: the spread (max − min) of the
    /// point-to-polygon factors at the quadrature points; the unoccluded factor when shadow
    /// rays found the pair partly or wholly hidden; for a cluster link, the larger of the
    /// factor itself and the range the kernel can take over the two bounding spheres.
    #[must_use]
    pub fn spread(&self) -> f32 {
        self.bound.abs()
    }

    /// The link's exact bits: receiver, source, factor and bound (for checkpoints).
    #[must_use]
    pub fn to_bits(&self) -> [u32; 4] {
        [
            self.receiver.to_bits(),
            self.source.to_bits(),
            self.factor.to_bits(),
            self.bound.to_bits(),
        ]
    }

    /// The link of [`Link::to_bits`].
    #[must_use]
    pub fn from_bits(bits: [u32; 4]) -> Self {
        Self {
            receiver: Handle::from_bits(bits[0]),
            source: Handle::from_bits(bits[1]),
            factor: f32::from_bits(bits[2]),
            bound: f32::from_bits(bits[3]),
        }
    }

    /// Whether two faces were found wholly visible to each other (every shadow ray arrived):
    /// then so are all pairs of their parts, and the links that refine this one take V = 1
    /// once their 4 quadrant rays confirm it, without the other 16 (after Hanrahan, Salzman
    /// & Aupperle 1991, §5, who let children inherit a parent's full visibility outright).
    #[must_use]
    pub fn sight(&self) -> Sight {
        if self.bound.is_sign_negative() {
            Sight::Clear
        } else {
            Sight::Unknown
        }
    }
}

/// The runs of `links` (sorted by receiver) that share a receiver, in order.
#[must_use]
pub fn receiver_groups(links: &[Link]) -> Vec<std::ops::Range<usize>> {
    let mut groups = Vec::new();
    let mut start = 0;
    for i in 1..=links.len() {
        if i == links.len() || links[i].receiver != links[start].receiver {
            groups.push(start..i);
            start = i;
        }
    }
    groups
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

/// Bounding sphere (centre, radius) of a handle.
fn sphere(mesh: &Mesh, clusters: &Clusters, h: Handle) -> (Vec3, f32) {
    match h.end() {
        End::Cluster(c) => {
            let c = &clusters.nodes[c];
            (c.center, c.radius)
        }
        End::Node(n) => mesh.nodes[n].sphere(),
    }
}

/// Whether the pair (r, s) is *resolved*: two faces always; with a cluster at one end or both,
/// when the cluster kernel can be trusted for it, which needs bounding spheres that lie apart
/// (and are not NaN) and no face whose plane cuts the other side's sphere (such a face sees
/// it partly from behind: a wall next to the cluster of its neighbours, say). An unresolved
/// pair's link carries a factor estimated by rays ([`View::unresolved_factor`]): its elements
/// take no factors of their own from it ([`super::leaf_rows`]), and it is gathered with no
/// direction ([`super::push_pull`]).
#[must_use]
pub fn resolved(mesh: &Mesh, clusters: &Clusters, r: Handle, s: Handle) -> bool {
    if !r.is_cluster() && !s.is_cluster() {
        return true;
    }
    let ((cr, rr), (cs, rs)) = (sphere(mesh, clusters, r), sphere(mesh, clusters, s));
    let distance = (cs - cr).length();
    if distance.is_nan() || distance <= rr + rs {
        return false;
    }
    let cuts = |h: Handle, other: Vec3, radius: f32| {
        h.as_node().is_some_and(|n| {
            let node = &mesh.nodes[n];
            let n = mesh.patches[node.patch as usize].normal;
            n.dot(other - node.face.corners()[0]).abs() <= radius
        })
    };
    !(cuts(r, cs, rs) || cuts(s, cr, rr))
}

/// Two disjoint bounding spheres: every segment between them lies within the angle `alpha`
/// of the centres' line `w` and is between `near` and `far` long.
#[derive(Clone, Copy, Debug)]
struct Separation {
    cr: Vec3,
    cs: Vec3,
    w: DVec3,
    alpha: f64,
    near: f64,
    far: f64,
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
        Self {
            mesh,
            clusters,
            bvh,
            lift: bvh.lift(),
        }
    }

    /// Surface area of a handle.
    #[must_use]
    pub fn area(&self, h: Handle) -> f64 {
        match h.end() {
            End::Cluster(c) => self.clusters.nodes[c].area,
            End::Node(n) => self.mesh.nodes[n].area(),
        }
    }

    /// Whether a handle reflects any of the light it receives: a face whose patch has ρ > 0
    /// on some channel, a cluster holding such a face. What a handle that does not receives
    /// changes no radiosity ([`super::refine`] never refines links to it).
    #[must_use]
    pub fn reflects(&self, h: Handle) -> bool {
        match h.end() {
            End::Cluster(c) => self.clusters.reflects(c),
            End::Node(n) => {
                let patch = &self.mesh.patches[self.mesh.nodes[n].patch as usize];
                patch.reflectance.max_element() > 0.0
            }
        }
    }

    /// Whether a handle is wholly part of a distant environment, whose light the elements
    /// gather along rays ([`super::distant`]) instead of links.
    #[must_use]
    pub fn distant(&self, h: Handle) -> bool {
        match h.end() {
            End::Cluster(c) => self.clusters.distant(c),
            End::Node(n) => self.mesh.patches[self.mesh.nodes[n].patch as usize].distant,
        }
    }

    /// The quadtree node of a handle, `None` for a cluster.
    fn node(&self, h: Handle) -> Option<&Node> {
        h.as_node().map(|n| &self.mesh.nodes[n])
    }

    /// Bounding sphere (centre, radius) of a handle.
    #[must_use]
    pub fn sphere(&self, h: Handle) -> (Vec3, f32) {
        sphere(self.mesh, self.clusters, h)
    }

    /// Appends the children of a handle to `out`: two clusters, the faces of a leaf cluster,
    /// the four children of a split face, or nothing for an element.
    pub fn children(&self, h: Handle, out: &mut Vec<Handle>) {
        match h.end() {
            End::Cluster(c) => {
                let c = &self.clusters.nodes[c];
                match c.children {
                    Some([a, b]) => out.extend([Handle::cluster(a), Handle::cluster(b)]),
                    None => out.extend(
                        self.clusters.faces[c.faces.start as usize..c.faces.end as usize]
                            .iter()
                            .map(|&f| Handle::node(f)),
                    ),
                }
            }
            End::Node(n) => {
                if let Some(c) = self.mesh.nodes[n].children {
                    out.extend((c..c + 4).map(Handle::node));
                }
            }
        }
    }

    /// The form factor and visibility of receiver `r` from source `s` (see the module
    /// documentation). `sight` is what is known of their visibility (see [`Sight`]).
    #[must_use]
    pub fn estimate(&self, r: Handle, s: Handle, sight: Sight) -> Estimate {
        if !r.is_cluster() && !s.is_cluster() {
            return self.face_to_face(r, s, sight);
        }
        if self.coplanar(r, s) {
            return Estimate::Nothing;
        }
        let Some(Separation {
            cr,
            cs,
            w,
            alpha,
            near,
            far,
        }) = self.trusted(r, s)
        else {
            return Estimate::Open;
        };
        let (lo_r, c_r, hi_r) = self.cosines(r, w, alpha);
        let (lo_s, c_s, hi_s) = self.cosines(s, -w, alpha);
        let kernel = self.area(s) / std::f64::consts::PI;
        let f = self.cluster_kernel(r, s, (cr, cs), c_r, c_s);
        let most = self.largest_kernel(s, hi_r, hi_s, near).min(1.0);
        let least = kernel * lo_r * lo_s / (far * far);
        if most.is_nan() || most <= 0.0 {
            return Estimate::Nothing;
        }
        let v = self.cluster_visibility(r, s, 0);
        if v <= 0.0 {
            // Blocked rays are too few to drop a whole group of surfaces: the link is
            // kept with no light and the unoccluded bound as its spread, so the oracle looks
            // closer while what it could carry matters, and keeps it (without light) once it
            // does not.
            return Estimate::Link(Link::new(r, s, 0.0, most as f32, Sight::Unknown));
        }
        let factor = (f * v) as f32;
        // The cluster model's own error (self-shadowing, uniform push) is not bounded by the
        // kernel's range: the factor itself is the least the link may be off by.
        let spread = (most - least).max(f).max(if v < 1.0 { most } else { 0.0 }) as f32;
        Estimate::Link(Link::new(r, s, factor, spread, Sight::Unknown))
    }

    /// The unoccluded factor of a link with a cluster at one end or both, c_r, c_s the two
    /// ends' cosine factors toward each other and `centres` their spheres' centres: the point
    /// kernel A_s c_r c_s / (π d²) between the centres, except that between a cluster and a
    /// face the face's solid angle from the cluster's centre replaces A·cosθ/d² (exact over
    /// the face, where the point kernel is off by the face's size over the distance squared:
    /// 8 % for a 1 m light node 3.6 m away). At most 1.
    fn cluster_kernel(
        &self,
        r: Handle,
        s: Handle,
        centres: (Vec3, Vec3),
        c_r: f64,
        c_s: f64,
    ) -> f64 {
        let (cr, cs) = centres;
        let face = |n: usize| self.mesh.nodes[n].face.corners_f64();
        let pi = std::f64::consts::PI;
        if let Some(s) = s.as_node() {
            let (polygon, n) = face(s);
            c_r * solid_angle(cr.as_dvec3(), &polygon[..n]) / pi
        } else if let Some(r_node) = r.as_node() {
            let (polygon, n) = face(r_node);
            c_s * self.area(s) * solid_angle(cs.as_dvec3(), &polygon[..n]) / (pi * self.area(r))
        } else {
            self.area(s) * c_r * c_s / (pi * f64::from(cr.distance(cs)).powi(2))
        }
        .min(1.0)
    }

    /// The unoccluded form factor F_rs that [`View::estimate`] finds for the pair before its
    /// shadow rays (0 where it would make no link): Lambert's contour integral over the
    /// receiver's quadrature points between two faces, [`View::cluster_kernel`] otherwise.
    /// A link's visibility is its factor over this; [`super::leaf_rows`] asks it of the link's
    /// source and each element below the link's receiver.
    #[must_use]
    pub fn unoccluded(&self, r: Handle, s: Handle) -> f64 {
        self.factor(r, s, false)
    }

    /// [`View::unoccluded`] for an element gathering through a link above it: the same, but
    /// with the receiver's centroid alone where the source is farther than
    /// [`FAR_FIELD`] diameters of it (as the matrix solvers' form factors do; most of an
    /// element's row lies there).
    #[must_use]
    pub fn element_factor(&self, e: Handle, s: Handle) -> f64 {
        self.factor(e, s, true)
    }

    /// [`View::unoccluded`], with the far-field rule when `far` is set.
    fn factor(&self, r: Handle, s: Handle, far: bool) -> f64 {
        if let (Some(nr), Some(ns)) = (self.node(r), self.node(s)) {
            let normal = |p: u32| self.mesh.patches[p as usize].normal;
            if nr.patch == ns.patch
                || !facing(&nr.face, normal(nr.patch), &ns.face, normal(ns.patch))
            {
                return 0.0;
            }
            let f = self.lambert(r, s, far).0;
            return if f > 0.0 { f.min(1.0) } else { 0.0 };
        }
        let ((cr, _), (cs, _)) = (self.sphere(r), self.sphere(s));
        let distance = cr.distance(cs);
        if distance.is_nan() || distance <= 0.0 {
            return 0.0;
        }
        let w = ((cs - cr) / distance).as_dvec3();
        let c_r = self.cosines(r, w, 0.0).1;
        let c_s = self.cosines(s, -w, 0.0).1;
        let f = self.cluster_kernel(r, s, (cr, cs), c_r, c_s);
        if f > 0.0 {
            f
        } else {
            0.0
        }
    }

    /// Lambert's contour integral from the receiver face `r` to the source face `s` at the
    /// receiver's quadrature points (2 × 2, or 4 × 4 in the near field; with `far`, its
    /// centroid alone beyond [`FAR_FIELD`] of its diameters): the weighted mean, and the least
    /// and largest point value.
    fn lambert(&self, r: Handle, s: Handle, far: bool) -> (f64, f64, f64) {
        let (Some(nr), Some(ns)) = (self.node(r), self.node(s)) else {
            return (0.0, 0.0, 0.0);
        };
        let ((cr, _), (cs, rs)) = (self.sphere(r), self.sphere(s));
        let (corners, sides) = ns.face.corners_f64();
        let polygon = &corners[..sides];
        if far && f64::from(cr.distance(cs) - rs) > FAR_FIELD * f64::from(nr.diameter()) {
            let (centroid, normal) = (nr.centroid(), nr.normal());
            let f = point_to_polygon(centroid.as_dvec3(), normal.as_dvec3(), polygon);
            return (f, f, f);
        }
        let grid = if self.near(r, s) {
            NEAR_QUADRATURE
        } else {
            QUADRATURE
        };
        let mut receiver = Receiver::default();
        receiver.set(&nr.face, grid);
        let (mut f, mut lo, mut hi) = (0.0, f64::INFINITY, 0.0f64);
        for &(x, w) in &receiver.points {
            let point = point_to_polygon(x, receiver.normal, polygon);
            f += w * point;
            lo = lo.min(point);
            hi = hi.max(point);
        }
        (f, lo, hi)
    }

    /// Whether two handles are in each other's near field: their bounding spheres' centres
    /// closer than [`NEAR`] times the sum of their radii.
    #[must_use]
    fn near(&self, r: Handle, s: Handle) -> bool {
        let ((cr, rr), (cs, rs)) = (self.sphere(r), self.sphere(s));
        cr.distance(cs) < NEAR * (rr + rs)
    }

    /// Whether every face of `r` and of `s` lies in one plane (either way round), so that no
    /// two of them see each other: a tessellated wall with itself or with its neighbouring
    /// pieces. Their bounding spheres overlap, so without this the refinement would open
    /// them down to pairs of faces only to find each pair empty (the staircase's walls and
    /// steps made tens of millions of such pairs in the second pass).
    #[must_use]
    pub fn coplanar(&self, r: Handle, s: Handle) -> bool {
        let plane = |h: Handle| match h.end() {
            End::Cluster(c) => self.clusters.nodes[c].plane,
            End::Node(n) => Some(face_plane(self.mesh, n as u32)),
        };
        match (plane(r), plane(s)) {
            (Some(a), Some(b)) => same_plane(a, b, 1e-5 * (self.sphere(r).1 + self.sphere(s).1)),
            _ => false,
        }
    }

    /// An upper bound on the unoccluded factor F_rs: A_s·max c_r·max c_s / (π·(d − ρ_r − ρ_s)²)
    /// from the two bounding spheres, and never more than min(1, A_s/A_r) (reciprocity: the
    /// most it can be when the spheres overlap).
    fn bound(&self, r: Handle, s: Handle) -> f64 {
        let most = (self.area(s) / self.area(r)).min(1.0);
        let Some(sep) = self.separation(r, s) else {
            return most;
        };
        let (_, _, hi_r) = self.cosines(r, sep.w, sep.alpha);
        let (_, _, hi_s) = self.cosines(s, -sep.w, sep.alpha);
        self.largest_kernel(s, hi_r, hi_s, sep.near).min(most)
    }

    /// The separation of a pair with a cluster at one end or both when the cluster kernel can
    /// be trusted for it ([`resolved`]), `None` when [`View::estimate`] must open a cluster
    /// instead.
    fn trusted(&self, r: Handle, s: Handle) -> Option<Separation> {
        resolved(self.mesh, self.clusters, r, s)
            .then(|| self.separation(r, s))
            .flatten()
    }

    /// Whether [`View::estimate`] can estimate the pair without opening a cluster
    /// ([`resolved`]).
    #[must_use]
    pub fn resolves(&self, r: Handle, s: Handle) -> bool {
        resolved(self.mesh, self.clusters, r, s)
    }

    /// How two handles' bounding spheres lie to each other, or `None` when they overlap (or
    /// the geometry is NaN).
    fn separation(&self, r: Handle, s: Handle) -> Option<Separation> {
        let ((cr, rr), (cs, rs)) = (self.sphere(r), self.sphere(s));
        let distance = (cs - cr).length();
        if distance.is_nan() || distance <= rr + rs {
            return None;
        }
        Some(Separation {
            cr,
            cs,
            w: ((cs - cr) / distance).as_dvec3(),
            alpha: f64::from((rr + rs) / distance).min(1.0).asin(),
            near: f64::from(distance - rr - rs),
            far: f64::from(distance + rr + rs),
        })
    }

    /// The point kernel A_s·c_r·c_s / (π d²) at the largest cosines and the nearest distance.
    fn largest_kernel(&self, s: Handle, hi_r: f64, hi_s: f64, near: f64) -> f64 {
        self.area(s) / std::f64::consts::PI * hi_r * hi_s / (near * near)
    }

    /// The cosine factor of handle `h` toward the unit direction `w`, with its least and
    /// largest value over directions within the angle `alpha` of `w`: c = max(0, n·ω) for a
    /// face, c = P(ω)/A for a cluster ([`Clusters::projected_area`]).
    fn cosines(&self, h: Handle, w: DVec3, alpha: f64) -> (f64, f64, f64) {
        match h.end() {
            End::Cluster(c) => {
                let cluster = &self.clusters.nodes[c];
                if cluster.area <= 0.0 {
                    return (0.0, 0.0, 0.0);
                }
                // P(ω) = ½ V·ω + ½ Σ A_f |n_f·ω| moves by at most (|V| + A)·α/2 when ω turns
                // by α.
                let turn = 0.5 * (cluster.vector_area.length() + cluster.area) * alpha;
                let p = self.clusters.projected_area(c, w);
                let share = |x: f64| (x / cluster.area).clamp(0.0, 1.0);
                (share(p - turn), share(p), share(p + turn))
            }
            End::Node(n) => {
                let node = &self.mesh.nodes[n];
                let n = self.mesh.patches[node.patch as usize].normal.as_dvec3();
                let theta = n.dot(w).clamp(-1.0, 1.0).acos();
                let cos = |t: f64| t.clamp(0.0, std::f64::consts::PI).cos().max(0.0);
                (cos(theta + alpha), cos(theta), cos(theta - alpha))
            }
        }
    }

    /// Lambert's unoccluded factor times the ray-cast visibility (4 rays suffice when the
    /// `sight` is clear and they all arrive), for two faces.
    fn face_to_face(&self, r: Handle, s: Handle, sight: Sight) -> Estimate {
        let (Some(nr), Some(ns)) = (self.node(r), self.node(s)) else {
            return Estimate::Open;
        };
        if nr.patch == ns.patch {
            return Estimate::Nothing;
        }
        let normal = |p: u32| self.mesh.patches[p as usize].normal;
        if !facing(&nr.face, normal(nr.patch), &ns.face, normal(ns.patch)) {
            return Estimate::Nothing;
        }
        let ((cr, rr), (cs, rs)) = (self.sphere(r), self.sphere(s));
        let overlap = cr.distance(cs) <= rr + rs
            && !touching(&nr.face, &ns.face, normal(nr.patch), normal(ns.patch));
        let (f, lo, hi) = self.lambert(r, s, false);
        if f.is_nan() {
            return Estimate::Nothing;
        }
        if f <= 0.0 {
            // The quadrature points see nothing of the source, yet parts of the two faces
            // face each other (a large floor node under a small tilted face, say): a link
            // without light whose spread is what it could carry, so the oracle looks closer.
            let bound = self.bound(r, s) as f32;
            return Estimate::Link(Link::new(r, s, 0.0, bound, Sight::Unknown));
        }
        let v = self.face_visibility(r, s, sight, true, 0);
        // Visibility known only from shadow rays: the unoccluded factor bounds what the link
        // may be wrong by, so the oracle refines it as long as that is too much to risk.
        let factor = f.min(1.0) * v;
        let spread = if v < 1.0 { f.min(1.0) } else { hi - lo };
        // Overlapping bounding spheres of faces that do not touch (a small face just above a
        // large one): the kernel may peak between the quadrature points, so the spread is
        // all the factor could be beyond f. (Faces meeting along an edge have a log-singular
        // kernel that the near-field quadrature integrates well: 0.2 % on Howell C-14.)
        let spread = if overlap {
            spread.max(self.bound(r, s) - f)
        } else {
            spread
        };
        let sight = if v >= 1.0 {
            Sight::Clear
        } else {
            Sight::Unknown
        };
        Estimate::Link(Link::new(r, s, factor as f32, spread as f32, sight))
    }
}

/// Whether two faces meet: a corner of each lies in the other's plane (to 10⁻⁴ of its size).
fn touching(a: &crate::mesh::Face, b: &crate::mesh::Face, na: Vec3, nb: Vec3) -> bool {
    let on = |of: &crate::mesh::Face, n: Vec3, other: &crate::mesh::Face| {
        let p = of.corners()[0];
        let tolerance = 1e-4 * p.distance(of.corners()[2]);
        other
            .corners()
            .iter()
            .any(|&q| n.dot(q - p).abs() <= tolerance)
    };
    on(a, na, b) && on(b, nb, a)
}
