//! Luminaires in the solvers and the pictures: their flux is conserved in a closed room by
//! every solver, the solvers agree with each other, a luminaire inside a closed two-sided
//! object lights its inner sides, and the evaluated picture's direct light is the inverse-square
//! law; a directional light lights a plane with E⊥ cos θ and casts the shadow of a box with the
//! area geometry gives it.

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

/// A 10 × 10 m ground of reflectance `ground` under a unit box of reflectance `box_rho` (none
/// when `None`), lit by a `directional` light of 1000 lx 45° high from −x.
fn sunlit(ground: f64, box_rho: Option<f64>) -> Scene {
    let mut toml = format!(
        r#"
[materials.ground]
reflectance = {ground}
[[objects]]
name = "ground"
material = "ground"
shape = "polygon"
vertices = [[-5.0, 0.0, -5.0], [-5.0, 0.0, 5.0], [5.0, 0.0, 5.0], [5.0, 0.0, -5.0]]
[[objects]]
name = "sun"
shape = "directional"
aim = [1.0, -1.0, 0.0]
illuminance = 1000.0
"#
    );
    if let Some(rho) = box_rho {
        toml.push_str(&format!(
            r#"
[materials.box]
reflectance = {rho}
[[objects]]
name = "box"
material = "box"
shape = "box"
min = [-0.5, 0.0, -0.5]
max = [0.5, 1.0, 0.5]
"#
        ));
    }
    Scene::from_toml_str(&toml, std::path::Path::new("sunlit.toml")).expect("scene")
}

#[test]
fn a_directional_light_gives_a_plane_e_cos_theta_in_every_solver() {
    // One plane, nothing else: no interreflection, so every element's B = ρ E⊥ cos 45°
    // exactly (no falloff with distance, wherever the element lies).
    let expected = 0.3 * 1000.0 * std::f64::consts::FRAC_1_SQRT_2;
    for method in [
        Method::GaussSeidel,
        Method::Jacobi,
        Method::Progressive,
        Method::Hierarchical,
    ] {
        let s = run(sunlit(0.3, None), method, 256);
        for e in 0..s.mesh.element_count() {
            let b = s.solution.radiosity[e].x;
            assert!(
                (b / expected - 1.0).abs() < 1e-6,
                "{method}: {b} vs {expected}"
            );
        }
    }
}

#[test]
fn a_directional_light_casts_the_shadow_geometry_gives() {
    // A black unit box on a ground of ρ 0.3, the sun 45° high: the ground is lit but for the
    // box's footprint and its shadow, 1 m longer (tan 45° × the box's height), so
    // Σ_ground A B = ρ E⊥ cos 45° (100 − 2) m². The 16-point first shot blurs the shadow's
    // edges within the elements that straddle them: measured 0.009 % off at 1 700 elements
    // and 0.0016 % at 6 800; asserted within 0.3 % and falling.
    let expected = 0.3 * 1000.0 * std::f64::consts::FRAC_1_SQRT_2 * 98.0;
    let error = |elements: usize| {
        let s = run(sunlit(0.3, Some(0.0)), Method::GaussSeidel, elements);
        let ground: f64 = (0..s.mesh.element_count())
            .filter(|&e| s.mesh.element_patch(e).reflectance.x > 0.0)
            .map(|e| s.mesh.element(e).area() * s.solution.radiosity[e].x)
            .sum();
        (ground / expected - 1.0).abs()
    };
    let (coarse, fine) = (error(1700), error(6800));
    assert!(coarse < 3e-3 && fine < 3e-3, "{coarse} {fine}");
    assert!(fine < coarse, "{coarse} then {fine}");
}

#[test]
fn the_sun_of_a_sky_is_a_directional_light_towards_its_position() {
    let toml = r#"
[sky]
type = "cie-12"
zenith_luminance = 5000.0
sun = [0.0, 1.0, 1.0]
sun_illuminance = 80000.0
[materials.ground]
reflectance = 0.2
[[objects]]
name = "ground"
material = "ground"
shape = "polygon"
vertices = [[-1.0, 0.0, -1.0], [-1.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 0.0, -1.0]]
"#;
    let scene = Scene::from_toml_str(toml, std::path::Path::new("sky.toml")).expect("scene");
    let sun = &scene.luminaires[0];
    assert_eq!((sun.name.as_str(), sun.position()), ("sun", None));
    // 45° high: 80 000 cos 45° on the ground; full on a wall facing it, none on its back.
    let e = sun.irradiance(Vec3::ZERO, Vec3::Y).x;
    assert!(
        (e / (80_000.0 * std::f64::consts::FRAC_1_SQRT_2) - 1.0).abs() < 1e-6,
        "{e}"
    );
    let facing = Vec3::new(0.0, 1.0, 1.0).normalize();
    assert!((sun.irradiance(Vec3::ZERO, facing).x / 80_000.0 - 1.0).abs() < 1e-6);
    assert_eq!(sun.irradiance(Vec3::ZERO, Vec3::NEG_Z), Rgb::ZERO);
}
