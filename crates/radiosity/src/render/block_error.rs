//! How far a picture is from a reference picture, the way the eye judges it.
//!
//! A path tracer's reference and our picture are both linear radiance, pixel for pixel from the
//! same camera. The measure compares their luminance Y = 0.2126 R + 0.7152 G + 0.0722 B
//! (ITU-R BT.709) averaged over k × k-pixel blocks, so noise finer than a block averages out as
//! it does for the eye, and takes the RMS of the relative errors of the blocks:
//!
//! ```text
//! error = sqrt( mean_blocks ((Y_b − Y_ref,b) / Y_ref,b)² ),    bias = mean_blocks (Y_b − Y_ref,b) / Y_ref,b
//! ```
//!
//! Blocks whose reference is darker than 10⁻³ of the reference's mean are left out: relative
//! errors of black are noise (the same measure as `benches/image/error.py`).

use super::Image;
use crate::color::luminance;

/// The error of a picture against a reference (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlockError {
    /// RMS of the blocks' relative luminance errors.
    pub rms: f64,
    /// Mean of the blocks' relative luminance errors (positive: too bright).
    pub bias: f64,
    /// The 99th percentile of the blocks' absolute relative errors: where a leak, a blotch or
    /// a seam shows that the RMS averages away.
    pub p99: f64,
    /// Blocks compared.
    pub blocks: usize,
}

/// The error of `image` against `reference` over `block` × `block`-pixel blocks (pixels beyond
/// the last whole block are left out); `None` if the sizes differ, the block is 0 or no block
/// is bright enough to compare.
#[must_use]
pub fn block_error(image: &Image, reference: &Image, block: u32) -> Option<BlockError> {
    if (image.width, image.height) != (reference.width, reference.height) || block == 0 {
        return None;
    }
    let (bw, bh) = (image.width / block, image.height / block);
    let mean = |img: &Image, bx: u32, by: u32| {
        let mut sum = 0.0;
        for y in by * block..(by + 1) * block {
            for x in bx * block..(bx + 1) * block {
                sum += luminance(img.pixels[(y * img.width + x) as usize]);
            }
        }
        sum / f64::from(block * block)
    };
    let pairs: Vec<(f64, f64)> = (0..bh)
        .flat_map(|by| (0..bw).map(move |bx| (bx, by)))
        .map(|(bx, by)| (mean(image, bx, by), mean(reference, bx, by)))
        .collect();
    if pairs.is_empty() {
        return None;
    }
    let floor = 1e-3 * pairs.iter().map(|p| p.1).sum::<f64>() / pairs.len() as f64;
    let relative: Vec<f64> = pairs
        .iter()
        .filter(|p| p.1 > floor)
        .map(|&(y, r)| (y - r) / r)
        .collect();
    if relative.is_empty() {
        return None;
    }
    let n = relative.len() as f64;
    let mut magnitudes: Vec<f64> = relative.iter().map(|e| e.abs()).collect();
    magnitudes.sort_by(f64::total_cmp);
    let rank = ((0.99 * n).ceil() as usize).clamp(1, magnitudes.len()) - 1;
    Some(BlockError {
        rms: (relative.iter().map(|e| e * e).sum::<f64>() / n).sqrt(),
        bias: relative.iter().sum::<f64>() / n,
        p99: magnitudes[rank],
        blocks: relative.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Rgb;

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> f64) -> Image {
        Image {
            width: w,
            height: h,
            pixels: (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .map(|(x, y)| Rgb::splat(f(x, y)))
                .collect(),
        }
    }

    #[test]
    fn a_uniform_scale_is_its_own_error_and_bias() {
        let reference = image(8, 8, |x, y| 1.0 + f64::from(x + y));
        let brighter = image(8, 8, |x, y| 1.03 * (1.0 + f64::from(x + y)));
        let e = block_error(&brighter, &reference, 4).unwrap();
        assert!((e.rms - 0.03).abs() < 1e-12 && (e.bias - 0.03).abs() < 1e-12);
        assert_eq!(e.blocks, 4);
        assert_eq!(block_error(&reference, &reference, 2).unwrap().rms, 0.0);
    }

    #[test]
    fn one_bad_block_in_a_hundred_is_the_99th_percentile() {
        let reference = image(40, 40, |_, _| 1.0);
        // 100 blocks of 4 × 4; one is 50 % too bright, one 20 %: the 99th percentile is the
        // second largest, the RMS far below either.
        let blotched = image(40, 40, |x, y| match (x / 4, y / 4) {
            (0, 0) => 1.5,
            (9, 9) => 1.2,
            _ => 1.0,
        });
        let e = block_error(&blotched, &reference, 4).unwrap();
        assert!((e.p99 - 0.2).abs() < 1e-12, "{e:?}");
        assert!((e.rms - (0.29f64 / 100.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn noise_finer_than_a_block_averages_out_black_blocks_are_left_out() {
        let reference = image(8, 8, |x, _| if x < 4 { 0.0 } else { 2.0 });
        // ±10 % in a checkerboard: zero error over 2 × 2 blocks, 10 % per pixel.
        let noisy = image(8, 8, |x, y| {
            let v = if x < 4 { 0.0 } else { 2.0 };
            v * if (x + y) % 2 == 0 { 1.1 } else { 0.9 }
        });
        let e = block_error(&noisy, &reference, 2).unwrap();
        assert!(e.rms < 1e-12, "{e:?}");
        assert_eq!(e.blocks, 8, "the black half is left out");
        assert!((block_error(&noisy, &reference, 1).unwrap().rms - 0.1).abs() < 1e-12);
        assert!(block_error(&noisy, &image(4, 4, |_, _| 1.0), 2).is_none());
    }
}
