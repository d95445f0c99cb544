//! Point luminaires in the solvers and the pictures: their flux is conserved in a closed room
//! by every solver, the solvers agree with each other, a luminaire inside a closed two-sided
//! object lights its inner sides, and the evaluated picture's direct light is the inverse-square
//! law.

use std::sync::Arc;

use glam::Vec3;
use radiosity::pipeline::{self, Settings, Solved};
use radiosity::progress::Silent;
use radiosity::scene::luminaire::{isotropic, Luminaire};
use radiosity::solve::{self, Method};
use radiosity::testing;
use radiosity::{Rgb, Scene};

/// The closed unit cube of reflectance `rho`, dark, with an isotropic lamp of `candela` at
/// `at`.
fn lit_cube(rho: f64, candela: f64, at: Vec3) -> Scene {
    let mut scene = testing::closed_cube(rho, [0.0; 6]);
    scene.luminaires.push(Luminaire::new(
        "lamp",
        at,
        Vec3::NEG_Y,
        0.0,
        Arc::new(isotropic(candela)),
        Rgb::ONE,
        1.0,
    ));
    scene
}

fn run(scene: Scene, method: Method, elements: usize) -> Solved {
    let settings = Settings {
        method: Some(method),
        subdivision: radiosity::mesh::Subdivision::Elements(elements),
        solve: solve::Settings {
            tolerance: 1e-8,
            max_iterations: 100_000,
            ..solve::Settings::default()
        },
        ..Settings::default()
    };
    pipeline::solve(scene, &settings, &Silent).unwrap()
}

/// Σ A B over all elements.
fn power(s: &Solved) -> f64 {
    (0..s.mesh.element_count())
        .map(|e| s.mesh.element(e).area() * s.solution.radiosity[e].x)
        .sum()
}

#[test]
fn a_closed_room_turns_the_flux_into_rho_over_one_minus_rho_of_it() {
    // All of Φ = 4π I falls on the walls, and with uniform ρ each bounce keeps ρ of it:
    // Σ A B = ρ Φ / (1 − ρ), and everything is absorbed. The first shot is a 16-point mean
    // per element, so the total it shoots carries the points' noise: measured 0.08 % off at
    // 384 elements for the three element solvers, 0.008 % for hierarchical radiosity (which
    // refines the lit walls); asserted within 0.3 %.
    let (rho, candela) = (0.5, 10.0);
    let flux = 4.0 * std::f64::consts::PI * candela;
    let expected = rho * flux / (1.0 - rho);
    for method in [
        Method::GaussSeidel,
        Method::Jacobi,
        Method::Progressive,
        Method::Hierarchical,
    ] {
        let s = run(lit_cube(rho, candela, Vec3::splat(0.5)), method, 384);
        let p = power(&s);
        assert!(
            (p / expected - 1.0).abs() < 3e-3,
            "{method}: Σ A B {p} vs {expected}"
        );
        let stats = s.stats(&radiosity::stats::Timings::default());
        assert!((stats.energy.emitted[0] / flux - 1.0).abs() < 1e-12);
        let absorbed = stats.energy.absorbed[0];
        assert!(
            (absorbed / flux - 1.0).abs() < 3e-3,
            "{method}: absorbed {absorbed} of {flux}"
        );
    }
}

#[test]
fn the_first_shot_converges_to_the_flux_as_the_elements_shrink() {
    // A lamp near a corner lights the walls very unevenly; the first shot's total error is
    // the points' noise, falling with the element count: measured 0.28 % at 96 elements,
    // 0.038 % at 1 536.
    let (rho, candela) = (0.5, 10.0);
    let expected = rho * 4.0 * std::f64::consts::PI * candela / (1.0 - rho);
    let error = |elements| {
        let s = run(
            lit_cube(rho, candela, Vec3::new(0.2, 0.3, 0.25)),
            Method::GaussSeidel,
            elements,
        );
        (power(&s) / expected - 1.0).abs()
    };
    let (coarse, fine) = (error(96), error(1536));
    assert!(fine < 2e-3, "{fine}");
    assert!(fine < coarse, "96 elements {coarse}, 1536 elements {fine}");
}

#[test]
fn a_lamp_inside_a_closed_two_sided_box_lights_its_inner_sides() {
    // Without a luminaire, a closed two-sided object keeps only its outer side (no light can
    // reach the inner one); with one inside, its inner sides are all the light falls on.
    let mut scene = testing::closed_cube(0.5, [0.0; 6]);
    for m in &mut scene.materials {
        m.two_sided = true;
    }
    scene.luminaires.push(Luminaire::new(
        "lamp",
        Vec3::splat(0.5),
        Vec3::NEG_Y,
        0.0,
        Arc::new(isotropic(10.0)),
        Rgb::ONE,
        1.0,
    ));
    let s = run(scene, Method::Hierarchical, 384);
    let expected = 0.5 * 4.0 * std::f64::consts::PI * 10.0 / 0.5;
    let p = power(&s);
    assert!((p / expected - 1.0).abs() < 3e-3, "{p} vs {expected}");
}

#[test]
fn hierarchical_and_gauss_seidel_agree_per_wall() {
    // Each wall's mean radiosity: measured within 0.05 %; asserted within 0.3 %.
    let at = Vec3::new(0.3, 0.8, 0.4);
    let a = run(lit_cube(0.6, 5.0, at), Method::GaussSeidel, 1536);
    let b = run(lit_cube(0.6, 5.0, at), Method::Hierarchical, 1536);
    let wall = |s: &Solved, name: &str| {
        let stats = s.stats(&radiosity::stats::Timings::default());
        stats
            .objects
            .iter()
            .find(|o| o.name == name)
            .unwrap()
            .radiosity[0]
    };
    for name in ["x0", "x1", "y0", "y1", "z0", "z1"] {
        let (g, h) = (wall(&a, name), wall(&b, name));
        assert!((h / g - 1.0).abs() < 3e-3, "{name}: {g} vs {h}");
    }
}
