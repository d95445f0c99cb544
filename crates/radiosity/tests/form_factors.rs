//! Form factors against closed forms and identities: Lambert's point-to-polygon formula, element
//! sums through the mesh, reciprocity, closed-enclosure row sums, ray-cast visibility.

use glam::DVec3;
use radiosity::formfactor::analytic::{
    parallel_rectangles, perpendicular_rectangles, point_to_polygon,
};
use radiosity::formfactor::{self, analytic, raycast, FormFactors, Settings};
use radiosity::mesh::Subdivision;
use radiosity::testing::{self, Prepared};

mod common;

use common::patch_to_patch;

fn analytic(quadrature: u32) -> Box<dyn FormFactors> {
    formfactor::build(&Settings::Analytic(analytic::Settings { quadrature }))
}

fn raycast(quadrature: u32, rays: u32) -> Box<dyn FormFactors> {
    formfactor::build(&Settings::RayCast(raycast::Settings {
        quadrature,
        rays,
        seed: 7,
    }))
}

#[test]
fn point_to_square_matches_catalogue() {
    let (point, normal, square) = testing::point_to_square();
    let f = point_to_polygon(point, normal, &square);
    // Howell B-3 four times, printed to 7 digits.
    assert!((f - 0.239_456_5).abs() < 1e-6, "{f}");
}

#[test]
fn point_to_coaxial_disk_is_r2_over_h2_plus_r2() {
    // A regular 4096-gon inscribed in the disk lacks a fraction ≈ (2π²/3)/N² ≈ 4e-7 of its
    // area, all near the rim; the form factor differs by less than that.
    let sides = 4096;
    for (radius, height) in [(1.0, 1.0), (0.5, 2.0), (3.0, 0.25)] {
        // Counter-clockwise seen from below (the disk faces down, towards the point).
        let disk: Vec<DVec3> = (0..sides)
            .map(|k| {
                let a = -2.0 * std::f64::consts::PI * f64::from(k) / f64::from(sides);
                DVec3::new(radius * a.cos(), radius * a.sin(), height)
            })
            .collect();
        let f = point_to_polygon(DVec3::ZERO, DVec3::Z, &disk);
        let exact = radius * radius / (height * height + radius * radius);
        assert!(
            (f - exact).abs() < 1e-6,
            "R {radius} h {height}: {f} vs {exact}"
        );
    }
}

#[test]
fn polygon_below_the_horizon_is_clipped() {
    // A wall at x = 1 facing −x, straddling the point's tangent plane z = 0.
    let wall = |z0: f64| {
        vec![
            DVec3::new(1.0, -0.5, z0),
            DVec3::new(1.0, -0.5, 1.0),
            DVec3::new(1.0, 0.5, 1.0),
            DVec3::new(1.0, 0.5, z0),
        ]
    };
    let straddling = point_to_polygon(DVec3::ZERO, DVec3::Z, &wall(-1.0));
    let clipped = point_to_polygon(DVec3::ZERO, DVec3::Z, &wall(0.0));
    assert!(
        (straddling - clipped).abs() < 1e-12,
        "{straddling} {clipped}"
    );
    // Independent check: the midpoint rule on cosθ cosθ' / (π r²) over the clipped wall, whose
    // integrand is smooth away from the point; 400² cells are good to about 1e-5.
    let n = 400;
    let mut brute = 0.0;
    for i in 0..n {
        for j in 0..n {
            let y = -0.5 + (f64::from(i) + 0.5) / f64::from(n);
            let z = (f64::from(j) + 0.5) / f64::from(n);
            let r2 = 1.0 + y * y + z * z;
            // cosθ = z/r at the point, cosθ' = 1/r at the wall.
            brute += z / (std::f64::consts::PI * r2 * r2) / f64::from(n * n);
        }
    }
    assert!((clipped - brute).abs() < 1e-5, "{clipped} vs {brute}");
}

#[test]
fn element_sums_match_closed_forms() {
    // 256 elements per square, 2 × 2 points each: a 32 × 32 midpoint rule on the receiver,
    // measured 3e-5 off for the parallel squares and 7e-6 for the perpendicular ones; 2e-4
    // leaves room for f32 storage and the visibility rays (all free here).
    let cases = [
        (
            testing::parallel_squares(1.0),
            parallel_rectangles(1.0, 1.0, 1.0),
        ),
        (
            testing::perpendicular_squares(),
            perpendicular_rectangles(1.0, 1.0, 1.0),
        ),
    ];
    for (scene, exact) in cases {
        assert!((exact - 0.1998249).abs() < 1e-7 || (exact - 0.2000438).abs() < 1e-7);
        let p = Prepared::new(&scene, Subdivision::Elements(512), 2);
        let g = p.geometry();
        assert_eq!(g.sources.len(), 2, "one source per square");
        for ff in [analytic(2), raycast(2, 4)] {
            for (from, to) in [(0, 1), (1, 0)] {
                let f = patch_to_patch(&g, ff.as_ref(), from, to);
                assert!((f - exact).abs() < 2e-4, "{}: {f} vs {exact}", scene.name);
            }
        }
    }
}

