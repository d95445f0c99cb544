//! Subdivision surfaces: Catmull-Clark (1978) for polygon meshes and Loop (1987) for
//! triangle meshes, with boundaries kept as creases.
//!
//! **Catmull-Clark.** Each face gets a face point F = average of its corners; each edge an
//! edge point (v₀ + v₁ + F_a + F_b)/4; each vertex of valence n moves to
//! (Q + 2R + (n − 3)P)/n, with Q the average of the adjacent face points and R of the
//! adjacent edge midpoints. Every k-gon becomes k quads (corner, edge point, face point, edge
//! point). The limit is a bicubic B-spline surface away from extraordinary vertices (C² there,
//! C¹ at them).
//!
//! **Loop.** Each edge gets (3/8)(v₀ + v₁) + (1/8)(a + b), a and b the opposite corners of its
//! two triangles; each vertex of valence n moves to (1 − nβ)P + β Σ neighbours, with Loop's
//! β = (1/n)(5/8 − (3/8 + ¼ cos(2π/n))²). Every triangle becomes four. The limit is a box
//! spline surface (quartic, C²) away from extraordinary vertices. Non-triangles are first
//! split into fans.
//!
//! **Boundaries as creases** (Hoppe et al. 1994): an edge with one face gets its midpoint, and a
//! vertex on exactly two boundary edges moves to (P₋ + 6P + P₊)/8 — the cubic B-spline rule,
//! so the boundary converges to the B-spline curve of the boundary polygon, independent of the
//! interior. Corners (a vertex with only its two boundary edges) and non-manifold vertices
//! stay fixed.
//!
//! Topology: a Catmull-Clark step gives V′ = V + E + F, E′ = 2E + Σ k_f, F′ = Σ k_f, so
//! V′ − E′ + F′ = V − E + F; a Loop step gives V′ = V + E, E′ = 2E + 3F, F′ = 4F, the same
//! again. A closed genus-0 mesh keeps Euler characteristic 2 at every level.

use std::collections::HashMap;

use glam::{DVec3, Vec3};

use crate::PolyMesh;

/// The subdivision scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    /// Catmull-Clark: any polygons in, quads out.
    CatmullClark,
    /// Loop: triangles in (others are fanned), triangles out.
    Loop,
}

/// Applies `scheme` `levels` times.
#[must_use]
pub fn subdivide(mesh: &PolyMesh, scheme: Scheme, levels: u32) -> PolyMesh {
    let mut m = mesh.clone();
    for _ in 0..levels {
        m = match scheme {
            Scheme::CatmullClark => catmull_clark_step(&m),
            Scheme::Loop => loop_step(&m),
        };
    }
    m
}

/// Undirected edges with the faces that use them, in first-seen order.
struct Edges {
    index: HashMap<(u32, u32), usize>,
    ends: Vec<(u32, u32)>,
    faces: Vec<Vec<usize>>,
}

impl Edges {
    fn new(mesh: &PolyMesh) -> Self {
        let mut e = Self {
            index: HashMap::new(),
            ends: Vec::new(),
            faces: Vec::new(),
        };
        for (f, face) in mesh.faces.iter().enumerate() {
            for k in 0..face.len() {
                let (a, b) = (face[k], face[(k + 1) % face.len()]);
                let key = (a.min(b), a.max(b));
                let next = e.ends.len();
                let i = *e.index.entry(key).or_insert(next);
                if i == next {
                    e.ends.push(key);
                    e.faces.push(Vec::new());
                }
                e.faces[i].push(f);
            }
        }
        e
    }

    fn id(&self, a: u32, b: u32) -> usize {
        self.index[&(a.min(b), a.max(b))]
    }

    fn is_boundary(&self, e: usize) -> bool {
        self.faces[e].len() == 1
    }

    /// Per vertex: neighbours across edges and neighbours across boundary edges.
    fn neighbours(&self, vertices: usize) -> (Vec<Vec<u32>>, Vec<Vec<u32>>) {
        let mut all = vec![Vec::new(); vertices];
        let mut boundary = vec![Vec::new(); vertices];
        for (e, &(a, b)) in self.ends.iter().enumerate() {
            all[a as usize].push(b);
            all[b as usize].push(a);
            if self.is_boundary(e) {
                boundary[a as usize].push(b);
                boundary[b as usize].push(a);
            }
        }
        (all, boundary)
    }
}

/// The crease rule for a vertex touching a boundary, `None` for interior vertices.
fn crease_vertex(p: DVec3, pos: &[DVec3], all: &[u32], boundary: &[u32]) -> Option<DVec3> {
    match boundary.len() {
        0 if !all.is_empty() => None,
        // On two boundary edges and nothing else: a corner of a single face, kept sharp.
        2 if all.len() > 2 => {
            Some((pos[boundary[0] as usize] + 6.0 * p + pos[boundary[1] as usize]) / 8.0)
        }
        _ => Some(p),
    }
}

fn to_f64(mesh: &PolyMesh) -> Vec<DVec3> {
    mesh.positions.iter().map(|p| p.as_dvec3()).collect()
}

fn to_f32(points: &[DVec3]) -> Vec<Vec3> {
    points.iter().map(|p| p.as_vec3()).collect()
}

