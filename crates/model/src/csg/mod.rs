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
//! neighbouring polygon does not know about, and where many planes cross near one point it
//! leaves clusters of nearly coincident vertices. The output is made watertight by welding
//! vertices closer than a tolerance, inserting every vertex that lies within it of another
//! polygon's edge into that edge (the same set, in the same order along the edge, from both
//! sides), removing the spikes and pinches this leaves and the zero-volume fins (a face and its
//! reverse), so every edge has exactly two oppositely oriented faces. The tolerance starts just
//! above the BSP's ε and grows by decades until the result is a closed, oriented 2-manifold
//! (checked with [`crate::brep::closed_topology`]); every loop is bounded.

use std::cmp::Ordering;
use std::collections::HashSet;

use glam::DVec3;

use crate::brep::closed_topology;
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
    close(&ta.all_polygons())
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

/// The faces of `mesh` as convex polygons in double precision. Corners within the BSP's ε of
/// the line through their neighbours (the T-junction vertices of an earlier Boolean, made
/// slightly reflex by rounding to f32) are dropped first: they do not change the face, and the
/// final weld puts them back into the edge. Faces still not convex are fanned into triangles.
fn polygons(mesh: &PolyMesh) -> Vec<Polygon> {
    let mut out = Vec::with_capacity(mesh.faces.len());
    for face in &mesh.faces {
        let mut vs: Vec<DVec3> = face
            .iter()
            .filter_map(|&i| mesh.positions.get(i as usize))
            .map(|p| p.as_dvec3())
            .collect();
        // Each pass removes one corner, so at most `len` passes.
        while vs.len() > 3 {
            let n = vs.len();
            let straight = (0..n).find(|&k| {
                let (a, b, c) = (vs[(k + n - 1) % n], vs[k], vs[(k + 1) % n]);
                let d = c - a;
                let len2 = d.length_squared();
                len2 > 0.0 && {
                    let t = ((b - a).dot(d) / len2).clamp(0.0, 1.0);
                    (a + d * t).distance(b) <= bsp::EPSILON
                }
            });
            match straight {
                Some(k) => {
                    vs.remove(k);
                }
                None => break,
            }
        }
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

/// Polygons → a closed indexed mesh. [`weld`] is tried with tolerances growing from just above
/// the BSP's ε to 10⁻³ of the bounding diagonal; the first result that is a closed, oriented
/// 2-manifold ([`closed_topology`]) is returned (else the last, the most aggressive). A small
/// tolerance keeps small true features; a larger one is needed where many splitting planes
/// cross near one point and leave a cluster of nearly coincident vertices.
fn close(polys: &[Polygon]) -> PolyMesh {
    let (lo, hi) = polys.iter().flat_map(|p| p.vertices.iter()).fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let diagonal = if polys.is_empty() {
        0.0
    } else {
        (hi - lo).length()
    };
    let mut mesh = PolyMesh::default();
    for scale in [1e-7, 1e-6, 1e-5, 1e-4, 1e-3] {
        mesh = weld(polys, (diagonal * scale).max(bsp::EPSILON * 4.0));
        if closed_topology(&mesh).is_ok() {
            break;
        }
    }
    mesh
}

/// Polygons → an indexed mesh: vertices closer than `tol` welded, T-junctions removed by
/// inserting vertices that lie within `tol` of an edge into it, spikes removed, pinched faces
/// split into their loops, and loops with fewer than three corners and zero-volume fins (a
/// face and its reverse) dropped.
fn weld(polys: &[Polygon], tol: f64) -> PolyMesh {
    // Weld: sort corners by x and merge those within `tol` (union-find, smallest index wins).
    let corners: Vec<DVec3> = polys
        .iter()
        .flat_map(|p| p.vertices.iter().copied())
        .collect();
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
    for p in polys {
        let mut f: Vec<u32> = index[at..at + p.vertices.len()].to_vec();
        at += p.vertices.len();
        f.dedup();
        while f.len() > 1 && f.first() == f.last() {
            f.pop();
        }
        if f.len() >= 3 {
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
    // A face pinched at a repeated corner (two sliver parts welded together) becomes one face
    // per loop; loops with fewer than three distinct corners are dropped.
    let mut loops: Vec<Vec<u32>> = Vec::with_capacity(faces.len());
    for f in &faces {
        let mut path: Vec<u32> = Vec::with_capacity(f.len());
        for &v in f {
            if let Some(j) = path.iter().position(|&u| u == v) {
                loops.push(path.split_off(j));
            }
            path.push(v);
        }
        loops.push(path);
    }
    loops.retain(|f| f.len() >= 3);
    // Two faces on the same corners in opposite order are a fin of zero volume: drop both.
    let canonical = |f: &[u32]| {
        let k = (0..f.len()).min_by_key(|&k| f[k]).unwrap_or(0);
        let mut c = f.to_vec();
        c.rotate_left(k);
        c
    };
    let seen: HashSet<Vec<u32>> = loops.iter().map(|f| canonical(f)).collect();
    let faces: Vec<Vec<u32>> = loops
        .into_iter()
        .filter(|f| {
            let mut r = f.clone();
            r.reverse();
            !seen.contains(&canonical(&r))
        })
        .collect();
    PolyMesh {
        positions: positions.iter().map(|p| p.as_vec3()).collect(),
        faces,
    }
}
