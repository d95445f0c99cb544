//! Reading radiance images: OpenEXR, Radiance HDR, PFM and PNG, for environment maps and
//! reference pictures.
//!
//! [`read_image`] picks the reader from the extension (case-insensitive):
//!
//! | extension | what is read | reference |
//! |---|---|---|
//! | `.exr` | the R, G, B channels of the first layer (any pixel type, alpha ignored) | OpenEXR |
//! | `.hdr`, `.pic` | RGBE pixels, flat or run-length encoded (old and new schemes); the usual `-Y h +X w` orientation only; `EXPOSURE` lines ignored | Ward 1991, "Real pixels" |
//! | `.pfm` | `PF` colour or `Pf` grey, either byte order, rows bottom to top | Portable Float Map |
//! | `.png` | 8- or 16-bit grey or RGB (alpha ignored), decoded from sRGB to linear | PNG 3rd ed. |
//!
//! An RGBE pixel (m_r, m_g, m_b, e) decodes to m·2^(e−136) (e = 0: black), the decoding of
//! Walter's `rgbe.c` that Mitsuba uses, so a map reads here as Mitsuba reads it.

use std::io::{self, BufRead, BufReader, Read};
use std::path::Path;

use super::ImageError;
use crate::color::srgb_to_linear;
use crate::render::Image;
use crate::Rgb;

/// Reads the image at `path` as linear radiance, in the format of its extension (module docs).
///
/// # Errors
/// [`ImageError::UnsupportedExtension`] for any other extension, [`ImageError::Io`] if the file
/// cannot be read, [`ImageError::Format`] if it is not a valid image of its format.
pub fn read_image(path: &Path) -> Result<Image, ImageError> {
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let format = |reason: String| ImageError::Format {
        path: path.to_path_buf(),
        reason,
    };
    let open = || {
        std::fs::File::open(path)
            .map(BufReader::new)
            .map_err(|cause| ImageError::Io {
                path: path.to_path_buf(),
                cause,
            })
    };
    match extension.as_str() {
        "exr" => read_exr(path).map_err(|e| io_or_format(path, e)),
        "hdr" | "pic" => parse_hdr(&mut open()?).map_err(|e| io_or_format(path, e)),
        "pfm" => read_pfm(path),
        "png" => parse_png(open()?).map_err(format),
        _ => Err(ImageError::UnsupportedExtension {
            path: path.to_path_buf(),
            extension,
        }),
    }
}

/// A reader's failure: the file system's, or the content's.
enum Failure {
    Io(io::Error),
    Format(String),
}

impl From<io::Error> for Failure {
    fn from(e: io::Error) -> Self {
        if e.kind() == io::ErrorKind::UnexpectedEof {
            Self::Format("truncated file".into())
        } else {
            Self::Io(e)
        }
    }
}

fn io_or_format(path: &Path, failure: Failure) -> ImageError {
    match failure {
        Failure::Io(cause) => ImageError::Io {
            path: path.to_path_buf(),
            cause,
        },
        Failure::Format(reason) => ImageError::Format {
            path: path.to_path_buf(),
            reason,
        },
    }
}

/// The RGB channels of the first layer of an OpenEXR file.
fn read_exr(path: &Path) -> Result<Image, Failure> {
    use exr::prelude::read_first_rgba_layer_from_file;
    let read = read_first_rgba_layer_from_file(
        path,
        |size, _| Image::new(size.width() as u32, size.height() as u32),
        |img: &mut Image, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            let i = pos.y() * img.width as usize + pos.x();
            img.pixels[i] = Rgb::new(r.into(), g.into(), b.into());
        },
    )
    .map_err(|e| match e {
        exr::error::Error::Io(cause) => Failure::from(cause),
        other => Failure::Format(other.to_string()),
    })?;
    Ok(read.layer_data.channel_data.pixels)
}

