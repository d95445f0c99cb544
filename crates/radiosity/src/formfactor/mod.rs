//! Form factors: how much of the light leaving one surface lands on another.
//!
//! The form factor from a receiving element i to a source j is
//!
//! ```text
//! F_ij = (1/A_i) ∫_{A_i} ∫_{A_j} cosθ_i cosθ_j V(x, y) / (π r²) dA_j dA_i ,
//! ```
//!
//! with reciprocity A_i F_ij = A_j F_ji and, in a closed scene, Σ_j F_ij = 1. The analytic and
//! ray-cast methods evaluate the inner integral *exactly* for the unoccluded case with Lambert's contour
//! integral ([`analytic::point_to_polygon`]), at an n × n grid of quadrature points on the
//! receiver (midpoint rule, weighted by area), so they share the same kernel:
//!
//! - [`Method::Analytic`]: no visibility at all. Exact (up to the receiver quadrature) for
//!   convex enclosures such as the furnace cube, where nothing can block anything; wrong
//!   wherever something casts a shadow.
//! - [`Method::RayCast`]: the unoccluded value times the fraction of shadow rays between
//!   stratified points on the receiver and on the source that reach their target through the
//!   BVH (Wallace, Elmquist & Haines 1989 sample visibility by rays; multiplying the visible
//!   fraction by the exact unoccluded factor is the estimator of Hanrahan, Salzman & Aupperle
//!   1991). The jitter of every ray comes from a hash of (element, source, ray, seed), so the
//!   result depends on neither the thread count nor the order of the calls.
//! - [`Method::Hemicube`] ([`hemicube`]): Cohen & Greenberg's (1985) hemicube, a z-buffer over
//!   five faces around each quadrature point; near sources take Lambert's exact factor times
//!   their visible share of cells (`docs/hemicube.md`).
//!
//! Pairs on the same patch (coplanar: cosθ = 0) and pairs that face away from each other get 0
//! without any work.
//!
//! Each method owns its settings; the defaults were measured on the Cornell box (see
//! [`raycast::Settings::default`]).

pub mod analytic;
pub(crate) mod exposure;
pub mod hemicube;
pub mod raycast;
pub(crate) mod visibility;

use glam::{DVec3, Vec3};

use crate::accel::Bvh;
use crate::mesh::{Face, Mesh, NEAR_REFINEMENT};
use crate::registry::registry;

/// What a form-factor method needs to see: the mesh, its visibility structure, and the sources.
#[derive(Clone, Copy, Debug)]
pub struct Geometry<'a> {
    /// Patches and element quadtrees; receivers are the elements.
    pub mesh: &'a Mesh,
    /// Hierarchy over `mesh.triangles`, for visibility.
    pub bvh: &'a Bvh,
    /// Node ids (into `mesh.nodes`) of the sources: a cut through the quadtrees
    /// (see [`Mesh::sources`]).
    pub sources: &'a [u32],
}

impl<'a> Geometry<'a> {
    /// Bundles the three.
    #[must_use]
    pub fn new(mesh: &'a Mesh, bvh: &'a Bvh, sources: &'a [u32]) -> Self {
        Self { mesh, bvh, sources }
    }

    /// The face of source `s` (an index into `sources`).
    #[must_use]
    pub fn source_face(&self, s: usize) -> &'a Face {
        &self.mesh.nodes[self.sources[s] as usize].face
    }

    /// The patch of source `s`.
    #[must_use]
    pub fn source_patch(&self, s: usize) -> u32 {
        self.mesh.nodes[self.sources[s] as usize].patch
    }

    /// How far rays start and end off their surfaces, along the normals ([`Bvh::lift`]).
    #[must_use]
    pub fn lift(&self) -> f32 {
        self.bvh.lift()
    }
}

/// A way of computing form factors between elements (receivers) and sources.
///
/// Both calls must give bit-identical values for the same pair, whatever the thread count.
pub trait FormFactors: Sync {
    /// F from element `element` to every source, for gathering: `out[s] = F_{element→s}`.
    /// `out.len()` is the number of sources.
    fn row(&self, g: &Geometry, element: usize, out: &mut [f32]);

