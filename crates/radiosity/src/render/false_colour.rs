//! False-colour pictures: instead of the tone-mapped picture, each pixel shows a photometric
//! quantity of the surface seen through it on a colour scale, with a legend — what lighting
//! designers read a rendering by (Radiance's `falsecolor`, the false-colour views of DIALux and
//! Relux).
//!
//! | quantity | a pixel shows | unit |
//! |---|---|---|
//! | [`Quantity::Lux`] | the illuminance E on the surface seen, Rec. 709 luminance of its irradiance ([`crate::color::luminance`], as the grids read it) | lx |
//! | [`Quantity::Luminance`] | the luminance of the radiance that surface sends to the eye (the picture's pixel, before tone mapping) | cd/m² |
//!
//! Both read in their units when the emitters' radiance is given in cd·m⁻², white on the three
//! channels (as `[sky]` and photometric scenes are): otherwise they are the radiometric
//! W·m⁻² and W·m⁻²·sr⁻¹ weighted by the luminous efficiency's Rec. 709 weights.
//!
//! The values are computed by [`super::evaluated::measured`] at the points of the evaluated
//! picture: each pixel holds the mean over the part of it that surfaces cover, and no value
//! where they cover less than half of it (the background; for illuminance also the back of a
//! one-sided surface and a sky's far tiles). A [`Measurement`] becomes
//!
//! - [`Measurement::picture`]: the colour of each value on a [`Scale`] (no value: black), with
//!   the legend in a white strip at the right — a colour bar from the lower to the upper end,
//!   its ends and nice levels labelled ([`Scale::levels`]), the unit above it; an end that
//!   values pass is marked ≤ or ≥;
//! - [`Measurement::data`]: the values themselves on all three channels (no value: 0), for
//!   float image files.
//!
//! The picture's pixels hold the sRGB colour codes decoded to linear light, so that a PNG
//! written at exposure 0 holds exactly the colour map's codes ([`crate::color::srgb_to_linear`]).

use super::font::{draw_text, text_width, GLYPH_H};
use super::Image;
use crate::color::scale::{colour, label, Scale};
use crate::registry::registry;
use crate::Rgb;

registry! {
    /// What a false-colour picture shows.
    pub enum Quantity {
        /// The illuminance on the surface seen through each pixel, lx: direct light exact,
        /// the rest from the solution, as the picture computes them.
        Lux = "lux",
        /// The luminance the surface seen through each pixel sends to the eye, cd/m².
        Luminance = "luminance",
    }
    /// An unknown false-colour quantity.
    pub struct UnknownQuantity = "unknown false-colour quantity";
}

impl Quantity {
    /// The unit of its values.
    #[must_use]
    pub fn unit(self) -> &'static str {
        match self {
            Quantity::Lux => "lx",
            Quantity::Luminance => "cd/m²",
        }
    }
}