/// Radiance HDR: a header of lines ending at an empty one, the resolution line, then one
/// scanline per row from the top, each flat, old-style run-length or new-style run-length.
fn parse_hdr(r: &mut impl BufRead) -> Result<Image, Failure> {
    let bad = |s: &str| Failure::Format(s.into());
    let mut line = String::new();
    let mut first = true;
    loop {
        line.clear();
        if r.read_line(&mut line)? == 0 {
            return Err(bad("truncated header"));
        }
        if first && !line.starts_with("#?") {
            return Err(bad("not a Radiance HDR file (no #? line)"));
        }
        first = false;
        let l = line.trim();
        if l.is_empty() {
            break;
        }
        if let Some(format) = l.strip_prefix("FORMAT=") {
            if format != "32-bit_rle_rgbe" {
                return Err(Failure::Format(format!(
                    "unsupported pixel format {format}"
                )));
            }
        }
    }
    line.clear();
    r.read_line(&mut line)?;
    let tokens: Vec<&str> = line.split_whitespace().collect();
    let (height, width) = match tokens.as_slice() {
        ["-Y", h, "+X", w] => (h.parse::<u32>(), w.parse::<u32>()),
        _ => {
            return Err(Failure::Format(format!(
                "unsupported resolution line {:?} (expected -Y h +X w)",
                line.trim()
            )))
        }
    };
    let (Ok(height), Ok(width)) = (height, width) else {
        return Err(Failure::Format(format!(
            "bad resolution line {:?}",
            line.trim()
        )));
    };
    let mut image = Image::new(width, height);
    let mut scan = vec![[0u8; 4]; width as usize];
    for row in image.pixels.chunks_mut(width.max(1) as usize) {
        read_scanline(r, &mut scan)?;
        for (p, &rgbe) in row.iter_mut().zip(&scan) {
            *p = decode_rgbe(rgbe);
        }
    }
    Ok(image)
}

/// One scanline of RGBE pixels into `scan`.
fn read_scanline(r: &mut impl BufRead, scan: &mut [[u8; 4]]) -> Result<(), Failure> {
    let width = scan.len();
    let mut first = [0u8; 4];
    r.read_exact(&mut first)?;
    let new_rle = (8..0x8000).contains(&width)
        && first[0] == 2
        && first[1] == 2
        && first[2] & 0x80 == 0
        && usize::from(first[2]) << 8 | usize::from(first[3]) == width;
    if !new_rle {
        // Flat pixels, where (1, 1, 1, n) repeats the previous pixel n << shift times.
        let mut shift = 0;
        let mut x: usize = 0;
        let mut pixel = first;
        loop {
            if pixel[..3] == [1, 1, 1] {
                let Some(&previous) = x.checked_sub(1).and_then(|p| scan.get(p)) else {
                    return Err(Failure::Format("a run before the first pixel".into()));
                };
                let n = usize::from(pixel[3]) << shift;
                if x + n > width {
                    return Err(Failure::Format("run past the end of a scanline".into()));
                }
                scan[x..x + n].fill(previous);
                x += n;
                shift += 8;
            } else {
                scan[x] = pixel;
                x += 1;
                shift = 0;
            }
            if x == width {
                return Ok(());
            }
            r.read_exact(&mut pixel)?;
        }
    }
    // New scheme: each channel separately, as runs (count > 128: one byte repeated count − 128
    // times) and dumps (count ≤ 128 literal bytes).
    for c in 0..4 {
        let mut x = 0;
        while x < width {
            let mut count = [0u8; 1];
            r.read_exact(&mut count)?;
            let count = usize::from(count[0]);
            if count > 128 {
                let n = count - 128;
                if x + n > width {
                    return Err(Failure::Format("run past the end of a scanline".into()));
                }
                let mut value = [0u8; 1];
                r.read_exact(&mut value)?;
                scan[x..x + n].iter_mut().for_each(|p| p[c] = value[0]);
                x += n;
            } else {
                if count == 0 || x + count > width {
                    return Err(Failure::Format("bad dump in a scanline".into()));
                }
                let mut values = [0u8; 128];
                r.read_exact(&mut values[..count])?;
                scan[x..x + count]
                    .iter_mut()
                    .zip(&values[..count])
                    .for_each(|(p, &v)| p[c] = v);
                x += count;
            }
        }
    }
    Ok(())
}

/// m·2^(e−136) per channel; black when e = 0.
fn decode_rgbe([r, g, b, e]: [u8; 4]) -> Rgb {
    if e == 0 {
        return Rgb::ZERO;
    }
    let f = 2f64.powi(i32::from(e) - 136);
    Rgb::new(f64::from(r), f64::from(g), f64::from(b)) * f
}