    /// F from every element to source `source`, for shooting: `out[e] = F_{e→source}`.
    /// `out.len()` is the number of elements.
    fn column(&self, g: &Geometry, source: usize, out: &mut [f32]);

    /// Whether a row sees only the sources it is given: then nothing else hides them, and a
    /// row over a few sources must be computed among all the others to be occluded. False for
    /// the methods that trace rays through the whole scene; true for the hemicube, whose
    /// z-buffer draws only its candidates.
    fn occluded_only_by_sources(&self) -> bool {
        false
    }

    /// Whether a row's factors tile the receiver's hemisphere, so that its sum is what the
    /// receiver sees of the scene to rounding and its errors are in how the hemisphere is
    /// shared out: then the gathering solvers balance the columns to the rows
    /// ([`crate::solve`]'s column balance). True for the hemicube; false for ray casting, whose
    /// rows are estimates like its columns.
    fn rows_tile_the_hemisphere(&self) -> bool {
        false
    }
}

registry! {
    /// The form-factor methods: the registry of the family. Adding one is a file with its
    /// [`FormFactors`] and its `Settings`, and a line here, whose doc comment is its help on the
    /// command line; the compiler then asks for its arms in [`Settings`] below.
    #[derive(Default)]
    pub enum Method {
        /// Lambert's closed form, without visibility (convex enclosures only).
        Analytic = "analytic",
        /// Lambert's closed form times a ray-cast visibility fraction.
        #[default]
        RayCast = "raycast",
        /// Item-buffer hemicubes (Cohen & Greenberg 1985).
        Hemicube = "hemicube",
    }
    /// An unknown method name.
    pub struct UnknownMethod = "unknown form-factor method";
}

/// A form-factor method with its own settings: one variant per [`Method`], with its arms in
/// [`Settings::of`], [`Settings::method`], [`Settings::options`] and [`build`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Settings {
    /// Lambert's contour integral, no visibility.
    Analytic(analytic::Settings),
    /// Lambert's contour integral times ray-cast visibility.
    RayCast(raycast::Settings),
    /// Item-buffer hemicubes.
    Hemicube(hemicube::Settings),
}

impl Default for Settings {
    /// Ray casting with its defaults ([`raycast::Settings::default`], where the measurement is).
    fn default() -> Self {
        Self::of(Method::RayCast)
    }
}

impl Settings {
    /// `method` with its default settings.
    #[must_use]
    pub fn of(method: Method) -> Self {
        match method {
            Method::Analytic => Self::Analytic(analytic::Settings::default()),
            Method::RayCast => Self::RayCast(raycast::Settings::default()),
            Method::Hemicube => Self::Hemicube(hemicube::Settings::default()),
        }
    }

    /// The method these settings are for.
    #[must_use]
    pub fn method(&self) -> Method {
        match self {
            Self::Analytic(_) => Method::Analytic,
            Self::RayCast(_) => Method::RayCast,
            Self::Hemicube(_) => Method::Hemicube,
        }
    }

    /// The options these settings have, to be set by name.
    pub fn options(&mut self) -> Options<'_> {
        match self {
            Self::Analytic(s) => Options {
                quadrature: Some(&mut s.quadrature),
                ..Options::default()
            },
            Self::RayCast(s) => Options {
                quadrature: Some(&mut s.quadrature),
                rays: Some(&mut s.rays),
                seed: Some(&mut s.seed),
                resolution: None,
            },
            Self::Hemicube(s) => Options {
                quadrature: Some(&mut s.quadrature),
                rays: None,
                seed: Some(&mut s.seed),
                resolution: Some(&mut s.resolution),
            },
        }
    }
}

/// The options of a method's [`Settings`], each `None` where the method has no such option: a
/// front end sets the ones it is given and refuses those the method has no use for.
#[derive(Debug, Default)]
pub struct Options<'a> {
    /// Quadrature points per receiver, as an n × n grid.
    pub quadrature: Option<&'a mut u32>,
    /// Shadow rays per element–source pair.
    pub rays: Option<&'a mut u32>,
    /// Seed of the jitter and of the rotations.
    pub seed: Option<&'a mut u64>,
    /// Cells along a full edge of a hemicube.
    pub resolution: Option<&'a mut u32>,
}

