//! Properties of patches, surfaces of revolution, sweeps, subdivision surfaces and their
//! tessellation, each with a stated tolerance.

use std::collections::HashMap;

use glam::{DVec3, Vec3};
use model::curve::{Curve, Nurbs};
use model::polymesh::vector_area;
use model::primitives::cuboid;
use model::surface::revolve::revolve;
use model::surface::subdivision::{subdivide, Scheme};
use model::surface::sweep::extrude;
use model::surface::{tessellate, NurbsSurface, TessellationSettings};
use model::teapot::teapot_patches;
use model::PolyMesh;

/// Directed-edge counts: (a, b) → uses.
fn half_edges(m: &PolyMesh) -> HashMap<(u32, u32), usize> {
    let mut h = HashMap::new();
    for f in &m.faces {
        for k in 0..f.len() {
            *h.entry((f[k], f[(k + 1) % f.len()])).or_insert(0) += 1;
        }
    }
    h
}

/// Closed, consistently oriented 2-manifold: every directed edge once and its reverse once.
fn assert_closed_oriented(m: &PolyMesh) {
    let h = half_edges(m);
    for (&(a, b), &n) in &h {
        assert_eq!(n, 1, "edge {a}-{b} used {n} times in one direction");
        assert_eq!(h.get(&(b, a)), Some(&1), "edge {a}-{b} has no twin");
    }
}

fn euler(m: &PolyMesh) -> i64 {
    let h = half_edges(m);
    let e = h
        .keys()
        .filter(|(a, b)| a < b || !h.contains_key(&(*b, *a)))
        .count();
    m.positions.len() as i64 - e as i64 + m.faces.len() as i64
}

/// Boundary edges (used once, no twin) and their total length.
fn boundary_length(m: &PolyMesh) -> f64 {
    let h = half_edges(m);
    h.keys()
        .filter(|(a, b)| !h.contains_key(&(*b, *a)))
        .map(|&(a, b)| f64::from((m.positions[a as usize] - m.positions[b as usize]).length()))
        .sum()
}

fn bumpy_patch() -> NurbsSurface {
    let mut p = Vec::new();
    for i in 0..4 {
        for j in 0..4 {
            let h = if (1..3).contains(&i) && (1..3).contains(&j) {
                2.0
            } else {
                0.0
            };
            p.push(DVec3::new(
                i as f64,
                h * ((i + j) % 2) as f64 + 0.3 * j as f64,
                j as f64,
            ));
        }
    }
    NurbsSurface::bezier(4, 4, &p).unwrap()
}

#[test]
fn bezier_patch_interpolates_its_corners_and_has_the_cross_product_normal() {
    let s = bumpy_patch();
    let h = s.homogeneous();
    for (u, v, k) in [(0.0, 0.0, 0), (1.0, 0.0, 12), (0.0, 1.0, 3), (1.0, 1.0, 15)] {
        assert!((s.point(u, v) - h[k].truncate()).length() < 1e-12);
    }
    // Partial derivatives against central differences (h = 1e-5, error ~1e-9).
    let (_, su, sv) = s.evaluate(0.3, 0.6);
    let d = 1e-5;
    let fu = (s.point(0.3 + d, 0.6) - s.point(0.3 - d, 0.6)) / (2.0 * d);
    let fv = (s.point(0.3, 0.6 + d) - s.point(0.3, 0.6 - d)) / (2.0 * d);
    assert!((su - fu).length() < 1e-6 && (sv - fv).length() < 1e-6);
    // Flipping reverses the normal and keeps the surface.
    let f = s.flipped();
    assert!((f.point(0.7, 0.6) - s.point(0.3, 0.6)).length() < 1e-12);
    assert!((f.normal(0.7, 0.6) + s.normal(0.3, 0.6)).length() < 1e-9);
}

