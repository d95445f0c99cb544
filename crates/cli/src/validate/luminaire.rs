//! Validation rows for point luminaires (CIE 171:2006's point-source cases): the direct
//! illuminance a point source gives a horizontal plane, by the inverse-square and cosine laws,
//!
//! ```text
//! E(d) = I cos θ / r² = I h / (h² + d²)^{3/2},
//! ```
//!
//! read by a calculation grid over a black floor (nothing reflects, so the reading is the
//! direct light alone); and a closed room of uniform reflectance around a point source, which
//! absorbs all of its flux Φ = 4π I however the light is interreflected.

use std::sync::Arc;

use glam::Vec3;
use radiosity::grids;
use radiosity::pipeline::{self, Settings};
use radiosity::progress::Silent;
use radiosity::scene::luminaire::{isotropic, Luminaire};
use radiosity::stats::Timings;
use radiosity::{solve, testing, Rgb, Scene};
use report::check::Check;

/// The source's intensity, cd.
const CANDELA: f64 = 1000.0;

/// Its height over the floor, m.
const HEIGHT: f32 = 2.0;

/// The rows: the plane at four distances aside, and the closed room's power balance.
pub fn rows() -> anyhow::Result<Vec<Check>> {
    let mut rows = plane()?;
    rows.push(closed_room()?);
    Ok(rows)
}

/// A lamp of `candela` at `at`.
fn lamp(at: Vec3, candela: f64) -> Luminaire {
    Luminaire::new(
        "lamp",
        at,
        Vec3::NEG_Y,
        0.0,
        Arc::new(isotropic(candela)),
        Rgb::ONE,
        1.0,
    )
}

/// Floor points 0, 1, 2 and 4 m aside of the point under the lamp.
fn plane() -> anyhow::Result<Vec<Check>> {
    let distances = [0.0_f32, 1.0, 2.0, 4.0];
    let mut toml = format!(
        r#"
[materials.black]
reflectance = 0.0

[[objects]]
name = "floor"
material = "black"
shape = "polygon"
vertices = [[-10.0, 0.0, -10.0], [-10.0, 0.0, 10.0], [10.0, 0.0, 10.0], [10.0, 0.0, -10.0]]

[[objects]]
name = "lamp"
shape = "point"
position = [0.0, {HEIGHT}, 0.0]
intensity = {CANDELA}
"#
    );
    for d in distances {
        toml.push_str(&format!(
            "\n[[grids]]\nname = \"d{d}\"\ncorners = [[{a}, 0.0, -0.01], [{b}, 0.0, -0.01], [{a}, 0.0, 0.01]]\nspacing = 1.0\n",
            a = d - 0.01,
            b = d + 0.01,
        ));
    }
    let scene = Scene::from_toml_str(&toml, std::path::Path::new("point-source.toml"))?;
    let solved = pipeline::solve(scene, &Settings::default(), &Silent)?;
    let readings = grids::measure(&solved.scene, &solved.mesh, &solved.solution, 0);
    Ok(distances
        .iter()
        .zip(&readings)
        .map(|(&d, r)| {
            let (h, d) = (f64::from(HEIGHT), f64::from(d));
            Check {
                case: format!(
                    "point source {CANDELA} cd, {HEIGHT} m over a black plane, {d} m aside (CIE 171 point source)"
                ),
                quantity: "direct illuminance (lx)",
                reference: CANDELA * h / (h * h + d * d).powf(1.5),
                ours: r.lux[0],
                tolerance: 1e-3,
            }
        })
        .collect())
}

/// The closed unit cube of ρ = 0.5 around a lamp off its centre: all of Φ is absorbed.
fn closed_room() -> anyhow::Result<Check> {
    let mut scene: Scene = testing::closed_cube(0.5, [0.0; 6]);
    scene
        .luminaires
        .push(lamp(Vec3::new(0.3, 0.7, 0.4), CANDELA / 100.0));
    let settings = Settings {
        method: Some(solve::Method::Hierarchical),
        ..Settings::default()
    };
    let stats = pipeline::solve(scene, &settings, &Silent)?.stats(&Timings::default());
    Ok(Check {
        case: "closed unit cube, ρ = 0.5, a 10 cd point source inside".into(),
        quantity: "absorbed / emitted power",
        reference: 1.0,
        ours: stats.energy.absorbed[0] / stats.energy.emitted[0],
        tolerance: 3e-3,
    })
}
