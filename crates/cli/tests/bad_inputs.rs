//! The bad-input corpus `tests/bad/`: every broken scene or mesh makes the real binary fail with
//! exit status 2 and one line `error: FILE[:LINE:COL]: [`KEY`: ]CAUSE`, without a panic and
//! without leaving any file behind.
//!
//! Each corpus file states what is expected on its first line (`# expect: …`), or, when its
//! format has no comments (glTF, GLB), in `tests/bad/EXPECT.toml`. The expectation is a list of
//! `file=NAME` (the file the error names, default the corpus file itself), `at=LINE:COL`,
//! `key=KEY` and `text=TEXT` (the rest of the line, a part of the message). Files named
//! `warn_*` are repairable: they render (exit 0) with a warning whose text follows `# warning:`.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Output;

mod common;

use common::{radiosity, scratch};

/// The corpus directory.
fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/bad")
}

/// `radiosity render SCENE` with small outputs, in `dir`.
fn render(dir: &Path, scene: &Path, quiet: bool) -> Output {
    let mut args = vec![
        "render".into(),
        scene.as_os_str().to_owned(),
        "-o".into(),
        "out.png".into(),
        "--stats".into(),
        "s.json".into(),
        "--width".into(),
        "8".into(),
        "--height".into(),
        "8".into(),
        "--elements".into(),
        "50".into(),
    ];
    if quiet {
        args.push("--quiet".into());
    }
    radiosity()
        .args(&args)
        .current_dir(dir)
        .output()
        .expect("the binary runs")
}

/// What one corpus file must produce.
#[derive(Debug, Default)]
struct Expect {
    file: Option<String>,
    at: Option<String>,
    key: Option<String>,
    text: Option<String>,
}

fn parse_expect(spec: &str) -> Expect {
    let mut e = Expect::default();
    let mut rest = spec.trim();
    while !rest.is_empty() {
        if let Some(text) = rest.strip_prefix("text=") {
            e.text = Some(text.to_string());
            break;
        }
        let (token, tail) = rest.split_once(' ').unwrap_or((rest, ""));
        match token.split_once('=') {
            Some(("file", v)) => e.file = Some(v.to_string()),
            Some(("at", v)) => e.at = Some(v.to_string()),
            Some(("key", v)) => e.key = Some(v.to_string()),
            _ => panic!("bad expectation token `{token}` in `{spec}`"),
        }
        rest = tail.trim_start();
    }
    e
}

/// `"name" = "spec"` lines of EXPECT.toml.
fn sidecar() -> Vec<(String, String)> {
    let text = fs::read_to_string(corpus().join("EXPECT.toml")).expect("EXPECT.toml");
    text.lines()
        .filter(|l| l.starts_with('"'))
        .map(|l| {
            let (name, spec) = l.split_once(" = ").expect("`\"name\" = \"spec\"`");
            (name.trim_matches('"').into(), spec.trim_matches('"').into())
        })
        .collect()
}

/// The expectation of `path`: its first line or its EXPECT.toml entry.
fn expectation(path: &Path, sidecar: &[(String, String)]) -> Expect {
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    if let Some((_, spec)) = sidecar.iter().find(|(n, _)| *n == name) {
        return parse_expect(spec);
    }
    let bytes = fs::read(path).expect("read corpus file");
    let first = String::from_utf8_lossy(&bytes)
        .lines()
        .next()
        .unwrap_or("")
        .to_string();
    let spec = first
        .strip_prefix("# expect:")
        .unwrap_or_else(|| panic!("{name}: no `# expect:` line and no EXPECT.toml entry"));
    parse_expect(spec)
}