#[test]
fn revolved_semicircle_is_an_exact_sphere_with_outward_normals() {
    // Profile: the right half of the unit circle in the xy-plane, running up the y axis.
    let arc = Nurbs::new(
        2,
        vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0],
        &[
            DVec3::new(0.0, -1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ],
        &[
            1.0,
            std::f64::consts::FRAC_1_SQRT_2,
            1.0,
            std::f64::consts::FRAC_1_SQRT_2,
            1.0,
        ],
    )
    .unwrap();
    let s = revolve(&arc, DVec3::ZERO, DVec3::Y, 360.0).unwrap();
    for i in 0..=20 {
        for j in 1..20 {
            let (u, v) = (i as f64 / 20.0, j as f64 / 20.0);
            let p = s.point(u, v);
            assert!((p.length() - 1.0).abs() < 1e-12, "{p}");
            assert!(s.normal(u, v).dot(p) > 0.999, "normal not outward");
        }
    }
    // Tessellated: vertices on the sphere (f32: 1e-6), closed, outward, and within the
    // chordal tolerance: a face centre is at most ε inside the sphere.
    let tol = 0.005;
    let m = tessellate(
        std::slice::from_ref(&s),
        &TessellationSettings {
            tolerance: tol,
            max_segments: 64,
        },
    );
    assert_closed_oriented(&m);
    assert_eq!(euler(&m), 2);
    for f in 0..m.faces.len() {
        let vs = m.face_positions(f);
        let c = vs.iter().copied().sum::<Vec3>() / vs.len() as f32;
        assert!(vector_area(&vs).dot(c) > 0.0, "face {f} inward");
        assert!(
            f64::from(1.0 - c.length()) < tol * 1.5,
            "face {f} too far: {}",
            c.length()
        );
    }
    for p in &m.positions {
        assert!((p.length() - 1.0).abs() < 1e-6);
    }
    let exact = 4.0 * std::f64::consts::PI;
    assert!((m.area() - exact).abs() / exact < 0.01, "{}", m.area());
}

#[test]
fn extruded_circle_is_a_cylinder() {
    let circle = Nurbs::circle(DVec3::ZERO, 2.0, DVec3::X, DVec3::Z);
    let s = extrude(&circle, DVec3::new(0.0, 3.0, 0.0)).unwrap();
    for i in 0..=16 {
        for j in 0..=4 {
            let p = s.point(i as f64 / 16.0, j as f64 / 4.0);
            assert!((DVec3::new(p.x, 0.0, p.z).length() - 2.0).abs() < 1e-12);
            assert!((p.y - 3.0 * j as f64 / 4.0).abs() < 1e-12);
        }
    }
    assert!((circle.point(0.3).length() - 2.0).abs() < 1e-12);
}

#[test]
fn tessellated_patches_meet_without_gaps() {
    // A curved patch and a flat one share the edge v = 0 of the first (reversed in the second):
    // the curved one needs many more segments there. After tessellation the only boundary is
    // the outer one: its length matches the outer boundary curves' length (chords are at most
    // 0.5 % shorter at this tolerance), so not one edge of the seam is open.
    let a = bumpy_patch();
    let h = a.homogeneous();
    let seam: Vec<DVec3> = (0..4).map(|i| h[i * 4].truncate()).collect();
    let mut p = Vec::new();
    for i in (0..4).rev() {
        for j in 0..4 {
            p.push(seam[i] - DVec3::Z * j as f64);
        }
    }
    let b = NurbsSurface::bezier(4, 4, &p).unwrap();
    let settings = TessellationSettings {
        tolerance: 0.002,
        max_segments: 64,
    };
    let m = tessellate(&[a.clone(), b.clone()], &settings);
    let arc = |s: &NurbsSurface, e: usize| {
        let pts: Vec<DVec3> = (0..=2000)
            .map(|k| {
                let t = k as f64 / 2000.0;
                match e {
                    0 => s.point(t, 0.0),
                    1 => s.point(1.0, t),
                    2 => s.point(t, 1.0),
                    _ => s.point(0.0, t),
                }
            })
            .collect();
        pts.windows(2).map(|w| (w[1] - w[0]).length()).sum::<f64>()
    };
    let outer = arc(&a, 1) + arc(&a, 2) + arc(&a, 3) + arc(&b, 1) + arc(&b, 2) + arc(&b, 3);
    let got = boundary_length(&m);
    assert!(
        got <= outer * 1.000_001 && got >= outer * 0.995,
        "boundary {got} vs outer {outer}"
    );
    // No directed edge twice: consistent orientation across the seam.
    assert!(half_edges(&m).values().all(|&n| n == 1));
}

