//! Hemicube form factors against closed forms, identities, and ray casting on the Cornell box.

use glam::Vec3;
use radiosity::formfactor::analytic::point_to_parallel_rectangle_corner;
use radiosity::formfactor::hemicube::raster::{Layout, NOTHING};
use radiosity::formfactor::hemicube::{Hemicube, DEFAULT_RESOLUTION};
use radiosity::formfactor::{self, FormFactors, Geometry, Method};
use radiosity::mesh::Subdivision;
use radiosity::pipeline::{self, Settings};
use radiosity::progress::Silent;
use radiosity::scene::{builtin, Material, Object, Polygon};
use radiosity::stats::Timings;
use radiosity::testing::{self, Prepared};
use radiosity::Scene;

const PARALLEL: f64 = 0.199_824_9;
const PERPENDICULAR: f64 = 0.200_043_8;
const POINT: f64 = 0.239_456_5;

fn default_hemicube() -> Hemicube {
    Hemicube::new(DEFAULT_RESOLUTION, 2, 0)
}

/// F from patch `from` to patch `to`, area-weighted over `from`'s elements, through rows.
fn by_rows(g: &Geometry, ff: &dyn FormFactors, from: u32, to: u32) -> f64 {
    let mut row = vec![0.0; g.sources.len()];
    let mut sum = 0.0;
    for e in (0..g.mesh.element_count()).filter(|&e| g.mesh.element(e).patch == from) {
        ff.row(g, e, &mut row);
        let f: f64 = (0..g.sources.len())
            .filter(|&s| g.source_patch(s) == to)
            .map(|s| f64::from(row[s]))
            .sum();
        sum += g.mesh.element(e).face.area() * f;
    }
    sum / g.mesh.patches[from as usize].area
}

/// The same through columns (hemicubes at the sources, then reciprocity).
fn by_columns(g: &Geometry, ff: &dyn FormFactors, from: u32, to: u32) -> f64 {
    let mut column = vec![0.0; g.mesh.element_count()];
    let mut sum = 0.0;
    for s in (0..g.sources.len()).filter(|&s| g.source_patch(s) == to) {
        ff.column(g, s, &mut column);
        for (e, &f) in column.iter().enumerate() {
            if g.mesh.element(e).patch == from {
                sum += g.mesh.element(e).face.area() * f64::from(f);
            }
        }
    }
    sum / g.mesh.patches[from as usize].area
}

fn relative(value: f64, exact: f64) -> f64 {
    (value - exact).abs() / exact
}

/// The hemicube at the centre of the bottom face of the unit cube, seeing the top face: one
/// receiver element, the top split into 16 sources, near-neighbour kernel off (so this is the
/// bare point-to-polygon hemicube).
fn point_to_square(resolution: u32, rotate: bool) -> f64 {
    let p = Prepared::new(
        &testing::parallel_squares(1.0),
        Subdivision::Elements(17),
        64,
    );
    let g = p.geometry();
    assert_eq!(g.mesh.nodes[g.mesh.elements[0] as usize].face.area(), 1.0);
    let ff = Hemicube::new(resolution, 1, 3)
        .with_near(0.0)
        .with_rotation(rotate);
    let mut row = vec![0.0; g.sources.len()];
    ff.row(&g, 0, &mut row);
    row.iter().map(|&f| f64::from(f)).sum()
}

#[test]
fn delta_form_factors_sum_to_one_and_match_the_midpoint_formula() {
    for resolution in [2, 8, 64, 256] {
        let layout = Layout { resolution };
        let deltas = layout.deltas();
        let sum: f64 = deltas.iter().sum();
        // Exact cell integrals: only rounding is left.
        assert!((sum - 1.0).abs() < 1e-10, "res {resolution}: {sum}");
        // Cohen & Greenberg's midpoint formula ΔA / π(x² + y² + 1)² on the top face agrees to
        // O(1/res²) relative.
        let h = 2.0 / f64::from(resolution);
        for j in 0..resolution {
            for i in 0..resolution {
                let x = -1.0 + h * (f64::from(i) + 0.5);
                let y = -1.0 + h * (f64::from(j) + 0.5);
                let midpoint = h * h / (std::f64::consts::PI * (x * x + y * y + 1.0).powi(2));
                let d = deltas[layout.index(0, i, j)];
                assert!(
                    relative(d, midpoint) < 2.0 * h * h,
                    "res {resolution} ({i},{j})"
                );
            }
        }
    }
}

