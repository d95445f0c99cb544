//! `cargo xtask` — the developer tools of the workspace, kept out of the `radiosity` program
//! that users install (rust-analyzer's `xtask` convention; the alias is in `.cargo/config.toml`).
//!
//! ```text
//! cargo xtask bench [--suite rays|hierarchical|image] [--json PATH] ...
//! cargo xtask suite [--solver NAME]... [--form-factors NAME]... [--format json]
//! cargo run --release -p xtask --features count -- traversal-counts [SCENE] [RAYS]
//! ```
//!
//! - [`bench`]: the benchmarks whose figures the README and `benches/README.md` quote.
//! - [`suite`]: the reference suite, scenes made elsewhere against Mitsuba 3 (`benches/suite`).
//! - [`traversal_counts`]: the BVH's per-ray work on the benchmark scenes.
//!
//! [`throughput`] is the ray-throughput measurement behind `bench --suite rays` and
//! `traversal-counts`. Failures print `Error: <cause>` and exit with status 1.
#![forbid(unsafe_code)]

mod bench;
mod suite;
mod throughput;
mod traversal_counts;

use std::path::{Path, PathBuf};

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
    /// Count the BVH's traversal steps and triangle packets per ray on the 1M-triangle scenes
    /// (zero unless built with `--features count`).
    TraversalCounts(traversal_counts::TraversalArgs),
}

fn main() -> anyhow::Result<()> {
    match Cli::parse().command {
        Command::Bench(args) => bench::run(&args),
        Command::Suite(args) => suite::run(&args),
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
