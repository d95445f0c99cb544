//! Coverage of a pixel by the surfaces it sees, sampled finely only where the surface changes.
//!
//! The evaluated picture ([`super::super::evaluated`]) computes its costly light once per pixel and
//! surface side, so what its primary rays buy is each pixel's *coverage*: the fraction c_K of
//! the pixel's area in which kind K (one side of one patch, or the background) is seen. The
//! pixel is Σ_K c_K L_K, and its error at an edge is the error of the c_K. A jittered n × n grid
//! estimates a straight edge's coverage with a standard deviation of about
//! √(n · p(1 − p)) / n² for a per-row fraction p (Mitchell 1987, "Generating antialiased images
//! at low sampling densities", on why stratification pays at edges): at n = 16 and a sliver
//! covering 3 % of the pixel along its side, about 0.8 % of the pixel, a quarter of the sliver,
//! and where the sliver is dark against a bright neighbour, of the block's radiance.
//!
//! So the samples go where the coverage is uncertain, as in Whitted's (1980) and Mitchell's
//! (1987) adaptive supersampling, each level keyed to the one above:
//!
//! 1. **First pass.** Every pixel shoots its s × s jittered grid (s from `--samples`). If all
//!    its rays see one kind K, and so do the rays of its four neighbours next to it (the row or
//!    column of theirs along the shared side), the pixel is K alone and the evaluation uses
//!    these rays. Seen over the whole image, a pixel is refined when one of its samples
//!    differs from a sample next to it on the image's grid of samples, so a sliver the pixel's
//!    own rays missed is still found when its neighbour's rays saw its surface next to the
//!    side. Each tile shoots the samples beside it in the pixels around it, so that tiles
//!    decide alone, in parallel.
//! 2. **Edge pixel.** Otherwise the pixel is sampled afresh on an [`EDGE_SIDE`]² grid of
//!    cells, one jittered ray each.
//! 3. **Cells.** A cell is refined by a [`REFINE_SIDE`]² jittered sub-grid, each sub-sample
//!    weighing 1/[`REFINE_SIDE`]² of the cell, when the samples next to its own differ from it:
//!    its neighbour cells' (their sub-samples along the shared side once refined), or at the
//!    pixel's side the neighbour pixel's first-pass samples there. A refined cell's neighbours
//!    are checked again, so refinement follows an edge across the pixel; of two cells that
//!    disagree only the first is refined unless its sub-samples show the edge is not in it.
//!
//! An edge thus gets a 64 × 64 grid where it passes, for 256 rays and 26 refined cells of 16
//! on average over the Cornell box's edge pixels, instead of 4 096 rays. The estimate is not
//! exactly unbiased: whether a cell is refined depends on its own ray, and a feature no ray of
//! a level meets goes unseen, as in any adaptive scheme.
//!
//! Measured at 256² against Mitsuba 3 (RMS of the relative luminance error over 4 × 4-pixel
//! blocks, `benches/image/error.py`): the Cornell box 0.711 → 0.673 % and the furnished room
//! 0.361 → 0.355 % at 16 first-pass samples, against an 8 × 8 first pass and a plain 16 × 16
//! grid at the edges before (with that scheme a 4 × 4 first pass gave 1.69 % on the box: it
//! missed the slivers of the box's slanted front edge, 1–4 % of a pixel). A 2 × 2 first pass
//! now gives 0.681 and 0.359 %, an 8 × 8 one 0.672 and 0.356 %. The box takes 3.6 million
//! primary rays: 1.05 million in the first pass, 61 000 beside the tiles, and 3 660 edge
//! pixels (5.6 %) of 256 cells and on average 420 sub-samples (26 refined cells); before, the
//! first pass alone took 4.2 million. The render stage is the same or a little shorter
//! (measured side by side on a shared machine: see `docs/raytracing.md`).
//!
//! Every ray's random stream is keyed by its pixel and a sample number that names its level and
//! place (first pass below [`FIRST_KEYS`], cells next, then sub-cells), never by the order of
//! work, so the image is the same for any number of threads.

use std::collections::VecDeque;
use std::ops::Range;

use super::sample::{grid_sample, pixel_samples, render_blocks_of, Sampler};
use crate::render::{Image, Watch};
use crate::Rgb;