/// A quantity measured at the surface seen through each pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    /// What was measured.
    pub quantity: Quantity,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width · height` values, row by row from the top; `None` where the pixel sees no
    /// surface.
    pub values: Vec<Option<f64>>,
}

/// The legend's ink, black, and its background, white (linear).
const INK: Rgb = Rgb::ZERO;
const PAPER: Rgb = Rgb::ONE;

impl Measurement {
    /// The values of the pixels that see a surface.
    pub fn seen(&self) -> impl Iterator<Item = f64> + '_ {
        self.values.iter().flatten().copied()
    }

    /// The value of pixel (x, y), `None` where it sees no surface.
    ///
    /// # Panics
    /// If x ≥ width or y ≥ height.
    #[must_use]
    pub fn get(&self, x: u32, y: u32) -> Option<f64> {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside"
        );
        self.values[y as usize * self.width as usize + x as usize]
    }

    /// The values as an image, the same on all three channels, 0 where no surface is seen.
    #[must_use]
    pub fn data(&self) -> Image {
        Image {
            width: self.width,
            height: self.height,
            pixels: self
                .values
                .iter()
                .map(|v| Rgb::splat(v.unwrap_or(0.0)))
                .collect(),
        }
    }

    /// The false-colour picture on `scale`, with its legend in a strip at the right (module
    /// docs): [`legend_width`] columns wider than the measurement.
    #[must_use]
    pub fn picture(&self, scale: &Scale) -> Image {
        let strip = legend_width(self.height, scale);
        let width = self.width + strip;
        let mut image = Image::new(width, self.height);
        for y in 0..self.height as usize {
            for x in 0..self.width as usize {
                let v = self.values[y * self.width as usize + x];
                image.pixels[y * width as usize + x] =
                    v.map_or(Rgb::ZERO, |v| linear(colour(scale.position(v))));
            }
        }
        let below = self.seen().any(|v| v < scale.lo);
        let above = self.seen().any(|v| v > scale.hi);
        draw_legend(
            &mut image,
            self.width,
            scale,
            (self.quantity.unit(), below, above),
        );
        image
    }
}

/// An 8-bit sRGB colour in linear light.
fn linear(code: [u8; 3]) -> Rgb {
    let [r, g, b] = code.map(|c| crate::color::srgb_to_linear(f64::from(c) / 255.0));
    Rgb::new(r, g, b)
}

/// The font's scale in a picture `height` pixels tall: 1 up to 511 rows, then one more per
/// 256.
fn font_scale(height: u32) -> u32 {
    (height / 256).max(1)
}

/// The labels of `scale`'s levels, in its order (lower end first), the ends marked ≤ and ≥
/// when values pass them.
fn labels(scale: &Scale, below: bool, above: bool) -> Vec<(f64, String)> {
    let levels = scale.levels();
    let last = levels.len() - 1;
    levels
        .into_iter()
        .enumerate()
        .map(|(k, level)| {
            let mark = match k {
                0 if below => "≤",
                k if k == last && above => "≥",
                _ => "",
            };
            (level, format!("{mark}{}", label(level)))
        })
        .collect()
}

/// The width of the legend strip of a picture `height` pixels tall on `scale`.
#[must_use]
pub fn legend_width(height: u32, scale: &Scale) -> u32 {
    let s = font_scale(height);
    let widest = labels(scale, true, true)
        .iter()
        .map(|(_, text)| text_width(text))
        .chain([text_width("cd/m²")])
        .max()
        .unwrap_or(0);
    // Padding, the bar, its ticks and a gap, the labels, padding.
    (4 + 10 + 5 + 4) * s + widest * s
}

/// Draws the legend into the strip of `image` right of column `left`: the unit, the bar from
/// `scale.lo` (bottom) to `scale.hi` (top), the labelled levels; `below` and `above` mark the
/// ends that values pass.
fn draw_legend(
    image: &mut Image,
    left: u32,
    scale: &Scale,
    (unit, below, above): (&str, bool, bool),
) {
    let (width, height) = (image.width, image.height);
    for y in 0..height {
        for x in left..width {
            image.pixels[(y * width + x) as usize] = PAPER;
        }
    }
    let s = font_scale(height);
    let (pad, th) = (4 * s, GLYPH_H * s);
    let clip = (left, width);
    draw_text(image, unit, (left + pad, pad), clip, s, INK);
    // The bar, top (hi) to bottom (lo), leaving half a label's height at each end.
    let (top, bottom) = (
        2 * pad + th + th / 2 + 1,
        height.saturating_sub(pad + th / 2 + 1),
    );
    if bottom <= top + 2 {
        return;
    }
    let (bx, bw) = (left + pad, 10 * s);
    let span = f64::from(bottom - top);
    for y in top..=bottom {
        let t = f64::from(bottom - y) / span;
        let c = linear(colour(t));
        for x in bx..bx + bw {
            image.pixels[(y * width + x) as usize] = c;
        }
    }
    // Its outline.
    for x in bx..bx + bw {
        image.pixels[(top * width + x) as usize] = INK;
        image.pixels[(bottom * width + x) as usize] = INK;
    }
    for y in top..=bottom {
        image.pixels[(y * width + bx) as usize] = INK;
        image.pixels[(y * width + bx + bw - 1) as usize] = INK;
    }
    // The labels: the ends first, then the levels between that keep clear of those drawn.
    let labels = labels(scale, below, above);
    let last = labels.len() - 1;
    let order = [0, last].into_iter().chain(1..last);
    let mut taken: Vec<u32> = Vec::new();
    for k in order {
        let (level, text) = &labels[k];
        let y = bottom - (scale.position(*level) * span).round() as u32;
        if taken.iter().any(|&t| t.abs_diff(y) < th + 2 * s) {
            continue;
        }
        taken.push(y);
        for x in bx + bw..bx + bw + 3 * s {
            for dy in 0..s {
                let row = (y + dy).saturating_sub(s / 2).min(height - 1);
                image.pixels[(row * width + x) as usize] = INK;
            }
        }
        let at = (bx + bw + 5 * s, y.saturating_sub(th / 2));
        draw_text(image, text, at, clip, s, INK);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::scale::Spacing;

    fn ramp(width: u32, height: u32) -> Measurement {
        let values = (0..width * height)
            .map(|k| {
                let x = k % width;
                (x > 0).then(|| 10.0 * f64::from(x))
            })
            .collect();
        Measurement {
            quantity: Quantity::Lux,
            width,
            height,
            values,
        }
    }

    /// Each pixel takes its value's colour exactly (as 8-bit codes after encoding), pixels
    /// without a value are black, and the legend strip beside them holds the unit, the bar
    /// (the scale's colours from its top to its bottom) and ink for the labels.
    #[test]
    fn the_picture_colours_each_value_and_carries_its_legend() {
        let m = ramp(40, 300);
        let scale = Scale::new(10.0, 400.0, Spacing::Log).unwrap();
        let picture = m.picture(&scale);
        let strip = legend_width(300, &scale);
        assert_eq!((picture.width, picture.height), (40 + strip, 300));
        let code = |p: Rgb| [p.x, p.y, p.z].map(crate::render::tonemap::encode_srgb8);
        assert_eq!(code(picture.get(0, 5)), [0, 0, 0], "no value: black");
        for x in [1, 7, 39] {
            let want = scale.colour(10.0 * f64::from(x));
            assert_eq!(code(picture.get(x, 100)), want, "column {x}");
        }
        // The bar: its middle row is the middle of the colour map.
        let s = font_scale(300);
        let (top, bottom) = (8 * s + 7 * s + 7 * s / 2 + 1, 300 - 4 * s - 7 * s / 2 - 1);
        let middle = (top + bottom) / 2;
        let bar = 40 + 4 * s + 5 * s;
        let t = f64::from(bottom - middle) / f64::from(bottom - top);
        assert_eq!(code(picture.get(bar, middle)), colour(t));
        // Ink in the strip: the unit at its top, the labels beside the bar.
        let ink = |x0: u32, x1: u32, y0: u32, y1: u32| {
            (y0..y1).any(|y| (x0..x1).any(|x| picture.get(x, y) == INK))
        };
        assert!(ink(40, 40 + strip, 0, 4 * s + 7 * s), "the unit");
        assert!(
            ink(
                bar + 12 * s,
                40 + strip,
                top.saturating_sub(7 * s),
                top + 7 * s
            ),
            "top label"
        );
        assert!(
            ink(bar + 12 * s, 40 + strip, bottom - 7 * s, bottom + 7 * s),
            "bottom label"
        );
    }

    #[test]
    fn the_labels_name_the_ends_and_mark_values_beyond_them() {
        let scale = Scale::new(20.0, 1000.0, Spacing::Log).unwrap();
        let texts: Vec<String> = labels(&scale, true, true)
            .into_iter()
            .map(|l| l.1)
            .collect();
        assert_eq!(texts, ["≤20", "50", "100", "200", "500", "≥1000"]);
        let texts: Vec<String> = labels(&scale, false, false)
            .into_iter()
            .map(|l| l.1)
            .collect();
        assert_eq!(texts.first().map(String::as_str), Some("20"));
    }

    #[test]
    fn the_data_image_holds_the_values() {
        let m = ramp(4, 2);
        let data = m.data();
        assert_eq!(data.get(0, 1), Rgb::ZERO);
        assert_eq!(data.get(3, 0), Rgb::splat(30.0));
        assert_eq!(m.seen().count(), 6);
        assert_eq!(m.get(2, 1), Some(20.0));
    }
}