/// The form-factor computer that `settings` describe.
#[must_use]
pub fn build(settings: &Settings) -> Box<dyn FormFactors> {
    match *settings {
        Settings::Analytic(s) => Box::new(analytic::Analytic::new(s.quadrature)),
        Settings::RayCast(s) => Box::new(raycast::RayCast::new(s.quadrature, s.rays, s.seed)),
        Settings::Hemicube(s) => {
            Box::new(hemicube::Hemicube::new(s.resolution, s.quadrature, s.seed))
        }
    }
}

/// Quadrature points and weights (summing to 1) of a receiver, with its unit normal.
#[derive(Clone, Debug, Default)]
pub(crate) struct Receiver {
    /// Points with their weights.
    pub points: Vec<(DVec3, f64)>,
    /// Unit normal.
    pub normal: DVec3,
    /// The face's centroid (the far field's one point, [`FAR_FIELD`]).
    pub centroid: DVec3,
    /// The face's diameter.
    pub diameter: f64,
}

impl Receiver {
    /// Fills the midpoint rule of an n × n grid on `face`: for a quadrilateral the cell centres
    /// of the bilinear map weighted by its Jacobian (exact cell areas for a planar quad), for a
    /// triangle the centroids of its n² congruent sub-triangles.
    pub fn set(&mut self, face: &Face, n: u32) {
        self.set_jittered(face, n, None);
    }

    /// [`Receiver::set`] with each point drawn in its cell (its sub-triangle for a triangle)
    /// from the hash of `seed` and the cell, weighted by the area it stands for: a stratified
    /// rule, unbiased for any integrand, where the midpoint rule misses what only a thin strip
    /// of the face sees (light leaving a wall through a slit a millimetre wide, seen from the
    /// wall's first millimetres only). `None`: the cell centres.
    pub fn set_jittered(&mut self, face: &Face, n: u32, seed: Option<u64>) {
        let n = n.max(1);
        let jitter = |cell: u32, axis: u64| match seed {
            Some(seed) => crate::hash::unit_f64(crate::hash::mix(
                seed ^ crate::hash::mix(u64::from(cell) * 2 + axis),
            )),
            None => 0.5,
        };
        self.points.clear();
        self.normal = face.normal().as_dvec3();
        self.centroid = face.centroid().as_dvec3();
        self.diameter = f64::from(face.diameter());
        let h = 1.0 / f64::from(n);
        let corner = |k: usize| face.corners()[k].as_dvec3();
        if face.is_quad() {
            let (a, b, cc, d) = (corner(0), corner(1), corner(2), corner(3));
            for j in 0..n {
                for i in 0..n {
                    let cell = j * n + i;
                    let (u, v) = (
                        (f64::from(i) + jitter(cell, 0)) * h,
                        (f64::from(j) + jitter(cell, 1)) * h,
                    );
                    let bottom = a.lerp(b, u);
                    let top = d.lerp(cc, u);
                    let du = (b - a).lerp(cc - d, v);
                    let dv = top - bottom;
                    self.points
                        .push((bottom.lerp(top, v), du.cross(dv).length()));
                }
            }
        } else {
            let a = corner(0);
            let (e1, e2) = (corner(1) - a, corner(2) - a);
            let at = |u: f64, v: f64| a + e1 * (u * h) + e2 * (v * h);
            // A point of the unit triangle: its centroid, or one drawn uniformly (the square
            // folded onto the triangle).
            let inside = |cell: u32| match seed {
                Some(_) => {
                    let (x, y) = (jitter(cell, 0), jitter(cell, 1));
                    if x + y > 1.0 {
                        (1.0 - x, 1.0 - y)
                    } else {
                        (x, y)
                    }
                }
                None => (1.0 / 3.0, 1.0 / 3.0),
            };
            let mut cell = 0;
            for i in 0..n {
                for j in 0..n - i {
                    let (fi, fj) = (f64::from(i), f64::from(j));
                    let (x, y) = inside(cell);
                    self.points.push((at(fi + x, fj + y), 1.0));
                    cell += 1;
                    if i + j + 1 < n {
                        // The inverted sub-triangle, from its right-angle corner.
                        let (x, y) = inside(cell);
                        self.points.push((at(fi + 1.0 - x, fj + 1.0 - y), 1.0));
                        cell += 1;
                    }
                }
            }
        }
        let total: f64 = self.points.iter().map(|p| p.1).sum();
        if total > 0.0 {
            for p in &mut self.points {
                p.1 /= total;
            }
        }
    }
}

