//! `cargo xtask` — the developer tools of the workspace, kept out of the `radiosity` program
//! that users install (rust-analyzer's `xtask` convention; the alias is in `.cargo/config.toml`).
//!
//! ```text
//! cargo xtask bench [--suite rays|hierarchical|image] [--json PATH] ...
//! cargo xtask suite [--solver NAME]... [--form-factors NAME]... [--format json]
//! cargo xtask figures [--check | --measure [SOURCE]]
//! cargo run --release -p xtask --features count -- traversal-counts [SCENE] [RAYS]
//! ```
//!
//! - [`bench`]: the benchmarks whose figures the README and `benches/README.md` quote.
//! - [`suite`]: the reference suite, scenes made elsewhere against Mitsuba 3 (`benches/suite`).
//! - [`figures`]: the README's table of figures and `docs/figures.md`, from the measurements
//!   in `benches/figures`.
//! - [`traversal_counts`]: the BVH's per-ray work on the benchmark scenes.
//!
//! [`throughput`] is the ray-throughput measurement behind `bench --suite rays` and
//! `traversal-counts`. Failures print `Error: <cause>` and exit with status 1.
#![forbid(unsafe_code)]

mod bench;
mod figures;
mod suite;
mod throughput;
mod traversal_counts;

use std::path::{Path, PathBuf};

use anyhow::{ensure, Context};
use clap::{Parser, Subcommand};

/// Developer tools of the radiosity workspace: benchmarks and the reference suite.
#[derive(Debug, Parser)]
#[command(name = "xtask")]
struct Cli {
    /// What to do.
    #[command(subcommand)]
    command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
enum Command {
    /// Measure the ray throughput of the visibility hierarchy (BVH), the hierarchical solver's
    /// growth, or our pictures against a path tracer's.
    Bench(bench::BenchArgs),
    /// Run the reference suite of `benches/suite` (scenes made elsewhere against Mitsuba 3;
    /// every object within 1 %) and print its table.
    Suite(suite::SuiteArgs),
    /// Render docs/figures.md and the README's Figures table from the measurements in
    /// benches/figures (`--check`: fail when either is stale; `--measure`: measure again first).
    Figures(figures::FiguresArgs),
    /// Count the BVH's traversal steps and triangle packets per ray on the 1M-triangle scenes
    /// (zero unless built with `--features count`).
    TraversalCounts(traversal_counts::TraversalArgs),
}

fn main() -> anyhow::Result<()> {
    match Cli::parse().command {
        Command::Bench(args) => bench::run(&args),
        Command::Suite(args) => suite::run(&args),
        Command::Figures(args) => figures::run(&args),
        Command::TraversalCounts(args) => {
            traversal_counts::run(&args);
            Ok(())
        }
    }
}

/// The repository's root folder (this crate is `crates/xtask` in it).
fn repository() -> PathBuf {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest
        .ancestors()
        .nth(2)
        .unwrap_or(manifest)
        .to_path_buf()
}

/// The `radiosity` program of this workspace, built by cargo beside this program (the same
/// target folder and profile), so that what `bench --suite image` and `figures --measure` run
/// is the code as it is.
pub(crate) fn radiosity_program() -> anyhow::Result<PathBuf> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut build = std::process::Command::new(cargo);
    build
        .args(["build", "--quiet", "-p", "cli", "--bin", "radiosity"])
        .current_dir(repository());
    if !cfg!(debug_assertions) {
        build.arg("--release");
    }
    let status = build.status().context("cannot run cargo")?;
    ensure!(
        status.success(),
        "cargo could not build the radiosity program"
    );
    let this = std::env::current_exe().context("cannot find this program")?;
    Ok(this.with_file_name(format!("radiosity{}", std::env::consts::EXE_SUFFIX)))
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    use super::*;

    #[test]
    fn clap_definition_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn the_repository_holds_the_suite() {
        assert!(repository().join("benches/suite/reference").is_dir());
    }
}