#[test]
fn rows_and_columns_agree_bit_for_bit() {
    let scene = testing::half_blocked_squares();
    let p = Prepared::new(&scene, Subdivision::MaxArea(0.07), usize::MAX);
    let g = p.geometry();
    let (n, m) = (p.mesh.element_count(), g.sources.len());
    for ff in [analytic(2), raycast(2, 8)] {
        let mut rows = vec![0.0; n * m];
        for (e, row) in rows.chunks_mut(m).enumerate() {
            ff.row(&g, e, row);
        }
        let mut column = vec![0.0; n];
        for s in 0..m {
            ff.column(&g, s, &mut column);
            for e in 0..n {
                assert_eq!(
                    rows[e * m + s].to_bits(),
                    column[e].to_bits(),
                    "pair {e} {s}"
                );
            }
        }
    }
}

#[test]
fn reciprocity_holds_between_elements() {
    // A_i F_ij = A_j F_ji holds exactly for exact form factors; here the receiver's 4 × 4
    // midpoint rule is the only error. It is largest for neighbours across a cube edge, whose
    // kernel is singular along that edge: 2 % of the larger side bounds it there.
    let p = Prepared::new(
        &testing::closed_cube(0.5, [0.0; 6]),
        Subdivision::Elements(96),
        1000,
    );
    let g = p.geometry();
    let n = p.mesh.element_count();
    assert_eq!(g.sources.len(), n);
    let ff = analytic(4);
    let mut matrix = vec![0.0f32; n * n];
    for (e, row) in matrix.chunks_mut(n).enumerate() {
        ff.row(&g, e, row);
    }
    let area = |e: usize| p.mesh.element(e).area();
    let mut worst: f64 = 0.0;
    for i in 0..n {
        for j in 0..i {
            let (a, b) = (
                area(i) * f64::from(matrix[i * n + j]),
                area(j) * f64::from(matrix[j * n + i]),
            );
            if a.max(b) > 0.0 {
                worst = worst.max((a - b).abs() / a.max(b));
            }
        }
    }
    assert!(worst < 0.02, "worst relative reciprocity error {worst}");
}

#[test]
fn rows_of_the_closed_cube_sum_to_one() {
    // Lambert's formula is exact at each quadrature point and the sources tile the cube, so
    // each row sums to 1 up to the f32 rounding of its ~100 entries (1e-6). Ray casting sees no
    // blocker in a convex enclosure, so it must give exactly the analytic values.
    let p = Prepared::new(
        &testing::closed_cube(0.5, [0.0; 6]),
        Subdivision::Elements(384),
        1000,
    );
    let g = p.geometry();
    let (n, m) = (p.mesh.element_count(), g.sources.len());
    let mut reference = vec![0.0f32; m];
    let mut row = vec![0.0f32; m];
    for e in 0..n {
        analytic(1).row(&g, e, &mut reference);
        let sum: f64 = reference.iter().map(|&f| f64::from(f)).sum();
        assert!((sum - 1.0).abs() < 1e-5, "element {e}: {sum}");
        raycast(1, 4).row(&g, e, &mut row);
        assert_eq!(row, reference, "element {e}");
    }
    // Coarse sources: the same.
    let p = Prepared::new(
        &testing::closed_cube(0.5, [0.0; 6]),
        Subdivision::Elements(384),
        24,
    );
    let g = p.geometry();
    let mut row = vec![0.0f32; g.sources.len()];
    for e in 0..p.mesh.element_count() {
        raycast(2, 4).row(&g, e, &mut row);
        let sum: f64 = row.iter().map(|&f| f64::from(f)).sum();
        assert!((sum - 1.0).abs() < 1e-5, "element {e}: {sum}");
    }
}

#[test]
fn blocker_hiding_half_halves_the_form_factor() {
    // See `testing::half_blocked_squares`: the exact value is 0.1998249 / 2 = 0.0999124. With
    // the squares' elements symmetric under the reflection that swaps blocked and free rays,
    // only the sampling noise of the visible fractions remains: 64 elements × 64 stratified
    // rays put it well below 1e-3. The unblocked value carries the error of a 16 × 16
    // midpoint rule on the receiver (1.2e-4).
    let scene = testing::half_blocked_squares();
    let p = Prepared::new(&scene, Subdivision::MaxArea(1.0 / 64.0), usize::MAX);
    let g = p.geometry();
    let f = patch_to_patch(&g, raycast(2, 64).as_ref(), 0, 1);
    let free = patch_to_patch(&g, analytic(2).as_ref(), 0, 1);
    assert!((free - 0.199_824_9).abs() < 3e-4, "unblocked {free}");
    assert!((f - 0.199_824_9 / 2.0).abs() < 1e-3, "blocked {f}");
}
