//! Tessellation of NURBS patches into planar polygons, adaptive to a chordal tolerance and
//! crack-free between patches that share an edge.
//!
//! **Adaptive density.** Each patch is cut into a regular n_u × n_v grid of its parameter
//! domain. n_u is grown until the chordal error of the u iso-curves — the distance between
//! the surface at the middle and quarter parameters of each grid segment and the chord
//! through its ends — is at most the tolerance ε on five iso-curves across the patch (the
//! error of a chord falls like h², so n grows by √(error/ε) per round); likewise n_v; then
//! both grow while a cell's centre is further than ε from the average of its corners (twist).
//! This is a sampled estimate, not a bound; for a Bézier segment of degree d the bound
//! (d(d−1)/8)·max|Δ²P|/n² (Filip, Magedson & Markot 1986) is of the same order.
//!
//! **No cracks.** Two patches that share a boundary curve (the same control points, in either
//! direction, as the teapot's 32 patches do) must cut it at the same points. The counts are
//! made to agree by uniting, over shared edges, the grid directions that cut them
//! (union–find) and giving each class the largest count any member needs; and the points of a
//! shared edge are evaluated once, from the boundary curve in one canonical direction, so the
//! two patches receive bit-identical vertices. Vertices are then welded by exact position,
//! which also closes collapsed edges (poles).
//!
//! **Orientation.** Cells are emitted counter-clockwise in (u, v), so the front of each polygon
//! is the patch's S_u × S_v side. A cell is a quad when it is planar to 0.1 % of its
//! diagonal, else two triangles along its shorter diagonal; cells degenerate at a pole become
//! triangles, and zero-area ones are dropped.

use std::collections::HashMap;

use glam::{DVec3, DVec4, Vec3};

use super::NurbsSurface;
use crate::curve::{Curve, Nurbs};
use crate::PolyMesh;

/// How finely to tessellate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TessellationSettings {
    /// Chordal tolerance ε: the largest allowed distance between the surface and its polygons
    /// (in scene units).
    pub tolerance: f64,
    /// Most segments along one parameter direction of one patch.
    pub max_segments: usize,
}

impl Default for TessellationSettings {
    fn default() -> Self {
        Self {
            tolerance: 0.01,
            max_segments: 64,
        }
    }
}

/// Tessellates `patches` into one welded mesh (see the module docs).
#[must_use]
pub fn tessellate(patches: &[NurbsSurface], settings: &TessellationSettings) -> PolyMesh {
    let tol = if settings.tolerance > 0.0 {
        settings.tolerance
    } else {
        f64::INFINITY
    };
    let max = settings.max_segments.max(1);
    // Segment counts each patch needs on its own: [u, v] per patch.
    let mut need: Vec<usize> = patches
        .iter()
        .flat_map(|p| {
            let (nu, nv) = needed_segments(p, tol, max);
            [nu, nv]
        })
        .collect();
    // Unite directions across shared edges. Edge e of patch k is cut by direction k*2 + e%2
    // (edges 0 and 2 run along u, 1 and 3 along v).
    let mut classes = UnionFind::new(need.len());
    let mut edge_owner: HashMap<EdgeKey, usize> = HashMap::new();
    let keys: Vec<[(EdgeKey, bool); 4]> = patches
        .iter()
        .map(|p| std::array::from_fn(|e| edge_key(p, e)))
        .collect();
    for (k, patch_keys) in keys.iter().enumerate() {
        for (e, (key, _)) in patch_keys.iter().enumerate() {
            if key.degenerate {
                continue;
            }
            let dir = k * 2 + e % 2;
            match edge_owner.get(key) {
                Some(&other) => classes.union(other, dir),
                None => {
                    edge_owner.insert(key.clone(), dir);
                }
            }
        }
    }
    let mut class_need: HashMap<usize, usize> = HashMap::new();
    for (d, &n) in need.iter().enumerate() {
        let c = classes.find(d);
        let e = class_need.entry(c).or_insert(0);
        *e = (*e).max(n);
    }
    for (d, n) in need.iter_mut().enumerate() {
        *n = class_need[&classes.find(d)];
    }
    // Shared edge points, evaluated once per canonical edge and segment count.
    let mut edge_points: HashMap<(EdgeKey, usize), Vec<Vec3>> = HashMap::new();
    let mut mesh = Welder::default();
    for (k, patch) in patches.iter().enumerate() {
        let (nu, nv) = (need[2 * k], need[2 * k + 1]);
        let (u0, u1) = patch.domain_u();
        let (v0, v1) = patch.domain_v();
        let mut grid = vec![Vec3::ZERO; (nu + 1) * (nv + 1)];
        let at = |i: usize, j: usize| i * (nv + 1) + j;
        for i in 0..=nu {
            for j in 0..=nv {
                let u = lerp(u0, u1, i, nu);
                let v = lerp(v0, v1, j, nv);
                grid[at(i, j)] = patch.point(u, v).as_vec3();
            }
        }
        // Overwrite the boundary with the canonical edge points.
        for (e, (key, reversed)) in keys[k].iter().enumerate() {
            let n = if e % 2 == 0 { nu } else { nv };
            let points = edge_points
                .entry((key.clone(), n))
                .or_insert_with(|| canonical_edge_points(key, n));
            for s in 0..=n {
                // Parameter index along the edge in its counter-clockwise direction.
                let p = points[if *reversed { n - s } else { s }];
                let idx = match e {
                    0 => at(s, 0),
                    1 => at(nu, s),
                    2 => at(nu - s, nv),
                    _ => at(0, nv - s),
                };
                grid[idx] = p;
            }
        }
        let ids: Vec<u32> = grid.iter().map(|&p| mesh.vertex(p)).collect();
        for i in 0..nu {
            for j in 0..nv {
                let cell = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                mesh.cell(cell.map(|c| ids[c]));
            }
        }
    }
    mesh.mesh
}

