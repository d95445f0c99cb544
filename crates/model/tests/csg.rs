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

/// Volume of the cube [−h, h]³ minus the concentric ball of radius ρ, for h < ρ < h√2: the
/// ball pokes through the six faces as spherical caps of height ρ − h, each of volume
/// π c² (3ρ − c) / 3, and does not reach the cube's edges.
fn cube_minus_ball(h: f64, rho: f64) -> f64 {
    let c = rho - h;
    let cap = PI * c * c * (3.0 * rho - c) / 3.0;
    8.0 * h.powi(3) - (4.0 / 3.0 * PI * rho.powi(3) - 6.0 * cap)
}

/// The radius of the largest ball about the origin inside a convex mesh: the least distance
/// of a face plane from the origin.
fn inradius(m: &PolyMesh) -> f64 {
    m.faces
        .iter()
        .map(|f| {
            let [a, b, c] = [f[0], f[1], f[2]].map(|i| m.positions[i as usize].as_dvec3());
            (b - a).cross(c - a).normalize().dot(a)
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn sphere_cutting_the_faces_leaves_a_closed_frame() {
    // The case that used to leave an open edge: cube half-size 0.45, ball radius 0.58.
    let (h, r) = (0.45f32, 0.58f32);
    let cube = cuboid(Vec3::splat(-h), Vec3::splat(h));
    let ball = icosphere(Vec3::ZERO, r, 3);
    let (h, r) = (f64::from(h), f64::from(r));
    let d = difference(&cube, &ball);
    let v = closed_volume("cube ∖ ball", &d);
    // Six round windows, one per face, leave the cube's frame of twelve bars: one shell of
    // genus 5, so V − E + F = 2 (1 − 5) = −8.
    let topo = closed_topology(&d).unwrap();
    assert_eq!((topo.shells, topo.holes), (1, 5));
    assert_eq!(
        topo.vertices as i64 - topo.edges as i64 + topo.faces as i64,
        -8
    );
    // The inscribed icosphere contains the ball of its inradius and lies in the ball of radius
    // r, and the removed volume grows with the radius: the result lies between the analytic
    // values for the two radii (both between h and h√2). Tolerance 1e-5: f32 coordinates.
    let r_in = inradius(&ball);
    assert!(r_in > h && r < h * 2f64.sqrt(), "{r_in}");
    let (lo, hi) = (cube_minus_ball(h, r), cube_minus_ball(h, r_in));
    assert!(
        v > lo * (1.0 - 1e-5) && v < hi * (1.0 + 1e-5),
        "{v} not in [{lo}, {hi}]"
    );
    // So the true solid's volume is matched to within the tessellation's spread, a few percent.
    assert!(rel(v, lo) < 0.05, "{v} vs {lo}");
}

#[test]
fn sweep_of_spheres_through_a_cube_stays_closed() {
    // Sizes from through the faces to past the corners, centred and off-centre (avoiding
    // tangency, where the true result is not a manifold): every Boolean result is a closed,
    // outward manifold, and A ∖ B and A ∩ B add up to A. The sweep must also terminate.
    let h = 0.45f32;
    let cube = cuboid(Vec3::splat(-h), Vec3::splat(h));
    let va = signed_volume(&cube);
    for subdivisions in [2, 3] {
        for (k, centre) in [Vec3::ZERO, Vec3::new(0.031, -0.017, 0.023)]
            .into_iter()
            .enumerate()
        {
            for r in [0.47f32, 0.5, 0.55, 0.58, 0.62, 0.7, 0.76] {
                let ball = icosphere(centre, r, subdivisions);
                let name = format!("subdivisions {subdivisions}, centre {k}, r {r}");
                let d = difference(&cube, &ball);
                let i = intersection(&cube, &ball);
                let vd = if d.faces.is_empty() {
                    0.0
                } else {
                    closed_volume(&format!("A ∖ B, {name}"), &d)
                };
                let vi = closed_volume(&format!("A ∩ B, {name}"), &i);
                closed_volume(&format!("A ∪ B, {name}"), &union(&cube, &ball));
                assert!(rel(vd + vi, va) < 1e-4, "{name}: {vd} + {vi} vs {va}");
            }
        }
    }
}

#[test]
fn booleans_chain_on_their_own_output() {
    // A Boolean's output (f32 corners, T-junction vertices in its edges) is a valid operand:
    // the cube's frame left by the ball, drilled by a bar through one of its edges.
    let frame = difference(
        &cuboid(Vec3::splat(-0.45), Vec3::splat(0.45)),
        &icosphere(Vec3::ZERO, 0.58, 3),
    );
    let bar = cuboid(Vec3::new(0.3, -1.0, 0.3), Vec3::new(0.37, 1.0, 0.37));
    let vf = closed_volume("frame", &frame);
    let drilled = difference(&frame, &bar);
    let vd = closed_volume("frame ∖ bar", &drilled);
    let vi = closed_volume("frame ∩ bar", &intersection(&frame, &bar));
    assert!(rel(vd + vi, vf) < 1e-5, "{vd} + {vi} vs {vf}");
    // The bar pierces the frame's top and bottom plates beside the corner x = z = 0.45 (there
    // x² + z² + 0.45² > 0.58²) and runs through the empty ball between them (at y = 0,
    // x² + z² < 0.58²): each piercing joins outside to outside, one more handle each.
    let topo = closed_topology(&drilled).unwrap();
    assert_eq!((topo.shells, topo.holes), (1, 5 + 2));
}