#[test]
fn point_to_square_within_one_percent_and_error_falls_with_resolution() {
    println!("point → opposite unit square at distance 1, exact {POINT}");
    println!("| resolution | no rotation | error | rotated | error |");
    println!("|---|---|---|---|---|");
    let mut errors = Vec::new();
    for resolution in [8, 16, 32, 64, 128, 256] {
        let plain = point_to_square(resolution, false);
        let rotated = point_to_square(resolution, true);
        println!(
            "| {resolution} | {plain:.7} | {:.3} % | {rotated:.7} | {:.3} % |",
            100.0 * relative(plain, POINT),
            100.0 * relative(rotated, POINT)
        );
        errors.push((resolution, relative(plain, POINT), relative(rotated, POINT)));
    }
    let at = |r: u32| *errors.iter().find(|e| e.0 == r).unwrap();
    let default = point_to_square(DEFAULT_RESOLUTION, true);
    assert!(relative(default, POINT) < 0.01, "{default}");
    // The edge cells are the error: it falls at least as 1/resolution (each 8× in resolution
    // must gain 4×, whatever the luck of a single alignment).
    for (low, high) in [(8, 64), (16, 128), (32, 256)] {
        assert!(at(high).1 < at(low).1 / 4.0, "{errors:?}");
        assert!(at(high).2 < at(low).2 / 4.0, "{errors:?}");
    }
}

#[test]
fn parallel_squares_within_one_percent_by_rows_and_columns() {
    let p = Prepared::new(
        &testing::parallel_squares(1.0),
        Subdivision::Elements(128),
        128,
    );
    let g = p.geometry();
    let ff = default_hemicube();
    println!("parallel unit squares 1 apart, exact {PARALLEL}");
    println!("| resolution | rows | error | columns | error |");
    println!("|---|---|---|---|---|");
    let mut errors = Vec::new();
    for resolution in [8, 16, 32, 64, 128, 256] {
        let h = Hemicube::new(resolution, 2, 0);
        let (r, c) = (by_rows(&g, &h, 0, 1), by_columns(&g, &h, 0, 1));
        println!(
            "| {resolution} | {r:.7} | {:.3} % | {c:.7} | {:.3} % |",
            100.0 * relative(r, PARALLEL),
            100.0 * relative(c, PARALLEL)
        );
        errors.push(relative(r, PARALLEL));
    }
    assert!(errors[5] < errors[0] / 4.0, "{errors:?}");
    let rows = by_rows(&g, &ff, 0, 1);
    let columns = by_columns(&g, &ff, 0, 1);
    assert!(relative(rows, PARALLEL) < 0.01, "rows {rows}");
    assert!(relative(columns, PARALLEL) < 0.01, "columns {columns}");
}

#[test]
fn perpendicular_squares_within_one_percent_with_near_neighbour_kernel() {
    let p = Prepared::new(
        &testing::perpendicular_squares(),
        Subdivision::Elements(128),
        128,
    );
    let g = p.geometry();
    let ff = default_hemicube();
    let bare = default_hemicube().with_near(0.0);
    let (rows, columns) = (by_rows(&g, &ff, 0, 1), by_columns(&g, &ff, 0, 1));
    let bare_rows = by_rows(&g, &bare, 0, 1);
    println!(
        "perpendicular: rows {rows:.7} columns {columns:.7} without near kernel {bare_rows:.7}, exact {PERPENDICULAR}"
    );
    assert!(relative(rows, PERPENDICULAR) < 0.01, "rows {rows}");
    assert!(relative(columns, PERPENDICULAR) < 0.01, "columns {columns}");
    // The kernel is what makes it: the bare centroid hemicube is worse at the shared edge.
    assert!(relative(bare_rows, PERPENDICULAR) > relative(rows, PERPENDICULAR));
}

#[test]
fn one_sided_blocker_seen_from_behind_hides_half() {
    let p = Prepared::new(
        &testing::half_blocked_squares(),
        Subdivision::Elements(300),
        300,
    );
    let g = p.geometry();
    let f = by_rows(&g, &default_hemicube(), 0, 1);
    // Exactly half of the unblocked value (see `half_blocked_squares`).
    assert!(relative(f, 0.5 * PARALLEL) < 0.01, "{f}");
}

/// The closed unit cube with a tiny two-sided square at its centre: its two patches look up
/// and down.
fn cube_with_centre_square() -> Scene {
    let mut scene = testing::closed_cube(0.5, [0.0; 6]);
    scene.materials.push(Material {
        name: "probe".into(),
        two_sided: true,
        ..Material::default()
    });
    scene.objects.push(Object {
        name: "probe".into(),
    });
    let e = 1e-3;
    scene.polygons.push(Polygon {
        vertices: vec![
            Vec3::new(0.5 - e, 0.5 - e, 0.5),
            Vec3::new(0.5 + e, 0.5 - e, 0.5),
            Vec3::new(0.5 + e, 0.5 + e, 0.5),
            Vec3::new(0.5 - e, 0.5 + e, 0.5),
        ],
        material: scene.materials.len() - 1,
        object: scene.objects.len() - 1,
    });
    scene
}