/// u or v at step `i` of `n` across [a, b], exact at both ends.
fn lerp(a: f64, b: f64, i: usize, n: usize) -> f64 {
    if i == n {
        b
    } else {
        a + (b - a) * i as f64 / n as f64
    }
}

/// Segment counts (n_u, n_v) that meet the chordal tolerance on this patch alone.
fn needed_segments(p: &NurbsSurface, tol: f64, max: usize) -> (usize, usize) {
    let (u0, u1) = p.domain_u();
    let (v0, v1) = p.domain_v();
    let across = [0.0, 0.25, 0.5, 0.75, 1.0];
    // Chordal error of the iso-curves along one direction with n segments.
    let iso_error = |along_u: bool, n: usize| {
        let mut worst: f64 = 0.0;
        for &s in &across {
            let eval = |t: f64| {
                if along_u {
                    p.point(u0 + (u1 - u0) * t, v0 + (v1 - v0) * s)
                } else {
                    p.point(u0 + (u1 - u0) * s, v0 + (v1 - v0) * t)
                }
            };
            for k in 0..n {
                let (a, b) = (k as f64 / n as f64, (k + 1) as f64 / n as f64);
                let (pa, pb) = (eval(a), eval(b));
                for f in [0.25, 0.5, 0.75] {
                    let chord = pa.lerp(pb, f);
                    worst = worst.max((eval(a + (b - a) * f) - chord).length());
                }
            }
        }
        worst
    };
    let grow = |n: usize, err: f64| -> usize {
        let factor = (err / tol).sqrt();
        ((n as f64 * factor).ceil() as usize).max(n + 1).min(max)
    };
    let mut n = [1usize, 1];
    for (d, nd) in n.iter_mut().enumerate() {
        loop {
            let err = iso_error(d == 0, *nd);
            if err <= tol || *nd >= max {
                break;
            }
            *nd = grow(*nd, err);
        }
    }
    // Twist: cell centres against the average of their corners.
    loop {
        let (nu, nv) = (n[0], n[1]);
        let mut worst: f64 = 0.0;
        for i in 0..nu {
            for j in 0..nv {
                let uv =
                    |a: usize, b: usize| p.point(lerp(u0, u1, a, 2 * nu), lerp(v0, v1, b, 2 * nv));
                let corners = uv(2 * i, 2 * j)
                    + uv(2 * i + 2, 2 * j)
                    + uv(2 * i, 2 * j + 2)
                    + uv(2 * i + 2, 2 * j + 2);
                worst = worst.max((uv(2 * i + 1, 2 * j + 1) - corners / 4.0).length());
            }
        }
        if worst <= tol || (nu >= max && nv >= max) {
            break;
        }
        n = [grow(nu, worst), grow(nv, worst)];
    }
    (n[0], n[1])
}

/// A boundary curve, identified by its exact control points and normalised knots in a
/// canonical direction.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct EdgeKey {
    bits: Vec<u64>,
    degenerate: bool,
}

fn key_bits(knots: &[f64], points: &[DVec4]) -> Vec<u64> {
    let (a, b) = (knots[0], knots[knots.len() - 1]);
    let mut bits: Vec<u64> = knots
        .iter()
        .map(|k| ((k - a) / (b - a)).to_bits())
        .collect();
    bits.push(u64::MAX);
    bits.extend(
        points
            .iter()
            .flat_map(|h| h.to_array().map(|x| (x + 0.0).to_bits())),
    );
    bits
}

