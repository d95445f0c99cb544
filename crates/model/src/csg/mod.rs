//! Constructive solid geometry on closed meshes with BSP trees (Naylor, Amanatides & Thibault
//! 1990; the formulation of Wallace's csg.js), and on implicit solids by min/max
//! ([`crate::implicit::Sdf::Union`] and friends).
//!
//! Each operand's polygons build a [`BspTree`] whose leaves classify space as inside or
//! outside. `a.clip_to(b)` deletes the parts of a's polygons inside b. With inversion
//! (complement: every plane flipped) the three operations are
//!
//! * A ∪ B: a.clip(b); b.clip(a); b = ¬(¬b clipped by a) — which drops the coplanar faces B
//!   shares with A in the same direction; then A's tree takes B's polygons;
//! * A ∩ B = ¬(¬A ∪ ¬B);  A ∖ B = ¬(¬A ∪ B).
//!
//! Coplanar faces are classified by [`bsp::EPSILON`] and by the direction of their normals, so
//! boxes sharing a face fuse without a sliver.
//!
//! Splitting leaves T-junctions: a polygon cut by a plane gets a new vertex on an edge that the
//! neighbouring polygon does not know about. The output is made watertight by welding vertices
//! closer than a tolerance and inserting every vertex that lies on another polygon's edge into
//! that edge, so every edge has exactly two oppositely oriented faces.

use std::cmp::Ordering;

use glam::DVec3;

use crate::spatial::bsp::{self, BspTree, Polygon};
use crate::PolyMesh;

/// A Boolean set operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CsgOp {
    /// A ∪ B.
    Union,
    /// A ∩ B.
    Intersection,
    /// A ∖ B.
    Difference,
}

/// The solid `a op b` of two closed, outward-oriented meshes, as a closed mesh (convex
/// polygons, fronts outward). Non-convex input faces are fanned into triangles first.
#[must_use]
pub fn apply(op: CsgOp, a: &PolyMesh, b: &PolyMesh) -> PolyMesh {
    let mut ta = BspTree::new(polygons(a));
    let mut tb = BspTree::new(polygons(b));
    let invert_a = matches!(op, CsgOp::Intersection | CsgOp::Difference);
    let invert_b = op == CsgOp::Intersection;
    if invert_a {
        ta.invert();
    }
    if invert_b {
        tb.invert();
    }
    ta.clip_to(&tb);
    tb.clip_to(&ta);
    tb.invert();
    tb.clip_to(&ta);
    tb.invert();
    ta.build(tb.all_polygons());
    if invert_a {
        ta.invert();
    }
    weld(ta.all_polygons())
}

/// A ∪ B.
#[must_use]
pub fn union(a: &PolyMesh, b: &PolyMesh) -> PolyMesh {
    apply(CsgOp::Union, a, b)
}

/// A ∩ B.
#[must_use]
pub fn intersection(a: &PolyMesh, b: &PolyMesh) -> PolyMesh {
    apply(CsgOp::Intersection, a, b)
}

/// A ∖ B.
#[must_use]
pub fn difference(a: &PolyMesh, b: &PolyMesh) -> PolyMesh {
    apply(CsgOp::Difference, a, b)
}

/// The faces of `mesh` as convex polygons in double precision.
fn polygons(mesh: &PolyMesh) -> Vec<Polygon> {
    let mut out = Vec::with_capacity(mesh.faces.len());
    for face in &mesh.faces {
        let vs: Vec<DVec3> = face
            .iter()
            .filter_map(|&i| mesh.positions.get(i as usize))
            .map(|p| p.as_dvec3())
            .collect();
        let Some(poly) = Polygon::new(vs.clone()) else {
            continue;
        };
        if is_convex(&poly) {
            out.push(poly);
        } else {
            out.extend(
                (1..vs.len() - 1).filter_map(|k| Polygon::new(vec![vs[0], vs[k], vs[k + 1]])),
            );
        }
    }
    out
}

/// Whether every corner turns the same way as the polygon's normal.
fn is_convex(p: &Polygon) -> bool {
    let n = p.vertices.len();
    (0..n).all(|i| {
        let (a, b, c) = (
            p.vertices[i],
            p.vertices[(i + 1) % n],
            p.vertices[(i + 2) % n],
        );
        (b - a).cross(c - b).dot(p.plane.normal) >= -1e-12
    })
}

