//! `cargo xtask bench`: what the engine costs, in suites.
//!
//! - `--suite rays` ([`rays`]): the BVH's ray throughput on four scenes, against Intel Embree
//!   (`benches/README.md`), from the measurement in [`crate::throughput`].
//! - `--suite hierarchical` ([`hierarchical`]): the hierarchical solver's time, links and memory
//!   from 10⁴ to 10⁶ elements.
//! - `--suite image` ([`image`]): our pictures against a path tracer's reference: error and
//!   time.
//!
//! Each prints a table on stdout and, with `--json PATH`, writes its figures as JSON.

mod hierarchical;
mod image;
mod rays;

use std::path::PathBuf;

use clap::{Args, ValueEnum};

/// Runs the suite `args` ask for.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    match args.suite {
        Suite::Rays => rays::run(args),
        Suite::Hierarchical => hierarchical::run(args),
        Suite::Image => image::run(args),
    }
}

/// `cargo xtask bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// What to measure: `rays` (BVH throughput), `hierarchical` (the hierarchical solver
    /// from 10⁴ to 10⁶ elements: the Cornell box at falling ε and a field of 200 spheres) or
    /// `image` (our pictures against a path tracer's reference picture: error and time).
    #[arg(long, value_enum, default_value_t = Suite::Rays)]
    pub suite: Suite,
    /// `--suite hierarchical`: the finest sphere tessellation of the field (icosphere
    /// subdivisions; 200 spheres × 20·4^s triangles, 4 = 1 024 000).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=5))]
    pub largest: u32,
    /// Run one case of `--suite hierarchical` and print its figures as JSON (used by the
    /// suite, which runs each case in a process of its own to measure its peak memory).
    #[arg(long, hide = true)]
    pub case: Option<usize>,
    /// Triangles in each large benchmark scene (the sphere field, closed and open, and the
    /// teapot); the built-in Cornell box is measured as it is.
    #[arg(long, default_value_t = 1_000_000, value_parser = clap::value_parser!(u64).range(1..=100_000_000))]
    pub triangles: u64,
    /// Measure only these scenes, comma-separated (default: all of `cornell`, `spheres`,
    /// `spheres-open`, `teapot`).
    #[arg(long, value_name = "NAME,...", value_delimiter = ',',
          value_parser = ["cornell", "spheres", "spheres-open", "teapot"])]
    pub scenes: Vec<String>,
    /// Incoherent rays per measurement.
    #[arg(long, default_value_t = 1_000_000, value_parser = clap::value_parser!(u64).range(1..=100_000_000))]
    pub rays: u64,
    /// Thread counts to measure, comma-separated (default: 1 and every core).
    #[arg(long, value_name = "N,...", value_delimiter = ',',
          value_parser = clap::value_parser!(u64).range(1..=4096))]
    pub threads: Vec<u64>,
    /// Seed of the ray generator.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Instruction set of the ray queries (default: the best this processor has; the results
    /// are the same bits either way).
    #[arg(long, value_enum)]
    pub isa: Option<BenchIsa>,
    /// Also write the reports as JSON.
    #[arg(long, value_name = "PATH")]
    pub json: Option<PathBuf>,
    /// `--suite image`: the reference picture, a linear-radiance PFM from the scene's camera
    /// (default: benches/image/reference/cornell_256.pfm, Mitsuba 3's Cornell box).
    #[arg(long, value_name = "PATH")]
    pub reference: Option<PathBuf>,
    /// `--suite image`: the scene the reference shows (file or built-in name).
    #[arg(long, default_value = "cornell")]
    pub scene: String,
    /// Also write each scene's triangles and rays to DIR/<scene>.bin (for tracing them with
    /// another tracer: `benches/embree_rays.py`).
    #[arg(long, value_name = "DIR")]
    pub workload: Option<PathBuf>,
}

/// `bench --isa`: see [`radiosity::accel::isa`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BenchIsa {
    /// SSE2, what every x86-64 processor runs.
    Baseline,
    /// AVX2, FMA, BMI1/2, LZCNT, POPCNT.
    Avx2,
}

/// `bench --suite`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Suite {
    /// Ray throughput of the BVH.
    Rays,
    /// Time, links and memory of the hierarchical solver against the element count.
    Hierarchical,
    /// Our pictures against a path tracer's converged picture: error and time.
    Image,
}