/// What a primary ray meets, as far as coverage goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Nothing: the ray leaves the scene.
    Background,
    /// One side of one patch.
    Surface {
        /// The patch.
        patch: u32,
        /// Whether its front.
        front: bool,
    },
}

/// Side of the grid of cells an edge pixel is sampled on, one ray per cell.
pub const EDGE_SIDE: u32 = 16;
/// Side of the grid of sub-cells a cell is refined by.
pub const REFINE_SIDE: u32 = 4;
/// The weight of a whole edge pixel, in units of one sub-sample: an unrefined cell's ray
/// weighs [`REFINE_SIDE`]², a sub-sample 1.
pub const EDGE_WEIGHT: u32 = (EDGE_SIDE * REFINE_SIDE) * (EDGE_SIDE * REFINE_SIDE);
/// Sample numbers of the first pass are below this (its grid is at most 8 × 8); the cells of an
/// edge pixel come next, then their sub-cells.
pub const FIRST_KEYS: u32 = 64;
/// The first sample number of the sub-cells.
const SUB_KEYS: u32 = FIRST_KEYS + EDGE_SIDE * EDGE_SIDE;

/// A side of a pixel or of a cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Side {
    Left,
    Right,
    Top,
    Bottom,
}

const SIDES: [Side; 4] = [Side::Left, Side::Right, Side::Top, Side::Bottom];

impl Side {
    fn opposite(self) -> Self {
        match self {
            Self::Left => Self::Right,
            Self::Right => Self::Left,
            Self::Top => Self::Bottom,
            Self::Bottom => Self::Top,
        }
    }

    /// The place next to (i, j) across this side on an n × n grid, if on the grid.
    fn step(self, (i, j): (u32, u32), n: u32) -> Option<(u32, u32)> {
        match self {
            Self::Left => i.checked_sub(1).map(|i| (i, j)),
            Self::Right => (i + 1 < n).then_some((i + 1, j)),
            Self::Top => j.checked_sub(1).map(|j| (i, j)),
            Self::Bottom => (j + 1 < n).then_some((i, j + 1)),
        }
    }

    /// The place m along this side of an n × n grid (top to bottom on the left and right,
    /// left to right on the top and bottom).
    fn at(self, m: u32, n: u32) -> (u32, u32) {
        match self {
            Self::Left => (0, m),
            Self::Right => (n - 1, m),
            Self::Top => (m, 0),
            Self::Bottom => (m, n - 1),
        }
    }

    /// How far along this side (i, j) is (see [`Side::at`]).
    fn along(self, (i, j): (u32, u32)) -> u32 {
        match self {
            Self::Left | Self::Right => j,
            Self::Top | Self::Bottom => i,
        }
    }
}

/// Renders a `width` × `height` image whose pixel is `shade(samples, total)`: the pixel's
/// probes, each with its weight out of `total`. `shoot(px, py, sampler)` casts the ray through
/// image point (px, py) and says what it met; the first pass takes an s × s grid
/// (s = `side`), edge pixels are sampled adaptively (see the module docs). Tiles run in
/// parallel; the image does not depend on the number of threads.
pub fn render_covered<T, F, S>(
    (width, height): (u32, u32),
    side: u32,
    jitter: bool,
    watch: &Watch,
    shoot: F,
    shade: S,
) -> Option<Image>
where
    F: Fn(f32, f32, Sampler) -> (Kind, T) + Sync,
    S: Fn(Vec<(T, u32)>, u32) -> Rgb + Sync,
{
    let pixels = render_covered_of((width, height), side, jitter, watch, shoot, shade)?;
    Some(Image {
        width,
        height,
        pixels,
    })
}