/// Polygons → an indexed mesh: vertices closer than the tolerance welded, slivers thinner than
/// it dropped, T-junctions removed by inserting vertices that lie on an edge into it.
fn weld(polys: Vec<Polygon>) -> PolyMesh {
    // Weld: sort corners by x and merge those within `tol` (union-find, smallest index wins).
    // Splits of nearly parallel planes can leave features far below the model's size; the
    // tolerance, 10⁻⁴ of the bounding diagonal (and never below the BSP's ε), removes them.
    let corners: Vec<DVec3> = polys
        .iter()
        .flat_map(|p| p.vertices.iter().copied())
        .collect();
    let (lo, hi) = corners.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let diagonal = if corners.is_empty() {
        0.0
    } else {
        (hi - lo).length()
    };
    let tol = (diagonal * 1e-4).max(bsp::EPSILON * 10.0);
    let mut order: Vec<usize> = (0..corners.len()).collect();
    order.sort_by(|&i, &j| {
        corners[i]
            .x
            .partial_cmp(&corners[j].x)
            .unwrap_or(Ordering::Equal)
    });
    let mut parent: Vec<usize> = (0..corners.len()).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    for (k, &i) in order.iter().enumerate() {
        for &j in &order[k + 1..] {
            if corners[j].x - corners[i].x > tol {
                break;
            }
            if corners[i].distance(corners[j]) <= tol {
                let (ri, rj) = (find(&mut parent, i), find(&mut parent, j));
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
    }
    let mut index = vec![u32::MAX; corners.len()];
    let mut positions: Vec<DVec3> = Vec::new();
    for i in 0..corners.len() {
        let r = find(&mut parent, i);
        if index[r] == u32::MAX {
            index[r] = positions.len() as u32;
            positions.push(corners[r]);
        }
        index[i] = index[r];
    }
    // Faces by welded index, without repeated corners.
    let mut faces: Vec<Vec<u32>> = Vec::with_capacity(polys.len());
    let mut at = 0;
    for p in &polys {
        let mut f: Vec<u32> = index[at..at + p.vertices.len()].to_vec();
        at += p.vertices.len();
        f.dedup();
        while f.len() > 1 && f.first() == f.last() {
            f.pop();
        }
        // A sliver thinner than the tolerance (a corner on the opposite edge) would make the
        // T-junction pass run an edge both ways; its neighbours close the gap without it.
        let mut newell = DVec3::ZERO;
        let mut longest: f64 = 0.0;
        for k in 0..f.len() {
            let (pa, pb) = (
                positions[f[k] as usize],
                positions[f[(k + 1) % f.len()] as usize],
            );
            newell += pa.cross(pb);
            longest = longest.max(pa.distance(pb));
        }
        if f.len() >= 3 && newell.length() * 0.5 > tol * longest {
            faces.push(f);
        }
    }
    // T-junctions: insert every vertex lying inside an edge, ordered along the edge.
    let mut by_x: Vec<u32> = (0..positions.len() as u32).collect();
    by_x.sort_by(|&i, &j| {
        positions[i as usize]
            .x
            .partial_cmp(&positions[j as usize].x)
            .unwrap_or(Ordering::Equal)
    });
    let xs: Vec<f64> = by_x.iter().map(|&i| positions[i as usize].x).collect();
    for f in &mut faces {
        let mut out = Vec::with_capacity(f.len());
        for k in 0..f.len() {
            let (a, b) = (f[k], f[(k + 1) % f.len()]);
            out.push(a);
            let (pa, pb) = (positions[a as usize], positions[b as usize]);
            let d = pb - pa;
            let len2 = d.length_squared();
            if len2 == 0.0 {
                continue;
            }
            let lo = xs.partition_point(|&x| x < pa.x.min(pb.x) - tol);
            let hi = xs.partition_point(|&x| x <= pa.x.max(pb.x) + tol);
            let mut on: Vec<(f64, u32)> = by_x[lo..hi]
                .iter()
                .copied()
                .filter(|&v| v != a && v != b)
                .filter_map(|v| {
                    let p = positions[v as usize];
                    let t = (p - pa).dot(d) / len2;
                    let off = (pa + d * t).distance(p);
                    (t > 0.0 && t < 1.0 && off <= tol).then_some((t, v))
                })
                .collect();
            on.sort_by(|x, y| x.0.partial_cmp(&y.0).unwrap_or(Ordering::Equal));
            out.extend(on.into_iter().map(|(_, v)| v));
        }
        // Remove spikes a → b → a left by a vertex inserted next to its own copy.
        let mut changed = true;
        while changed && out.len() >= 3 {
            changed = false;
            let n = out.len();
            if let Some(k) = (0..n).find(|&k| out[(k + n - 1) % n] == out[(k + 1) % n]) {
                let (a, b) = (k, (k + 1) % n);
                let (first, second) = (a.max(b), a.min(b));
                out.remove(first);
                out.remove(second);
                changed = true;
            }
        }
        *f = out;
    }
    faces.retain(|f| {
        let mut distinct = f.clone();
        distinct.sort_unstable();
        distinct.dedup();
        distinct.len() >= 3
    });
    PolyMesh {
        positions: positions.iter().map(|p| p.as_vec3()).collect(),
        faces,
    }
}