/// Whether two faces can exchange light at all: some corner of each lies strictly in front of
/// the other's plane (the plane through its first corner with its patch's normal `n`). Coplanar
/// faces, and faces back to back, cannot.
pub(crate) fn facing(receiver: &Face, n_receiver: Vec3, source: &Face, n_source: Vec3) -> bool {
    let in_front = |of: &Face, n: Vec3, points: &[Vec3]| {
        let p = of.corners()[0];
        // A tolerance relative to the face's size (its first diagonal).
        let scale = p.distance(of.corners()[2]).max(f32::MIN_POSITIVE);
        points.iter().any(|&q| n.dot(q - p) > 1e-6 * scale)
    };
    in_front(receiver, n_receiver, source.corners())
        && in_front(source, n_source, receiver.corners())
}

/// Beyond this many receiver diameters from a source's nearest possible point, the receiver's
/// quadrature is its centroid alone.
///
/// The midpoint rule's error on a receiver of diameter d is second order in d over the distance
/// r, about (d/r)²/4 for the 1/r² kernel: under 0.4 % per pair at 8 diameters, where most pairs
/// of a scene lie, and less for the object means, whose pairs err both ways. Lambert's contour
/// integral is most of the form factors' time (`perf record`: 57 % of a ray-cast solve of the
/// Cornell box, most of it in `atan2`), so evaluating it once instead of n² times there took the
/// default Cornell solve from 13.0 to 7.5 s of CPU; its object means moved by 0.035 % at most,
/// every scene of `benches/suite` by 0.05 points at most, and the 256² picture from 1.94 % to
/// 1.95 % (docs/decisions/far-field.md).
pub(crate) const FAR_FIELD: f64 = 8.0;

/// The unoccluded form factor from a receiver to a source polygon: the weighted sum of
/// Lambert's point-to-polygon factor over the receiver's quadrature points, or at its centroid
/// alone in the far field ([`FAR_FIELD`]).
pub(crate) fn unoccluded(receiver: &Receiver, source: &[DVec3]) -> f64 {
    let centre = source.iter().sum::<DVec3>() / source.len() as f64;
    let radius = source
        .iter()
        .map(|c| c.distance(centre))
        .fold(0.0, f64::max);
    if receiver.centroid.distance(centre) - radius > FAR_FIELD * receiver.diameter {
        return analytic::point_to_polygon(receiver.centroid, receiver.normal, source);
    }
    receiver
        .points
        .iter()
        .map(|&(x, w)| w * analytic::point_to_polygon(x, receiver.normal, source))
        .sum()
}

/// The unoccluded form factor from element `e` (whose quadrature is `receiver`) to source `s`,
/// or 0 without work for a pair on one patch or a pair facing away.
pub(crate) fn pair_unoccluded(g: &Geometry, receiver: &Receiver, e: usize, s: usize) -> f64 {
    let element = g.mesh.element(e);
    let source = &g.mesh.nodes[g.sources[s] as usize];
    if element.patch == source.patch {
        return 0.0;
    }
    let normal = |patch: u32| g.mesh.patches[patch as usize].normal;
    if !facing(
        &element.face,
        normal(element.patch),
        &source.face,
        normal(source.patch),
    ) {
        return 0.0;
    }
    let (corners, sides) = source.face.corners_f64();
    unoccluded(receiver, &corners[..sides])
}

/// The side of element `e`'s receiver grid: `n`, or [`NEAR_REFINEMENT`] times more in the
/// near field of another surface ([`crate::mesh::Node::near`]).
fn grid(g: &Geometry, e: usize, n: u32) -> u32 {
    node_grid(g.mesh.element(e), n)
}

/// The side of the integration grid over quadtree node `node`: `n`, or [`NEAR_REFINEMENT`]
/// times more in the near field of another surface.
pub(crate) fn node_grid(node: &crate::mesh::Node, n: u32) -> u32 {
    if node.near {
        n * NEAR_REFINEMENT
    } else {
        n
    }
}

