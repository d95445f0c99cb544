//! CSG of closed meshes: volumes against closed forms and the inclusion–exclusion identity, and
//! every result closed and outward.

use std::f64::consts::PI;

use glam::Vec3;
use model::brep::{closed_topology, signed_volume};
use model::csg::{difference, intersection, union};
use model::primitives::{cuboid, icosphere};
use model::PolyMesh;

/// Asserts that `m` is a closed, oriented manifold with outward faces; returns its volume.
fn closed_volume(name: &str, m: &PolyMesh) -> f64 {
    let topo = closed_topology(m).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(topo.shells >= 1, "{name}");
    let v = signed_volume(m);
    assert!(v > 0.0, "{name}: inward faces ({v})");
    v
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn cube_minus_sphere_matches_analytic_volume() {
    let cube = cuboid(Vec3::splat(-1.0), Vec3::splat(1.0));
    let ball = icosphere(Vec3::ZERO, 0.8, 3);
    let d = difference(&cube, &ball);
    let v = closed_volume("cube ∖ ball", &d);
    // Exact against the polyhedra: the ball lies inside the cube, so vol = 8 − vol(ball mesh)
    // up to round-off.
    let exact = 8.0 - signed_volume(&ball);
    assert!(rel(v, exact) < 1e-5, "{v} vs {exact}");
    // And against the true sphere: the inscribed icosphere (1280 faces) is 1.5 % short of the
    // ball, which moves 8 − 4/3 π r³ by 0.4 %.
    let analytic = 8.0 - 4.0 / 3.0 * PI * 0.8f64.powi(3);
    assert!(rel(v, analytic) < 0.01, "{v} vs {analytic}");
    // The ball's surface is inside: a closed cube with a closed cavity, two shells.
    assert_eq!(closed_topology(&d).unwrap().shells, 2);
}

#[test]
fn sphere_cutting_a_corner_obeys_inclusion_exclusion() {
    let a = cuboid(Vec3::ZERO, Vec3::ONE);
    let b = icosphere(Vec3::splat(1.0), 0.6, 3);
    let (va, vb) = (signed_volume(&a), signed_volume(&b));
    let u = closed_volume("A ∪ B", &union(&a, &b));
    let i = closed_volume("A ∩ B", &intersection(&a, &b));
    let d = closed_volume("A ∖ B", &difference(&a, &b));
    let e = closed_volume("B ∖ A", &difference(&b, &a));
    // vol(A ∪ B) = vol A + vol B − vol(A ∩ B); vol A = vol(A ∖ B) + vol(A ∩ B).
    // Tolerance: f32 output coordinates, relative round-off ~1e-6.
    assert!(rel(u, va + vb - i) < 1e-5, "{u} vs {}", va + vb - i);
    assert!(rel(va, d + i) < 1e-5, "{va} vs {}", d + i);
    assert!(rel(vb, e + i) < 1e-5, "{vb} vs {}", e + i);
    // One octant of the ball is inside the cube (up to tessellation of the ball).
    assert!(rel(i, vb / 8.0) < 0.02, "{i} vs {}", vb / 8.0);
}

#[test]
fn coplanar_faces_fuse() {
    // Two unit cubes sharing the face x = 1, and a third overlapping on a coplanar top.
    let a = cuboid(Vec3::ZERO, Vec3::ONE);
    let b = cuboid(Vec3::new(1.0, 0.0, 0.0), Vec3::new(2.0, 1.0, 1.0));
    let ab = union(&a, &b);
    let v = closed_volume("side by side", &ab);
    assert!(rel(v, 2.0) < 1e-6, "{v}");
    // The shared wall is gone: the union's area is that of a 2 × 1 × 1 box.
    assert!(rel(ab.area(), 10.0) < 1e-6, "{}", ab.area());
    let c = cuboid(Vec3::new(0.5, 0.0, 0.5), Vec3::new(1.5, 1.0, 1.5));
    let abc = union(&ab, &c);
    let v = closed_volume("coplanar top and bottom", &abc);
    assert!(rel(v, 2.5) < 1e-6, "{v}");
    // Same-size cubes: A ∩ A = A, A ∖ A = ∅.
    let i = intersection(&a, &a);
    assert!(rel(closed_volume("A ∩ A", &i), 1.0) < 1e-6);
    assert!(difference(&a, &a).faces.is_empty());
    // Touching at a face only: the intersection is empty.
    assert!(signed_volume(&intersection(&a, &b)).abs() < 1e-9);
}

#[test]
fn drilled_part_has_a_through_hole() {
    // A box drilled through by a thin box: genus 1.
    let block = cuboid(Vec3::ZERO, Vec3::new(2.0, 1.0, 2.0));
    let drill = cuboid(Vec3::new(0.8, -1.0, 0.8), Vec3::new(1.2, 2.0, 1.2));
    let d = difference(&block, &drill);
    let topo = closed_topology(&d).unwrap();
    assert_eq!((topo.shells, topo.holes), (1, 1));
    assert!(rel(signed_volume(&d), 4.0 - 0.16) < 1e-6);
}
