//! Ctrl-C during a solve, checkpoints and resuming, through the command line.
//!
//! No test here depends on how fast the machine is: each run reports its stages on stderr as
//! lines (`--progress-every 0`: a line as each stage starts and at each step of its work), and
//! the test sends SIGINT once the line of the stage it means to interrupt has appeared. The
//! stage has seconds to minutes of work left by then. A timeout guards only against a run
//! that hangs; it never decides success.

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, ExitStatus, Output, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

mod common;

use common::{radiosity, scratch};

/// How long a test waits for a line or for the exit before it calls the run hung: a guard,
/// far beyond what any run here takes on a loaded machine.
const GUARD: Duration = Duration::from_secs(900);

/// Whether `line` is a progress line of `stage` (`STAGE: DONE[/TOTAL] UNIT after S s`) with
/// at least `done` units done.
fn progress_of(line: &str, stage: &str, done: u64) -> bool {
    line.strip_prefix(stage)
        .and_then(|rest| rest.strip_prefix(": "))
        .filter(|rest| rest.ends_with(" s") && rest.contains(" after "))
        .and_then(|rest| rest.split([' ', '/']).next())
        .and_then(|n| n.parse::<u64>().ok())
        .is_some_and(|n| n >= done)
}

/// The lines of a child's stderr as they come, read on a thread of their own.
fn stderr_lines(child: &mut std::process::Child) -> Receiver<String> {
    let stderr = child.stderr.take().expect("stderr piped");
    let (send, lines) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            if send.send(line).is_err() {
                break;
            }
        }
    });
    lines
}

/// Runs `cmd` (stderr piped), waits for a stderr line that satisfies `ready`, sends SIGINT and
/// waits for the exit; returns the exit status and the whole stderr.
fn interrupted_when(mut cmd: Command, ready: impl Fn(&str) -> bool) -> Output {
    let mut child = cmd.spawn().expect("spawns");
    let lines = stderr_lines(&mut child);
    let mut seen: Vec<String> = Vec::new();
    let deadline = Instant::now() + GUARD;
    loop {
        match lines.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
            Ok(line) => {
                let found = ready(&line);
                seen.push(line);
                if found {
                    break;
                }
            }
            Err(RecvTimeoutError::Timeout) => {
                let _ = child.kill();
                panic!("hung: no awaited line in {GUARD:?}:\n{}", seen.join("\n"));
            }
            Err(RecvTimeoutError::Disconnected) => {
                let status = child.wait().expect("waits");
                panic!(
                    "ended ({status}) before the awaited line:\n{}",
                    seen.join("\n")
                );
            }
        }
    }
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(killed.success());
    // The rest of stderr, to its end: the run has exited (or closed stderr) by then.
    loop {
        match lines.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
            Ok(line) => seen.push(line),
            Err(RecvTimeoutError::Disconnected) => break,
            Err(RecvTimeoutError::Timeout) => {
                let _ = child.kill();
                panic!("hung after SIGINT:\n{}", seen.join("\n"));
            }
        }
    }
    let status: ExitStatus = child.wait().expect("waits");
    Output {
        status,
        stdout: Vec::new(),
        stderr: (seen.join("\n") + "\n").into_bytes(),
    }
}

fn stats_iterations(path: &Path) -> (String, u64) {
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(path).expect("stats written")).expect("valid JSON");
    let solver = &json["solver"];
    let objects = json["objects"].to_string();
    (objects, solver["iterations"].as_u64().expect("iterations"))
}

