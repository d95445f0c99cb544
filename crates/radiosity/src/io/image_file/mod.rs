//! Image files: tone-mapped PNG and linear-radiance PFM, OpenEXR and Radiance HDR; [`read`]
//! reads them back (and environment maps) as linear radiance.
//!
//! [`write_image`] picks the format from the extension:
//!
//! | extension | content | reference |
//! |---|---|---|
//! | `.png` | 8-bit sRGB after exposure ([`crate::render::tonemap`]), with an sRGB chunk | PNG 3rd ed. |
//! | `.pfm` | linear f32 RGB, little-endian (scale −1.0), rows bottom to top | Portable Float Map |
//! | `.exr` | linear f32 RGB | OpenEXR |
//! | `.hdr` | linear RGBE (shared-exponent 8-bit mantissas), flat scanlines | Ward 1991, "Real pixels" |
//!
//! Float formats hold radiance unscaled (the exposure applies to PNG only), so they compare
//! directly with a path tracer's output. Every file goes through [`write_atomic`]: a failed
//! write leaves no partial file.

use std::io::{self, Cursor, Write};
use std::path::{Path, PathBuf};

pub mod read;

pub use read::{read_image, read_pfm};

use super::atomic::write_atomic;
use crate::render::{tonemap, Image};
use crate::Rgb;

/// An error writing or reading an image file; every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The extension names no supported format.
    #[error("{}: unsupported image extension {extension:?} (expected .png, .exr, .hdr or .pfm)", path.display())]
    UnsupportedExtension {
        /// The file.
        path: PathBuf,
        /// Its extension (empty when it has none).
        extension: String,
    },
    /// The file system or an encoder failed. The cause is part of the message, not a separate
    /// source, so a chain printer (anyhow's `{:#}`) says it once.
    #[error("{}: {cause}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        cause: io::Error,
    },
    /// A file read back is not a valid image of its format.
    #[error("{}: {reason}", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
}

/// Writes `image` to `path` in the format of its extension (case-insensitive): `.png`
/// tone-mapped with an exposure of `exposure_stops`, or `.pfm`, `.exr`, `.hdr` as linear
/// radiance (the exposure is not applied to them).
///
/// # Errors
/// [`ImageError::UnsupportedExtension`] for any other extension, [`ImageError::Io`] if writing
/// fails; no file is left behind then.
pub fn write_image(path: &Path, image: &Image, exposure_stops: f32) -> Result<(), ImageError> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let io_error = |cause| ImageError::Io {
        path: path.to_path_buf(),
        cause,
    };
    match extension.as_str() {
        "png" => write_atomic(path, |w| write_png(w, image, exposure_stops)).map_err(io_error),
        "pfm" => write_atomic(path, |w| write_pfm(w, image)).map_err(io_error),
        "hdr" => write_atomic(path, |w| write_hdr(w, image)).map_err(io_error),
        "exr" => {
            let bytes = encode_exr(image).map_err(io_error)?;
            write_atomic(path, |w| w.write_all(&bytes)).map_err(io_error)
        }
        _ => Err(ImageError::UnsupportedExtension {
            path: path.to_path_buf(),
            extension,
        }),
    }
}