#[test]
fn six_faces_of_the_cube_seen_from_its_centre_sum_to_one() {
    let p = Prepared::new(
        &cube_with_centre_square(),
        Subdivision::Elements(6 * 64),
        1000,
    );
    let g = p.geometry();
    // From the centre, the face straight ahead at distance ½ and each of the other four.
    let ahead = 4.0 * point_to_parallel_rectangle_corner(0.5, 0.5, 0.5);
    let beside = (1.0 - ahead) / 4.0;
    for near in [0.0, 2.0] {
        let ff = default_hemicube().with_near(near);
        let mut total = 0.0;
        for probe in [6, 7] {
            let e = (0..g.mesh.element_count())
                .find(|&e| g.mesh.element(e).patch == probe)
                .unwrap();
            let normal = g.mesh.patches[probe as usize].normal;
            let mut row = vec![0.0; g.sources.len()];
            ff.row(&g, e, &mut row);
            let mut faces = [0.0; 6];
            for (s, &f) in row.iter().enumerate() {
                assert!(g.source_patch(s) < 6 || f == 0.0, "the probe sees itself");
                if g.source_patch(s) < 6 {
                    faces[g.source_patch(s) as usize] += f64::from(f);
                }
            }
            let sum: f64 = faces.iter().sum();
            // The cells' deltas sum to 1 to rounding; f32 storage of the row adds ~1e-6.
            assert!((sum - 1.0).abs() < 1e-5, "near {near}: {sum}");
            for (k, &f) in faces.iter().enumerate() {
                // Faces are −x, +x, −y, +y, −z, +z; the probe looks along ±z.
                let expected = if k / 2 == 2 {
                    if (k == 5) == (normal.z > 0.0) {
                        ahead
                    } else {
                        0.0
                    }
                } else {
                    beside / 2.0
                };
                assert!(
                    (f - expected).abs() < 0.01 * ahead,
                    "face {k}: {f} vs {expected}"
                );
            }
            total += sum;
        }
        // Both hemicubes together: the whole sphere, the six faces' 2 (= 1 per hemisphere).
        assert!((total - 2.0).abs() < 2e-5);
    }
}

#[test]
fn rows_and_columns_do_not_depend_on_thread_count() {
    let p = Prepared::new(
        &testing::half_blocked_squares(),
        Subdivision::Elements(200),
        50,
    );
    let g = p.geometry();
    let ff = default_hemicube();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut column = vec![0.0; g.mesh.element_count()];
            ff.column(&g, 3, &mut column);
            let mut row = vec![0.0; g.sources.len()];
            ff.row(&g, 5, &mut row);
            (row, column)
        })
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert!(one.0.iter().any(|&f| f > 0.0) && one.1.iter().any(|&f| f > 0.0));
}

#[test]
fn view_shows_the_sources_it_sums() {
    let p = Prepared::new(
        &testing::parallel_squares(1.0),
        Subdivision::Elements(32),
        32,
    );
    let g = p.geometry();
    let ff = Hemicube::new(32, 2, 0).with_near(0.0);
    let view = ff.view(&g, 0);
    let mut sums = vec![0.0; g.sources.len()];
    for (&item, &d) in view.items.iter().zip(&view.deltas) {
        if item != NOTHING {
            sums[item as usize] += d;
        }
    }
    let mut row = vec![0.0; g.sources.len()];
    ff.row(&g, 0, &mut row);
    for (s, &f) in row.iter().enumerate() {
        assert!((sums[s] - f64::from(f)).abs() < 1e-6);
    }
}

/// Per-object radiosity of the Cornell box with hemicube and ray-cast form factors.
#[test]
fn cornell_box_agrees_with_ray_casting_per_object() {
    let scene = || builtin::load("cornell").unwrap().unwrap();
    let solve = |method: Method| {
        let settings = Settings {
            subdivision: Subdivision::Elements(1024),
            form_factors: formfactor::Settings {
                method,
                ..formfactor::Settings::default()
            },
            ..Settings::default()
        };
        pipeline::solve(scene(), &settings, &Silent)
            .unwrap()
            .stats(&Timings::default())
            .objects
    };
    let (hemicube, raycast) = (solve(Method::Hemicube), solve(Method::RayCast));
    for (h, r) in hemicube.iter().zip(&raycast) {
        assert_eq!(h.name, r.name);
        for c in 0..3 {
            let error = relative(h.radiosity[c], r.radiosity[c]);
            println!("{} channel {c}: {:.3} %", h.name, 100.0 * error);
            // The ray-cast reference is itself within ~0.2 % (formfactor::Settings::default).
            assert!(error < 0.01, "{} channel {c}: {h:?} vs {r:?}", h.name);
        }
    }
}
