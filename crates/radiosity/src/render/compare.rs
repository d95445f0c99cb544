//! Side-by-side comparison images with labels, drawn with a built-in 5 × 7 bitmap font.
//!
//! The lecture sets an "OpenGL" (local illumination) image beside a radiosity image of the same
//! scene; [`compose`] puts any number of radiance images in one row, each under a caption band.
//! Captions are drawn in radiance too (a chosen value that the exposure maps to white), so the
//! composite is written like any other image.

use super::Image;
use crate::Rgb;

/// Black columns between panels.
const GAP: u32 = 4;
/// Glyph size in font pixels.
const GLYPH_W: u32 = 5;
const GLYPH_H: u32 = 7;

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
        let text = text_width(caption) * scale;
        let left = x0 + image.width.saturating_sub(text) / 2;
        draw_text(
            &mut out,
            caption,
            (left, 2 * scale),
            (x0, x0 + image.width),
            scale,
            ink,
        );
        x0 += image.width + GAP;
    }
    out
}

/// Width of `text` in font pixels (glyphs are 5 wide with 1 pixel between them).
#[must_use]
pub fn text_width(text: &str) -> u32 {
    let n = text.chars().count() as u32;
    if n == 0 {
        0
    } else {
        n * (GLYPH_W + 1) - 1
    }
}

/// Draws `text` with its top-left corner at `at`, each font pixel a `scale` × `scale` square of
/// radiance `ink`, clipped to the columns `clip` = [from, to) and to the image.
pub fn draw_text(
    image: &mut Image,
    text: &str,
    at: (u32, u32),
    clip: (u32, u32),
    scale: u32,
    ink: Rgb,
) {
    for (k, c) in text.chars().enumerate() {
        let rows = glyph(c);
        let gx = at.0 + k as u32 * (GLYPH_W + 1) * scale;
        for (r, bits) in rows.iter().enumerate() {
            for col in 0..GLYPH_W {
                if bits & (1 << (GLYPH_W - 1 - col)) == 0 {
                    continue;
                }
                for dy in 0..scale {
                    for dx in 0..scale {
                        let x = gx + col * scale + dx;
                        let y = at.1 + r as u32 * scale + dy;
                        if x >= clip.0 && x < clip.1 && x < image.width && y < image.height {
                            image.pixels[y as usize * image.width as usize + x as usize] = ink;
                        }
                    }
                }
            }
        }
    }
}

/// The 5 × 7 glyph of `c` (upper case), one byte per row, bit 4 the leftmost pixel.
fn glyph(c: char) -> [u8; 7] {
    match c.to_ascii_uppercase() {
        'A' => [0x0e, 0x11, 0x11, 0x1f, 0x11, 0x11, 0x11],
        'B' => [0x1e, 0x11, 0x11, 0x1e, 0x11, 0x11, 0x1e],
        'C' => [0x0e, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0e],
        'D' => [0x1e, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1e],
        'E' => [0x1f, 0x10, 0x10, 0x1e, 0x10, 0x10, 0x1f],
        'F' => [0x1f, 0x10, 0x10, 0x1e, 0x10, 0x10, 0x10],
        'G' => [0x0e, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0f],
        'H' => [0x11, 0x11, 0x11, 0x1f, 0x11, 0x11, 0x11],
        'I' => [0x0e, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0e],
        'J' => [0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0c],
        'K' => [0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11],
        'L' => [0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1f],
        'M' => [0x11, 0x1b, 0x15, 0x15, 0x11, 0x11, 0x11],
        'N' => [0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11],
        'O' => [0x0e, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0e],
        'P' => [0x1e, 0x11, 0x11, 0x1e, 0x10, 0x10, 0x10],
        'Q' => [0x0e, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0d],
        'R' => [0x1e, 0x11, 0x11, 0x1e, 0x14, 0x12, 0x11],
        'S' => [0x0f, 0x10, 0x10, 0x0e, 0x01, 0x01, 0x1e],
        'T' => [0x1f, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04],
        'U' => [0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0e],
        'V' => [0x11, 0x11, 0x11, 0x11, 0x11, 0x0a, 0x04],
        'W' => [0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0a],
        'X' => [0x11, 0x11, 0x0a, 0x04, 0x0a, 0x11, 0x11],
        'Y' => [0x11, 0x11, 0x0a, 0x04, 0x04, 0x04, 0x04],
        'Z' => [0x1f, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1f],
        '0' => [0x0e, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0e],
        '1' => [0x04, 0x0c, 0x04, 0x04, 0x04, 0x04, 0x0e],
        '2' => [0x0e, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1f],
        '3' => [0x1f, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0e],
        '4' => [0x02, 0x06, 0x0a, 0x12, 0x1f, 0x02, 0x02],
        '5' => [0x1f, 0x10, 0x1e, 0x01, 0x01, 0x11, 0x0e],
        '6' => [0x06, 0x08, 0x10, 0x1e, 0x11, 0x11, 0x0e],
        '7' => [0x1f, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0e, 0x11, 0x11, 0x0e, 0x11, 0x11, 0x0e],
        '9' => [0x0e, 0x11, 0x11, 0x0f, 0x01, 0x02, 0x0c],
        ' ' => [0; 7],
        '-' => [0, 0, 0, 0x1f, 0, 0, 0],
        '+' => [0, 0x04, 0x04, 0x1f, 0x04, 0x04, 0],
        '=' => [0, 0, 0x1f, 0, 0x1f, 0, 0],
        '.' => [0, 0, 0, 0, 0, 0x0c, 0x0c],
        ',' => [0, 0, 0, 0, 0x0c, 0x04, 0x08],
        ':' => [0, 0x0c, 0x0c, 0, 0x0c, 0x0c, 0],
        '(' => [0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02],
        ')' => [0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08],
        '/' => [0x01, 0x02, 0x02, 0x04, 0x08, 0x08, 0x10],
        _ => [0x0e, 0x11, 0x01, 0x02, 0x04, 0, 0x04],
    }
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
    fn text_draws_the_glyph_bits() {
        // "I" at scale 2: the top row 0x0e lights font columns 1..=3, i.e. pixels 2..8.
        let mut image = Image::new(12, 16);
        let ink = Rgb::new(1.0, 2.0, 3.0);
        draw_text(&mut image, "i", (0, 0), (0, 12), 2, ink);
        for x in 0..12 {
            let lit = (2..8).contains(&x);
            assert_eq!(image.get(x, 0) == ink, lit, "column {x}");
            assert_eq!(image.get(x, 1) == ink, lit, "column {x}");
        }
        // The stem (0x04) is font column 2: pixels 4 and 5 on row 2 (image rows 4, 5).
        assert_eq!(image.get(4, 4), ink);
        assert_eq!(image.get(3, 4), Rgb::ZERO);
        let count = image.pixels.iter().filter(|&&p| p == ink).count();
        // 3 + 1 + 1 + 1 + 1 + 1 + 3 = 11 font pixels, 4 image pixels each.
        assert_eq!(count, 44);
        assert_eq!(text_width("ab"), 11);
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