/// Computes `out[s] = pair(receiver, s)` for every source of one element.
pub(crate) fn row_with<F>(g: &Geometry, n: u32, element: usize, out: &mut [f32], pair: F)
where
    F: Fn(&Receiver, usize) -> f32,
{
    let mut receiver = Receiver::default();
    receiver.set(&g.mesh.element(element).face, grid(g, element, n));
    for (s, value) in out.iter_mut().enumerate() {
        *value = pair(&receiver, s);
    }
}

/// Computes `out[e] = pair(receiver e, source)` for every element in parallel chunks, with one
/// reusable receiver buffer per chunk (each value depends on its pair only).
pub(crate) fn column_with<F>(g: &Geometry, n: u32, out: &mut [f32], pair: F)
where
    F: Fn(&Receiver, usize) -> f32 + Sync,
{
    use rayon::prelude::*;
    const CHUNK: usize = 256;
    out.par_chunks_mut(CHUNK)
        .enumerate()
        .for_each(|(chunk, values)| {
            let mut receiver = Receiver::default();
            for (k, value) in values.iter_mut().enumerate() {
                let e = chunk * CHUNK + k;
                receiver.set(&g.mesh.element(e).face, grid(g, e, n));
                *value = pair(&receiver, e);
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_method_is_named_parsed_and_built() {
        let err = "nusselt".parse::<Method>().unwrap_err().to_string();
        assert!(err.starts_with("unknown form-factor method `nusselt` (choose "));
        for m in Method::ALL {
            assert_eq!(m.name().parse::<Method>(), Ok(m));
            assert!(err.contains(m.name()), "{err}");
            let settings = Settings::of(m);
            assert_eq!(settings.method(), m);
            let _built: Box<dyn FormFactors> = build(&settings);
        }
    }

    #[test]
    fn quadrature_weights_sum_to_one_and_centroid_is_exact() {
        let tri = Face::triangle(
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.5),
        );
        let quad = Face::quad(
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.5, 1.0, 0.0),
            Vec3::new(0.5, 1.0, 0.0),
        );
        let mut r = Receiver::default();
        for face in [tri, quad] {
            for n in 1..5 {
                r.set(&face, n);
                assert_eq!(r.points.len(), (n * n) as usize);
                let w: f64 = r.points.iter().map(|p| p.1).sum();
                assert!((w - 1.0).abs() < 1e-12);
                // The midpoint rule integrates linear functions exactly: the weighted mean of
                // the points is the centroid.
                let mean: DVec3 = r.points.iter().map(|p| p.0 * p.1).sum();
                assert!(
                    (mean - face.centroid().as_dvec3()).length() < 1e-6,
                    "{face:?} {n}"
                );
            }
        }
    }

    /// What only a thin strip of the face sees — here, the strip itself: the 1 % of a
    /// triangle's and a quad's area along the edge x = 0 — the midpoint rule never finds;
    /// the jittered rule finds it in proportion to its area, averaged over seeds.
    #[test]
    fn the_jittered_rule_finds_a_thin_strip_in_proportion_to_its_area() {
        let tri = Face::triangle(Vec3::ZERO, Vec3::X, Vec3::Y);
        let quad = Face::quad(Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y);
        // The share of each face's area with x < 0.01 (the triangle's is 1 − 0.99²).
        for (face, exact) in [(tri, 1.0 - 0.99f64 * 0.99), (quad, 0.01)] {
            let strip = |r: &Receiver| -> f64 {
                r.points.iter().filter(|p| p.0.x < 0.01).map(|p| p.1).sum()
            };
            let mut r = Receiver::default();
            r.set(&face, 2);
            assert_eq!(strip(&r), 0.0);
            let seeds = 20_000;
            let mut mean = 0.0;
            for seed in 0..seeds {
                r.set_jittered(&face, 2, Some(seed));
                let w: f64 = r.points.iter().map(|p| p.1).sum();
                assert!((w - 1.0).abs() < 1e-12);
                mean += strip(&r) / seeds as f64;
            }
            assert!((mean - exact).abs() < 0.1 * exact, "{mean} vs {exact}");
        }
    }
}
