//! `radiosity validate`: a built-in suite of cases with known answers, printed as a table
//! (case, quantity, reference, ours, relative error, pass).
//!
//! Every case runs the whole engine (meshing, form factors, solver, statistics) on a scene built
//! in code and reads its answer from the statistics, as a user would:
//!
//! - **View factors.** A non-reflecting square emitting exitance E lights a receiver of
//!   reflectance ρ that nothing else lights, so the receiver's mean radiosity is B = ρ F E and
//!   F = B / (ρ E). References: Howell's catalogue C-11 (coaxial parallel unit squares one
//!   apart, 0.1998249), C-14 (perpendicular unit squares sharing an edge, 0.2000438), half of
//!   C-11 behind a blocker that hides exactly half of the light (ray-cast visibility), and
//!   Lambert's point-to-polygon formula against Howell B-3.
//! - **Integrating sphere** (CIE 171:2006, test case 5.8). In a closed room of total area S_T
//!   and uniform reflectance ρ, a source of power Φ gives the mean irradiance
//!   Ē = Φ / (S_T (1 − ρ)), wherever the source is: every bounce spreads the remaining power
//!   over the whole enclosure. The room is 4 × 4 × 4 m with the centre ninth of the ceiling
//!   emitting (tolerance 0.5 %: the element quadrature leaves the rows of the form-factor matrix
//!   summing to 1 within about 10⁻³). The engine's Ē is Σ A (B − E) / (ρ S_T) from the per-object radiosities (H =
//!   (B − E)/ρ); for ρ = 0, where B says nothing about H, it is the absorbed power over S_T.
//! - **Direct irradiance.** A small square source of radiance L and area A_s at distance r
//!   gives a receiver the irradiance H = L A_s cos θ_s cos θ_r / r² (the inverse-square cosine
//!   law), exact as A_s / r² → 0; the receiver is a tiny square of reflectance ρ, H = B / ρ.
//! - **Energy conservation.** In a closed scene every emitted watt is eventually absorbed:
//!   Σ A (1 − ρ) H = Σ A E.
//! - **Cornell box against an independent path tracer.** The built-in `cornell` scene's
//!   per-object mean radiosity B = E + ρ H against Mitsuba 3 (`path` integrator, an
//!   `irradiancemeter` on each object for its mean irradiance H, Russian roulette, no depth
//!   truncation to speak of), computed by `benches/cornell_reference.py` from the same scene file
//!   and committed as `crates/cli/data/cornell_reference.json` (compiled in, so `validate` needs
//!   no file at run time). One row per object, the mean of its three channels; for the light,
//!   whose B is nearly all its own exitance E = π L_e, the reflected part B − E. Measured with
//!   `radiosity solve cornell --elements N --stats s.json` (the engine's ray-cast defaults), the
//!   worst object is 0.68 % off at 948 elements and 0.36 % at 3 792 and 15 168 (a floor set by
//!   the 2 × 2 quadrature of the form factors); the reference's standard error is at most 0.2 %
//!   (floor) and 0.12 % elsewhere. Hence the tolerance 1.5 % ≥ 0.7 % + 3 × 0.2 %.
//! - **Daylight through an opening** (CIE 171:2006 §5.9–5.13): a black room lit by a CIE sky
//!   through a roof opening or a window, floor points read by the calculation grids against
//!   an independent quadrature of the sky over the opening ([`daylight`]).
//! - **Point luminaires** (CIE 171:2006's point-source cases): a point source's direct
//!   illuminance on a plane by the inverse-square and cosine laws, and a closed room around one
//!   absorbing its whole flux ([`luminaire`]).
//!
//! The reference suite (scenes made elsewhere against Mitsuba 3) is a developer tool with the
//! same rows: `cargo xtask suite`.

mod daylight;
mod luminaire;

use std::io::Write;

use clap::Args;
use glam::Vec3;
use radiosity::formfactor::{self, analytic};
use radiosity::mesh::Subdivision;
use radiosity::pipeline::{self, Settings};
use radiosity::progress::Silent;
use radiosity::scene::{Material, Object, Polygon};
use radiosity::stats::{Stats, Timings};
use radiosity::{solve, testing, Rgb, Scene};
use report::check::{self, Check, Format};

