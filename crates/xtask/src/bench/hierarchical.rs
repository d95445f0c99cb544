//! `cargo xtask bench --suite hierarchical`: how the hierarchical solver's time, links and memory
//! grow with the number of elements, from about 10⁴ to 10⁶.
//!
//! Two series:
//!
//! - **The Cornell box at falling ε** ([`EPSILONS`]): the same scene refined further, so the
//!   elements multiply where light varies (shadow edges, corners).
//! - **A field of 200 spheres** (20 × 10 on a 1 m grid, radius 0.35 m, alternately white and
//!   red) on a 20 × 10 m floor under an 8 × 4 m area light 4 m up, every sphere an icosphere of
//!   20·4^s triangles for s = 1 … `--largest` (16 000 to 1 024 000 triangles): many meshes, so
//!   the clusters carry the coupling between them.
//!
//! Each case runs in a process of its own (this program with the hidden `--case K`), which
//! prints its figures as one JSON line, its peak resident memory read from `/proc/self/status`
//! (`VmHWM`; absent off Linux). The suite prints a table and fits the growth exponent k of
//! time ∝ elements^k and links ∝ elements^k by least squares on the logarithms, per series.

use std::io::{IsTerminal, Write};
use std::process::Command;

use anyhow::{bail, Context};
use radiosity::pipeline::{self, Settings};
use radiosity::progress::{Progress, Silent, Work};
use radiosity::scene::builtin;
use radiosity::{solve, Scene};
use report::Bars;
use serde::{Deserialize, Serialize};

use super::BenchArgs;

/// The Cornell box's ε, coarse to fine.
const EPSILONS: [f64; 4] = [1e-3, 1e-4, 3e-5, 1e-5];

/// One case of the suite.
#[derive(Clone, Copy, Debug)]
enum Case {
    /// The built-in Cornell box at this ε.
    Cornell(f64),
    /// The sphere field with this icosphere subdivision, at the default ε.
    Field(u32),
}

/// What one case measured.
#[derive(Debug, Serialize, Deserialize)]
struct Figures {
    series: String,
    epsilon: f64,
    triangles: usize,
    elements: usize,
    links: u64,
    seconds: f64,
    refine_seconds: f64,
    solve_seconds: f64,
    /// The solver's own account of its hierarchy (nodes, clusters, links).
    hierarchy_bytes: u64,
    /// Peak resident memory of the whole process.
    peak_rss_bytes: Option<u64>,
}

/// Runs the suite, or one case of it with `--case`.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    let cases: Vec<Case> = EPSILONS
        .iter()
        .map(|&e| Case::Cornell(e))
        .chain((1..=args.largest).map(Case::Field))
        .collect();
    if let Some(k) = args.case {
        let case = *cases.get(k).context("no such case")?;
        let figures = measure(case)?;
        println!("{}", serde_json::to_string(&figures)?);
        return Ok(());
    }
    let exe = std::env::current_exe().context("cannot find this program")?;
    let mut all = Vec::new();
    let mut out = std::io::stdout().lock();
    writeln!(
        out,
        "{:<8} {:>8} {:>10} {:>10} {:>11} {:>9} {:>9} {:>9} {:>10} {:>10}",
        "series",
        "epsilon",
        "triangles",
        "elements",
        "links",
        "time s",
        "refine s",
        "solve s",
        "peak MB",
        "hier. MB"
    )?;
    let bars = Bars::new(std::io::stderr().is_terminal());
    bars.start("bench cases", Work::of(cases.len() as u64, "cases"));
    for k in 0..cases.len() {
        let output = Command::new(&exe)
            .args(["bench", "--suite", "hierarchical", "--largest"])
            .arg(args.largest.to_string())
            .arg("--case")
            .arg(k.to_string())
            .output()
            .context("cannot run a case")?;
        if !output.status.success() {
            bail!(
                "case {k} failed: {}",
                String::from_utf8_lossy(&output.stderr).trim()
            );
        }
        let f: Figures = serde_json::from_slice(&output.stdout).context("a case's figures")?;
        let mb = |b: u64| b as f64 / 1e6;
        writeln!(
            out,
            "{:<8} {:>8.0e} {:>10} {:>10} {:>11} {:>9.2} {:>9.2} {:>9.2} {:>10} {:>10.0}",
            f.series,
            f.epsilon,
            f.triangles,
            f.elements,
            f.links,
            f.seconds,
            f.refine_seconds,
            f.solve_seconds,
            f.peak_rss_bytes
                .map_or_else(|| "-".to_string(), |b| format!("{:.0}", mb(b))),
            mb(f.hierarchy_bytes),
        )?;
        all.push(f);
        bars.advance(1);
    }
    bars.finish();
    let mut fits = Vec::new();
    for series in ["cornell", "field"] {
        let points: Vec<&Figures> = all.iter().filter(|f| f.series == series).collect();
        if points.len() < 2 {
            continue;
        }
        let time = exponent(points.iter().map(|f| (f.elements as f64, f.seconds)));
        let links = exponent(points.iter().map(|f| (f.elements as f64, f.links as f64)));
        writeln!(
            out,
            "{series}: time ∝ elements^{time:.2}, links ∝ elements^{links:.2}"
        )?;
        fits.push(
            serde_json::json!({ "series": series, "time_exponent": time, "links_exponent": links }),
        );
    }
    if let Some(path) = &args.json {
        let json = serde_json::to_vec_pretty(&serde_json::json!({ "cases": all, "fits": fits }))?;
        radiosity::io::atomic::write_atomic(path, |w| w.write_all(&json))
            .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    Ok(())
}

