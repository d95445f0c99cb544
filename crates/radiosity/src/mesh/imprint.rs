//! Imprints: root faces cut along the outline of a polygon lying on them or hovering just in
//! front of them.
//!
//! A block's bottom lying on a floor, a rug, a picture hung flat on a wall, an emitter a
//! millimetre in front of a wall: the surface underneath has a region the other polygon covers
//! and a region in the open, and their radiosities differ by orders of magnitude (dark under
//! the block; lit by light trapped in the gap under an emitter that faces the wall). An element
//! that straddles the outline averages the two and shines the average into the room, the light
//! leak of non-conforming meshes (Baum, Mann, Smith & Winget 1991). The cure is to put element
//! edges on the outline, a D⁰ discontinuity (Heckbert 1992; Lischinski, Tampieri & Greenberg
//! 1992). For a convex outline this is exact and cheap: the root faces are cut along it before
//! the quadtrees are built, so no element of any level straddles it. (The quadtree refinement
//! of [`super::contact`] remains for what this does not cover: solids standing on a floor
//! without a bottom face, small or curved covers.)
//!
//! The cut of a convex face F by a convex outline Q (projected along F's normal) is convex
//! pieces: F ∩ Q, and for each edge k of Q the part of F outside edge k and inside edges
//! 0..k, clipped in turn (Sutherland & Hodgman 1974). Measured on
//! `scenes/suite/emitter-near-wall-facing` against Mitsuba 3: see docs/validation.md.

use glam::{DVec3, Vec3};

use super::root_faces::{is_planar, root_faces};
use super::triangulate::is_convex;
use super::Face;
use crate::scene::facing_emitters::NEAR;
use crate::Scene;

/// Only polygons of at least this share of the scene's area imprint, and are imprinted: finer
/// outlines are the quadtree refinement's, and the pairs to test stay few.
const MIN_SHARE: f64 = 1e-4;

/// A piece whose area is below this fraction of the face it comes from is a sliver of rounding
/// (an outline edge along the face's own edge), not a piece.
const SLIVER: f64 = 1e-6;

/// A planar piece of a polygon with the root faces of its quadtree (see [`super::patch`]).
pub(super) struct Piece {
    /// Index into [`Scene::polygons`].
    pub polygon: usize,
    /// Unit normal.
    pub normal: Vec3,
    /// Root faces.
    pub roots: Vec<Face>,
    /// Polygons whose outline was cut into the roots.
    pub imprinted: Vec<u32>,
}

impl Piece {
    /// The area of the root faces.
    pub fn area(&self) -> f64 {
        self.roots.iter().map(Face::area).sum()
    }

    /// Cuts the root faces along the convex outline `q` (projected along the piece's normal);
    /// says whether any was cut.
    pub fn cut(&mut self, q: &[DVec3]) -> bool {
        let normal = self.normal.as_dvec3();
        let mut cut = false;
        self.roots = self
            .roots
            .iter()
            .flat_map(|f| match split(f, normal, q) {
                Some(parts) => {
                    cut = true;
                    parts
                }
                None => vec![*f],
            })
            .collect();
        cut
    }
}

/// The area from which pieces take part in imprints and shadow outlines, as cutters and as
/// cut: [`MIN_SHARE`] of all the pieces' area.
pub(super) fn large_area(pieces: &[Piece]) -> f64 {
    MIN_SHARE * pieces.iter().map(Piece::area).sum::<f64>()
}

/// The unit normal of `vertices` if they make a planar convex polygon of at least `large`
/// area.
pub(super) fn convex_normal(vertices: &[Vec3], large: f64) -> Option<Vec3> {
    let vector = model::polymesh::vector_area(vertices);
    let normal = vector.normalize_or_zero();
    (f64::from(vector.length()) >= large
        && is_planar(vertices, normal)
        && is_convex(vertices, normal))
    .then_some(normal)
}

/// A convex planar polygon that may imprint others.
struct Outline {
    polygon: usize,
    corners: Vec<DVec3>,
    lo: DVec3,
    hi: DVec3,
    /// How far in front of (or behind) a surface it may hover and still imprint: [`NEAR`] of
    /// its size, the distance at which [`crate::scene::facing_emitters`] warns.
    reach: f64,
}

