//! Enclosures: two-sided objects whose inner sides no light can reach.
//!
//! The back sides of a closed two-sided object's polygons face into its volume, which no light
//! can reach through the surface; a solver given them anyway can only err (a cluster model
//! pushing light onto them, a straddling element leaking into them: a two-sided scanned mesh in
//! a box came out 40 % too bright). So they are not made: a closed two-sided object is its
//! outward side. Closed means every directed edge (exact corner positions) is met once in each
//! direction, so the surface is watertight and consistently oriented; outward means its signed
//! volume V = Σ a·(b × c)/6 over a fan of each polygon is positive (the divergence theorem over
//! the closed surface). Emitting objects are left alone, and so are objects whose bounds hold a
//! point luminaire, which may light them from inside.
//!
//! A solid *standing on a floor* is closed by the floor. Modelling tools and hand-written OBJ
//! files leave out the bottom of a box that stands on something (the bare OBJ room of
//! `scenes/suite/bare-obj-many`); its open edges make one plane loop lying on the floor, and
//! the floor caps it. Mitsuba 3 sees its inner sides dark, and they are; given patches, the
//! floor's elements straddling the footprint leak light onto them (measured there with
//! hierarchical radiosity: the block's inner sides 0.0027 W·m⁻² against 0, +0.79 % of the
//! block's radiosity). Such an object counts as closed when
//!
//! * every edge is met once in each direction, or once only (an open edge), and the open
//!   edges' corners lie in one plane (within [`PLANE_TOLERANCE`] of the object's size);
//! * the surface with that plane's cap has a positive volume, not a negligible one (a flat
//!   panel's "volume" is zero) — the cap's vector area is −N/2 for the open edges' Newell sum
//!   N = Σ a × b, so V = V_faces − p·N/6 for any point p of the plane;
//! * the footprint lies on another object's polygons in that plane whose side facing the
//!   solid (+N) reflects: each open corner, each open edge's midpoint and the cap's centroid
//!   lies in one of them (corners on their edges count).

use std::collections::HashMap;

use glam::{DVec3, Vec3};

use super::imprint::bounds;
use crate::scene::coincident::exact_bits;
use crate::Scene;

/// How far (relative to the object's diameter) an open corner may lie from the floor's plane.
const PLANE_TOLERANCE: f64 = 1e-4;

/// A capped volume below this fraction of the object's diameter cubed is a flat panel's.
const MIN_VOLUME: f64 = 1e-6;

/// An undirected edge by its corners' bit patterns, smaller first.
type Edge = ([u32; 3], [u32; 3]);

/// For every object of `scene`: whether its polygons close a surface around a volume, facing
/// outward, alone or with a floor they stand on (see the module docs).
pub(super) fn enclosed_objects(scene: &Scene) -> Vec<bool> {
    let n = scene.objects.len();
    // Per object and undirected edge: +1000 + 1 for a → b, −1000 + 1 for b → a, and the
    // directed corners of the last time it was met.
    let mut edges: Vec<HashMap<Edge, (i32, Vec3, Vec3)>> = vec![HashMap::new(); n];
    let mut volume = vec![0.0f64; n];
    let mut eligible = vec![true; n];
    let mut extent = vec![(DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)); n];
    for polygon in &scene.polygons {
        let material = &scene.materials[polygon.material];
        let o = polygon.object;
        eligible[o] &= material.two_sided && !material.is_emitter();
        let vs = &polygon.vertices;
        for (k, &a) in vs.iter().enumerate() {
            let b = vs[(k + 1) % vs.len()];
            let (ka, kb) = (exact_bits(a), exact_bits(b));
            let (lo, hi, sign) = if ka < kb { (ka, kb, 1) } else { (kb, ka, -1) };
            let entry = edges[o].entry((lo, hi)).or_insert((0, a, b));
            *entry = (entry.0 + sign * 1000 + 1, a, b);
            let (lo, hi) = &mut extent[o];
            (*lo, *hi) = (lo.min(a.as_dvec3()), hi.max(a.as_dvec3()));
        }
        let a = vs[0].as_dvec3();
        for w in vs[1..].windows(2) {
            volume[o] += a.dot(w[0].as_dvec3().cross(w[1].as_dvec3())) / 6.0;
        }
    }
    // A point luminaire inside lights the inner sides: an object whose bounds hold one keeps
    // them.
    for (o, (lo, hi)) in extent.iter().enumerate() {
        let holds = |p: DVec3| p.cmpge(*lo).all() && p.cmple(*hi).all();
        if scene
            .luminaires
            .iter()
            .any(|l| l.position().is_some_and(|p| holds(p.as_dvec3())))
        {
            eligible[o] = false;
        }
    }
    let mut enclosed = vec![false; n];
    let mut footprints = Vec::new();
    for o in 0..n {
        if !eligible[o] || edges[o].is_empty() {
            continue;
        }
        // Once in each direction: the sum is (+1000 + 1) + (−1000 + 1) = 2.
        if edges[o].values().all(|e| e.0 == 2) {
            enclosed[o] = volume[o] > 0.0;
            continue;
        }
        // Met once (±1000 + 1) or once in each direction, nothing else; in key order, so that
        // the result does not depend on the map's.
        let mut open: Vec<(&Edge, DVec3, DVec3)> = Vec::new();
        for (key, &(count, a, b)) in &edges[o] {
            match count {
                2 => {}
                1001 | -999 => open.push((key, a.as_dvec3(), b.as_dvec3())),
                _ => {
                    open.clear();
                    break;
                }
            }
        }
        open.sort_unstable_by_key(|e| *e.0);
        let open: Vec<(DVec3, DVec3)> = open.into_iter().map(|(_, a, b)| (a, b)).collect();
        let size = (extent[o].1 - extent[o].0).length();
        footprints.extend(Footprint::new(o, volume[o], &open, size));
    }
    // One pass over the polygons for every footprint: which of its probes some reflecting
    // polygon of another object in its plane covers.
    for q in &scene.polygons {
        let (lo, hi) = bounds(q.vertices.iter().copied());
        let two_sided = scene.materials[q.material].two_sided;
        for f in &mut footprints {
            if q.object == f.object
                || (lo - f.hi).max_element() > 0.0
                || (f.lo - hi).max_element() > 0.0
                || f.covered.iter().all(|&c| c)
            {
                continue;
            }
            let Some(normal) = model::polymesh::vector_area(&q.vertices)
                .as_dvec3()
                .try_normalize()
            else {
                continue;
            };
            let facing = normal.dot(f.up);
            let coplanar = facing.abs() > 1.0 - 1e-6
                && q.vertices
                    .iter()
                    .all(|v| f.up.dot(v.as_dvec3() - f.origin).abs() <= f.tolerance);
            if !coplanar || !(facing > 0.0 || two_sided) {
                continue;
            }
            let vs: Vec<DVec3> = q.vertices.iter().map(|v| v.as_dvec3()).collect();
            for (probe, covered) in f.probes.iter().zip(&mut f.covered) {
                *covered |= covers(&vs, normal, *probe, f.tolerance);
            }
        }
    }
    for f in footprints {
        enclosed[f.object] = f.covered.iter().all(|&c| c);
    }
    enclosed
}

