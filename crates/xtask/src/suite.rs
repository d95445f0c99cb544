//! `cargo xtask suite`: our solvers against the Mitsuba 3 references of `benches/suite`
//! (scenes with the traits of files made elsewhere: two-sided and non-planar walls, closed
//! meshes, thin partitions, an emitter against a wall, a Blender-style glTF, a bare OBJ with
//! thousands of faces, a furnished room).
//!
//! Each reference (`benches/suite/reference/<scene>.json`, made by
//! `benches/suite/reference.py`) holds every object's mean radiosity B per channel with its
//! standard error (≤ 0.2 %). For every scene and every asked (solver, form-factor method) pair
//! the whole engine runs at its default settings, and one row reports the object and channel
//! furthest from the reference; it passes within [`TOLERANCE`]. A scene whose reference says it
//! is `closed` (a room closed on every side) gets a second row: the power its surfaces absorb
//! over the power they emit, worst channel, which must be one within [`ENERGY_TOLERANCE`]. The
//! rows are those of `radiosity validate` ([`report::check`]), as a Markdown table or JSON. The
//! files are read from the repository at run time (`--dir`, default this repository), not
//! compiled in: the scenes are a few megabytes.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use radiosity::mesh::Subdivision;
use radiosity::pipeline::{self, Settings};
use radiosity::progress::{Progress, Silent, Work};
use radiosity::stats::Timings;
use radiosity::{formfactor, solve, Scene};
use report::check::{self, Check, Format};
use report::Bars;

/// `cargo xtask suite`.
#[derive(Debug, Args)]
pub struct SuiteArgs {
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Markdown)]
    pub format: Format,
    /// The repository that holds `benches/suite` and `scenes/suite` [default: this one].
    #[arg(long, value_name = "DIR")]
    pub dir: Option<PathBuf>,
    /// Scenes to run (repeatable; default: all).
    #[arg(long = "scene", value_name = "NAME")]
    pub scenes: Vec<String>,
    /// Solvers (repeatable): auto, jacobi, gauss-seidel, progressive, hierarchical, or all
    /// [default: auto].
    #[arg(long = "solver", value_name = "NAME")]
    pub solvers: Vec<String>,
    /// Form-factor methods (repeatable): raycast, hemicube [default: raycast]. (Analytic form
    /// factors ignore visibility; every suite scene has shadows.)
    #[arg(long = "form-factors", value_name = "NAME", value_enum)]
    pub form_factors: Vec<formfactor::Method>,
}

/// Runs the suite, prints its rows, and fails when one is out of tolerance.
pub fn run(args: &SuiteArgs) -> anyhow::Result<()> {
    let solvers = solvers(&args.solvers)?;
    let form_factors = if args.form_factors.is_empty() {
        vec![formfactor::Method::RayCast]
    } else {
        args.form_factors.clone()
    };
    let root = args.dir.clone().unwrap_or_else(crate::repository);
    let bars = Bars::new(std::io::stderr().is_terminal());
    let checks = rows(&root, &args.scenes, &solvers, &form_factors, &bars)?;
    let mut out = std::io::stdout().lock();
    match args.format {
        Format::Json => {
            let json: Vec<_> = checks.iter().map(Check::json).collect();
            writeln!(out, "{}", serde_json::to_string_pretty(&json)?)?;
        }
        Format::Markdown => writeln!(out, "{}", check::markdown(&checks))?,
    }
    let failed = checks.iter().filter(|c| !c.pass()).count();
    anyhow::ensure!(failed == 0, "{failed} suite case(s) out of tolerance");
    Ok(())
}

/// A solver of the suite: one of the engine's, or `None` for the automatic choice (`auto`).
type Solver = Option<solve::Method>;

/// The solvers `--solver` names: `auto`, one of the engine's, or `all` (the automatic choice
/// and every solver); the automatic choice when none is named.
fn solvers(names: &[String]) -> anyhow::Result<Vec<Solver>> {
    if names.iter().any(|n| n == "all") {
        return Ok(std::iter::once(None)
            .chain(solve::Method::ALL.map(Some))
            .collect());
    }
    if names.is_empty() {
        return Ok(vec![None]);
    }
    names
        .iter()
        .map(|n| match n.as_str() {
            "auto" => Ok(None),
            _ => n
                .parse::<solve::Method>()
                .map(Some)
                .map_err(|e| anyhow::anyhow!("{e}, auto or all")),
        })
        .collect()
}

/// Largest accepted relative error of any object's radiosity in any channel.
pub const TOLERANCE: f64 = 0.01;

/// Largest accepted departure of a closed scene's absorbed over emitted power from one.
pub const ENERGY_TOLERANCE: f64 = 1e-3;

/// One object of a reference: its name and mean radiosity per channel.
struct Reference {
    name: String,
    radiosity: [f64; 3],
}

/// One reference file: its scene (relative to the repository), whether the scene is closed,
/// and its objects.
struct ReferenceFile {
    scene: PathBuf,
    closed: bool,
    objects: Vec<Reference>,
}

