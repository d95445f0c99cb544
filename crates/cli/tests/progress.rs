//! What `render` and `solve` say on a stderr that is not a terminal: a summary line per stage
//! (`STAGE done: COUNT WHAT, ... in S s`) and progress lines within (`STAGE[ (PHASE)]:
//! DONE[/TOTAL] UNIT after S s`), checked against the statistics file of the same run.

use std::path::Path;
use std::process::Output;

mod common;

use common::{radiosity, scratch};

/// A summary line, `STAGE done: COUNT WHAT, COUNT WHAT... in S s`, taken apart.
#[derive(Debug)]
struct Summary {
    stage: String,
    figures: Vec<(u64, String)>,
    seconds: f64,
}

impl Summary {
    /// The line taken apart, or `None` if it is no summary line; panics on a summary line
    /// out of format.
    fn parse(line: &str) -> Option<Self> {
        let (stage, rest) = line.split_once(" done: ")?;
        let (figures, seconds) = rest
            .strip_suffix(" s")
            .and_then(|r| r.rsplit_once(" in "))
            .unwrap_or_else(|| panic!("no `in S s`: {line}"));
        let figures = figures
            .split(", ")
            .map(|figure| {
                let (count, what) = figure.split_once(' ').unwrap_or_else(|| panic!("{line}"));
                let count = count.parse().unwrap_or_else(|_| panic!("{line}"));
                (count, what.to_owned())
            })
            .collect();
        Some(Self {
            stage: stage.to_owned(),
            figures,
            seconds: seconds_of(seconds, 2, line),
        })
    }

    /// The count of `what`; panics if the line has none.
    fn count(&self, what: &str) -> u64 {
        self.figures
            .iter()
            .find(|(_, w)| w == what)
            .unwrap_or_else(|| panic!("no {what} in {self:?}"))
            .0
    }
}

/// The seconds of `line`, checked to be a number ≥ 0 with `decimals` digits after the point.
fn seconds_of(text: &str, decimals: usize, line: &str) -> f64 {
    let seconds: f64 = text.parse().unwrap_or_else(|_| panic!("{line}"));
    assert!(seconds >= 0.0, "{line}");
    assert_eq!(
        text.split_once('.').map(|(_, d)| d.len()),
        Some(decimals),
        "{line}"
    );
    seconds
}

/// The stage and phase of a progress line `STAGE[ (PHASE)]: DONE[/TOTAL] UNIT after S s`,
/// checked for format.
fn progress_stage(line: &str) -> Option<(&str, Option<&str>)> {
    let (stage, rest) = line.split_once(": ")?;
    let (stage, phase) = match stage.split_once(" (") {
        Some((stage, phase)) => {
            let phase = phase.strip_suffix(')');
            assert!(phase.is_some_and(|p| !p.is_empty()), "{line}");
            (stage, phase)
        }
        None => (stage, None),
    };
    let (work, seconds) = rest.strip_suffix(" s")?.rsplit_once(" after ")?;
    let (done, unit) = work.split_once(' ')?;
    let counts: Vec<&str> = done.split('/').collect();
    assert!(
        counts.len() <= 2 && counts.iter().all(|c| c.parse::<u64>().is_ok()),
        "{line}"
    );
    assert!(!unit.is_empty() && !unit.contains(' '), "{line}");
    seconds_of(seconds, 1, line);
    Some((stage, phase))
}

/// The summaries of `stderr`, in order.
fn summaries(stderr: &str) -> Vec<Summary> {
    stderr.lines().filter_map(Summary::parse).collect()
}

fn stats(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).expect("stats written")).expect("valid JSON")
}

fn succeeded(out: &Output) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{stderr}");
    stderr
}