/// Cuts the root faces of every large piece along the outlines of the large convex polygons
/// lying on it or hovering within reach of its plane (either side).
pub(super) fn imprint(scene: &Scene, pieces: &mut [Piece]) {
    let large = large_area(pieces);
    let outlines: Vec<Outline> = scene
        .polygons
        .iter()
        .enumerate()
        .filter_map(|(polygon, p)| outline(polygon, &p.vertices, large))
        .collect();
    if outlines.is_empty() {
        return;
    }
    for piece in pieces.iter_mut().filter(|p| p.area() >= large) {
        let normal = piece.normal.as_dvec3();
        let origin = piece.roots[0].corners()[0].as_dvec3();
        let (lo, hi) = bounds(piece.roots.iter().flat_map(|f| f.corners().iter().copied()));
        for q in &outlines {
            let overlaps = (q.lo - q.reach).cmple(hi).all() && (q.hi + q.reach).cmpge(lo).all();
            if q.polygon == piece.polygon
                || !overlaps
                || q.corners
                    .iter()
                    .any(|c| normal.dot(*c - origin).abs() > q.reach)
            {
                continue;
            }
            if piece.cut(&q.corners) {
                piece.imprinted.push(q.polygon as u32);
            }
        }
    }
}

/// The polygon as an outline, if it is convex, planar and at least `large` in area.
fn outline(polygon: usize, vertices: &[Vec3], large: f64) -> Option<Outline> {
    convex_normal(vertices, large)?;
    let corners: Vec<DVec3> = vertices.iter().map(|v| v.as_dvec3()).collect();
    let (lo, hi) = bounds(vertices.iter().copied());
    Some(Outline {
        polygon,
        corners,
        lo,
        hi,
        reach: f64::from(NEAR * super::face::diameter(vertices)),
    })
}

/// The bounding box of some points, in `f64`.
pub(super) fn bounds(points: impl Iterator<Item = Vec3>) -> (DVec3, DVec3) {
    points.fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(p.as_dvec3()), hi.max(p.as_dvec3())),
    )
}

/// The convex face `face` (unit normal `normal`) cut along the outline `q` projected on its
/// plane, as root faces; `None` when the outline leaves the face whole (it misses the face,
/// covers it, or touches it only along its edges).
fn split(face: &Face, normal: DVec3, q: &[DVec3]) -> Option<Vec<Face>> {
    let whole = face.area();
    let centre = q.iter().sum::<DVec3>() / q.len() as f64;
    let mut inside: Vec<DVec3> = face.corners().iter().map(|c| c.as_dvec3()).collect();
    let mut parts = Vec::new();
    for k in 0..q.len() {
        let (a, b) = (q[k], q[(k + 1) % q.len()]);
        // The plane through the edge and along the face's normal, positive on Q's side.
        let mut m = normal.cross(b - a);
        if m.dot(centre - a) < 0.0 {
            m = -m;
        }
        let (outside, rest) = clip(&inside, m, a);
        if polygon_area(&outside) > SLIVER * whole {
            parts.push(outside);
        }
        inside = rest;
        if polygon_area(&inside) <= SLIVER * whole {
            break;
        }
    }
    // Cut only where the outline overlaps the face and leaves part of it open.
    if parts.is_empty() || polygon_area(&inside) <= SLIVER * whole {
        return None;
    }
    parts.push(inside);
    let normal = normal.as_vec3();
    Some(
        parts
            .iter()
            .flat_map(|p| {
                let corners: Vec<Vec3> = simplify(p).iter().map(|c| c.as_vec3()).collect();
                root_faces(&corners, normal)
            })
            .filter(|f| f.area() > SLIVER * whole)
            .collect(),
    )
}

/// The convex polygon `p` split by the plane through `a` with normal `m`: (the part where
/// m·(x − a) < 0, the part where it is ≥ 0), each in `p`'s order.
fn clip(p: &[DVec3], m: DVec3, a: DVec3) -> (Vec<DVec3>, Vec<DVec3>) {
    let (mut below, mut above) = (Vec::new(), Vec::new());
    for (i, &u) in p.iter().enumerate() {
        let v = p[(i + 1) % p.len()];
        let (du, dv) = (m.dot(u - a), m.dot(v - a));
        if du < 0.0 {
            below.push(u);
        } else {
            above.push(u);
        }
        if (du < 0.0) != (dv < 0.0) {
            let x = u + (v - u) * (du / (du - dv));
            below.push(x);
            above.push(x);
        }
    }
    (below, above)
}

/// The area of a planar polygon.
fn polygon_area(p: &[DVec3]) -> f64 {
    if p.len() < 3 {
        return 0.0;
    }
    let mut v = DVec3::ZERO;
    for (i, a) in p.iter().enumerate() {
        v += a.cross(p[(i + 1) % p.len()]);
    }
    0.5 * v.length()
}

