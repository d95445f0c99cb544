//! Deterministic sampling: hashed random numbers, stratified pixel samples, points of
//! triangles and the tile loop every ray-traced image runs in.
//!
//! Every random number is a hash of *where* it is used — pixel, sample, dimension — never of
//! the order in which threads reach it, so images are bit-identical for any thread count. The
//! hash is SplitMix64's finaliser (Steele, Lea & Flood 2014), a bijection of 64-bit words with
//! good avalanche.
//!
//! Stratification: the s × s samples of a pixel sit one in each sub-square, jittered inside it;
//! n gather or shadow samples are stratified in their first dimension ((k + ξ)/n) and random in
//! the second. Cosine-weighted hemisphere directions come from
//! [`crate::sampling::cosine_direction`].

use std::ops::Range;

use glam::Vec3;
use rayon::prelude::*;

use crate::hash::{mix, unit_f32};
use crate::progress::Work;
use crate::render::{Image, Watch};
use crate::Rgb;

/// Side of the square tiles images are rendered in parallel over.
const TILE: u32 = 16;

/// A stream of random numbers in [0, 1) keyed by its position in the image (a pixel and a
/// sample of it); each draw hashes the key with a running counter.
#[derive(Clone, Debug)]
pub struct Sampler {
    key: u64,
    counter: u64,
}

impl Sampler {
    /// The stream of sample `sample` of pixel (`x`, `y`).
    #[must_use]
    pub fn new(x: u32, y: u32, sample: u32) -> Self {
        let key = mix(mix(u64::from(x) | (u64::from(y) << 32)) ^ u64::from(sample));
        Self { key, counter: 0 }
    }

    /// The next number in [0, 1) (24 random bits, exact in f32).
    pub fn next_f32(&mut self) -> f32 {
        self.counter += 1;
        let bits = mix(self.key ^ self.counter.wrapping_mul(0xd1b5_4a32_d192_ed03));
        unit_f32(bits)
    }
}

/// Side s of the s × s stratified grid for `samples_per_pixel` (the largest s with s² ≤ it,
/// between 1 and 8), as the rasterizer counts.
#[must_use]
pub fn grid_side(samples_per_pixel: u32) -> u32 {
    let mut s = 1;
    while s < 8 && (s + 1) * (s + 1) <= samples_per_pixel {
        s += 1;
    }
    s
}

/// A point of triangle `tri`, uniform in area, from (u₁, u₂) ∈ [0, 1)².
#[must_use]
pub fn triangle_point(tri: &[Vec3; 3], u1: f32, u2: f32) -> Vec3 {
    let s = u1.sqrt();
    let (b1, b2) = (1.0 - s, u2 * s);
    tri[0] * (1.0 - b1 - b2) + tri[1] * b1 + tri[2] * b2
}

/// Renders a `width` × `height` image whose pixel (x, y) is the mean of `shade(px, py,
/// sampler)` over an s × s jittered grid of points (px, py) in it (s from
/// [`grid_side`]`(samples_per_pixel)`; `jitter = false` puts them at the sub-square centres, as
/// the rasterizer does). See [`render_pixels`] for the tiles.
pub fn render_tiles<F>(
    width: u32,
    height: u32,
    samples_per_pixel: u32,
    jitter: bool,
    watch: &Watch,
    shade: F,
) -> Option<Image>
where
    F: Fn(f32, f32, &mut Sampler) -> Rgb + Sync,
{
    let side = grid_side(samples_per_pixel);
    let norm = 1.0 / f64::from(side * side);
    render_pixels(width, height, watch, |x, y| {
        let mut sum = Rgb::ZERO;
        for (px, py, mut sampler) in pixel_samples(x, y, side, jitter) {
            sum += shade(px, py, &mut sampler);
        }
        sum * norm
    })
}

/// The s × s sample points (px, py) of pixel (x, y), each with its own random stream (whose
/// first two draws placed it, when `jitter`): sample k = j·s + i is [`grid_sample`] (i, j)
/// keyed k.
pub fn pixel_samples(
    x: u32,
    y: u32,
    side: u32,
    jitter: bool,
) -> impl Iterator<Item = (f32, f32, Sampler)> {
    (0..side * side).map(move |k| grid_sample(x, y, side, (k % side, k / side), k, jitter))
}

/// The sample point (px, py) in sub-square (i, j) of the `side` × `side` grid over pixel
/// (x, y), with the random stream of sample `key` of the pixel: its first two draws place the
/// point in the sub-square when `jitter`, else it sits at the centre. Distinct samples of a
/// pixel need distinct keys.
#[must_use]
pub fn grid_sample(
    x: u32,
    y: u32,
    side: u32,
    (i, j): (u32, u32),
    key: u32,
    jitter: bool,
) -> (f32, f32, Sampler) {
    let mut sampler = Sampler::new(x, y, key);
    let (dx, dy) = if jitter {
        (sampler.next_f32(), sampler.next_f32())
    } else {
        (0.5, 0.5)
    };
    let px = x as f32 + (i as f32 + dx) / side as f32;
    let py = y as f32 + (j as f32 + dy) / side as f32;
    (px, py, sampler)
}