/// [`render_covered`] for pixels of any kind `P` (what `shade` makes of a pixel's probes):
/// the `width · height` pixels row by row.
pub fn render_covered_of<T, P, F, S>(
    (width, height): (u32, u32),
    side: u32,
    jitter: bool,
    watch: &Watch,
    shoot: F,
    shade: S,
) -> Option<Vec<P>>
where
    P: Clone + Default + Send,
    F: Fn(f32, f32, Sampler) -> (Kind, T) + Sync,
    S: Fn(Vec<(T, u32)>, u32) -> P + Sync,
{
    debug_assert!(side * side <= FIRST_KEYS);
    render_blocks_of(width, height, watch, |xs, ys| {
        let pixels: Vec<(u32, u32)> = ys
            .clone()
            .flat_map(|y| xs.clone().map(move |x| (x, y)))
            .collect();
        // The first pass over the tile, and the kinds seen around it.
        let first: Vec<Vec<(Kind, T)>> = pixels
            .iter()
            .map(|&(x, y)| {
                pixel_samples(x, y, side, jitter)
                    .map(|(px, py, sampler)| shoot(px, py, sampler))
                    .collect()
            })
            .collect();
        let grid = KindGrid::new((&xs, &ys), (width, height), side, jitter, &first, &shoot);
        pixels
            .iter()
            .zip(first)
            .map(|(&(x, y), rays)| {
                let evidence = SIDES.map(|s| grid.facing(x, y, s));
                let own = rays[0].0;
                let alone =
                    rays.iter().all(|r| r.0 == own) && evidence.iter().flatten().all(|&k| k == own);
                if alone {
                    shade(rays.into_iter().map(|(_, t)| (t, 1)).collect(), side * side)
                } else {
                    shade(edge_samples((x, y), jitter, &evidence, &shoot), EDGE_WEIGHT)
                }
            })
            .collect()
    })
}

/// The first-pass kinds of a tile's pixels and of the samples of the pixels around it next to
/// the tile, on the grid of samples of the tile and a border one pixel wide.
struct KindGrid {
    /// The pixel at the grid's corner (one left of and above the tile's first).
    corner: (i64, i64),
    side: u32,
    /// Samples per row.
    stride: usize,
    kinds: Vec<Option<Kind>>,
}

impl KindGrid {
    /// The grid of the tile of pixels `xs` × `ys` from its `first` pass, the samples next to it
    /// in the pixels around shot by `shoot` (those outside the `size` of the image stay unknown).
    fn new<T>(
        (xs, ys): (&Range<u32>, &Range<u32>),
        size: (u32, u32),
        side: u32,
        jitter: bool,
        first: &[Vec<(Kind, T)>],
        shoot: &impl Fn(f32, f32, Sampler) -> (Kind, T),
    ) -> Self {
        let (w, h) = (xs.len() + 2, ys.len() + 2);
        let n = side as usize;
        let mut grid = Self {
            corner: (i64::from(xs.start) - 1, i64::from(ys.start) - 1),
            side,
            stride: w * n,
            kinds: vec![None; w * h * n * n],
        };
        let pixels = ys.clone().flat_map(|y| xs.clone().map(move |x| (x, y)));
        for ((x, y), rays) in pixels.zip(first) {
            for (k, ray) in rays.iter().enumerate() {
                let k = k as u32;
                grid.set((x, y), (k % side, k / side), ray.0);
            }
        }
        // The pixels around the tile: only their samples along the side facing it.
        let around = |s: Side| -> Vec<(u32, u32)> {
            let (xs, ys) = (xs.clone(), ys.clone());
            match s {
                Side::Left => xs
                    .start
                    .checked_sub(1)
                    .map(|x| ys.map(|y| (x, y)).collect()),
                Side::Right => (xs.end < size.0).then(|| ys.map(|y| (xs.end, y)).collect()),
                Side::Top => ys
                    .start
                    .checked_sub(1)
                    .map(|y| xs.map(|x| (x, y)).collect()),
                Side::Bottom => (ys.end < size.1).then(|| xs.map(|x| (x, ys.end)).collect()),
            }
            .unwrap_or_default()
        };
        for s in SIDES {
            for (x, y) in around(s) {
                for m in 0..side {
                    let (i, j) = s.opposite().at(m, side);
                    let (px, py, sampler) = grid_sample(x, y, side, (i, j), j * side + i, jitter);
                    grid.set((x, y), (i, j), shoot(px, py, sampler).0);
                }
            }
        }
        grid
    }

    fn index(&self, (x, y): (i64, i64), (i, j): (u32, u32)) -> usize {
        let n = i64::from(self.side);
        let gx = (x - self.corner.0) * n + i64::from(i);
        let gy = (y - self.corner.1) * n + i64::from(j);
        gy as usize * self.stride + gx as usize
    }

    fn set(&mut self, (x, y): (u32, u32), at: (u32, u32), kind: Kind) {
        let k = self.index((i64::from(x), i64::from(y)), at);
        self.kinds[k] = Some(kind);
    }