/// `p` without repeated corners and corners on a straight line through their neighbours (the
/// clip leaves both where an outline passes through a corner).
fn simplify(p: &[DVec3]) -> Vec<DVec3> {
    let size = p
        .iter()
        .flat_map(|a| p.iter().map(move |b| a.distance(*b)))
        .fold(0.0, f64::max);
    let mut out: Vec<DVec3> = Vec::with_capacity(p.len());
    for &c in p {
        if out.last().is_none_or(|l| l.distance(c) > 1e-9 * size) {
            out.push(c);
        }
    }
    while out.len() > 1 && out[0].distance(out[out.len() - 1]) <= 1e-9 * size {
        out.pop();
    }
    let mut k = 0;
    while out.len() > 3 && k < out.len() {
        let n = out.len();
        let (a, b, c) = (out[(k + n - 1) % n], out[k], out[(k + 1) % n]);
        if (b - a).cross(c - b).length() <= 1e-9 * size * size {
            out.remove(k);
        } else {
            k += 1;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wall() -> Face {
        Face::quad(
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(4.0, 3.0, 0.0),
            Vec3::new(0.0, 3.0, 0.0),
        )
    }

    /// A rectangle at height `z` over the wall, wound as `facing` says.
    fn window(z: f64, facing_wall: bool) -> Vec<DVec3> {
        let mut w = vec![
            DVec3::new(1.0, 1.0, z),
            DVec3::new(2.5, 1.0, z),
            DVec3::new(2.5, 2.0, z),
            DVec3::new(1.0, 2.0, z),
        ];
        if facing_wall {
            w.reverse();
        }
        w
    }

    fn inside(f: &Face, q: &[DVec3]) -> bool {
        let c = f.centroid().as_dvec3();
        (q[0].x..=q[1].x).contains(&c.x) && (q[0].y..=q[2].y).contains(&c.y)
    }

    /// Whether a face lies wholly inside the window's outline or wholly outside it.
    fn one_side(f: &Face) -> bool {
        let t = 1e-5;
        let within = f.corners().iter().all(|c| {
            (1.0 - t..=2.5 + t).contains(&f64::from(c.x))
                && (1.0 - t..=2.0 + t).contains(&f64::from(c.y))
        });
        let (lo, hi) = bounds(f.corners().iter().copied());
        let apart = hi.x <= 1.0 + t || lo.x >= 2.5 - t || hi.y <= 1.0 + t || lo.y >= 2.0 - t;
        within || apart
    }

    #[test]
    fn an_outline_cuts_the_face_into_pieces_inside_and_outside_it() {
        for facing_wall in [false, true] {
            let q = window(0.001, facing_wall);
            let parts = split(&wall(), DVec3::Z, &q).expect("the window lies over the wall");
            let total: f64 = parts.iter().map(Face::area).sum();
            assert!((total - 12.0).abs() < 1e-5, "area kept: {total}");
            let q = window(0.0, false);
            let covered: f64 = parts.iter().filter(|f| inside(f, &q)).map(Face::area).sum();
            assert!((covered - 1.5).abs() < 1e-5, "covered area {covered}");
            for f in &parts {
                assert!(f.normal().dot(Vec3::Z) > 0.999, "orientation kept");
                assert!(one_side(f), "{f:?} straddles the outline");
            }
        }
    }

    #[test]
    fn an_outline_that_misses_covers_or_borders_the_face_leaves_it_whole() {
        let far = window(0.0, false)
            .iter()
            .map(|c| *c + DVec3::new(10.0, 0.0, 0.0))
            .collect::<Vec<_>>();
        assert!(split(&wall(), DVec3::Z, &far).is_none());
        let cover: Vec<DVec3> = [(-1.0, -1.0), (5.0, -1.0), (5.0, 4.0), (-1.0, 4.0)]
            .iter()
            .map(|&(x, y)| DVec3::new(x, y, 0.0))
            .collect();
        assert!(split(&wall(), DVec3::Z, &cover).is_none());
        let neighbour: Vec<DVec3> = [(4.0, 0.0), (6.0, 0.0), (6.0, 3.0), (4.0, 3.0)]
            .iter()
            .map(|&(x, y)| DVec3::new(x, y, 0.0))
            .collect();
        assert!(split(&wall(), DVec3::Z, &neighbour).is_none());
    }

    #[test]
    fn an_outline_through_the_face_corners_leaves_no_slivers() {
        // A block's bottom flush with the floor's corner: two pieces, both quads.
        let q: Vec<DVec3> = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.5), (0.0, 1.5)]
            .iter()
            .map(|&(x, y)| DVec3::new(x, y, 0.0))
            .collect();
        let parts = split(&wall(), DVec3::Z, &q).expect("cut");
        let total: f64 = parts.iter().map(Face::area).sum();
        assert!((total - 12.0).abs() < 1e-5);
        assert!(parts.iter().all(|f| f.area() > 0.1), "{parts:?}");
    }
}
