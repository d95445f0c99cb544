//! `cargo xtask bench --suite image`: our pictures against a path tracer's converged picture.
//!
//! The reference is a linear-radiance PFM that Mitsuba 3 rendered from the scene's own camera
//! (`benches/image/reference.py`; the committed one is the Cornell box at 256², see
//! `benches/image/reference/README.md`). Each configuration below is the `radiosity` program's
//! `render` command (cargo builds the program first, beside this one), run in a process of its
//! own at the reference's size and timed whole (parse, mesh, solve, render, write), and its
//! picture compared with the reference by
//! [`radiosity::render::block_error::block_error`]: the RMS of the relative luminance error
//! over 4 × 4-pixel blocks, the measure the image issue states its goals in.

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::process::Command;
use std::time::Instant;

use anyhow::{bail, Context};
use radiosity::io::atomic::write_atomic;
use radiosity::io::image_file::read_pfm;
use radiosity::progress::{Progress, Work};
use radiosity::render::block_error::block_error;
use report::Bars;
use serde::Serialize;

use super::BenchArgs;

/// The configurations measured: a name and the `render` flags that make it.
const CONFIGURATIONS: [(&str, &[&str]); 11] = [
    ("default (--mode final, 16 samples)", &[]),
    ("--quality final", &["--quality", "final"]),
    (
        "--mode final --samples 64",
        &["--mode", "final", "--samples", "64"],
    ),
    (
        "--mode final --elements 16000",
        &["--mode", "final", "--elements", "16000"],
    ),
    (
        "--solver hierarchical --mode final",
        &["--solver", "hierarchical", "--mode", "final"],
    ),
    (
        "--mode radiosity (lit mesh refined for display, 64 samples)",
        &["--mode", "radiosity"],
    ),
    (
        "--mode radiosity --display averaged",
        &["--mode", "radiosity", "--display", "averaged"],
    ),
    (
        "--mode radiosity --display averaged --samples 4 (the interpolated picture at its coarsest)",
        &[
            "--mode",
            "radiosity",
            "--display",
            "averaged",
            "--samples",
            "4",
        ],
    ),
    (
        "--mode radiosity --elements 16000",
        &["--mode", "radiosity", "--elements", "16000"],
    ),
    (
        "--mode radiosity --solver hierarchical",
        &["--mode", "radiosity", "--solver", "hierarchical"],
    ),
    (
        "--mode raytrace --gather 16",
        &["--mode", "raytrace", "--gather", "16"],
    ),
];

/// One configuration's figures.
#[derive(Debug, Serialize)]
struct Figures {
    configuration: String,
    /// RMS relative luminance error over blocks.
    error: f64,
    /// Mean relative luminance error over blocks (positive: too bright).
    bias: f64,
    /// The whole command, seconds.
    seconds: f64,
}

/// Renders every configuration, prints error and time, and writes the JSON report if asked.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    let reference_path = args.reference.clone().unwrap_or_else(default_reference);
    let reference = read_pfm(&reference_path)?;
    let exe = crate::radiosity_program()?;
    let dir = Scratch::new()?;
    let mut out = std::io::stdout().lock();
    writeln!(
        out,
        "{} against {} ({}×{}, {}×{}-pixel blocks)",
        args.scene,
        reference_path.display(),
        reference.width,
        reference.height,
        BLOCK,
        BLOCK
    )?;
    let width = CONFIGURATIONS.iter().map(|c| c.0.len()).max().unwrap_or(0);
    writeln!(
        out,
        "{:<width$} {:>9} {:>9} {:>9}",
        "configuration", "error", "bias", "time s"
    )?;
    let bars = Bars::new(std::io::stderr().is_terminal());
    bars.start(
        "bench image",
        Work::of(CONFIGURATIONS.len() as u64, "configurations"),
    );
    let mut all = Vec::new();
    for (k, (name, flags)) in CONFIGURATIONS.iter().enumerate() {
        let image = dir.0.join(format!("{k}.pfm"));
        let start = Instant::now();
        let output = Command::new(&exe)
            .args(["render", &args.scene, "-q", "--width"])
            .arg(reference.width.to_string())
            .arg("--height")
            .arg(reference.height.to_string())
            .args(*flags)
            .arg("-o")
            .arg(&image)
            .output()
            .context("cannot run a render")?;
        let seconds = start.elapsed().as_secs_f64();
        if !output.status.success() {
            bail!(
                "{name}: {}",
                String::from_utf8_lossy(&output.stderr)
                    .trim()
                    .trim_start_matches("error: ")
            );
        }
        let ours = read_pfm(&image)?;
        let e = block_error(&ours, &reference, BLOCK)
            .with_context(|| format!("{name}: the picture does not match the reference's size"))?;
        writeln!(
            out,
            "{name:<width$} {:>8.2}% {:>+8.2}% {seconds:>9.1}",
            100.0 * e.rms,
            100.0 * e.bias
        )?;
        all.push(Figures {
            configuration: (*name).to_string(),
            error: e.rms,
            bias: e.bias,
            seconds,
        });
        bars.advance(1);
    }
    bars.finish();
    if let Some(path) = &args.json {
        let json = serde_json::to_vec_pretty(&all)?;
        write_atomic(path, |w| w.write_all(&json))
            .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    Ok(())
}

/// Block size of the error measure, pixels.
const BLOCK: u32 = 4;

/// The committed reference, in the repository.
fn default_reference() -> PathBuf {
    crate::repository().join("benches/image/reference/cornell_256.pfm")
}

/// A fresh directory for the renders, removed when dropped (also when a render fails).
struct Scratch(PathBuf);

impl Scratch {
    fn new() -> anyhow::Result<Self> {
        let dir =
            std::env::temp_dir().join(format!("radiosity-bench-image-{}", std::process::id()));
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("{}: cannot create", dir.display()))?;
        Ok(Self(dir))
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