/// `radiosity validate`.
#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Markdown)]
    pub format: Format,
    /// Also compare the published scenes in DIR (one folder per scene, Mitsuba XML) with
    /// Mitsuba 3's references: block error, 99th percentile, mean radiance ratio, power, time.
    #[arg(long, value_name = "DIR")]
    pub corpus: Option<std::path::PathBuf>,
    /// The references of `--corpus` (`<scene>.exr` + `<scene>.json`, from
    /// benches/corpus/reference.py).
    #[arg(long, value_name = "DIR", default_value = "benches/corpus/reference")]
    pub corpus_references: std::path::PathBuf,
    /// Corpus scenes to run (repeatable; default: every one with a reference).
    #[arg(long = "corpus-scene", value_name = "NAME")]
    pub corpus_scenes: Vec<String>,
}

/// Runs the suite and prints the table; fails when a case is out of tolerance.
pub fn run(args: &ValidateArgs) -> anyhow::Result<()> {
    let rows = suite()?;
    let corpus = match &args.corpus {
        Some(dir) => crate::corpus::rows(dir, &args.corpus_references, &args.corpus_scenes)?,
        None => Vec::new(),
    };
    let mut out = std::io::stdout().lock();
    match args.format {
        Format::Json => {
            let mut json: Vec<_> = rows.iter().map(Check::json).collect();
            for c in &corpus {
                let mut v = serde_json::to_value(c)?;
                v["case"] = format!("corpus: {}", c.scene).into();
                v["quantity"] = "picture vs Mitsuba 3, 4 x 4-block RMS".into();
                v["pass"] = c.pass().into();
                json.push(v);
            }
            writeln!(out, "{}", serde_json::to_string_pretty(&json)?)?;
        }
        Format::Markdown => {
            writeln!(out, "{}", check::markdown(&rows))?;
            if !corpus.is_empty() {
                writeln!(out, "\n{}", crate::corpus::table(&corpus))?;
            }
        }
    }
    let failed =
        rows.iter().filter(|r| !r.pass()).count() + corpus.iter().filter(|c| !c.pass()).count();
    anyhow::ensure!(failed == 0, "{failed} validation case(s) out of tolerance");
    Ok(())
}

