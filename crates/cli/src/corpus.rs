//! `radiosity validate --corpus DIR`: published scenes against Mitsuba 3 rendering the same
//! files.
//!
//! `DIR` holds one folder per scene (`scene_mi3.xml`, else `scene.xml`; a Mitsuba 0.6 file's
//! `scene_mi3.xml` is its Mitsuba 3 upgrade). A scene's reference is
//! `REFS/<scene>.exr` (or `.pfm`) with `REFS/<scene>.json`, written by
//! `benches/corpus/reference.py`: Mitsuba 3 rendering the scene with every BSDF replaced by the
//! diffuse approximation our reader uses (docs/mitsuba.md), with its own noise (`noise`, the
//! RMS over 4 × 4 blocks of the relative error of its mean) and the times and errors of cheaper
//! renders (`ladder`). Each scene is rendered by this program's own `render` command at default
//! settings, at the reference's size, in a process of its own, timed whole. Per scene:
//!
//! - `error`: the RMS over 4 × 4-pixel blocks of the relative luminance error
//!   ([`block_error`]), the reference's noise removed in quadrature, √(e² − σ²);
//! - `p99`: the 99th percentile of the blocks' absolute relative errors;
//! - `ratio`: our mean radiance over the reference's, per channel;
//! - `power`: absorbed over emitted power (the stats' energy balance; 1 for a closed scene);
//! - `seconds`, and Mitsuba's time to our error: along the ladder's two nearest renders, with
//!   error ∝ time^(−1/k) between them (k = 2 for an unbiased Monte Carlo estimate).
//!
//! Goals: error ≤ 2 %, p99 ≤ 10 %, ratio within 1 %.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use anyhow::{bail, Context};
use radiosity::io::image_file::read_image;
use radiosity::render::block_error::block_error;
use radiosity::render::Image;
use serde::{Deserialize, Serialize};

/// Block size of the error measure, pixels.
const BLOCK: u32 = 4;

/// One scene's figures.
#[derive(Debug, Serialize)]
pub struct CorpusRow {
    /// The scene's folder name.
    pub scene: String,
    /// Block RMS error, reference noise removed.
    pub error: f64,
    /// 99th-percentile block error.
    pub p99: f64,
    /// Our mean radiance over the reference's, R, G, B.
    pub ratio: [f64; 3],
    /// Absorbed over emitted power, worst channel.
    pub power: f64,
    /// Our whole command, seconds.
    pub seconds: f64,
    /// Mitsuba 3's time to our error, seconds, when the ladder brackets it.
    pub mitsuba_seconds: Option<f64>,
    /// The reference's own noise.
    pub reference_noise: f64,
}

impl CorpusRow {
    /// Whether the scene meets the goals.
    #[must_use]
    pub fn pass(&self) -> bool {
        self.error <= 0.02 && self.p99 <= 0.10 && self.ratio.iter().all(|r| (r - 1.0).abs() <= 0.01)
    }
}

#[derive(Debug, Deserialize)]
struct ReferenceInfo {
    #[serde(default)]
    noise: f64,
    #[serde(default)]
    ladder: Vec<Rung>,
}

#[derive(Clone, Copy, Debug, Deserialize)]
struct Rung {
    seconds: f64,
    error: f64,
}

/// The scene file of a corpus folder.
fn scene_file(dir: &Path) -> Option<PathBuf> {
    ["scene_mi3.xml", "scene.xml"]
        .iter()
        .map(|f| dir.join(f))
        .find(|p| p.is_file())
}

