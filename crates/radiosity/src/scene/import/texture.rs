//! Texture images as a radiosity patch sees them: the mean reflectance over the image.
//!
//! A radiosity element has one reflectance ρ, so a textured material enters the solve with the
//! texture's mean, taken in linear RGB: 8- and 16-bit images are sRGB-encoded by convention
//! (IEC 61966-2-1) and decoded first unless they are declared raw (data such as masks), as
//! Mitsuba's `bitmap` (`raw = false`) and glTF's `baseColorTexture` do. PNG and JPEG are read
//! through the `image` crate; the alpha channel is ignored.

use std::path::Path;

use crate::scene::import::mitsuba::xml::srgb_to_linear;
use crate::Rgb;

/// The mean linear RGB of the image at `path` (`raw`: the stored values are already linear).
///
/// # Errors
/// The file cannot be read or decoded; the message names the cause (the caller names the
/// file).
pub fn mean_rgb(path: &Path, raw: bool) -> Result<Rgb, String> {
    let image = image::ImageReader::open(path)
        .map_err(|e| format!("cannot read: {e}"))?
        .with_guessed_format()
        .map_err(|e| format!("cannot read: {e}"))?
        .decode()
        .map_err(|e| format!("cannot decode: {e}"))?;
    let rgb = image.to_rgb16();
    // Decode through a table: 65 536 entries once instead of a power per texel.
    let table: Vec<f64> = (0..=u16::MAX)
        .map(|v| {
            let c = f64::from(v) / f64::from(u16::MAX);
            if raw {
                c
            } else {
                srgb_to_linear(c)
            }
        })
        .collect();
    let mut sum = Rgb::ZERO;
    for p in rgb.pixels() {
        sum += Rgb::new(
            table[usize::from(p[0])],
            table[usize::from(p[1])],
            table[usize::from(p[2])],
        );
    }
    let n = f64::from(rgb.width()) * f64::from(rgb.height());
    if n == 0.0 {
        return Err("the image is empty".into());
    }
    Ok(sum / n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_half_black_half_white_png_averages_in_linear_light() {
        let dir = std::env::temp_dir().join(format!("radiosity-texture-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("checker.png");
        let img = image::RgbImage::from_fn(4, 2, |x, _| {
            if x < 2 {
                image::Rgb([255, 255, 255])
            } else {
                image::Rgb([0, 0, 0])
            }
        });
        img.save(&path).unwrap();
        let mean = mean_rgb(&path, false).unwrap();
        assert!((mean - Rgb::splat(0.5)).length() < 1e-12, "{mean}");
        // sRGB 128 is linear 0.2158; read raw it is 128/255.
        image::RgbImage::from_pixel(2, 2, image::Rgb([128, 128, 128]))
            .save(&path)
            .unwrap();
        assert!((mean_rgb(&path, false).unwrap().x - 0.215_861).abs() < 1e-4);
        assert!((mean_rgb(&path, true).unwrap().x - 128.0 / 255.0).abs() < 1e-4);
        assert!(mean_rgb(&dir.join("missing.png"), false).is_err());
        std::fs::remove_dir_all(&dir).ok();
    }
}