/// Every case of the suite.
fn suite() -> anyhow::Result<Vec<Check>> {
    let mut rows = Vec::new();
    let parallel = analytic::parallel_rectangles(1.0, 1.0, 1.0);
    for (case, scene, reference) in [
        (
            "parallel unit squares, 1 apart (Howell C-11)",
            testing::parallel_squares(1.0),
            parallel,
        ),
        (
            "perpendicular unit squares (Howell C-14)",
            testing::perpendicular_squares(),
            analytic::perpendicular_rectangles(1.0, 1.0, 1.0),
        ),
        (
            "parallel squares, half blocked (C-11 / 2)",
            testing::half_blocked_squares(),
            0.5 * parallel,
        ),
    ] {
        rows.push(Check {
            case: case.into(),
            quantity: "view factor F",
            reference,
            ours: view_factor(scene)?,
            tolerance: 0.01,
        });
    }
    let (point, normal, square) = testing::point_to_square();
    rows.push(Check {
        case: "point to parallel square (Howell B-3)".into(),
        quantity: "view factor F",
        reference: 4.0 * analytic::point_to_parallel_rectangle_corner(0.5, 0.5, 1.0),
        ours: analytic::point_to_polygon(point, normal, &square),
        tolerance: 1e-6,
    });
    for rho in [0.0, 0.2, 0.5, 0.8] {
        rows.push(integrating_sphere(rho)?);
    }
    rows.push(direct_irradiance()?);
    let stats = solved(
        testing::closed_cube(0.5, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
        600,
        formfactor::Method::Analytic,
    )?;
    rows.push(Check {
        case: "closed unit cube, ρ = 0.5, one face emitting".into(),
        quantity: "absorbed / emitted power",
        reference: 1.0,
        ours: stats.energy.absorbed[0] / stats.energy.emitted[0],
        tolerance: 1e-3,
    });
    rows.extend(cornell()?);
    rows.extend(daylight::rows()?);
    rows.extend(luminaire::rows()?);
    Ok(rows)
}

/// Output of `benches/cornell_reference.py` (Mitsuba 3 on `scenes/cornell/scene.toml`).
const CORNELL_REFERENCE: &str = include_str!("../../data/cornell_reference.json");

/// Elements of our Cornell box solve (948 after quadtree rounding): under a second in release.
const CORNELL_ELEMENTS: usize = 1000;

/// Largest accepted relative error of an object's mean radiosity against the path tracer.
const CORNELL_TOLERANCE: f64 = 0.015;

/// One row per object of the built-in Cornell box: our mean radiosity (mean of R, G, B) at
/// [`CORNELL_ELEMENTS`] elements against the committed path-traced reference.
fn cornell() -> anyhow::Result<Vec<Check>> {
    let reference: serde_json::Value = serde_json::from_str(CORNELL_REFERENCE)?;
    let renderer = reference["renderer"].as_str().unwrap_or("path tracer");
    let objects = reference["objects"]
        .as_object()
        .ok_or_else(|| anyhow::anyhow!("no `objects` in the Cornell reference"))?;
    let scene = radiosity::scene::builtin::load("cornell")
        .ok_or_else(|| anyhow::anyhow!("no built-in scene `cornell`"))??;
    // Emitted exitance E = π L_e of each object (one material per Cornell object).
    let mut exitance = vec![Rgb::ZERO; scene.objects.len()];
    for polygon in &scene.polygons {
        exitance[polygon.object] =
            scene.materials[polygon.material].emission * std::f64::consts::PI;
    }
    let exitance: Vec<(String, Rgb)> = scene
        .objects
        .iter()
        .map(|o| o.name.clone())
        .zip(exitance)
        .collect();
    let stats = solved(scene, CORNELL_ELEMENTS, formfactor::Method::RayCast)?;
    anyhow::ensure!(
        stats.objects.len() == objects.len(),
        "the Cornell reference has {} objects, the scene {}",
        objects.len(),
        stats.objects.len()
    );
    let mut rows = Vec::with_capacity(objects.len());
    for (name, e) in exitance {
        let theirs = objects
            .get(&name)
            .and_then(|o| o["radiosity"].as_array())
            .and_then(|b| check::rgb(b))
            .ok_or_else(|| anyhow::anyhow!("no radiosity of `{name}` in the Cornell reference"))?;
        let ours = stats
            .objects
            .iter()
            .find(|o| o.name == name)
            .map(|o| Rgb::from(o.radiosity))
            .ok_or_else(|| anyhow::anyhow!("no object `{name}` in the statistics"))?;
        let emitting = e != Rgb::ZERO;
        rows.push(Check {
            case: format!("Cornell box vs {renderer} path tracer: {name}"),
            quantity: if emitting {
                "reflected radiosity B − πL_e, mean of R, G, B (W/m²)"
            } else {
                "radiosity B, mean of R, G, B (W/m²)"
            },
            reference: (theirs - e).element_sum() / 3.0,
            ours: (ours - e).element_sum() / 3.0,
            tolerance: CORNELL_TOLERANCE,
        });
    }
    Ok(rows)
}

/// The suite's solver settings: about `elements` elements, Gauss-Seidel to 10⁻⁹.
fn settings(elements: usize, method: formfactor::Method) -> Settings {
    Settings {
        subdivision: Subdivision::Elements(elements),
        discontinuity: false,
        display: pipeline::Display::Averaged,
        form_factors: formfactor::Settings::of(method),
        solve: solve::Settings {
            tolerance: 1e-9,
            ..solve::Settings::default()
        },
        method: Some(solve::Method::GaussSeidel),
    }
}

/// Solves `scene` with [`settings`] and returns its statistics.
fn solved(scene: Scene, elements: usize, method: formfactor::Method) -> anyhow::Result<Stats> {
    let solved = pipeline::solve(scene, &settings(elements, method), &Silent)?;
    Ok(solved.stats(&Timings::default()))
}

/// Mean radiosity (channel 0) of the object named `name`.
fn radiosity_of(stats: &Stats, name: &str) -> anyhow::Result<f64> {
    stats
        .objects
        .iter()
        .find(|o| o.name == name)
        .map(|o| o.radiosity[0])
        .ok_or_else(|| anyhow::anyhow!("no object `{name}` in the statistics"))
}

/// F from object 0 to object 1 of a two-square test scene: object 1 emits E = π (radiance 1)
/// and reflects nothing, so object 0's radiosity is ρ F E.
fn view_factor(mut scene: Scene) -> anyhow::Result<f64> {
    scene.materials[1].emission = Rgb::ONE;
    scene.materials[1].reflectance = Rgb::ZERO;
    let rho = scene.materials[0].reflectance.x;
    let receiver = scene.objects[0].name.clone();
    let stats = solved(scene, 800, formfactor::Method::RayCast)?;
    Ok(radiosity_of(&stats, &receiver)? / (rho * std::f64::consts::PI))
}

/// Adds a polygon with a material of its own to `scene`.
fn add(scene: &mut Scene, object: &str, vertices: Vec<Vec3>, rho: f64, radiance: f64) {
    let object = match scene.objects.iter().position(|o| o.name == object) {
        Some(o) => o,
        None => {
            scene.objects.push(Object {
                name: object.into(),
            });
            scene.objects.len() - 1
        }
    };
    scene.materials.push(Material {
        name: format!("m{}", scene.materials.len()),
        reflectance: Rgb::splat(rho),
        emission: Rgb::splat(radiance),
        ..Material::default()
    });
    scene.polygons.push(Polygon {
        vertices,
        material: scene.materials.len() - 1,
        object,
        uv: None,
    });
}

/// The square `corner, corner + u, corner + u + v, corner + v` (its front faces along u × v).
fn quad(corner: Vec3, u: Vec3, v: Vec3) -> Vec<Vec3> {
    vec![corner, corner + u, corner + u + v, corner + v]
}

/// CIE 171:2006 TC 5.8: the 4 m cube room, uniform ρ, the centre ninth of the ceiling emitting.
fn integrating_sphere(rho: f64) -> anyhow::Result<Check> {
    const SIDE: f32 = 4.0;
    let mut scene = Scene {
        name: "integrating sphere".into(),
        ..Scene::default()
    };
    for axis in 0..3 {
        let (b, c) = (Vec3::AXES[(axis + 1) % 3], Vec3::AXES[(axis + 2) % 3]);
        for side in [0.0, SIDE] {
            // Inward: b × c is +axis, so the face at 0 uses (b, c) and the far face (c, b).
            let (u, v) = if side == 0.0 { (b, c) } else { (c, b) };
            let base = Vec3::AXES[axis] * side;
            // The ceiling (y = 4) is cut into 3 × 3 tiles, the centre one the lamp.
            let tiles = if axis == 1 && side == SIDE { 3 } else { 1 };
            let t = SIDE / tiles as f32;
            for i in 0..tiles {
                for j in 0..tiles {
                    let corner = base + (i as f32 * t) * u + (j as f32 * t) * v;
                    let lamp = tiles == 3 && i == 1 && j == 1;
                    let (object, radiance) = if lamp { ("lamp", 10.0) } else { ("walls", 0.0) };
                    add(
                        &mut scene,
                        object,
                        quad(corner, t * u, t * v),
                        rho,
                        radiance,
                    );
                }
            }
        }
    }
    let stats = solved(scene, 1200, formfactor::Method::Analytic)?;
    let total_area: f64 = stats.objects.iter().map(|o| o.area).sum();
    let power = stats.energy.emitted[0];
    let mean = if rho > 0.0 {
        let leaving: f64 = stats.objects.iter().map(|o| o.area * o.radiosity[0]).sum();
        (leaving - power) / (rho * total_area)
    } else {
        stats.energy.absorbed[0] / total_area
    };
    Ok(Check {
        case: format!("integrating sphere, CIE 171 TC 5.8, ρ = {rho}"),
        quantity: "mean irradiance (W/m²)",
        reference: power / (total_area * (1.0 - rho)),
        ours: mean,
        tolerance: 5e-3,
    })
}

/// A 0.1 m square lamp (radiance 100, not reflecting) 2 m up, facing down; a 0.02 m receiver
/// square on the floor 1 m to the side, facing up, ρ = 0.5.
fn direct_irradiance() -> anyhow::Result<Check> {
    let (radiance, side, height, offset, rho) = (100.0, 0.1_f32, 2.0_f32, 1.0_f32, 0.5);
    let mut scene = Scene {
        name: "direct irradiance".into(),
        ..Scene::default()
    };
    let lamp = Vec3::new(-side / 2.0, height, -side / 2.0);
    add(
        &mut scene,
        "lamp",
        quad(lamp, side * Vec3::X, side * Vec3::Z),
        0.0,
        radiance,
    );
    let r = 0.02_f32;
    let target = Vec3::new(offset - r / 2.0, 0.0, -r / 2.0);
    add(
        &mut scene,
        "target",
        quad(target, r * Vec3::Z, r * Vec3::X),
        rho,
        0.0,
    );
    let stats = solved(scene, 64, formfactor::Method::RayCast)?;
    let (h, d) = (f64::from(height), f64::from(offset));
    let r2 = h * h + d * d;
    let cos = h / r2.sqrt();
    let area = f64::from(side * side);
    Ok(Check {
        case: format!("0.1 m square lamp, floor point {offset} m aside, {height} m below"),
        quantity: "direct irradiance (W/m²)",
        reference: radiance * area * cos * cos / r2,
        ours: radiosity_of(&stats, "target")? / rho,
        tolerance: 0.01,
    })
}