/// The rows of the suite under `root` (the repository), for the scenes named in `only` (all when
/// empty), every solver of `solvers` and form-factor method of `form_factors`.
///
/// # Errors
/// The reference folder is missing or a reference is malformed, or a scene fails to load or
/// solve.
pub fn rows(
    root: &Path,
    only: &[String],
    solvers: &[Solver],
    form_factors: &[formfactor::Method],
    progress: &dyn Progress,
) -> anyhow::Result<Vec<Check>> {
    let folder = root.join("benches").join("suite").join("reference");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&folder)
        .map_err(|e| anyhow::anyhow!("{}: {e}: give the repository with --dir", folder.display()))?
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .filter(|p| {
            only.is_empty()
                || p.file_stem()
                    .and_then(|s| s.to_str())
                    .is_some_and(|s| only.iter().any(|o| o == s))
        })
        .collect();
    files.sort();
    anyhow::ensure!(
        !files.is_empty(),
        "no suite reference matches in {}",
        folder.display()
    );
    let mut out = Vec::new();
    let cases = files.len() * solvers.len() * form_factors.len();
    progress.start("suite", Work::of(cases as u64, "cases"));
    for file in &files {
        let reference = read_reference(file)?;
        let scene_path = root.join(&reference.scene);
        let label = file.file_stem().and_then(|s| s.to_str()).unwrap_or("?");
        let scene = Scene::load(&scene_path).map_err(|e| anyhow::anyhow!("{}", e))?;
        for &solver in solvers {
            for &ff in form_factors {
                out.extend(scene_rows(label, scene.clone(), solver, ff, &reference)?);
                progress.advance(1);
            }
        }
    }
    progress.finish();
    Ok(out)
}

/// One reference JSON.
fn read_reference(file: &Path) -> anyhow::Result<ReferenceFile> {
    let bad = |what: &str| anyhow::anyhow!("{}: {what}", file.display());
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(file)?).map_err(|e| bad(&e.to_string()))?;
    let scene = json["scene"].as_str().ok_or_else(|| bad("no `scene`"))?;
    let objects = json["objects"]
        .as_array()
        .ok_or_else(|| bad("no `objects`"))?
        .iter()
        .map(|o| {
            let name = o["name"]
                .as_str()
                .ok_or_else(|| bad("an object without `name`"))?;
            let rgb = o["radiosity"]
                .as_array()
                .and_then(|v| check::rgb(v))
                .ok_or_else(|| bad(&format!("`{name}` has no radiosity [r, g, b]")))?;
            Ok(Reference {
                name: name.to_owned(),
                radiosity: rgb.to_array(),
            })
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    Ok(ReferenceFile {
        scene: PathBuf::from(scene),
        closed: json["closed"].as_bool().unwrap_or(false),
        objects,
    })
}

/// Solves `scene` at the default settings with `solver` and `ff`: the row of the object and
/// channel furthest from its reference, and for a closed scene the row of its power balance.
fn scene_rows(
    label: &str,
    scene: Scene,
    solver: Solver,
    ff: formfactor::Method,
    reference: &ReferenceFile,
) -> anyhow::Result<Vec<Check>> {
    let references = &reference.objects;
    let settings = Settings {
        subdivision: Subdivision::default(),
        discontinuity: false,
        display: pipeline::Display::Averaged,
        form_factors: formfactor::Settings::of(ff),
        solve: solve::Settings::default(),
        // The automatic choice as the command line makes it: `radiosity solve SCENE` for the
        // default form factors, `radiosity solve SCENE --form-factors FF` for the others (the
        // default method named explicitly would also count as asking for a uniform mesh).
        method: match solver {
            None => solve::plan::unsized_method(ff != formfactor::Settings::default().method()),
            Some(m) => Some(m),
        },
    };
    let start = Instant::now();
    let stats = pipeline::solve(scene, &settings, &Silent)?.stats(&Timings::default());
    let seconds = start.elapsed().as_secs_f64();
    let mut worst: Option<(f64, &Reference, usize, f64)> = None;
    for reference in references {
        let ours = stats
            .objects
            .iter()
            .find(|o| o.name == reference.name)
            .ok_or_else(|| {
                anyhow::anyhow!("{label}: no object `{}` in our stats", reference.name)
            })?;
        for c in 0..3 {
            let error = (ours.radiosity[c] - reference.radiosity[c]).abs()
                / reference.radiosity[c].abs().max(f64::MIN_POSITIVE);
            if worst.is_none_or(|w| error > w.0) {
                worst = Some((error, reference, c, ours.radiosity[c]));
            }
        }
    }
    let (_, worst, channel, ours) =
        worst.ok_or_else(|| anyhow::anyhow!("{label}: the reference has no objects"))?;
    let run = format!(
        "suite {label} ({}, {}, {seconds:.1} s)",
        solver.map_or("auto", |m| m.name()),
        ff.name()
    );
    let mut rows = vec![Check {
        case: format!("{run}: {} ({})", worst.name, ["r", "g", "b"][channel]),
        quantity: "radiosity B of the worst object and channel (W/m²)",
        reference: worst.radiosity[channel],
        ours,
        tolerance: TOLERANCE,
    }];
    if reference.closed {
        let balance = |c: usize| stats.energy.absorbed[c] / stats.energy.emitted[c];
        let c = (0..3)
            .max_by(|&a, &b| {
                (balance(a) - 1.0)
                    .abs()
                    .total_cmp(&(balance(b) - 1.0).abs())
            })
            .unwrap_or(0);
        rows.push(Check {
            case: format!("{run}: closed, power balance ({})", ["r", "g", "b"][c]),
            quantity: "absorbed / emitted power, worst channel",
            reference: 1.0,
            ours: balance(c),
            tolerance: ENERGY_TOLERANCE,
        });
    }
    Ok(rows)
}