#[test]
fn teapot_has_32_patches_and_a_crack_free_consistent_tessellation() {
    let patches = teapot_patches();
    assert_eq!(patches.len(), 32);
    let m = tessellate(&patches, &TessellationSettings::default());
    assert!(
        half_edges(&m).values().all(|&n| n == 1),
        "inconsistent orientation"
    );
    // Boundary curves not shared by two patches (the rim's inner lip, the lid's edge, the
    // ends of the handle and spout): the mesh's open boundary must be exactly those.
    let mut uses: HashMap<Vec<[u64; 3]>, (usize, f64)> = HashMap::new();
    for p in &patches {
        for e in 0..4 {
            let (_, pts) = p.boundary(e);
            let mut key: Vec<[u64; 3]> = pts
                .iter()
                .map(|h| (h.truncate() / h.w).to_array().map(|x| (x + 0.0).to_bits()))
                .collect();
            let rev: Vec<[u64; 3]> = key.iter().rev().copied().collect();
            if rev < key {
                key = rev;
            }
            if pts.windows(2).all(|w| w[0] == w[1]) {
                continue;
            }
            let len: f64 = (0..200)
                .map(|k| {
                    let c = |t: f64| {
                        let (u0, u1) = p.domain_u();
                        let (v0, v1) = p.domain_v();
                        match e {
                            0 => p.point(u0 + (u1 - u0) * t, v0),
                            1 => p.point(u1, v0 + (v1 - v0) * t),
                            2 => p.point(u0 + (u1 - u0) * t, v1),
                            _ => p.point(u0, v0 + (v1 - v0) * t),
                        }
                    };
                    (c((k + 1) as f64 / 200.0) - c(k as f64 / 200.0)).length()
                })
                .sum();
            let entry = uses.entry(key).or_insert((0, len));
            entry.0 += 1;
        }
    }
    let open: f64 = uses.values().filter(|(n, _)| *n == 1).map(|(_, l)| l).sum();
    let got = boundary_length(&m);
    // Chords of a tessellation at ε = 0.01 on curves of radius ≥ 0.2 are within 2 % of arcs.
    assert!(
        (got - open).abs() / open < 0.02,
        "mesh boundary {got} vs open curves {open}"
    );
}

#[test]
fn catmull_clark_cube_stays_closed_with_euler_characteristic_2() {
    let mut m = cuboid(Vec3::splat(-1.0), Vec3::splat(1.0));
    let mut prev_angle = f32::MAX;
    for level in 0..5 {
        assert_closed_oriented(&m);
        assert_eq!(euler(&m), 2, "level {level}");
        // Smoothing: the largest angle between neighbouring face normals shrinks.
        let normals: Vec<Vec3> = (0..m.faces.len())
            .map(|f| vector_area(&m.face_positions(f)).normalize())
            .collect();
        let mut edge_faces: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
        for (f, face) in m.faces.iter().enumerate() {
            for k in 0..face.len() {
                let (a, b) = (face[k], face[(k + 1) % face.len()]);
                edge_faces.entry((a.min(b), a.max(b))).or_default().push(f);
            }
        }
        let angle = edge_faces
            .values()
            .map(|fs| normals[fs[0]].angle_between(normals[fs[1]]))
            .fold(0.0, f32::max);
        assert!(angle < prev_angle, "level {level}: {angle}");
        prev_angle = angle;
        m = subdivide(&m, Scheme::CatmullClark, 1);
    }
    // Level 5 has 6·4⁵ quads. Every vertex is an average of cube points, so it lies inside the
    // cube (|p| ≤ √3); the limit surface bulges little, so no vertex is nearer than 0.5.
    assert_eq!(m.faces.len(), 6 * 4usize.pow(5));
    assert!(m
        .positions
        .iter()
        .all(|p| p.length() > 0.5 && p.length() <= 3f32.sqrt() + 1e-6));
}

#[test]
fn loop_subdivision_stays_closed_and_keeps_euler_characteristic() {
    let mut m = cuboid(Vec3::splat(-1.0), Vec3::splat(1.0));
    for level in 1..=4 {
        m = subdivide(&m, Scheme::Loop, 1);
        assert_closed_oriented(&m);
        assert_eq!(euler(&m), 2, "level {level}");
        assert!(m.faces.iter().all(|f| f.len() == 3));
    }
    assert_eq!(m.faces.len(), 12 * 4usize.pow(4));
}

#[test]
fn boundaries_are_creases() {
    // An open box (no top): the boundary rule uses boundary points only, so the rim stays in
    // the plane y = 1 (to f32 rounding) at every level, with both schemes, and the mesh keeps
    // Euler characteristic 1 (a disc).
    let mut open = cuboid(Vec3::splat(-1.0), Vec3::splat(1.0));
    open.faces.remove(3);
    for scheme in [Scheme::CatmullClark, Scheme::Loop] {
        let mut m = open.clone();
        for _ in 0..3 {
            m = subdivide(&m, scheme, 1);
            assert_eq!(euler(&m), 1);
            let h = half_edges(&m);
            for &(a, b) in h.keys().filter(|(a, b)| !h.contains_key(&(*b, *a))) {
                for v in [a, b] {
                    assert!((m.positions[v as usize].y - 1.0).abs() < 1e-6);
                }
            }
        }
    }
}