/// A PNG, expanded to 8 or 16 bits per channel, decoded from sRGB to linear.
fn parse_png(r: impl Read) -> Result<Image, String> {
    let mut decoder = png::Decoder::new(r);
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(|e| e.to_string())?;
    let mut buf = vec![0; reader.output_buffer_size()];
    let frame = reader.next_frame(&mut buf).map_err(|e| e.to_string())?;
    let channels = match frame.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        png::ColorType::Indexed => return Err("palette not expanded".into()),
    };
    let wide = frame.bit_depth == png::BitDepth::Sixteen;
    let bytes = if wide { 2 } else { 1 };
    let value = |i: usize| {
        let v = if wide {
            f64::from(u16::from_be_bytes([buf[2 * i], buf[2 * i + 1]])) / 65535.0
        } else {
            f64::from(buf[i]) / 255.0
        };
        srgb_to_linear(v)
    };
    let mut image = Image::new(frame.width, frame.height);
    for (k, p) in image.pixels.iter_mut().enumerate() {
        let y = k / frame.width as usize;
        let x = k % frame.width as usize;
        let i = (y * frame.line_size) / bytes + x * channels;
        *p = if channels < 3 {
            Rgb::splat(value(i))
        } else {
            Rgb::new(value(i), value(i + 1), value(i + 2))
        };
    }
    Ok(image)
}

/// Reads a Portable Float Map (`PF` colour or `Pf` grey, either byte order) as linear radiance.
///
/// # Errors
/// [`ImageError::Io`] if the file cannot be read, [`ImageError::Format`] if it is not a
/// complete PFM file.
pub fn read_pfm(path: &Path) -> Result<Image, ImageError> {
    let bytes = std::fs::read(path).map_err(|cause| ImageError::Io {
        path: path.to_path_buf(),
        cause,
    })?;
    parse_pfm(&bytes).map_err(|reason| ImageError::Format {
        path: path.to_path_buf(),
        reason,
    })
}

fn parse_pfm(bytes: &[u8]) -> Result<Image, String> {
    // Header: four whitespace-separated tokens, then exactly one whitespace byte.
    let mut tokens = Vec::with_capacity(4);
    let mut pos = 0;
    while tokens.len() < 4 {
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        let start = pos;
        while pos < bytes.len() && !bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if start == pos {
            return Err("truncated PFM header".into());
        }
        tokens.push(String::from_utf8_lossy(&bytes[start..pos]).into_owned());
    }
    let data = bytes.get(pos + 1..).unwrap_or_default();
    let channels = match tokens[0].as_str() {
        "PF" => 3,
        "Pf" => 1,
        other => return Err(format!("not a PFM file (magic {other:?})")),
    };
    let parse = |t: &str, what: &str| t.parse::<u32>().map_err(|_| format!("bad {what} {t:?}"));
    let width = parse(&tokens[1], "width")?;
    let height = parse(&tokens[2], "height")?;
    let scale: f32 = tokens[3]
        .parse()
        .map_err(|_| format!("bad scale {:?}", tokens[3]))?;
    if scale == 0.0 || !scale.is_finite() {
        return Err(format!("bad scale {scale}"));
    }
    let expected = width as usize * height as usize * channels * 4;
    if data.len() < expected {
        return Err(format!(
            "{} bytes of pixel data, {expected} expected for {width}×{height}",
            data.len()
        ));
    }
    let value = |i: usize| {
        let b = [
            data[4 * i],
            data[4 * i + 1],
            data[4 * i + 2],
            data[4 * i + 3],
        ];
        f64::from(if scale < 0.0 {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        })
    };
    let mut image = Image::new(width, height);
    let w = width as usize;
    for (y, row) in image.pixels.chunks_mut(w.max(1)).enumerate() {
        let file_row = height as usize - 1 - y;
        for (x, pixel) in row.iter_mut().enumerate() {
            let i = (file_row * w + x) * channels;
            *pixel = if channels == 3 {
                Rgb::new(value(i), value(i + 1), value(i + 2))
            } else {
                Rgb::splat(value(i))
            };
        }
    }
    Ok(image)
}