/// `radiosity render ARGS` writing `out.png` and `stats.json` in `dir`, its stderr captured.
fn render_in(dir: &Path, args: &[&str]) -> Command {
    let mut cmd = radiosity();
    cmd.arg("render")
        .args(args)
        .arg("-o")
        .arg(dir.join("out.png"))
        .arg("--stats")
        .arg(dir.join("stats.json"))
        .args(["--progress-every", "0"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    cmd
}

/// A progressive solve far too long to finish: 3000 elements to a residual of 10⁻¹².
fn long_render(dir: &Path) -> Command {
    let mut cmd = render_in(
        dir,
        &[
            "cornell",
            "--solver",
            "progressive",
            "--elements",
            "3000",
            "--tolerance",
            "1e-12",
            "--width",
            "32",
            "--height",
            "32",
        ],
    );
    cmd.arg("--checkpoint").arg(dir.join("state.json"));
    cmd
}

/// Runs the long progressive render `cmd` and interrupts it once it has done an iteration.
fn interrupted_in_the_solve(cmd: Command) -> Output {
    interrupted_when(cmd, |line| progress_of(line, "solve", 1))
}

/// `radiosity solve cornell FLAGS EXTRA --stats DIR/STATS`, its stderr captured.
fn cornell_solve(dir: &Path, flags: &[&str], extra: &[&str], stats: &str) -> Command {
    let mut cmd = radiosity();
    cmd.args(["solve", "cornell"])
        .args(flags)
        .args(extra)
        .arg("--stats")
        .arg(dir.join(stats))
        .stderr(Stdio::piped());
    cmd
}

/// Checks that a resumed run succeeded with the uninterrupted run's objects and iterations
/// (`resumed.json` against `full.json` in `dir`).
fn assert_resumed_like_full(dir: &Path, resumed: &Output) {
    let stderr = String::from_utf8_lossy(&resumed.stderr);
    assert!(resumed.status.success(), "{stderr}");
    assert_eq!(
        stats_iterations(&dir.join("resumed.json")),
        stats_iterations(&dir.join("full.json"))
    );
}

#[test]
fn sigint_writes_the_solution_so_far_and_exits_130() {
    let dir = scratch("sigint");
    let out = interrupted_in_the_solve(long_render(&dir));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    let line = stderr
        .lines()
        .find(|l| l.starts_with("interrupted after "))
        .unwrap_or_else(|| panic!("no interruption message in {stderr}"));
    assert!(
        line.contains("iterations: wrote the solution so far"),
        "{line}"
    );
    let png = std::fs::read(dir.join("out.png")).expect("image written");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    // The default mode (final) is not run on an interrupted solve: the picture is the
    // interpolated one, and the run says so.
    assert!(
        stderr.contains("the picture is the solution so far, interpolated"),
        "{stderr}"
    );
    let (_, iterations) = stats_iterations(&dir.join("stats.json"));
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("stats.json")).expect("stats"))
            .expect("valid JSON");
    assert_eq!(json["solver"]["interrupted"], true);
    assert!(
        line.contains(&format!(" {iterations} iterations")),
        "{line}"
    );
    // The checkpoint saved at the interruption resumes; only the final files remain.
    let state = std::fs::read(dir.join("state.json")).expect("checkpoint written");
    assert!(!state.is_empty());
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["out.png", "state.json", "stats.json"]);
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn sigint_stops_the_hierarchical_solver_too() {
    // ε = 10⁻⁷ refines for minutes; the stop flag is read before every link of a refinement
    // round (`refine::tests`) and between gather iterations, and the links of the last whole
    // round give a valid solution. The signal comes as the hierarchical stage begins.
    let dir = scratch("sigint-hierarchical");
    let cmd = render_in(
        &dir,
        &[
            "cornell",
            "--solver",
            "hierarchical",
            "--epsilon",
            "1e-7",
            "--width",
            "32",
            "--height",
            "32",
        ],
    );
    let out = interrupted_when(cmd, |line| progress_of(line, "hierarchical", 0));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(
        stderr.lines().any(|l| l.starts_with("interrupted after ")),
        "{stderr}"
    );
    let png = std::fs::read(dir.join("out.png")).expect("image written");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("stats.json")).expect("stats written"))
            .expect("valid JSON");
    assert_eq!(json["solver"]["method"], "hierarchical");
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

/// A progressive solve of a small Cornell box to convergence, optionally capped or resumed.
fn small_solve(dir: &Path, extra: &[&str], stats: &str) -> Output {
    solve_with(
        dir,
        &["--solver", "progressive", "--elements", "150"],
        extra,
        stats,
    )
}

