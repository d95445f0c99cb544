//! `cargo xtask figures`: one source for the measured figures.
//!
//! The measurements are JSON files in `benches/figures/`, each what one command wrote (or, for
//! a *transcribed* source, the numbers it printed), and `benches/figures/figures.toml`
//! ([`manifest`]) says for each row of the table where its values are in them ([`path`]) and
//! how to print them. From those, [`render`] makes `docs/figures.md` and the README's table
//! between `<!-- figures:begin -->` and `<!-- figures:end -->`.
//!
//! - `cargo xtask figures` writes both files.
//! - `--check` writes nothing and fails when either is not what rendering gives (a test runs
//!   it, so a stale table fails CI).
//! - `--measure [SOURCE]` first reruns the command of every source whose file is its output (or
//!   of the one named), with the release `radiosity` program of this workspace first on the
//!   `PATH`, then writes both files. Never run by tests: it takes minutes.

pub mod manifest;
pub mod path;
pub mod render;

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{bail, ensure, Context};
use clap::Args;

use manifest::{Kind, Manifest};

/// `cargo xtask figures`.
#[derive(Debug, Args)]
pub struct FiguresArgs {
    /// Write nothing; fail when docs/figures.md or the README's table is not what the
    /// measurements give.
    #[arg(long, conflicts_with = "measure")]
    pub check: bool,
    /// Rerun the measuring command of every source the manifest can rerun, or of SOURCE, then
    /// write the tables.
    #[arg(long, value_name = "SOURCE", num_args = 0..=1, default_missing_value = "")]
    pub measure: Option<String>,
    /// The repository that holds benches/figures, docs and the README [default: this one].
    #[arg(long, value_name = "DIR")]
    pub dir: Option<PathBuf>,
}

/// Runs `cargo xtask figures`.
pub fn run(args: &FiguresArgs) -> anyhow::Result<()> {
    let root = args.dir.clone().unwrap_or_else(crate::repository);
    let folder = root.join("benches/figures");
    let manifest = Manifest::read(&folder.join("figures.toml"))?;
    if let Some(name) = &args.measure {
        measure(&manifest, &root, name)?;
    }
    let table = render::table(&manifest, &folder)?;
    let files = [
        (
            root.join("docs/figures.md"),
            render::page(&manifest, &table),
        ),
        (
            root.join("README.md"),
            render::splice(&read(&root.join("README.md"))?, &table)?,
        ),
    ];
    if args.check {
        let stale: Vec<String> = files
            .iter()
            .filter(|(path, text)| std::fs::read_to_string(path).ok().as_ref() != Some(text))
            .map(|(path, _)| path.display().to_string())
            .collect();
        ensure!(
            stale.is_empty(),
            "{} not what benches/figures gives: run `cargo xtask figures`",
            stale.join(" and ")
        );
        return Ok(());
    }
    for (path, text) in &files {
        radiosity::io::atomic::write_atomic(path, |w| w.write_all(text.as_bytes()))
            .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    Ok(())
}

fn read(path: &Path) -> anyhow::Result<String> {
    std::fs::read_to_string(path).with_context(|| format!("{}", path.display()))
}

/// Reruns the command of the source `name`, or of every source whose file is its command's
/// output when `name` is empty.
fn measure(manifest: &Manifest, root: &Path, name: &str) -> anyhow::Result<()> {
    if !name.is_empty() && !manifest.sources.contains_key(name) {
        let names: Vec<&str> = manifest.sources.keys().map(String::as_str).collect();
        bail!("no source {name:?}; the sources are {}", names.join(", "));
    }
    let program = crate::radiosity_program()?;
    let bin = program.parent().context("the program's folder")?;
    let path = std::env::join_paths(std::iter::once(bin.to_path_buf()).chain(
        std::env::split_paths(&std::env::var_os("PATH").unwrap_or_default()),
    ))?;
    for (source_name, source) in &manifest.sources {
        if !name.is_empty() && source_name != name {
            continue;
        }
        if source.kind == Kind::Transcribed {
            eprintln!(
                "{source_name}: transcribed; run `{}` and copy its figures into benches/figures/{}",
                source.command, source.file
            );
            continue;
        }
        eprintln!("{source_name}: {}", source.command);
        let status = Command::new("sh")
            .args(["-c", &source.command])
            .current_dir(root)
            .env("PATH", &path)
            .status()
            .context("cannot run sh")?;
        // A check out of tolerance fails the command but its figures are still measured.
        if !status.success() {
            eprintln!("{source_name}: the command exited with {status}");
        }
        let file = root.join("benches/figures").join(&source.file);
        serde_json::from_str::<serde_json::Value>(&read(&file)?)
            .with_context(|| format!("{}: not JSON", file.display()))?;
    }
    Ok(())
}