#[cfg(test)]
mod tests {
    use super::super::write_image;
    use super::*;
    use std::path::PathBuf;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("radiosity-read-{}", std::process::id()));
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
    fn exr_and_pfm_read_back_exactly() {
        for name in ["back.exr", "back.pfm", "BACK.PFM"] {
            let path = scratch(name);
            write_image(&path, &gradient(), 0.0).expect("write");
            assert_eq!(read_image(&path).expect("read"), gradient(), "{name}");
            std::fs::remove_file(&path).expect("cleanup");
        }
    }

    #[test]
    fn hdr_reads_back_within_a_mantissa_step() {
        let path = scratch("back.hdr");
        write_image(&path, &gradient(), 0.0).expect("write");
        let read = read_image(&path).expect("read");
        for (a, b) in read.pixels.iter().zip(&gradient().pixels) {
            // Truncated 8-bit mantissas: at most one step, 1/128 of the largest channel.
            assert!(
                (*a - *b).abs().max_element() <= b.max_element() / 128.0,
                "{a} {b}"
            );
        }
        std::fs::remove_file(&path).expect("cleanup");
    }

    #[test]
    fn hdr_run_length_scanlines_decode() {
        // Two rows of 8: the first new-style (red a run of 8 × 64, green a dump of 8 values,
        // blue a run, exponent a run of 129: 2^(129−136) = 1/128), the second flat with an
        // old-style run repeating its first pixel 7 times.
        let mut bytes = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 8\n".to_vec();
        bytes.extend([2, 2, 0, 8]);
        bytes.extend([128 + 8, 64]);
        bytes.extend([8, 0, 16, 32, 48, 64, 80, 96, 112]);
        bytes.extend([128 + 8, 0]);
        bytes.extend([128 + 8, 129]);
        bytes.extend([128, 0, 0, 130, 1, 1, 1, 7]);
        let image = parse_hdr(&mut &bytes[..]).map_err(|_| ()).expect("parse");
        assert_eq!((image.width, image.height), (8, 2));
        for x in 0..8 {
            assert_eq!(image.get(x, 0), Rgb::new(0.5, x as f64 / 8.0, 0.0));
            assert_eq!(image.get(x, 1), Rgb::new(2.0, 0.0, 0.0));
        }
    }

    #[test]
    fn png_decodes_srgb_to_linear() {
        let path = scratch("codes.png");
        let mut image = Image::new(3, 1);
        image.pixels = vec![Rgb::ZERO, Rgb::new(0.5, 0.5, 0.25), Rgb::splat(1.0)];
        write_image(&path, &image, 0.0).expect("write");
        let read = read_image(&path).expect("read");
        for (a, b) in read.pixels.iter().zip(&image.pixels) {
            // 8-bit sRGB codes: half a code step near 0.5 is about 0.2 % of the value.
            assert!((*a - *b).abs().max_element() <= 3e-3, "{a} {b}");
        }
        std::fs::remove_file(&path).expect("cleanup");
    }

    #[test]
    fn bad_files_are_named_errors() {
        for (name, bytes) in [
            ("magic.hdr", &b"P6\n"[..]),
            (
                "short.hdr",
                &b"#?RADIANCE\n\n-Y 2 +X 2\n\x10\x10\x10\x80"[..],
            ),
            ("sideways.hdr", &b"#?RADIANCE\n\n+X 2 -Y 2\n"[..]),
            ("noise.png", &b"\x89PNG but not"[..]),
            ("noise.exr", &b"not an exr"[..]),
        ] {
            let path = scratch(name);
            std::fs::write(&path, bytes).expect("seed");
            let err = read_image(&path).expect_err(name);
            assert!(matches!(err, ImageError::Format { .. }), "{name}: {err}");
            assert!(err.to_string().contains(name), "{err}");
            std::fs::remove_file(&path).expect("cleanup");
        }
        assert!(matches!(
            read_image(&scratch("picture.bmp")),
            Err(ImageError::UnsupportedExtension { .. })
        ));
        assert!(matches!(
            read_image(&scratch("missing.hdr")),
            Err(ImageError::Io { .. })
        ));
    }

    #[test]
    fn bad_pfm_files_are_format_errors() {
        for (name, bytes) in [
            ("magic.pfm", &b"P6\n1 1\n255\n\0\0\0"[..]),
            ("short.pfm", &b"PF\n2 2\n-1.0\n\0\0\0\0"[..]),
            ("header.pfm", &b"PF\n2"[..]),
        ] {
            let path = scratch(name);
            std::fs::write(&path, bytes).expect("seed");
            assert!(
                matches!(read_pfm(&path), Err(ImageError::Format { .. })),
                "{name}"
            );
            std::fs::remove_file(&path).expect("cleanup");
        }
    }
}