/// One Catmull-Clark step.
fn catmull_clark_step(mesh: &PolyMesh) -> PolyMesh {
    let pos = to_f64(mesh);
    let edges = Edges::new(mesh);
    let (nv, ne) = (pos.len(), edges.ends.len());
    let face_points: Vec<DVec3> = mesh
        .faces
        .iter()
        .map(|f| f.iter().map(|&i| pos[i as usize]).sum::<DVec3>() / f.len() as f64)
        .collect();
    let edge_points: Vec<DVec3> = (0..ne)
        .map(|e| {
            let (a, b) = edges.ends[e];
            let (pa, pb) = (pos[a as usize], pos[b as usize]);
            if edges.faces[e].len() == 2 {
                let fs = &edges.faces[e];
                (pa + pb + face_points[fs[0]] + face_points[fs[1]]) / 4.0
            } else {
                (pa + pb) / 2.0
            }
        })
        .collect();
    // Adjacent face-point sums per vertex.
    let mut q = vec![(DVec3::ZERO, 0usize); nv];
    for (f, face) in mesh.faces.iter().enumerate() {
        for &i in face {
            q[i as usize].0 += face_points[f];
            q[i as usize].1 += 1;
        }
    }
    let (all, boundary) = edges.neighbours(nv);
    let vertex_points: Vec<DVec3> = (0..nv)
        .map(|v| {
            let p = pos[v];
            if let Some(c) = crease_vertex(p, &pos, &all[v], &boundary[v]) {
                return c;
            }
            let n = all[v].len() as f64;
            let qf = q[v].0 / q[v].1 as f64;
            let r = all[v]
                .iter()
                .map(|&w| (p + pos[w as usize]) / 2.0)
                .sum::<DVec3>()
                / n;
            (qf + 2.0 * r + (n - 3.0) * p) / n
        })
        .collect();
    let mut positions = vertex_points;
    positions.extend(edge_points);
    positions.extend(face_points);
    let mut faces = Vec::new();
    for (f, face) in mesh.faces.iter().enumerate() {
        let k = face.len();
        let fp = (nv + ne + f) as u32;
        for i in 0..k {
            let (prev, cur, next) = (face[(i + k - 1) % k], face[i], face[(i + 1) % k]);
            faces.push(vec![
                cur,
                (nv + edges.id(cur, next)) as u32,
                fp,
                (nv + edges.id(prev, cur)) as u32,
            ]);
        }
    }
    PolyMesh {
        positions: to_f32(&positions),
        faces,
    }
}

/// Splits every face with more than three corners into a fan of triangles.
fn triangulate(mesh: &PolyMesh) -> PolyMesh {
    let faces = mesh
        .faces
        .iter()
        .flat_map(|f| (1..f.len().saturating_sub(1)).map(move |i| vec![f[0], f[i], f[i + 1]]))
        .collect();
    PolyMesh {
        positions: mesh.positions.clone(),
        faces,
    }
}

/// One Loop step.
fn loop_step(mesh: &PolyMesh) -> PolyMesh {
    let mesh = triangulate(mesh);
    let pos = to_f64(&mesh);
    let edges = Edges::new(&mesh);
    let (nv, ne) = (pos.len(), edges.ends.len());
    let edge_points: Vec<DVec3> = (0..ne)
        .map(|e| {
            let (a, b) = edges.ends[e];
            let (pa, pb) = (pos[a as usize], pos[b as usize]);
            if edges.faces[e].len() != 2 {
                return (pa + pb) / 2.0;
            }
            // The corners of the two triangles opposite the edge.
            let opposite = |f: usize| {
                let t = &mesh.faces[f];
                let o = t.iter().find(|&&i| i != a && i != b).copied().unwrap_or(a);
                pos[o as usize]
            };
            let fs = &edges.faces[e];
            0.375 * (pa + pb) + 0.125 * (opposite(fs[0]) + opposite(fs[1]))
        })
        .collect();
    let (all, boundary) = edges.neighbours(nv);
    let mut positions: Vec<DVec3> = (0..nv)
        .map(|v| {
            let p = pos[v];
            if let Some(c) = crease_vertex(p, &pos, &all[v], &boundary[v]) {
                return c;
            }
            let n = all[v].len() as f64;
            let c = 0.375 + 0.25 * (2.0 * std::f64::consts::PI / n).cos();
            let beta = (0.625 - c * c) / n;
            (1.0 - n * beta) * p + beta * all[v].iter().map(|&w| pos[w as usize]).sum::<DVec3>()
        })
        .collect();
    positions.extend(edge_points);
    let faces = mesh
        .faces
        .iter()
        .flat_map(|t| {
            let (a, b, c) = (t[0], t[1], t[2]);
            let ab = (nv + edges.id(a, b)) as u32;
            let bc = (nv + edges.id(b, c)) as u32;
            let ca = (nv + edges.id(c, a)) as u32;
            [
                vec![a, ab, ca],
                vec![ab, b, bc],
                vec![ca, bc, c],
                vec![ab, bc, ca],
            ]
        })
        .collect();
    PolyMesh {
        positions: to_f32(&positions),
        faces,
    }
}
