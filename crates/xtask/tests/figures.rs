//! `cargo xtask figures --check`: the README's table of figures and `docs/figures.md` are what
//! the committed measurements in `benches/figures/` give, and a stale copy of either is caught.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn figures(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_xtask"))
        .arg("figures")
        .args(args)
        .arg("--dir")
        .arg(dir)
        .output()
        .expect("the binary runs")
}

/// The committed tables are current: a measurement or a manifest row changed without
/// `cargo xtask figures` fails here.
#[test]
fn the_committed_figures_are_current() {
    let out = figures(&["--check"], &repository());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A copy of the files the tables come from, in a folder of its own, removed when dropped.
struct Copy(PathBuf);

impl Copy {
    fn new(name: &str) -> Self {
        let root = repository();
        let dir = std::env::temp_dir().join(format!("xtask-figures-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("docs")).unwrap();
        std::fs::create_dir_all(dir.join("benches/figures")).unwrap();
        for file in ["README.md", "docs/figures.md"] {
            std::fs::copy(root.join(file), dir.join(file)).unwrap();
        }
        for entry in std::fs::read_dir(root.join("benches/figures")).unwrap() {
            let path = entry.unwrap().path();
            std::fs::copy(
                &path,
                dir.join("benches/figures").join(path.file_name().unwrap()),
            )
            .unwrap();
        }
        Self(dir)
    }

    fn edit(&self, file: &str, from: &str, to: &str) {
        let path = self.0.join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains(from), "{file} has no {from:?}");
        std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    }
}

impl Drop for Copy {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A hand edit of the README's table, and a new measurement the tables do not show yet, fail
/// the check, naming the stale files; rendering mends them.
#[test]
fn a_stale_table_fails_the_check_until_rendered() {
    let copy = Copy::new("stale");
    copy.edit(
        "README.md",
        "<!-- figures:end -->",
        "| edited | by hand | |\n<!-- figures:end -->",
    );
    let out = figures(&["--check"], &copy.0);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("README.md") && !stderr.contains("figures.md"),
        "{stderr}"
    );

    // The hierarchical solver's largest case measured again, slower.
    let text = std::fs::read_to_string(copy.0.join("benches/figures/hierarchical.json")).unwrap();
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let largest = json["cases"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|c| c["triangles"] == 1_024_002)
        .expect("the largest case");
    largest["seconds"] = serde_json::json!(999.0);
    std::fs::write(
        copy.0.join("benches/figures/hierarchical.json"),
        serde_json::to_string_pretty(&json).unwrap(),
    )
    .unwrap();
    let out = figures(&["--check"], &copy.0);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("README.md") && stderr.contains("figures.md"),
        "{stderr}"
    );

    let out = figures(&[], &copy.0);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(figures(&["--check"], &copy.0).status.success());
    let readme = std::fs::read_to_string(copy.0.join("README.md")).unwrap();
    assert!(readme.contains("999 s") && !readme.contains("edited"));
}

/// A manifest row whose path finds nothing is an error naming the row, not an empty cell.
#[test]
fn a_path_that_finds_nothing_names_its_row() {
    let copy = Copy::new("path");
    copy.edit(
        "benches/figures/figures.toml",
        "?series=field/",
        "?series=no-such-series/",
    );
    let out = figures(&["--check"], &copy.0);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("hierarchical radiosity, 10⁶ elements"),
        "{stderr}"
    );
}
