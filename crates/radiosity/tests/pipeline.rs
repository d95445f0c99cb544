//! The whole pipeline on the built-in scenes: energy balance, stats, and a golden image.

use std::sync::atomic::AtomicBool;

use radiosity::mesh::Subdivision;
use radiosity::pipeline::{self, Settings};
use radiosity::progress::Silent;
use radiosity::render::local::LocalSettings;
use radiosity::render::raytrace::RaytraceSettings;
use radiosity::render::{render, Mode, RasterSettings, Watch};
use radiosity::scene::builtin;
use radiosity::stats::Timings;
use radiosity::{Rgb, Scene};

fn scene(name: &str) -> Scene {
    builtin::load(name)
        .expect("built-in exists")
        .expect("built-in loads")
}

fn settings(elements: usize) -> Settings {
    Settings {
        subdivision: Subdivision::Elements(elements),
        ..Settings::default()
    }
}

/// In the closed furnace (ρ = 0.5 everywhere) every emitted watt is absorbed in the end, and the
/// total leaving power is Σ A E / (1 − ρ).
#[test]
fn furnace_absorbs_what_it_emits() {
    let solved = pipeline::solve(scene("furnace"), &settings(600), &Silent).unwrap();
    let stats = solved.stats(&Timings::default());
    for c in 0..3 {
        let (emitted, absorbed) = (stats.energy.emitted[c], stats.energy.absorbed[c]);
        // Tolerance: the solver's residual (1e-4) and the row sums of the ray-cast form factors.
        assert!(
            (absorbed - emitted).abs() < 2e-3 * emitted,
            "{absorbed} vs {emitted}"
        );
        let leaving: f64 = stats.objects.iter().map(|o| o.area * o.radiosity[c]).sum();
        assert!(
            (leaving - emitted / 0.5).abs() < 2e-3 * leaving,
            "{leaving}"
        );
    }
}

/// The Cornell box is open at the front, so some light escapes: absorbed < emitted; walls of a
/// colour are brightest in that colour; the light's radiosity is at least its exitance.
#[test]
fn cornell_box_is_plausible() {
    let solved = pipeline::solve(scene("cornell"), &settings(500), &Silent).unwrap();
    let stats = solved.stats(&Timings::default());
    let emitted = Rgb::from_array(stats.energy.emitted);
    let absorbed = Rgb::from_array(stats.energy.absorbed);
    assert!(absorbed.cmplt(emitted).all() && absorbed.cmpgt(emitted * 0.5).all());
    let object = |name: &str| {
        let o = stats.objects.iter().find(|o| o.name == name).expect(name);
        Rgb::from_array(o.radiosity)
    };
    let (red, green) = (object("left_wall"), object("right_wall"));
    assert!(red.x > red.y && red.x > red.z, "{red}");
    assert!(green.y > green.x && green.y > green.z, "{green}");
    let light = object("light");
    let exitance = Rgb::new(17.0, 12.0, 4.0) * std::f64::consts::PI;
    assert!(light.cmpge(exitance).all() && light.cmplt(exitance * 1.1).all());
    assert_eq!(stats.objects.len(), 8);
    assert_eq!(stats.materials.len(), 4);
}

/// Every render mode pictures a solved scene through `Solved::render`: the radiosity mode is
/// the rasterised lit mesh, bit for bit; every mode gives finite, non-negative radiance at the
/// asked size, and nothing once the stop flag is set.
#[test]
fn every_render_mode_pictures_the_solved_scene() {
    let solved = pipeline::solve(scene("cornell"), &settings(200), &Silent).unwrap();
    let camera = &solved.scene.cameras[0];
    let raster = RasterSettings {
        width: 24,
        height: 16,
        samples_per_pixel: 1,
    };
    let modes = [
        Mode::Radiosity,
        Mode::Local(LocalSettings::default()),
        Mode::Raytrace(RaytraceSettings::default()),
        Mode::Final(RaytraceSettings::default()),
    ];
    let stop = AtomicBool::new(true);
    let stopped = Watch {
        progress: &Silent,
        stop: Some(&stop),
    };
    for mode in &modes {
        let image = solved
            .render(mode, camera, &raster, &Watch::SILENT)
            .unwrap();
        assert_eq!((image.width, image.height), (24, 16), "{mode:?}");
        assert!(
            image
                .pixels
                .iter()
                .all(|p| p.is_finite() && p.min_element() >= 0.0),
            "{mode:?}"
        );
        if *mode == Mode::Radiosity {
            assert_eq!(image, render(&solved.lit, camera, &raster));
        }
        assert!(
            solved.render(mode, camera, &raster, &stopped).is_none(),
            "{mode:?}"
        );
    }
}

/// A 64 × 64 picture of the Cornell box at 400 elements against the stored golden PFM. The
/// tolerance (2 % of the mean radiance, per pixel on average, and 25 % on any single pixel)
/// allows for floating-point differences between machines and compilers, not for changes in
/// method: a different form-factor estimator or a broken rasterizer moves it far more.
#[test]
fn cornell_box_matches_golden_image() {
    let solved = pipeline::solve(scene("cornell"), &settings(400), &Silent).unwrap();
    let camera = &solved.scene.cameras[0];
    let image = render(
        &solved.lit,
        camera,
        &RasterSettings {
            width: 64,
            height: 64,
            samples_per_pixel: 4,
        },
    );
    let golden_path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/cornell_64.pfm");
    if std::env::var_os("RADIOSITY_BLESS").is_some() {
        radiosity::io::image_file::write_image(&golden_path, &image, 0.0).unwrap();
    }
    let golden = radiosity::io::image_file::read_pfm(&golden_path).expect("golden image");
    assert_eq!((golden.width, golden.height), (64, 64));
    let mean = golden.mean().element_sum() / 3.0;
    let mut total = 0.0;
    for (a, b) in image.pixels.iter().zip(&golden.pixels) {
        let d = (*a - *b).abs().max_element();
        assert!(d < 0.25 * mean.max(b.max_element()), "{a} vs {b}");
        total += d;
    }
    let average = total / image.pixels.len() as f64;
    assert!(
        average < 0.02 * mean,
        "mean difference {average} vs mean {mean}"
    );
}
