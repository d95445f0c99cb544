//! The solvers against each other, across thread counts, and at their edges.

use std::sync::atomic::{AtomicU64, Ordering};

use radiosity::formfactor::{self, Geometry};
use radiosity::mesh::Subdivision;
use radiosity::progress::{Progress, Silent, Work};
use radiosity::scene::builtin;
use radiosity::solve::{self, matrix::Matrix, Method, Settings, Solution, SolveError};
use radiosity::testing::{self, Prepared};
use radiosity::{Rgb, Scene};

fn cornell() -> Scene {
    builtin::load("cornell").unwrap().unwrap()
}

fn ff_settings() -> formfactor::Settings {
    formfactor::Settings::RayCast(formfactor::raycast::Settings {
        quadrature: 2,
        rays: 4,
        seed: 1,
    })
}

fn run(g: &Geometry, method: Method, tolerance: f64) -> Solution {
    let ff = formfactor::build(&ff_settings());
    let settings = Settings {
        tolerance,
        max_iterations: 1_000_000,
        ..Settings::default()
    };
    solve::solve(g, ff.as_ref(), method, &settings, &Silent).unwrap()
}

/// Largest relative difference between two solutions, relative to the largest value.
fn difference(a: &[Rgb], b: &[Rgb]) -> f64 {
    let scale = a.iter().map(|x| x.max_element()).fold(0.0, f64::max);
    a.iter()
        .zip(b)
        .map(|(x, y)| (*x - *y).abs().max_element())
        .fold(0.0, f64::max)
        / scale
}

#[test]
fn solvers_agree_on_cube_and_cornell() {
    // At residual 1e-9 every solver is within ~1e-9 · ρ/(1 − ρ) of the common fixed point (same
    // stored or recomputed form factors, bit for bit); 1e-6 of the brightest element is a
    // loose bound on what is left.
    let cube = testing::closed_cube(0.6, [0.0, 0.0, 1.0, 0.0, 0.0, 0.0]);
    for (scene, elements) in [(cube, 384), (cornell(), 300)] {
        let p = Prepared::new(&scene, Subdivision::Elements(elements), 10_000);
        let g = p.geometry();
        let reference = run(&g, Method::Jacobi, 1e-9);
        assert!(reference.radiosity.iter().all(|b| b.is_finite()));
        for method in [Method::GaussSeidel, Method::Progressive] {
            let s = run(&g, method, 1e-9);
            let d = difference(&reference.radiosity, &s.radiosity);
            // The stored matrix scales rows summing above one down to one (solve/matrix.rs);
            // progressive refinement computes columns and never sees a whole row, so it keeps
            // the quadrature's excess: at 300 Cornell elements 1.7e-4 of the brightest element.
            let bound = if method == Method::Progressive {
                1e-3
            } else {
                1e-6
            };
            assert!(d < bound, "{}: {method} differs by {d}", scene.name);
            assert!(s.residual < 1e-9);
        }
    }
}

#[test]
fn one_and_two_threads_give_identical_solutions() {
    let p = Prepared::new(&cornell(), Subdivision::Elements(300), 64);
    let g = p.geometry();
    let pools = [1, 2].map(|n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    });
    for method in Method::ALL {
        let [a, b] = [&pools[0], &pools[1]].map(|pool| pool.install(|| run(&g, method, 1e-4)));
        let bits = |s: &Solution| -> Vec<[u64; 3]> {
            s.radiosity
                .iter()
                .map(|b| b.to_array().map(f64::to_bits))
                .collect()
        };
        assert_eq!(bits(&a), bits(&b), "{method}");
        assert_eq!(
            (a.iterations, a.residual.to_bits(), a.links),
            (b.iterations, b.residual.to_bits(), b.links)
        );
    }
}