#[test]
fn a_piped_render_says_each_stage_with_its_counts_and_seconds() {
    // A uniform mesh (Gauss-Seidel: form factors, then a solve), the lit mesh refined for its
    // export, and the evaluated picture; every step of every stage reported (interval 0).
    let dir = scratch("progress-render");
    let out = radiosity()
        .args(["render", "cornell", "--elements", "150", "--width", "24"])
        .args(["--height", "16", "--progress-every", "0", "-o"])
        .arg(dir.join("out.png"))
        .arg("--export")
        .arg(dir.join("lit.glb"))
        .arg("--stats")
        .arg(dir.join("stats.json"))
        .output()
        .expect("runs");
    let stderr = succeeded(&out);
    let json = stats(&dir.join("stats.json"));
    let done = summaries(&stderr);
    let stages: Vec<&str> = done.iter().map(|s| s.stage.as_str()).collect();
    assert_eq!(
        stages,
        [
            "meshing",
            "form factors",
            "solve",
            "evaluation",
            "display",
            "evaluation",
            "render"
        ],
        "{stderr}"
    );
    let elements = json["elements"].as_u64().expect("elements");
    assert_eq!(done[0].count("patches"), json["patches"].as_u64().unwrap());
    assert_eq!(done[0].count("elements"), elements);
    // One form-factor row per element.
    assert_eq!(done[1].figures, [(elements, "rows".to_owned())]);
    assert_eq!(
        done[2].count("iterations"),
        json["solver"]["iterations"].as_u64().unwrap()
    );
    assert_eq!(done[2].count("links"), json["links"].as_u64().unwrap());
    // The export settles every element, the picture at most all.
    assert_eq!(done[3].count("elements"), elements);
    assert!(done[4].count("vertices") > 0 && done[4].count("triangles") > 0);
    assert!((1..=elements).contains(&done[5].count("elements")));
    assert_eq!(done[6].figures, [(24 * 16, "pixels".to_owned())]);
    // Each stage's seconds lie within the run's (rounded to hundredths).
    let total = json["timings"]["total"].as_f64().expect("total");
    assert!(done.iter().all(|s| s.seconds <= total + 0.005), "{stderr}");
    // Interval 0: every stage reports its start, then each step, before its summary.
    let mut current = None;
    for line in stderr.lines() {
        if let Some(summary) = Summary::parse(line) {
            assert_eq!(current, Some(summary.stage.clone()), "{stderr}");
            current = None;
        } else if let Some((stage, _)) = progress_stage(line) {
            current.get_or_insert_with(|| {
                let start = format!("{stage}: 0");
                assert!(line.starts_with(&start), "{line}");
                stage.to_owned()
            });
            assert_eq!(current.as_deref(), Some(stage), "{stderr}");
        }
    }
    // The meshing reports its passes as phases, in order.
    let phases: Vec<&str> = stderr
        .lines()
        .filter_map(progress_stage)
        .filter(|(stage, _)| *stage == "meshing")
        .filter_map(|(_, phase)| phase)
        .collect();
    let mut order = phases.clone();
    order.dedup();
    assert_eq!(
        order,
        ["subdivision", "contacts", "shadows", "near field", "bvh"],
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn a_piped_hierarchical_solve_says_its_elements_and_links() {
    // Every step reported (interval 0): the passes come as phases, each refining then
    // gathering, and the leaf solve last.
    let dir = scratch("progress-solve");
    let out = radiosity()
        .args([
            "solve",
            "cornell",
            "--epsilon",
            "1e-3",
            "--progress-every",
            "0",
        ])
        .arg("--stats")
        .arg(dir.join("stats.json"))
        .output()
        .expect("runs");
    let stderr = succeeded(&out);
    let json = stats(&dir.join("stats.json"));
    let done = summaries(&stderr);
    let stages: Vec<&str> = done.iter().map(|s| s.stage.as_str()).collect();
    assert_eq!(stages, ["meshing", "hierarchical"], "{stderr}");
    let hierarchical = &done[1];
    assert_eq!(
        hierarchical.count("elements"),
        json["elements"].as_u64().unwrap()
    );
    assert_eq!(hierarchical.count("links"), json["links"].as_u64().unwrap());
    assert_eq!(
        hierarchical.count("iterations"),
        json["solver"]["iterations"].as_u64().unwrap()
    );
    let mut phases: Vec<&str> = stderr
        .lines()
        .filter_map(progress_stage)
        .filter(|(stage, _)| *stage == "hierarchical")
        .filter_map(|(_, phase)| phase)
        .collect();
    phases.dedup();
    let passes = (phases.len() - 1) / 2;
    assert!(passes >= 2, "{stderr}");
    let expected: Vec<String> = (1..=passes)
        .flat_map(|p| {
            [
                format!("pass {p}/{passes}, refining"),
                format!("pass {p}/{passes}, gathering"),
            ]
        })
        .chain(["leaf solve".to_owned()])
        .collect();
    assert_eq!(phases, expected, "{stderr}");
    // Only the summaries, the progress lines and the run's closing lines.
    for line in stderr.lines() {
        let known = Summary::parse(line).is_some()
            || progress_stage(line).is_some()
            || line.starts_with("wrote ")
            || line.starts_with("cornell: ");
        assert!(known, "{line}");
    }
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn quiet_silences_the_progress_lines() {
    let dir = scratch("progress-quiet");
    let out = radiosity()
        .args(["render", "cornell", "--elements", "100", "--width", "16"])
        .args(["--height", "16", "--progress-every", "0", "--quiet", "-o"])
        .arg(dir.join("out.png"))
        .output()
        .expect("runs");
    let stderr = succeeded(&out);
    assert!(stderr.is_empty(), "{stderr}");
    std::fs::remove_dir_all(&dir).expect("cleanup");
}