/// 8-bit sRGB RGB PNG of the exposed image.
fn write_png(w: &mut dyn Write, image: &Image, stops: f32) -> io::Result<()> {
    let mut encoder = png::Encoder::new(w, image.width, image.height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let mut writer = encoder.write_header().map_err(io::Error::other)?;
    writer
        .write_image_data(&tonemap::to_srgb8(image, stops))
        .map_err(io::Error::other)?;
    writer.finish().map_err(io::Error::other)
}

/// Portable Float Map: `PF\n{w} {h}\n-1.0\n`, then little-endian f32 RGB, bottom row first.
fn write_pfm(w: &mut dyn Write, image: &Image) -> io::Result<()> {
    write!(w, "PF\n{} {}\n-1.0\n", image.width, image.height)?;
    let width = image.width as usize;
    let mut row_bytes = Vec::with_capacity(width * 12);
    for row in image.pixels.chunks(width.max(1)).rev() {
        row_bytes.clear();
        for c in row {
            for v in c.to_array() {
                row_bytes.extend_from_slice(&(v as f32).to_le_bytes());
            }
        }
        w.write_all(&row_bytes)?;
    }
    Ok(())
}

/// Radiance HDR with flat (not run-length encoded) RGBE scanlines, top row first.
fn write_hdr(w: &mut dyn Write, image: &Image) -> io::Result<()> {
    write!(
        w,
        "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {} +X {}\n",
        image.height, image.width
    )?;
    let bytes: Vec<u8> = image.pixels.iter().flat_map(|&c| rgbe(c)).collect();
    w.write_all(&bytes)
}

/// Ward's shared-exponent encoding: mantissas m = ⌊c · 256 / 2^e⌋ with 2^(e−1) ≤ max c < 2^e,
/// exponent byte e + 128. Negative and NaN channels count as 0; values below 2⁻¹²⁰ as black.
/// The largest channel's mantissa lies in [128, 256), so a flat scanline never starts with
/// the (2, 2, <128) marker of a run-length encoded one.
fn rgbe(c: Rgb) -> [u8; 4] {
    let c = c
        .to_array()
        .map(|v| if v > 0.0 { v.min(1e38) } else { 0.0 });
    let max = c[0].max(c[1]).max(c[2]);
    if max < 2f64.powi(-120) {
        return [0; 4];
    }
    let mut e = max.log2().floor() as i32 + 1;
    // Guard the floor against rounding: 2^(e−1) ≤ max < 2^e.
    if max >= 2f64.powi(e) {
        e += 1;
    } else if max < 2f64.powi(e - 1) {
        e -= 1;
    }
    let scale = 256.0 / 2f64.powi(e);
    [
        (c[0] * scale) as u8,
        (c[1] * scale) as u8,
        (c[2] * scale) as u8,
        (e + 128) as u8,
    ]
}

/// OpenEXR, linear f32 RGB, encoded in memory (the encoder needs to seek).
fn encode_exr(image: &Image) -> io::Result<Vec<u8>> {
    use exr::prelude::{SpecificChannels, Vec2, WritableImage};
    let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
        let c = image.pixels[y * image.width as usize + x];
        (c.x as f32, c.y as f32, c.z as f32)
    });
    let exr_image =
        exr::image::Image::from_channels((image.width as usize, image.height as usize), channels);
    let mut bytes = Cursor::new(Vec::new());
    exr_image
        .write()
        .to_buffered(&mut bytes)
        .map_err(io::Error::other)?;
    Ok(bytes.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_io_error_says_its_cause_once() {
        let err = write_image(Path::new("/sys/radiosity.png"), &Image::new(1, 1), 0.0)
            .expect_err("/sys takes no files");
        // The cause is in the message and not repeated as a source, which a chain printer
        // would append a second time.
        assert!(std::error::Error::source(&err).is_none());
        assert!(err.to_string().starts_with("/sys/radiosity.png: "), "{err}");
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("radiosity-image-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("scratch dir");
        dir.join(name)
    }

    /// A 5×3 image with distinct, f32-representable values in every channel.
    fn gradient() -> Image {
        let mut image = Image::new(5, 3);
        for (i, p) in image.pixels.iter_mut().enumerate() {
            let i = i as f64;
            *p = Rgb::new(i * 0.25, 100.0 - i, 1.0 / 1024.0 * i);
        }
        image
    }

    #[test]
    fn pfm_round_trip_is_exact_and_bottom_up() {
        let path = scratch("round.pfm");
        let image = gradient();
        write_image(&path, &image, 3.0).expect("write");
        let bytes = std::fs::read(&path).expect("bytes");
        assert!(bytes.starts_with(b"PF\n5 3\n-1.0\n"));
        // The first stored pixel is the bottom-left one, (0, 2) = pixel 10.
        let first = f32::from_le_bytes(bytes[12..16].try_into().expect("4 bytes"));
        assert_eq!(f64::from(first), image.get(0, 2).x);
        assert_eq!(read_pfm(&path).expect("read"), image);
        std::fs::remove_file(&path).expect("cleanup");
    }

    #[test]
    fn exr_round_trip_is_exact() {
        use exr::prelude::read_first_rgba_layer_from_file;
        let path = scratch("round.exr");
        let image = gradient();
        write_image(&path, &image, 0.0).expect("write");
        let read = read_first_rgba_layer_from_file(
            &path,
            |size, _| Image::new(size.width() as u32, size.height() as u32),
            |img: &mut Image, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
                let i = pos.y() * img.width as usize + pos.x();
                img.pixels[i] = Rgb::new(r.into(), g.into(), b.into());
            },
        )
        .expect("read exr");
        assert_eq!(read.layer_data.channel_data.pixels, image);
        std::fs::remove_file(&path).expect("cleanup");
    }

    #[test]
    fn png_holds_exposed_srgb_codes() {
        let path = scratch("codes.png");
        let mut image = Image::new(3, 1);
        image.pixels = vec![Rgb::ZERO, Rgb::new(0.5, 0.5, 0.25), Rgb::splat(2.0)];
        // One stop of exposure: 0.25 → 0.5 → 188, 0.5 → 1.0 → 255, 2 → 4 → 255.
        write_image(&path, &image, 1.0).expect("write");
        let decoder = png::Decoder::new(std::fs::File::open(&path).expect("open"));
        let mut reader = decoder.read_info().expect("info");
        assert!(reader.info().srgb.is_some(), "sRGB chunk");
        let mut buf = vec![0; reader.output_buffer_size()];
        let frame = reader.next_frame(&mut buf).expect("frame");
        assert_eq!((frame.width, frame.height), (3, 1));
        assert_eq!(&buf[..9], &[0, 0, 0, 255, 255, 188, 255, 255, 255]);
        std::fs::remove_file(&path).expect("cleanup");
    }

    #[test]
    fn hdr_rgbe_decodes_within_mantissa_precision() {
        let path = scratch("round.hdr");
        let image = gradient();
        write_image(&path, &image, 0.0).expect("write");
        let bytes = std::fs::read(&path).expect("bytes");
        let header = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 3 +X 5\n";
        assert!(bytes.starts_with(header));
        let data = &bytes[header.len()..];
        assert_eq!(data.len(), 15 * 4);
        for (p, &c) in data.chunks(4).zip(&image.pixels) {
            // Ward's decoder: (m + 0.5) · 2^(e − 136); error ≤ half a step of 2^e/256, i.e.
            // at most 1/256 of the largest channel.
            let decode = |m: u8| (f64::from(m) + 0.5) * 2f64.powi(i32::from(p[3]) - 136);
            let max = c.max_element();
            for (m, v) in p[..3].iter().zip(c.to_array()) {
                assert!((decode(*m) - v).abs() <= max / 256.0, "{m} vs {v}");
            }
        }
        assert_eq!(rgbe(Rgb::ZERO), [0; 4]);
        assert_eq!(rgbe(Rgb::new(1.0, 0.5, -1.0)), [128, 64, 0, 129]);
        std::fs::remove_file(&path).expect("cleanup");
    }

    #[test]
    fn unknown_extension_is_named_and_writes_nothing() {
        let path = scratch("picture.bmp");
        let err = write_image(&path, &gradient(), 0.0).expect_err("bmp");
        assert!(err.to_string().contains("\"bmp\""), "{err}");
        assert!(!path.exists());
        assert!(matches!(
            write_image(&scratch("noext"), &gradient(), 0.0),
            Err(ImageError::UnsupportedExtension { .. })
        ));
    }
}