#[test]
fn progressive_ambient_accounts_for_the_unshot_power() {
    // In a closed scene of uniform ρ, unshot power U will still add U·ρ/(1 − ρ) to the
    // radiosity power, which is exactly what adding ρ · ambient to every element adds. After
    // 10 shots the total with the ambient matches the converged total, while the total
    // without it is far off. Each shot delivers Σ_e A_e F_es ΔB_s, which equals A_s ΔB_s only
    // up to the receiver quadrature's reciprocity error (measured 2.4e-4 here): 1e-3.
    let rho = 0.5;
    let scene = testing::closed_cube(rho, [0.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let p = Prepared::new(&scene, Subdivision::Elements(96), 10_000);
    let g = p.geometry();
    let ff = formfactor::build(&ff_settings());
    let settings = Settings {
        tolerance: 0.0,
        max_iterations: 10,
        ..Settings::default()
    };
    let s = solve::solve(&g, ff.as_ref(), Method::Progressive, &settings, &Silent).unwrap();
    assert_eq!(s.iterations, 10);
    assert!(s.residual > 0.1);
    let area = |e: usize| p.mesh.element(e).area();
    let plain: f64 = s
        .radiosity
        .iter()
        .enumerate()
        .map(|(e, b)| b.x * area(e))
        .sum();
    let with_ambient: f64 = s
        .radiosity
        .iter()
        .enumerate()
        .map(|(e, b)| (b.x + rho * s.ambient.x) * area(e))
        .sum();
    let converged = std::f64::consts::PI / (1.0 - rho);
    assert!(
        (with_ambient - converged).abs() < 1e-3 * converged,
        "{with_ambient} vs {converged}"
    );
    assert!(converged - plain > 0.1 * converged, "{plain}");
}

#[test]
fn matrix_too_large_is_an_error_before_allocating() {
    let p = Prepared::new(&cornell(), Subdivision::Elements(300), 10_000);
    let g = p.geometry();
    let n = p.mesh.element_count() as u64;
    let ff = formfactor::build(&ff_settings());
    for method in [Method::Jacobi, Method::GaussSeidel] {
        let settings = Settings {
            max_matrix_bytes: 1000,
            ..Settings::default()
        };
        let err = solve::solve(&g, ff.as_ref(), method, &settings, &Silent).unwrap_err();
        assert_eq!(
            err,
            SolveError::MatrixTooLarge {
                bytes: n * n * 4,
                limit: 1000
            }
        );
    }
    // Progressive refinement stores no matrix.
    let settings = Settings {
        max_matrix_bytes: 1000,
        max_iterations: 5,
        ..Settings::default()
    };
    assert!(solve::solve(&g, ff.as_ref(), Method::Progressive, &settings, &Silent).is_ok());
    // A size that would overflow memory is refused by the same check.
    assert_eq!(Matrix::bytes(usize::MAX, usize::MAX), u64::MAX);
}

#[test]
fn no_emitters_and_no_elements_give_zero_at_once() {
    let dark = testing::closed_cube(0.5, [0.0; 6]);
    let empty = Scene::default();
    for scene in [dark, empty] {
        let p = Prepared::new(&scene, Subdivision::Elements(96), 10_000);
        let g = p.geometry();
        for method in Method::ALL {
            let s = run(&g, method, 1e-6);
            assert_eq!(s.radiosity.len(), p.mesh.element_count());
            assert!(s.radiosity.iter().all(|b| *b == Rgb::ZERO));
            assert_eq!((s.iterations, s.links), (0, 0));
            assert_eq!(s.residual, 0.0);
        }
    }
}

/// Counts the units of work reported.
#[derive(Default)]
struct Count {
    total: AtomicU64,
    done: AtomicU64,
}

impl Progress for Count {
    fn start(&self, stage: &str, work: Work) {
        if stage == "form factors" {
            assert_eq!(work.unit, "rows");
            self.total.store(work.total, Ordering::Relaxed);
        }
    }
    fn advance(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }
    fn finish(&self) {}
}

#[test]
fn matrix_reports_every_row() {
    let p = Prepared::new(&cornell(), Subdivision::Elements(100), 10_000);
    let g = p.geometry();
    let ff = formfactor::build(&ff_settings());
    let count = Count::default();
    let m = Matrix::compute(&g, ff.as_ref(), u64::MAX, &count).unwrap();
    let n = p.mesh.element_count() as u64;
    assert_eq!(count.total.load(Ordering::Relaxed), n);
    assert_eq!(count.done.load(Ordering::Relaxed), n);
    assert!(m.links() > 0 && m.links() < n * n);
}

#[test]
fn every_solver_returns_the_irradiance_of_its_radiosity() {
    // B = E + ρH for the irradiance H each solver reports: exactly for progressive refinement
    // (it adds ρ·FΔB to B and FΔB to H), within the residual for the gathering solvers (H
    // gathers the final B, which the last sweep read one step earlier), and the irradiance
    // where ρ = 0 (which B cannot tell) agrees between them.
    // The light reflects nothing here, and the red wall no red.
    let mut scene = cornell();
    for m in &mut scene.materials {
        if m.emission.max_element() > 0.0 {
            m.reflectance = Rgb::ZERO;
        }
        if m.reflectance.x > 2.0 * m.reflectance.y {
            m.reflectance.x = 0.0;
        }
    }
    let p = Prepared::new(&scene, Subdivision::Elements(300), 10_000);
    let g = p.geometry();
    let mut light = Vec::new();
    for method in [Method::Jacobi, Method::GaussSeidel, Method::Progressive] {
        let s = run(&g, method, 1e-9);
        let implied: Vec<Rgb> = (0..g.mesh.element_count())
            .map(|e| {
                let patch = g.mesh.element_patch(e);
                patch.emission + patch.reflectance * s.irradiance[e]
            })
            .collect();
        let bound = if method == Method::Progressive {
            1e-12
        } else {
            1e-7
        };
        let d = difference(&s.radiosity, &implied);
        assert!(d < bound, "{method}: {d:e}");
        let dark: Vec<Rgb> = (0..g.mesh.element_count())
            .filter(|&e| g.mesh.element_patch(e).reflectance.min_element() <= 0.0)
            .map(|e| s.irradiance[e])
            .collect();
        assert!(dark.len() > 10, "{}", dark.len());
        assert!(dark.iter().all(|h| h.min_element() > 0.0), "{method}");
        light.push(dark);
    }
    // Jacobi and Gauss-Seidel gather through the same matrix; progressive refinement's
    // columns are not capped at the hemisphere as the rows are, and the light, set in the
    // ceiling, is where rows come out above one (measured 6.5e-4 apart).
    let (gs, progressive) = (
        difference(&light[0], &light[1]),
        difference(&light[0], &light[2]),
    );
    assert!(gs < 1e-6 && progressive < 2e-3, "{gs:e} {progressive:e}");
}
