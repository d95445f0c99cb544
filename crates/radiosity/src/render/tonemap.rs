//! Tone mapping: from linear radiance to 8-bit sRGB.
//!
//! An exposure of `stops` multiplies radiance by 2^stops; the result is clamped to [0, 1] and
//! encoded with the sRGB transfer function (IEC 61966-2-1):
//!
//! V = 12.92·L for L ≤ 0.003 130 8, V = 1.055·L^(1/2.4) − 0.055 otherwise,
//!
//! then quantized to round(255·V).
//!
//! [`auto_exposure`] follows Reinhard et al. 2002, "Photographic tone reproduction for digital
//! images": the scene's *key* is the log-average luminance L̄ = exp(mean ln(δ + L_w)) over the
//! pixels that see something (L_w > 0), and the exposure maps it to middle grey, 0.18:
//! stops = log₂(0.18 / L̄). Bright emitters then clip to white while diffuse surfaces sit in
//! the middle of the range — in the Cornell box, the light (radiance 17, 12, 4) is white and
//! the walls are mid-grey.

use super::image::Image;
use crate::color::luminance;
use crate::Rgb;

/// Middle grey: where [`auto_exposure`] puts the image's log-average luminance.
pub const MIDDLE_GREY: f64 = 0.18;
/// Offset δ inside the logarithm, guarding against tiny luminances.
const LOG_DELTA: f64 = 1e-6;

/// The radiance multiplier of an exposure of `stops`: 2^stops.
#[must_use]
pub fn exposure_scale(stops: f32) -> f64 {
    f64::from(stops).exp2()
}

/// The sRGB transfer function of a linear value, with the input clamped to [0, 1] (NaN → 0);
/// its inverse is [`crate::color::srgb_to_linear`].
#[must_use]
pub fn linear_to_srgb(linear: f64) -> f64 {
    let l = if linear.is_nan() {
        0.0
    } else {
        linear.clamp(0.0, 1.0)
    };
    if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

/// A linear value encoded as an 8-bit sRGB code: round(255 · srgb(clamp(v, 0, 1))).
#[must_use]
pub fn encode_srgb8(linear: f64) -> u8 {
    (255.0 * linear_to_srgb(linear)).round() as u8
}

/// A radiance value exposed by `scale` and encoded as 8-bit sRGB per channel.
#[must_use]
pub fn tonemap_pixel(radiance: Rgb, scale: f64) -> [u8; 3] {
    let c = radiance * scale;
    [encode_srgb8(c.x), encode_srgb8(c.y), encode_srgb8(c.z)]
}

/// The image exposed by `stops` and encoded as 8-bit sRGB, three bytes per pixel, row-major.
#[must_use]
pub fn to_srgb8(image: &Image, stops: f32) -> Vec<u8> {
    let scale = exposure_scale(stops);
    image
        .pixels
        .iter()
        .flat_map(|&c| tonemap_pixel(c, scale))
        .collect()
}

/// The exposure, in stops, that maps the log-average luminance of the image's non-black
/// pixels to [`MIDDLE_GREY`] (Reinhard et al. 2002). An image without any lit pixel gets 0.
#[must_use]
pub fn auto_exposure(image: &Image) -> f32 {
    let (sum, count) = image
        .pixels
        .iter()
        .map(|&c| luminance(c))
        .filter(|l| l.is_finite() && *l > 0.0)
        .fold((0.0, 0usize), |(sum, n), l| {
            (sum + (LOG_DELTA + l).ln(), n + 1)
        });
    if count == 0 {
        return 0.0;
    }
    let key = (sum / count as f64).exp();
    (MIDDLE_GREY / key).log2() as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::srgb_to_linear;

    #[test]
    fn srgb_codes_of_known_values() {
        assert_eq!(encode_srgb8(0.0), 0);
        assert_eq!(encode_srgb8(1.0), 255);
        // srgb(0.5) = 1.055 · 0.5^(1/2.4) − 0.055 = 0.7354 → 187.5 → 188.
        assert_eq!(encode_srgb8(0.5), 188);
        // 0.18 (middle grey) → 0.4614 → 118.
        assert_eq!(encode_srgb8(0.18), 118);
        assert_eq!(encode_srgb8(-3.0), 0);
        assert_eq!(encode_srgb8(7.0), 255);
        assert_eq!(encode_srgb8(f64::NAN), 0);
        // The two branches meet at the threshold (continuity to 1e-7).
        let t = 0.003_130_8;
        assert!((12.92 * t - (1.055 * f64::powf(t, 1.0 / 2.4) - 0.055)).abs() < 1e-7);
    }

    /// Every 8-bit code survives decoding to linear and encoding back: an image of linear
    /// colours written at exposure 0 holds exactly the codes it was made from.
    #[test]
    fn srgb_codes_round_trip_through_linear() {
        for code in 0..=255u8 {
            let linear = srgb_to_linear(f64::from(code) / 255.0);
            assert_eq!(encode_srgb8(linear), code);
        }
    }

    #[test]
    fn exposure_doubles_per_stop() {
        assert_eq!(exposure_scale(0.0), 1.0);
        assert_eq!(exposure_scale(1.0), 2.0);
        assert_eq!(exposure_scale(-2.0), 0.25);
        let mut image = Image::new(1, 1);
        image.pixels[0] = Rgb::new(0.25, 0.5, 1.0);
        assert_eq!(to_srgb8(&image, 1.0), vec![188, 255, 255]);
    }

    #[test]
    fn auto_exposure_maps_log_average_to_middle_grey() {
        // Grey pixels of luminance 0.01 and 1 (log-average 0.1) plus black background.
        let mut image = Image::new(4, 1);
        image.pixels[0] = Rgb::splat(0.01);
        image.pixels[1] = Rgb::splat(1.0);
        let stops = auto_exposure(&image);
        let key = ((LOG_DELTA + 0.01f64).ln() / 2.0 + (LOG_DELTA + 1.0f64).ln() / 2.0).exp();
        // f32 stops: relative error of the scaled key ~1e-7.
        assert!((key * exposure_scale(stops) - MIDDLE_GREY).abs() < 1e-6);
        assert!((f64::from(stops) - 0.18f64.log2() + 0.1f64.log2()).abs() < 1e-4);
        assert_eq!(auto_exposure(&Image::new(3, 3)), 0.0);
    }
}