/// Checks one failing run against its expectation; returns the problems found.
fn check_failure(name: &str, out: &Output, expect: &Expect, dir: &Path) -> Vec<String> {
    let mut problems = Vec::new();
    let stderr = String::from_utf8_lossy(&out.stderr);
    if out.status.code() != Some(2) {
        problems.push(format!("exit status {:?}, not 2", out.status.code()));
    }
    if stderr.contains("panicked") || stderr.contains("RUST_BACKTRACE") {
        problems.push("panicked".into());
    }
    let lines: Vec<&str> = stderr.lines().collect();
    match lines.as_slice() {
        [line] if line.starts_with("error: ") => {
            let file = expect.file.as_deref().unwrap_or(name);
            let mut wanted = vec![file.to_string()];
            wanted.extend(expect.at.iter().map(|at| format!(":{at}: ")));
            wanted.extend(expect.key.iter().map(|key| format!("`{key}`")));
            wanted.extend(expect.text.clone());
            for w in wanted {
                if !line.contains(&w) {
                    problems.push(format!("`{w}` missing from `{line}`"));
                }
            }
        }
        _ => problems.push(format!("stderr is not one `error: ` line: {stderr:?}")),
    }
    let left: Vec<_> = fs::read_dir(dir).expect("read scratch").collect();
    if !left.is_empty() {
        problems.push(format!("{} file(s) left behind", left.len()));
    }
    problems
}

/// The corpus files (not the helper files under `data/`, not EXPECT.toml), sorted.
fn corpus_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = fs::read_dir(corpus())
        .expect("tests/bad exists")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.is_file() && p.file_name().is_some_and(|n| n != "EXPECT.toml"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_broken_input_fails_cleanly_with_one_located_line() {
    let sidecar = sidecar();
    let files: Vec<PathBuf> = corpus_files()
        .into_iter()
        .filter(|p| {
            !p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("warn_")
        })
        .collect();
    assert!(files.len() >= 40, "only {} corpus files", files.len());
    let mut failures = Vec::new();
    for path in &files {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let dir = scratch(&name);
        let out = render(&dir, &path.canonicalize().unwrap(), true);
        let problems = check_failure(&name, &out, &expectation(path, &sidecar), &dir);
        if !problems.is_empty() {
            failures.push(format!("{name}: {}", problems.join("; ")));
        }
        let _ = fs::remove_dir_all(&dir);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn missing_and_unreadable_scene_files_fail_cleanly() {
    let dir = scratch("missing");
    let missing = dir.join("no_such_scene.toml");
    let out = render(&dir, &missing, true);
    let expect = Expect::default();
    let problems = check_failure("no_such_scene.toml", &out, &expect, &dir);
    assert!(problems.is_empty(), "{problems:?}");

    // A directory where a scene file is expected (root can read any file, so permissions
    // cannot make one unreadable in this test).
    let other = scratch("directory");
    let scene_dir = other.join("scene_dir.toml");
    fs::create_dir_all(&scene_dir).unwrap();
    let out = render(&dir, &scene_dir, true);
    let problems = check_failure("scene_dir.toml", &out, &expect, &dir);
    assert!(problems.is_empty(), "{problems:?}");
    let _ = fs::remove_dir_all(&dir);
    let _ = fs::remove_dir_all(&other);
}

#[test]
fn repairable_inputs_render_with_a_warning() {
    let files: Vec<PathBuf> = corpus_files()
        .into_iter()
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("warn_")
        })
        .collect();
    assert!(!files.is_empty());
    for path in &files {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let text = fs::read_to_string(path).unwrap();
        let warning = text
            .lines()
            .next()
            .and_then(|l| l.strip_prefix("# warning: "))
            .unwrap_or_else(|| panic!("{name}: no `# warning:` line"));
        let dir = scratch(&name);
        let out = render(&dir, path, false);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{name}: {stderr}");
        assert!(
            stderr
                .lines()
                .any(|l| l.starts_with("warning: ") && l.contains(&name) && l.contains(warning)),
            "{name}: no warning containing `{warning}`: {stderr}"
        );
        assert!(dir.join("out.png").is_file() && dir.join("s.json").is_file());
        let _ = fs::remove_dir_all(&dir);
    }
}