    /// The kinds of the samples of the pixel across side `s` of tile pixel (x, y) along the
    /// shared side (see [`Side::at`]): empty outside the image.
    fn facing(&self, x: u32, y: u32, s: Side) -> Vec<Kind> {
        let (i, j) = s
            .step((1, 1), 3)
            .expect("the middle of three has neighbours");
        let neighbour = (
            i64::from(x) + i64::from(i) - 1,
            i64::from(y) + i64::from(j) - 1,
        );
        (0..self.side)
            .filter_map(|m| self.kinds[self.index(neighbour, s.opposite().at(m, self.side))])
            .collect()
    }
}

/// The probes of edge pixel (x, y), each with its weight out of [`EDGE_WEIGHT`]: one ray per
/// cell of an [`EDGE_SIDE`]² grid, cells where the kind changes refined by [`REFINE_SIDE`]²
/// sub-samples (see the module docs). `evidence[s]`: the kinds of the first-pass samples of
/// the neighbour across side s of the pixel (in [`SIDES`] order) along that side, or none.
fn edge_samples<T>(
    (x, y): (u32, u32),
    jitter: bool,
    evidence: &[Vec<Kind>; 4],
    shoot: &impl Fn(f32, f32, Sampler) -> (Kind, T),
) -> Vec<(T, u32)> {
    let (n, r) = (EDGE_SIDE, REFINE_SIDE);
    let mut cells: Vec<(Kind, Option<T>)> = (0..n * n)
        .map(|k| {
            let (px, py, sampler) = grid_sample(x, y, n, (k % n, k / n), FIRST_KEYS + k, jitter);
            let (kind, probe) = shoot(px, py, sampler);
            (kind, Some(probe))
        })
        .collect();
    let mut subs: Vec<Option<Vec<Kind>>> = vec![None; cells.len()];
    let mut out = Vec::new();
    let mut queue: VecDeque<u32> = (0..n * n).collect();
    let mut queued = vec![true; cells.len()];
    while let Some(k) = queue.pop_front() {
        queued[k as usize] = false;
        let cell = (k % n, k / n);
        if subs[k as usize].is_some() || !disagrees(cell, &cells, &subs, evidence) {
            continue;
        }
        // Refine the cell: its ray gives way to an r × r grid of fresh ones.
        let mut kinds = Vec::with_capacity((r * r) as usize);
        for m in 0..r * r {
            let at = (cell.0 * r + m % r, cell.1 * r + m / r);
            let (px, py, sampler) = grid_sample(x, y, n * r, at, SUB_KEYS + k * r * r + m, jitter);
            let (kind, probe) = shoot(px, py, sampler);
            kinds.push(kind);
            out.push((probe, 1));
        }
        subs[k as usize] = Some(kinds);
        cells[k as usize].1 = None;
        // Its neighbours see its sub-samples now.
        for s in SIDES {
            if let Some((i, j)) = s.step(cell, n) {
                let nb = (j * n + i) as usize;
                if subs[nb].is_none() && !queued[nb] {
                    queued[nb] = true;
                    queue.push_back(nb as u32);
                }
            }
        }
    }
    out.extend(
        cells
            .into_iter()
            .filter_map(|(_, probe)| probe.map(|p| (p, r * r))),
    );
    out
}

