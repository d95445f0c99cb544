//! Validation rows for point luminaires (CIE 171:2006's point-source cases): the direct
//! illuminance a point source gives a horizontal plane, by the inverse-square and cosine laws,
//!
//! ```text
//! E(d) = I cos θ / r² = I h / (h² + d²)^{3/2},
//! ```
//!
//! read by a calculation grid over a black floor (nothing reflects, so the reading is the
//! direct light alone); a closed room of uniform reflectance around a point source, which
//! absorbs all of its flux Φ = 4π I however the light is interreflected; and the room cases,
//! the illuminance on a room's surfaces with the light interreflected (CIE 171's interior
//! luminaire in a room of uniform reflectance ρ). In a closed room every bounce keeps ρ of the
//! light, so the surfaces receive Φ (1 + ρ + ρ² + …) in all and their mean illuminance is
//!
//! ```text
//! Ē = Φ / (A (1 − ρ))              (A the room's whole surface)
//! ```
//!
//! whatever the luminaire's distribution and wherever it hangs. In a cube with an isotropic
//! source at its centre the six faces are alike, so each face's own mean is Ē too; a downlight
//! at the ceiling lights the faces unevenly and only the mean over all six is Ē. Both are read
//! by grids of 0.2 m cells on the faces, their direct light exact and the rest gathered from
//! the solution, as a lighting designer reads a room. The grid's mean is a midpoint rule,
//! which over the floor under the central source reads the direct light 0.06 % high at these
//! cells (0.015 % at 0.1 m): part of the error the rows show.

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

/// The rows: the plane at four distances aside, the closed room's power balance, and the room
/// cases.
pub fn rows() -> anyhow::Result<Vec<Check>> {
    let mut rows = plane()?;
    rows.push(closed_room()?);
    for rho in [0.2, 0.5] {
        rows.push(room_case(rho, Source::Central)?);
    }
    rows.push(room_case(0.5, Source::Downlight)?);
    Ok(rows)
}

/// The side of the room cases' cube, m.
const ROOM: f64 = 4.0;

/// The luminaire of a room case.
#[derive(Clone, Copy, PartialEq)]
enum Source {
    /// An isotropic point source of [`CANDELA`] at the room's centre.
    Central,
    /// A spot of [`CANDELA`] on its axis (cone 60°, beam 45°) 1 cm under the ceiling's
    /// centre, aimed down.
    Downlight,
}

/// A cube room of reflectance `rho` lit by `source`, each face carrying a grid: the mean
/// illuminance of the floor (the central source) or of all six faces (the downlight) against
/// Φ / (A (1 − ρ)) (module docs).
fn room_case(rho: f64, source: Source) -> anyhow::Result<Check> {
    let a = ROOM;
    let light = match source {
        Source::Central => format!(
            "shape = \"point\"\nposition = [{h}, {h}, {h}]\nintensity = {CANDELA}",
            h = a / 2.0
        ),
        Source::Downlight => format!(
            "shape = \"spot\"\nposition = [{h}, {y}, {h}]\nintensity = {CANDELA}\ncone = 60.0\nbeam = 45.0",
            h = a / 2.0,
            y = a - 0.01
        ),
    };
    let mut toml =
        format!("[materials.wall]\nreflectance = {rho}\n\n[[objects]]\nname = \"lamp\"\n{light}\n");
    // The six faces, each counter-clockwise seen from inside, and the normal they face.
    type Side = (&'static str, [[f64; 3]; 4], [f64; 3]);
    let faces: [Side; 6] = [
        (
            "floor",
            [[0.0, 0.0, 0.0], [0.0, 0.0, a], [a, 0.0, a], [a, 0.0, 0.0]],
            [0.0, 1.0, 0.0],
        ),
        (
            "ceiling",
            [[0.0, a, 0.0], [a, a, 0.0], [a, a, a], [0.0, a, a]],
            [0.0, -1.0, 0.0],
        ),
        (
            "west",
            [[0.0, 0.0, 0.0], [0.0, a, 0.0], [0.0, a, a], [0.0, 0.0, a]],
            [1.0, 0.0, 0.0],
        ),
        (
            "east",
            [[a, 0.0, 0.0], [a, 0.0, a], [a, a, a], [a, a, 0.0]],
            [-1.0, 0.0, 0.0],
        ),
        (
            "north",
            [[0.0, 0.0, 0.0], [a, 0.0, 0.0], [a, a, 0.0], [0.0, a, 0.0]],
            [0.0, 0.0, 1.0],
        ),
        (
            "south",
            [[0.0, 0.0, a], [0.0, a, a], [a, a, a], [a, 0.0, a]],
            [0.0, 0.0, -1.0],
        ),
    ];
    let measured: &[&str] = match source {
        Source::Central => &["floor"],
        Source::Downlight => &["floor", "ceiling", "west", "east", "north", "south"],
    };
    for (name, v, n) in faces {
        toml.push_str(&format!(
            "\n[[objects]]\nname = \"{name}\"\nmaterial = \"wall\"\nshape = \"polygon\"\nvertices = {v:?}\n"
        ));
        if measured.contains(&name) {
            toml.push_str(&format!(
                "\n[[grids]]\nname = \"{name}\"\non = \"{name}\"\nnormal = {n:?}\nspacing = 0.2\n"
            ));
        }
    }
    let scene = Scene::from_toml_str(&toml, std::path::Path::new("room-case.toml"))?;
    let flux = scene.luminaires[0].flux().x;
    let solved = pipeline::solve(scene, &Settings::default(), &Silent)?;
    let readings = grids::measure(&solved.scene, &solved.mesh, &solved.solution, 0);
    let mean = readings.iter().map(|r| r.statistics.average).sum::<f64>() / readings.len() as f64;
    let (case, quantity) = match source {
        Source::Central => (
            format!("cube room {a} m, ρ = {rho}, {CANDELA} cd point source at its centre (CIE 171 interior luminaire)"),
            "floor's mean illuminance (lx)",
        ),
        Source::Downlight => (
            format!("cube room {a} m, ρ = {rho}, downlight (spot, cone 60°) under the ceiling (CIE 171 interior luminaire)"),
            "mean illuminance of the six faces (lx)",
        ),
    };
    Ok(Check {
        case,
        quantity,
        reference: flux / (6.0 * a * a * (1.0 - rho)),
        ours: mean,
        tolerance: 1e-2,
    })
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
