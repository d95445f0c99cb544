//! Side-by-side comparison images with labels, drawn with the built-in 5 × 7 bitmap font
//! ([`super::font`]).
//!
//! The lecture sets an "OpenGL" (local illumination) image beside a radiosity image of the same
//! scene; [`compose`] puts any number of radiance images in one row, each under a caption band.
//! Captions are drawn in radiance too (a chosen value that the exposure maps to white), so the
//! composite is written like any other image.

use super::font::GLYPH_H;
pub use super::font::{draw_text, text_width};
use super::Image;
use crate::Rgb;

/// Black columns between panels.
const GAP: u32 = 4;

/// Places `panels` (caption, image) left to right under caption bands, captions centred and
/// drawn with radiance `ink`. Panels of different heights are aligned at the top; the rest is
/// black. Captions are upper-cased; characters without a glyph show as `?`; a caption wider
/// than its panel is cut.
#[must_use]
pub fn compose(panels: &[(&str, &Image)], ink: Rgb) -> Image {
    let narrowest = panels.iter().map(|(_, i)| i.width).min().unwrap_or(0);
    let scale = (narrowest / 160).max(1);
    let band = GLYPH_H * scale + 4 * scale;
    let width = panels.iter().map(|(_, i)| i.width).sum::<u32>()
        + GAP * (panels.len() as u32).saturating_sub(1);
    let height = band + panels.iter().map(|(_, i)| i.height).max().unwrap_or(0);
    let mut out = Image::new(width, height);
    let mut x0 = 0;
    for (caption, image) in panels {
        let w = image.width as usize;
        if w > 0 {
            // Rows past the end of a short pixel vector stay black.
            for (y, row) in image
                .pixels
                .chunks_exact(w)
                .take(image.height as usize)
                .enumerate()
            {
                let dst = (band as usize + y) * width as usize + x0 as usize;
                out.pixels[dst..dst + w].copy_from_slice(row);
            }
        }
        let caption = caption.to_ascii_uppercase();
        let text = text_width(&caption) * scale;
        let left = x0 + image.width.saturating_sub(text) / 2;
        draw_text(
            &mut out,
            &caption,
            (left, 2 * scale),
            (x0, x0 + image.width),
            scale,
            ink,
        );
        x0 += image.width + GAP;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panels_sit_side_by_side_under_their_captions() {
        let mut a = Image::new(2, 3);
        a.pixels.fill(Rgb::splat(1.0));
        let mut b = Image::new(3, 2);
        b.pixels.fill(Rgb::splat(2.0));
        let ink = Rgb::splat(9.0);
        let out = compose(&[("", &a), ("", &b)], ink);
        // Scale 1: the band is 7 + 4 = 11 rows; widths 2 + 4 (gap) + 3.
        assert_eq!((out.width, out.height), (9, 14));
        assert_eq!(out.get(1, 11), Rgb::splat(1.0));
        assert_eq!(out.get(1, 13), Rgb::splat(1.0));
        assert_eq!(out.get(3, 12), Rgb::ZERO, "the gap is black");
        assert_eq!(out.get(6, 12), Rgb::splat(2.0));
        assert_eq!(out.get(6, 13), Rgb::ZERO, "below the shorter panel");
    }

    #[test]
    fn captions_are_clipped_to_their_panel() {
        // "WWWW" is 23 font pixels wide, more than the 8-pixel first panel: its ink must stop
        // at column 8, leaving the gap and the second panel's band black.
        let (a, b) = (Image::new(8, 2), Image::new(20, 2));
        let out = compose(&[("WWWW", &a), ("", &b)], Rgb::ONE);
        let inked = |x: u32| (0..out.height).any(|y| out.get(x, y) == Rgb::ONE);
        assert!((0..8).any(inked));
        assert!(!(8..out.width).any(inked));
    }
}