/// Where an object with open edges would stand on a floor: the plane of its open edges and the
/// points of that plane a floor must cover.
struct Footprint {
    object: usize,
    /// The open edges' plane: a point of it and the unit normal into the solid (+N).
    origin: DVec3,
    up: DVec3,
    tolerance: f64,
    /// Each open corner, each open edge's midpoint and the cap's centroid.
    probes: Vec<DVec3>,
    /// Which probes a floor polygon covers.
    covered: Vec<bool>,
    /// The probes' bounding box, widened by the tolerance.
    lo: DVec3,
    hi: DVec3,
}

impl Footprint {
    /// The footprint of object `o` (faces' signed volume `volume`, diameter `size`) along its
    /// open edges `open` (directed as its polygons run them), if they lie in one plane and cap
    /// a volume that is not negligible.
    fn new(o: usize, volume: f64, open: &[(DVec3, DVec3)], size: f64) -> Option<Self> {
        let newell: DVec3 = open.iter().map(|(a, b)| a.cross(*b)).sum();
        let up = newell.try_normalize()?;
        let origin = open.first()?.0;
        let tolerance = PLANE_TOLERANCE * size;
        if open
            .iter()
            .any(|(a, _)| up.dot(*a - origin).abs() > tolerance)
            || volume - origin.dot(newell) / 6.0 <= MIN_VOLUME * size.powi(3)
        {
            return None;
        }
        // The cap's area centroid, from a fan about the origin (signed areas along +N).
        let (mut weight, mut centroid) = (0.0, DVec3::ZERO);
        for (a, b) in open {
            let w = (*a - origin).cross(*b - origin).dot(up);
            weight += w;
            centroid += w * (origin + *a + *b) / 3.0;
        }
        let mut probes: Vec<DVec3> = open
            .iter()
            .flat_map(|(a, b)| [*a, 0.5 * (*a + *b)])
            .collect();
        probes.push(centroid / weight);
        let (lo, hi) = probes.iter().fold(
            (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        Some(Self {
            object: o,
            origin,
            up,
            tolerance,
            covered: vec![false; probes.len()],
            probes,
            lo: lo - DVec3::splat(tolerance),
            hi: hi + DVec3::splat(tolerance),
        })
    }
}

/// Whether the planar polygon `vs` of unit normal `n` contains `x` (a point of its plane), or
/// passes within `tolerance` of it: the crossing number of a ray along the polygon's plane.
fn covers(vs: &[DVec3], n: DVec3, x: DVec3, tolerance: f64) -> bool {
    let u = (vs[1] - vs[0]).normalize_or_zero();
    let v = n.cross(u);
    let flat = |q: DVec3| ((q - x).dot(u), (q - x).dot(v));
    let mut inside = false;
    for (k, &a) in vs.iter().enumerate() {
        let (ax, ay) = flat(a);
        let (bx, by) = flat(vs[(k + 1) % vs.len()]);
        // Within tolerance of the edge a → b: on it.
        let (dx, dy) = (bx - ax, by - ay);
        let t = (-(ax * dx + ay * dy) / (dx * dx + dy * dy).max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        if (ax + t * dx).hypot(ay + t * dy) <= tolerance {
            return true;
        }
        if (ay > 0.0) != (by > 0.0) && ax - ay * dx / dy > 0.0 {
            inside = !inside;
        }
    }
    inside
}