/// Whether a sample next to unrefined `cell` differs from the cell's: of the neighbour cells
/// (their sub-samples along the shared side if refined) or, at the pixel's sides, of the
/// `evidence` of the neighbour pixels' first pass.
fn disagrees<T>(
    cell: (u32, u32),
    cells: &[(Kind, Option<T>)],
    subs: &[Option<Vec<Kind>>],
    evidence: &[Vec<Kind>; 4],
) -> bool {
    let (n, r) = (EDGE_SIDE, REFINE_SIDE);
    let own = cells[(cell.1 * n + cell.0) as usize].0;
    SIDES
        .iter()
        .zip(evidence)
        .any(|(&s, evidence)| match s.step(cell, n) {
            Some((i, j)) => {
                let nb = (j * n + i) as usize;
                match &subs[nb] {
                    Some(kinds) => (0..r).any(|m| {
                        let (si, sj) = s.opposite().at(m, r);
                        kinds[(sj * r + si) as usize] != own
                    }),
                    None => cells[nb].0 != own,
                }
            }
            None if evidence.is_empty() => false,
            None => {
                // The neighbour pixel's samples beside the cell.
                let (a, m) = (s.along(cell) as usize, evidence.len());
                let (lo, hi) = (a * m / n as usize, ((a + 1) * m - 1) / n as usize);
                evidence[lo..=hi].iter().any(|&k| k != own)
            }
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: Kind = Kind::Surface {
        patch: 0,
        front: true,
    };
    const B: Kind = Kind::Surface {
        patch: 1,
        front: true,
    };

    /// A 12 × 8 image of `B` left of the line x = `edge` and `A` right of it; each pixel is
    /// the coverage of `B`, and the number of rays shot is counted.
    fn covered(edge: impl Fn(f32) -> f32 + Sync, side: u32) -> (Image, usize) {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let rays = AtomicUsize::new(0);
        let image = render_covered(
            (12, 8),
            side,
            true,
            &Watch::SILENT,
            |px, py, _| {
                rays.fetch_add(1, Ordering::Relaxed);
                let kind = if px < edge(py) { B } else { A };
                (kind, kind)
            },
            |samples, total| {
                let b: u32 = samples.iter().filter(|s| s.0 == B).map(|s| s.1).sum();
                Rgb::splat(f64::from(b) / f64::from(total))
            },
        )
        .expect("not stopped");
        (image, rays.into_inner())
    }

    #[test]
    fn a_three_percent_sliver_gets_its_coverage_and_missed_slivers_are_found_by_the_neighbour() {
        // Column 3 holds a sliver of B 0.03 wide along its left side, which a 4 × 4 first
        // pass misses in most rows (each of its four rays of the column meets the sliver with
        // probability 0.12); the pixel left of it is B alone. A 16 × 16 grid counts the sliver
        // in each of its 16 rows with probability 0.48, a standard deviation of
        // √(16 · 0.48 · 0.52) / 256 = 0.0078, a quarter of the sliver; refined 4 × 4 in each
        // cell it crosses, each of 64 rows holds 1.92 sub-columns of it, a standard deviation
        // of √(64 · 0.92 · 0.08) / 4096 = 0.0005 (2 % of the sliver). Measured over the 8
        // rows: 2.2 % RMS; with the 16 × 16 grid alone (no refinement), 29 %.
        let (image, _) = covered(|_| 3.03, 4);
        let mut sum = 0.0;
        for y in 0..8 {
            let c = image.get(3, y).x;
            sum += (c / 0.03 - 1.0).powi(2);
            assert_eq!(image.get(2, y).x, 1.0);
            assert_eq!(image.get(5, y).x, 0.0);
        }
        let rms = (sum / 8.0).sqrt();
        assert!(rms < 0.06, "relative error of the sliver's coverage {rms}");
    }

    #[test]
    fn a_slanted_edge_costs_a_fraction_of_a_fine_grid_and_pure_pixels_their_first_pass() {
        // The edge x = 3.3 + 0.4 y crosses columns 3 to 6: its exact coverage of pixel (x, y)
        // is the mean of clamp(3.3 + 0.4 (y + v) − x, 0, 1) over v ∈ [0, 1).
        let edge = |py: f32| 3.3 + 0.4 * py;
        let (image, rays) = covered(edge, 4);
        let mut worst = 0.0f64;
        for y in 0..8 {
            for x in 0..12 {
                let exact = (0..1000)
                    .map(|k| {
                        let v = (f64::from(y) + (f64::from(k) + 0.5) / 1000.0) * 0.4;
                        (3.3 + v - f64::from(x)).clamp(0.0, 1.0)
                    })
                    .sum::<f64>()
                    / 1000.0;
                worst = worst.max((image.get(x, y).x - exact).abs());
            }
        }
        // Measured: within 0.002 of the pixel (8 sub-samples of 4 096); the 16 × 16 grid
        // alone, 0.015.
        assert!(worst < 0.003, "worst coverage error {worst}");
        // Measured: 9 264 rays, 1 536 of them the first pass; a 64 × 64 grid in each of the
        // 16 pixels the edge crosses would take 65 536.
        assert!(rays < 16_000, "{rays} rays");
    }

    #[test]
    fn coverage_does_not_depend_on_the_thread_count() {
        let edge = |py: f32| 3.03 + 0.1 * py;
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a pool")
                .install(|| covered(edge, 4))
        };
        let (one, rays) = run(1);
        let (three, again) = run(3);
        assert_eq!(one.pixels, three.pixels);
        assert_eq!(rays, again);
    }
}