/// `radiosity solve cornell` with `solver`'s flags, quick form factors and a checkpoint after
/// every iteration, to convergence.
fn solve_with(dir: &Path, solver: &[&str], extra: &[&str], stats: &str) -> Output {
    radiosity()
        .args(["solve", "cornell"])
        .args(solver)
        .args([
            "--form-factors",
            "raycast",
            "--quadrature",
            "1",
            "--rays",
            "4",
        ])
        .args([
            "--tolerance",
            "1e-5",
            "--checkpoint-every",
            "0.000001",
            "-q",
        ])
        .args(extra)
        .arg("--stats")
        .arg(dir.join(stats))
        .output()
        .expect("runs")
}

#[test]
fn resuming_a_checkpoint_gives_the_uninterrupted_answer() {
    // (The hierarchical solver's --max-iterations caps the iterations but not the refinement,
    // so a capped run is no prefix of a full one: it is interrupted instead, below.)
    let solvers: [&[&str]; 2] = [
        &["--solver", "progressive", "--elements", "150"],
        &["--solver", "jacobi", "--elements", "150"],
    ];
    for solver in solvers {
        let dir = scratch(&format!("resume-{}", solver[1]));
        let state = dir.join("state.ckpt");
        let state = state.to_str().expect("utf-8 path");
        let full = solve_with(&dir, solver, &[], "full.json");
        assert!(full.status.success());
        let (objects, iterations) = stats_iterations(&dir.join("full.json"));
        let half = (iterations / 2).to_string();
        let capped = solve_with(
            &dir,
            solver,
            &["--max-iterations", &half, "--checkpoint", state],
            "half.json",
        );
        assert!(capped.status.success());
        let resumed = solve_with(&dir, solver, &["--resume", state], "resumed.json");
        assert!(
            resumed.status.success(),
            "{}",
            String::from_utf8_lossy(&resumed.stderr)
        );
        assert_eq!(
            stats_iterations(&dir.join("resumed.json")),
            (objects, iterations),
            "{solver:?}"
        );
        std::fs::remove_dir_all(&dir).expect("cleanup");
    }
}