/// Solves one case with the hierarchical solver and collects its figures.
fn measure(case: Case) -> anyhow::Result<Figures> {
    let (series, epsilon, scene) = match case {
        Case::Cornell(e) => (
            "cornell",
            e,
            builtin::load("cornell").context("the built-in Cornell box is missing")??,
        ),
        Case::Field(s) => ("field", solve::DEFAULT_EPSILON, field(s)?),
    };
    let triangles = scene.polygons.len();
    let mut settings = Settings {
        method: Some(solve::Method::Hierarchical),
        ..Settings::default()
    };
    settings.solve.epsilon = epsilon;
    let solved = pipeline::solve(scene, &settings, &Silent)?;
    let timings = &solved.timings;
    let hierarchy = solved.solution.hierarchy.unwrap_or_default();
    Ok(Figures {
        series: series.to_string(),
        epsilon,
        triangles,
        elements: solved.mesh.element_count(),
        links: hierarchy.links,
        seconds: timings.mesh + timings.form_factors + timings.solve,
        refine_seconds: timings.form_factors,
        solve_seconds: timings.solve,
        hierarchy_bytes: hierarchy.peak_memory_bytes,
        peak_rss_bytes: peak_rss(),
    })
}

/// The sphere field (module documentation) with icospheres of `subdivisions`.
fn field(subdivisions: u32) -> anyhow::Result<Scene> {
    let mut text = String::from(
        "[camera]\neye = [10.0, 6.0, -8.0]\ntarget = [10.0, 0.0, 5.0]\nup = [0.0, 1.0, 0.0]\n\
         fov_y = 50.0\n\n\
         [materials.white]\nreflectance = [0.7, 0.7, 0.7]\n\
         [materials.red]\nreflectance = [0.7, 0.2, 0.2]\n\
         [materials.light]\nreflectance = [0.0, 0.0, 0.0]\nemission = [10.0, 10.0, 10.0]\n\n\
         [[objects]]\nname = \"floor\"\nmaterial = \"white\"\nshape = \"polygon\"\n\
         vertices = [[0.0, 0.0, 0.0], [0.0, 0.0, 10.0], [20.0, 0.0, 10.0], [20.0, 0.0, 0.0]]\n\n\
         [[objects]]\nname = \"light\"\nmaterial = \"light\"\nshape = \"polygon\"\n\
         vertices = [[6.0, 4.0, 3.0], [14.0, 4.0, 3.0], [14.0, 4.0, 7.0], [6.0, 4.0, 7.0]]\n",
    );
    for i in 0..20 {
        for j in 0..10 {
            let material = if (i + j) % 2 == 1 { "red" } else { "white" };
            text.push_str(&format!(
                "\n[[objects]]\nname = \"sphere_{i}_{j}\"\nmaterial = \"{material}\"\n\
                 shape = \"sphere\"\ncenter = [{}.5, 0.4, {}.5]\nradius = 0.35\n\
                 subdivisions = {subdivisions}\n",
                i, j
            ));
        }
    }
    Ok(Scene::from_toml_str(
        &text,
        std::path::Path::new("sphere-field.toml"),
    )?)
}

/// The process's peak resident memory (`VmHWM` of `/proc/self/status`), in bytes.
fn peak_rss() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// The least-squares slope of log y against log x.
fn exponent(points: impl Iterator<Item = (f64, f64)>) -> f64 {
    let logs: Vec<(f64, f64)> = points
        .filter(|&(x, y)| x > 0.0 && y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = logs.len() as f64;
    let (mx, my) = logs
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x / n, b + y / n));
    let (sxy, sxx) = logs.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    if sxx > 0.0 {
        sxy / sxx
    } else {
        f64::NAN
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_recovers_a_power_law() {
        let points = [1e4, 1e5, 1e6].map(|x: f64| (x, 3.0 * x.powf(1.1)));
        assert!((exponent(points.into_iter()) - 1.1).abs() < 1e-12);
    }

    #[test]
    fn the_field_has_200_spheres_of_20_4_to_the_s_triangles() {
        let scene = field(1).unwrap();
        assert_eq!(scene.objects.len(), 202);
        assert_eq!(scene.polygons.len(), 2 + 200 * 80);
    }
}