/// The key of edge `e` (counter-clockwise around the patch) and whether its canonical
/// direction is the reverse of that.
fn edge_key(p: &NurbsSurface, e: usize) -> (EdgeKey, bool) {
    let (knots, points) = p.boundary(e);
    let (a, b) = (knots[0], knots[knots.len() - 1]);
    let rev_knots: Vec<f64> = knots.iter().rev().map(|k| a + b - k).collect();
    let rev_points: Vec<DVec4> = points.iter().rev().copied().collect();
    let fwd = key_bits(&knots, &points);
    let rev = key_bits(&rev_knots, &rev_points);
    let degenerate = points.windows(2).all(|w| w[0] == w[1]);
    if fwd <= rev {
        (
            EdgeKey {
                bits: fwd,
                degenerate,
            },
            false,
        )
    } else {
        (
            EdgeKey {
                bits: rev,
                degenerate,
            },
            true,
        )
    }
}

/// `n + 1` points along a canonical edge (knots normalised to [0, 1]).
fn canonical_edge_points(key: &EdgeKey, n: usize) -> Vec<Vec3> {
    let sep = key.bits.iter().position(|&b| b == u64::MAX).unwrap_or(0);
    let knots: Vec<f64> = key.bits[..sep].iter().map(|&b| f64::from_bits(b)).collect();
    let coords: Vec<f64> = key.bits[sep + 1..]
        .iter()
        .map(|&b| f64::from_bits(b))
        .collect();
    let homogeneous: Vec<DVec4> = coords.chunks_exact(4).map(DVec4::from_slice).collect();
    let points: Vec<DVec3> = homogeneous.iter().map(|h| h.truncate() / h.w).collect();
    let weights: Vec<f64> = homogeneous.iter().map(|h| h.w).collect();
    let degree = knots.len().saturating_sub(points.len() + 1);
    match Nurbs::new(degree, knots, &points, &weights) {
        Some(curve) => (0..=n)
            .map(|s| curve.point(lerp(0.0, 1.0, s, n)).as_vec3())
            .collect(),
        None => vec![points.first().copied().unwrap_or(DVec3::ZERO).as_vec3(); n + 1],
    }
}

/// Disjoint sets over grid directions.
struct UnionFind(Vec<usize>);

impl UnionFind {
    fn new(n: usize) -> Self {
        Self((0..n).collect())
    }

    fn find(&mut self, mut x: usize) -> usize {
        while self.0[x] != x {
            self.0[x] = self.0[self.0[x]];
            x = self.0[x];
        }
        x
    }

    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        self.0[ra.max(rb)] = ra.min(rb);
    }
}

/// Builds a mesh whose vertices are welded by exact position.
#[derive(Default)]
struct Welder {
    mesh: PolyMesh,
    index: HashMap<[u32; 3], u32>,
}

impl Welder {
    fn vertex(&mut self, p: Vec3) -> u32 {
        let key = (p + Vec3::ZERO).to_array().map(f32::to_bits);
        *self.index.entry(key).or_insert_with(|| {
            self.mesh.positions.push(p);
            self.mesh.positions.len() as u32 - 1
        })
    }

    /// Adds a grid cell (counter-clockwise) as a quad, two triangles, one triangle or nothing.
    fn cell(&mut self, c: [u32; 4]) {
        let mut ids: Vec<u32> = c.to_vec();
        ids.dedup();
        if ids.len() > 1 && ids[0] == ids[ids.len() - 1] {
            ids.pop();
        }
        let pos = |i: u32| self.mesh.positions[i as usize];
        match ids.len() {
            3 => self.triangle([ids[0], ids[1], ids[2]]),
            4 => {
                let vs: Vec<Vec3> = ids.iter().map(|&i| pos(i)).collect();
                let area = crate::polymesh::vector_area(&vs);
                let (d02, d13) = ((vs[2] - vs[0]).length(), (vs[3] - vs[1]).length());
                let size = d02.max(d13);
                let centre = vs.iter().copied().sum::<Vec3>() / 4.0;
                let n = area.normalize_or_zero();
                let bend = vs
                    .iter()
                    .map(|&v| n.dot(v - centre).abs())
                    .fold(0.0, f32::max);
                if bend <= 1e-3 * size && area.length() > 1e-6 * size * size {
                    self.mesh.faces.push(ids);
                } else if d02 <= d13 {
                    self.triangle([ids[0], ids[1], ids[2]]);
                    self.triangle([ids[0], ids[2], ids[3]]);
                } else {
                    self.triangle([ids[0], ids[1], ids[3]]);
                    self.triangle([ids[1], ids[2], ids[3]]);
                }
            }
            _ => {}
        }
    }

    /// Adds a triangle unless it has (nearly) zero area.
    fn triangle(&mut self, t: [u32; 3]) {
        let vs = t.map(|i| self.mesh.positions[i as usize]);
        let size = (vs[1] - vs[0])
            .length()
            .max((vs[2] - vs[0]).length())
            .max((vs[2] - vs[1]).length());
        let area = crate::polymesh::vector_area(&vs).length();
        if size > 0.0 && area > 1e-6 * size * size {
            self.mesh.faces.push(t.to_vec());
        }
    }
}