/// Renders and compares every scene of `corpus` that has a reference in `references` (or the
/// ones named in `only`); scenes without a reference are named on stderr and skipped.
///
/// # Errors
/// A folder or reference that cannot be read, or a render that fails.
pub fn rows(corpus: &Path, references: &Path, only: &[String]) -> anyhow::Result<Vec<CorpusRow>> {
    let mut names: Vec<String> = std::fs::read_dir(corpus)
        .with_context(|| format!("{}: cannot read the corpus", corpus.display()))?
        .filter_map(Result::ok)
        .filter(|e| e.path().is_dir() && scene_file(&e.path()).is_some())
        .filter_map(|e| e.file_name().to_str().map(str::to_string))
        .filter(|n| only.is_empty() || only.contains(n))
        .collect();
    names.sort();
    let exe = std::env::current_exe().context("cannot find this program")?;
    let scratch = std::env::temp_dir().join(format!("radiosity-corpus-{}", std::process::id()));
    std::fs::create_dir_all(&scratch)?;
    let mut rows = Vec::new();
    for name in names {
        let reference_path = ["exr", "pfm"]
            .iter()
            .map(|x| references.join(format!("{name}.{x}")))
            .find(|p| p.is_file());
        let Some(reference_path) = reference_path else {
            eprintln!("{name}: no reference in {}, skipped", references.display());
            continue;
        };
        let reference = read_image(&reference_path)?;
        let info: ReferenceInfo = match std::fs::read(references.join(format!("{name}.json"))) {
            Ok(bytes) => serde_json::from_slice(&bytes)
                .with_context(|| format!("{name}.json: not a reference description"))?,
            Err(_) => ReferenceInfo {
                noise: 0.0,
                ladder: Vec::new(),
            },
        };
        let file = scene_file(&corpus.join(&name)).context("no scene file")?;
        let (image_path, stats_path) = (
            scratch.join(format!("{name}.pfm")),
            scratch.join(format!("{name}.json")),
        );
        let start = Instant::now();
        let output = Command::new(&exe)
            .arg("render")
            .arg(&file)
            .args(["-q", "--width"])
            .arg(reference.width.to_string())
            .arg("--height")
            .arg(reference.height.to_string())
            .arg("-o")
            .arg(&image_path)
            .arg("--stats")
            .arg(&stats_path)
            .output()
            .context("cannot run a render")?;
        let seconds = start.elapsed().as_secs_f64();
        if !output.status.success() {
            bail!("{name}: {}", String::from_utf8_lossy(&output.stderr).trim());
        }
        let ours = read_image(&image_path)?;
        let e = block_error(&ours, &reference, BLOCK)
            .with_context(|| format!("{name}: the picture does not match the reference's size"))?;
        let error = (e.rms * e.rms - info.noise * info.noise).max(0.0).sqrt();
        let stats: serde_json::Value = serde_json::from_slice(&std::fs::read(&stats_path)?)?;
        let channel = |key: &str, i: usize| stats["energy"][key][i].as_f64().unwrap_or(0.0);
        let power = (0..3)
            .map(|i| channel("absorbed", i) / channel("emitted", i))
            .filter(|r| r.is_finite())
            .fold(1.0, |worst: f64, r| {
                if (r - 1.0).abs() > (worst - 1.0).abs() {
                    r
                } else {
                    worst
                }
            });
        rows.push(CorpusRow {
            scene: name,
            error,
            p99: e.p99,
            ratio: mean_ratio(&ours, &reference),
            power,
            seconds,
            mitsuba_seconds: time_to_error(&info.ladder, error),
            reference_noise: info.noise,
        });
    }
    std::fs::remove_dir_all(&scratch).ok();
    Ok(rows)
}

/// Our mean radiance over the reference's, per channel.
fn mean_ratio(ours: &Image, reference: &Image) -> [f64; 3] {
    let sum = |img: &Image| img.pixels.iter().copied().sum::<radiosity::Rgb>();
    (sum(ours) / sum(reference)).to_array()
}

/// The time a path tracer needs to reach `error`, interpolated on log-log between the two
/// rungs of its ladder that bracket it (or extrapolated from the nearest two with the slope
/// −1/2 of Monte Carlo noise when none does).
fn time_to_error(ladder: &[Rung], error: f64) -> Option<f64> {
    let mut rungs: Vec<Rung> = ladder
        .iter()
        .copied()
        .filter(|r| r.seconds > 0.0 && r.error > 0.0)
        .collect();
    rungs.sort_by(|a, b| a.seconds.total_cmp(&b.seconds));
    if rungs.is_empty() || error <= 0.0 {
        return None;
    }
    let last = rungs[rungs.len() - 1];
    if error <= last.error {
        // Beyond the ladder: error ∝ t^(−1/2).
        return Some(last.seconds * (last.error / error).powi(2));
    }
    for w in rungs.windows(2) {
        let (a, b) = (w[0], w[1]);
        if error <= a.error && error >= b.error && a.error > b.error {
            let k = (b.seconds / a.seconds).ln() / (a.error / b.error).ln();
            return Some(a.seconds * (a.error / error).powf(k));
        }
    }
    Some(rungs[0].seconds * (rungs[0].error / error).powi(2))
}

/// The Markdown table of the rows.
#[must_use]
pub fn table(rows: &[CorpusRow]) -> String {
    let mut s = String::from(
        "| scene | error | p99 block | mean ratio R G B | absorbed / emitted | ours s | Mitsuba 3 s to our error | ratio of times | reference noise | pass |\n|---|---:|---:|---|---:|---:|---:|---:|---:|---|\n",
    );
    for r in rows {
        let mitsuba = r
            .mitsuba_seconds
            .map_or_else(|| "—".to_string(), |t| format!("{t:.1}"));
        let times = r
            .mitsuba_seconds
            .map_or_else(|| "—".to_string(), |t| format!("{:.3} ×", r.seconds / t));
        s.push_str(&format!(
            "| {} | {:.2} % | {:.2} % | {:.3} {:.3} {:.3} | {:.4} | {:.1} | {mitsuba} | {times} | {:.2} % | {} |\n",
            r.scene,
            100.0 * r.error,
            100.0 * r.p99,
            r.ratio[0],
            r.ratio[1],
            r.ratio[2],
            r.power,
            r.seconds,
            100.0 * r.reference_noise,
            if r.pass() { "yes" } else { "no" }
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_to_error_follows_the_ladder() {
        let ladder = [
            Rung {
                seconds: 1.0,
                error: 0.08,
            },
            Rung {
                seconds: 4.0,
                error: 0.04,
            },
            Rung {
                seconds: 16.0,
                error: 0.02,
            },
        ];
        // Between rungs on the 1/√t line: 0.0283 at t = 8.
        let t = time_to_error(&ladder, 0.04 / 2f64.sqrt()).unwrap();
        assert!((t - 8.0).abs() < 1e-9, "{t}");
        // Beyond the last rung, t ∝ 1/e².
        assert!((time_to_error(&ladder, 0.01).unwrap() - 64.0).abs() < 1e-9);
        assert!(time_to_error(&[], 0.01).is_none());
    }
}