#[test]
fn a_mismatched_or_broken_checkpoint_is_refused_with_one_line() {
    let dir = scratch("mismatch");
    let state = dir.join("state.json");
    let state_arg = state.to_str().expect("utf-8 path");
    let made = small_solve(
        &dir,
        &["--max-iterations", "5", "--checkpoint", state_arg],
        "a.json",
    );
    assert!(made.status.success());
    let other = small_solve(&dir, &["--resume", state_arg, "--seed", "7"], "b.json");
    let broken = dir.join("broken.json");
    std::fs::write(&broken, b"{\"format\": 1").expect("write");
    let garbage = small_solve(
        &dir,
        &["--resume", broken.to_str().expect("utf-8")],
        "c.json",
    );
    for (out, cause) in [
        (other, "does not belong to this run"),
        (garbage, "not a checkpoint"),
    ] {
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(
            stderr.starts_with("error: ") && stderr.contains("cannot resume"),
            "{stderr}"
        );
        assert!(stderr.contains(cause), "{stderr}");
    }
    assert!(!dir.join("b.json").exists() && !dir.join("c.json").exists());
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn sigint_during_the_render_stage_stops_it_and_writes_nothing() {
    // A quick solve (200 elements) and a long ray-traced render (a 256-ray final gather per
    // pixel): the signal comes as the render stage begins; the render used to ignore it and
    // report success.
    let dir = scratch("sigint-render");
    let cmd = render_in(
        &dir,
        &[
            "cornell",
            "--elements",
            "200",
            "--mode",
            "raytrace",
            "--gather",
            "256",
            "--width",
            "256",
            "--height",
            "256",
        ],
    );
    let out = interrupted_when(cmd, |line| progress_of(line, "render", 0));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(
        stderr
            .lines()
            .any(|l| l == "interrupted while rendering: wrote nothing"),
        "{stderr}"
    );
    assert!(!dir.join("out.png").exists() && !dir.join("stats.json").exists());
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn an_interrupted_run_keeps_existing_outputs_unless_asked() {
    let dir = scratch("sigint-keep");
    for partial in [false, true] {
        std::fs::write(dir.join("out.png"), b"finished").expect("write");
        let mut cmd = long_render(&dir);
        if partial {
            cmd.arg("--write-partial");
        }
        let out = interrupted_in_the_solve(cmd);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(130), "{stderr}");
        let png = std::fs::read(dir.join("out.png")).expect("image");
        if partial {
            assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        } else {
            assert_eq!(png, b"finished");
            assert!(stderr.contains("kept "), "{stderr}");
        }
    }
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn sigint_in_the_form_factor_stage_leaves_a_checkpoint_that_resumes_to_the_same_answer() {
    // The form factors are ~95 % of a Gauss-Seidel run (6 s here, meshing 0.05 s): the signal
    // comes once the first rows are done. The checkpoint keeps the rows computed so far;
    // resumed, the run computes the rest and ends with the uninterrupted run's answer, bit for
    // bit. (That the stage stops at its next chunk of rows: `checkpoint::tests`.)
    let flags = ["--elements", "2500"];
    let first_rows = |line: &str| progress_of(line, "form factors", 1);
    resume_after_sigint("sigint-form-factors", &flags, first_rows, |dir| {
        let cut: serde_json::Value =
            serde_json::from_slice(&std::fs::read(dir.join("cut.json")).expect("stats"))
                .expect("json");
        assert_eq!(cut["solver"]["interrupted"], true);
        assert_eq!(cut["solver"]["iterations"], 0);
    });
}

#[test]
fn an_interrupted_hierarchical_solve_resumes_to_the_same_answer() {
    // ε = 3·10⁻⁶ on the Cornell box: 10 s, 7 refine-and-solve passes, each of which leaves a
    // checkpoint (--checkpoint-every 0). A pass refines, gathers, then saves; the next pass's
    // first line (`hierarchical (pass 2/7, refining): ...`) comes after that save, so the
    // signal, sent on it, finds the first pass's checkpoint on disk.
    let flags = [
        "--solver",
        "hierarchical",
        "--epsilon",
        "3e-6",
        "--checkpoint-every",
        "0.000001",
    ];
    let second_pass = |line: &str| line.starts_with("hierarchical (pass 2/");
    resume_after_sigint("sigint-hierarchical-resume", &flags, second_pass, |_| {});
}

/// Solves the Cornell box with `flags` whole (`full.json`), then again with a checkpoint and
/// SIGINT once a stderr line satisfies `ready` (`cut.json`, exit status 130, then
/// `check(dir)`), then resumed from that checkpoint: the resumed run must give the whole
/// run's answer.
fn resume_after_sigint(
    name: &str,
    flags: &[&str],
    ready: impl Fn(&str) -> bool,
    check: impl FnOnce(&Path),
) {
    let dir = scratch(name);
    let solve = |extra: &[&str], stats: &str| cornell_solve(&dir, flags, extra, stats);
    let state = dir.join("state.ckpt");
    let state = state.to_str().expect("utf-8 path");
    let full = solve(&["-q"], "full.json").output().expect("runs");
    assert!(full.status.success());
    let cut = solve(
        &["--checkpoint", state, "--progress-every", "0"],
        "cut.json",
    );
    let out = interrupted_when(cut, ready);
    assert_eq!(
        out.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    check(&dir);
    let resumed = solve(&["--resume", state, "-q"], "resumed.json")
        .output()
        .expect("runs");
    assert_resumed_like_full(&dir, &resumed);
    std::fs::remove_dir_all(&dir).expect("cleanup");
}

#[test]
fn sigint_while_meshing_stops_at_once_and_writes_nothing() {
    // `solids` spends ~2 s in contact and shadow refinement; the refinements read the flag
    // before each element (`mesh::tests`). The signal comes as the meshing stage begins.
    let dir = scratch("sigint-meshing");
    let mut cmd = radiosity();
    cmd.args(["render", "solids", "-o"])
        .arg(dir.join("out.png"))
        .arg("--stats")
        .arg(dir.join("stats.json"))
        .args(["--progress-every", "0"])
        .stderr(Stdio::piped());
    let out = interrupted_when(cmd, |line| progress_of(line, "meshing", 0));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert_eq!(
        stderr.lines().last(),
        Some("interrupted while meshing: wrote nothing"),
        "{stderr}"
    );
    assert!(!dir.join("out.png").exists() && !dir.join("stats.json").exists());
    std::fs::remove_dir_all(&dir).expect("cleanup");
}