/// Renders a `width` × `height` image whose pixel (x, y) is `pixel(x, y)`, in parallel over
/// the tiles of [`render_blocks`].
pub fn render_pixels<F>(width: u32, height: u32, watch: &Watch, pixel: F) -> Option<Image>
where
    F: Fn(u32, u32) -> Rgb + Sync,
{
    render_blocks(width, height, watch, |xs, ys| {
        ys.flat_map(|y| xs.clone().map(move |x| (x, y)))
            .map(|(x, y)| pixel(x, y))
            .collect()
    })
}

/// Renders a `width` × `height` image by tiles of 16 × 16 pixels (fewer at the right and
/// bottom borders): `tile(xs, ys)` returns the pixels of columns `xs` and rows `ys`, row by row.
/// Tiles run in parallel; the result does not depend on the number of threads. `None` if
/// `watch` was told to stop before the last tile.
pub fn render_blocks<F>(width: u32, height: u32, watch: &Watch, tile: F) -> Option<Image>
where
    F: Fn(Range<u32>, Range<u32>) -> Vec<Rgb> + Sync,
{
    let pixels = render_blocks_of(width, height, watch, tile)?;
    Some(Image {
        width,
        height,
        pixels,
    })
}

/// [`render_blocks`] for pixels of any kind: the `width · height` pixels row by row.
pub fn render_blocks_of<P, F>(width: u32, height: u32, watch: &Watch, tile: F) -> Option<Vec<P>>
where
    P: Clone + Default + Send,
    F: Fn(Range<u32>, Range<u32>) -> Vec<P> + Sync,
{
    let mut image = vec![P::default(); width as usize * height as usize];
    let (tiles_x, tiles_y) = (width.div_ceil(TILE), height.div_ceil(TILE));
    watch
        .progress
        .start("render", Work::of(u64::from(tiles_x * tiles_y), "tiles"));
    let tiles: Vec<(u32, Vec<P>)> = (0..tiles_x * tiles_y)
        .into_par_iter()
        .map(|t| {
            if watch.stopped() {
                return (t, Vec::new());
            }
            let (x0, y0) = ((t % tiles_x) * TILE, (t / tiles_x) * TILE);
            let out = tile(x0..(x0 + TILE).min(width), y0..(y0 + TILE).min(height));
            watch.progress.advance(1);
            (t, out)
        })
        .collect();
    if !watch.stopped() {
        watch
            .progress
            .tally(u64::from(width) * u64::from(height), "pixels");
    }
    watch.progress.end(watch.stopped());
    if watch.stopped() {
        return None;
    }
    for (tile, pixels) in tiles {
        let (x0, y0) = ((tile % tiles_x) * TILE, (tile / tiles_x) * TILE);
        let w = (x0 + TILE).min(width) - x0;
        for (k, p) in pixels.into_iter().enumerate() {
            let (x, y) = (x0 + k as u32 % w, y0 + k as u32 / w);
            image[y as usize * width as usize + x as usize] = p;
        }
    }
    Some(image)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sampler_is_uniform_and_keyed_by_position() {
        // 4096 draws: the mean of U[0,1) is 1/2 with standard error 1/√(12·4096) ≈ 0.0045.
        let mut s = Sampler::new(3, 5, 7);
        let draws: Vec<f32> = (0..4096).map(|_| s.next_f32()).collect();
        assert!(draws.iter().all(|&u| (0.0..1.0).contains(&u)));
        let mean = draws.iter().sum::<f32>() / 4096.0;
        assert!((mean - 0.5).abs() < 0.02, "{mean}");
        assert_eq!(Sampler::new(3, 5, 7).next_f32(), draws[0]);
        assert_ne!(Sampler::new(5, 3, 7).next_f32(), draws[0]);
    }

    #[test]
    fn a_set_stop_flag_gives_no_image_and_every_tile_is_reported() {
        use crate::progress::{Progress, Silent};
        use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
        use std::sync::Mutex;
        struct Count(AtomicU64, Mutex<Vec<(u64, &'static str)>>);
        impl Progress for Count {
            fn start(&self, stage: &str, work: Work) {
                assert_eq!((stage, work), ("render", Work::of(6, "tiles")));
            }
            fn advance(&self, n: u64) {
                self.0.fetch_add(n, Ordering::Relaxed);
            }
            fn tally(&self, count: u64, what: &'static str) {
                self.1.lock().expect("lock").push((count, what));
            }
            fn finish(&self) {}
        }
        let count = Count(AtomicU64::new(0), Mutex::new(Vec::new()));
        let watch = Watch {
            progress: &count,
            stop: None,
        };
        assert!(render_tiles(37, 21, 1, false, &watch, |_, _, _| Rgb::ONE).is_some());
        assert_eq!(count.0.load(Ordering::Relaxed), 6, "3 × 2 tiles of 16²");
        assert_eq!(*count.1.lock().expect("lock"), [(37 * 21, "pixels")]);
        let stop = AtomicBool::new(true);
        let watch = Watch {
            progress: &Silent,
            stop: Some(&stop),
        };
        assert!(render_tiles(37, 21, 1, false, &watch, |_, _, _| Rgb::ONE).is_none());
    }

    #[test]
    fn tiles_cover_every_pixel_once() {
        let image = render_tiles(37, 21, 4, true, &Watch::SILENT, |px, py, _| {
            Rgb::new(f64::from(px.floor()), f64::from(py.floor()), 1.0)
        })
        .expect("not stopped");
        for y in 0..21 {
            for x in 0..37 {
                assert_eq!(image.get(x, y), Rgb::new(f64::from(x), f64::from(y), 1.0));
            }
        }
    }
}
