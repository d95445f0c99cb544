//! Textures as reflectance: an image of albedo laid over a surface by its texture coordinates.
//!
//! A textured material's reflectance varies over a surface as ρ(x) = f · t(uv(x)), the factor f
//! (glTF `baseColorFactor`) times the texture t at the point's texture coordinates. A
//! radiosity patch has one reflectance, so the solve gives each polygon its area mean
//!
//! ρ_P = f · (1/A_P) ∫_P t(uv(x)) dA(x),
//!
//! clamped to [`MAX_REFLECTANCE`] per channel ([`TextureMap::mean_over`]). A polygon is fanned
//! from its first corner; over each triangle uv is affine, so the mean over its area is the
//! mean over its footprint in texture space, taken exactly (`footprint.rs`). The triangles'
//! means are weighted by their areas. A polygon without texture coordinates takes the mean of
//! the whole image ([`TextureMap::mean`]), which is also the material's
//! [`crate::scene::Material::reflectance`] (what the renderers see).
//!
//! Conventions:
//!
//! - texels are linear RGB: 8- and 16-bit images are sRGB-encoded by convention
//!   (IEC 61966-2-1) and decoded ([`crate::color::srgb_to_linear`]) unless declared raw (data
//!   such as masks, Mitsuba's `raw = true`). PNG and JPEG are read through the `image` crate;
//!   the alpha channel is ignored;
//! - texture coordinates put (0, 0) at the image's top-left corner, u to the right and v down
//!   (glTF's convention; OBJ's `vt`, whose v points up, is flipped when read);
//! - texel (i, j) covers [i, i+1) × [j, j+1) in texel coordinates (u·W, v·H) and is constant
//!   there (nearest filtering), so a mean is a sum of texels weighted by covered area;
//! - outside [0, 1] the [`Wrap`] mode of each axis applies, `REPEAT` by default (glTF
//!   samplers, §5.26).

use std::path::Path;
use std::sync::Arc;

use glam::{DVec2, Vec2, Vec3};

use crate::color::srgb_to_linear;
use crate::scene::MAX_REFLECTANCE;
use crate::Rgb;

mod footprint;

/// A decoded image of linear RGB values.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    width: usize,
    height: usize,
    /// 16-bit codes, row by row from the top.
    codes: Vec<[u16; 3]>,
    /// The linear value of each code.
    decode: Vec<f64>,
    /// The sum of each row, for runs of whole periods.
    row_sums: Vec<Rgb>,
}

impl Texture {
    /// Reads and decodes the image at `path` (`raw`: the stored values are already linear).
    ///
    /// # Errors
    /// The file cannot be read or decoded; the message names the cause (the caller names the
    /// file).
    pub fn open(path: &Path, raw: bool) -> Result<Self, String> {
        let bytes = std::fs::read(path).map_err(|e| format!("cannot read: {e}"))?;
        Self::decode(&bytes, raw)
    }

    /// Decodes a PNG or JPEG image held in memory (`raw` as in [`Texture::open`]).
    ///
    /// # Errors
    /// The bytes are not an image of a supported format, or the image is empty.
    pub fn decode(bytes: &[u8], raw: bool) -> Result<Self, String> {
        let image = image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| format!("cannot read: {e}"))?
            .decode()
            .map_err(|e| format!("cannot decode: {e}"))?
            .into_rgb16();
        let (width, height) = (image.width() as usize, image.height() as usize);
        if width == 0 || height == 0 {
            return Err("the image is empty".into());
        }
        // Decode through a table: 65 536 entries once instead of a power per texel.
        let decode: Vec<f64> = (0..=u16::MAX)
            .map(|v| {
                let c = f64::from(v) / f64::from(u16::MAX);
                if raw {
                    c
                } else {
                    srgb_to_linear(c)
                }
            })
            .collect();
        let codes: Vec<[u16; 3]> = image.pixels().map(|p| p.0).collect();
        let mut texture = Self {
            width,
            height,
            codes,
            decode,
            row_sums: Vec::new(),
        };
        texture.row_sums = (0..height)
            .map(|j| (0..width).map(|i| texture.texel(i, j)).sum())
            .collect();
        Ok(texture)
    }

    /// The image's width and height in texels.
    #[must_use]
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The linear value of texel (i, j), column i from the left, row j from the top.
    ///
    /// # Panics
    /// If (i, j) is outside the image.
    #[must_use]
    pub fn texel(&self, i: usize, j: usize) -> Rgb {
        let [r, g, b] = self.codes[j * self.width + i];
        Rgb::new(
            self.decode[usize::from(r)],
            self.decode[usize::from(g)],
            self.decode[usize::from(b)],
        )
    }

    /// The mean of the whole image.
    #[must_use]
    pub fn mean(&self) -> Rgb {
        self.row_sums.iter().sum::<Rgb>() / (self.width * self.height) as f64
    }
}

/// What happens outside [0, 1] along one texture axis (glTF sampler `wrapS`/`wrapT`; MTL
/// `-clamp on` is [`Wrap::ClampToEdge`] on both).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// The image repeats.
    #[default]
    Repeat,
    /// The image repeats, every other copy mirrored.
    MirroredRepeat,
    /// The edge texels extend outward.
    ClampToEdge,
}

impl Wrap {
    /// The texel index in 0..n of cell index `i`.
    fn index(self, i: i64, n: usize) -> usize {
        let n = n as i64;
        let k = match self {
            Self::Repeat => i.rem_euclid(n),
            Self::MirroredRepeat => {
                let m = i.rem_euclid(2 * n);
                if m < n {
                    m
                } else {
                    2 * n - 1 - m
                }
            }
            Self::ClampToEdge => i.clamp(0, n - 1),
        };
        k as usize
    }
}

/// A material's texture: ρ(uv) = `factor` × the texture at uv, with a wrap mode per axis.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureMap {
    /// The image, shared by the materials that use it.
    pub texture: Arc<Texture>,
    /// The wrap modes along u and v.
    pub wrap: [Wrap; 2],
    /// The factor every texel is multiplied by.
    pub factor: Rgb,
}

/// Footprints spanning more rows or columns than this many texels (UVs far outside [0, 1])
/// take the whole image's mean, which is what a repeating texture tends to over them.
const MAX_SPAN: f64 = 65_536.0;

impl TextureMap {
    /// The reflectance over the whole image: factor × mean, clamped to [`MAX_REFLECTANCE`].
    #[must_use]
    pub fn mean(&self) -> Rgb {
        clamped(self.factor * self.texture.mean())
    }

    /// The reflectance of a polygon with corners `vertices` and texture coordinates `uv` (one
    /// per corner): the area mean of factor × texture over it (module docs), clamped to
    /// [`MAX_REFLECTANCE`]. Without one coordinate per corner, or for a polygon of no area,
    /// [`TextureMap::mean`].
    #[must_use]
    pub fn mean_over(&self, vertices: &[Vec3], uv: &[Vec2]) -> Rgb {
        if uv.len() != vertices.len() || uv.len() < 3 {
            return self.mean();
        }
        let (mut sum, mut weight) = (Rgb::ZERO, 0.0);
        for k in 1..vertices.len() - 1 {
            let (a, b, c) = (vertices[0], vertices[k], vertices[k + 1]);
            let area = 0.5 * f64::from((b - a).cross(c - a).length());
            if area > 0.0 {
                sum += area * self.triangle_mean([uv[0], uv[k], uv[k + 1]]);
                weight += area;
            }
        }
        if weight > 0.0 {
            clamped(self.factor * sum / weight)
        } else {
            self.mean()
        }
    }

    /// The texture's mean over a triangle of texture coordinates (before the factor). A
    /// footprint of no area (a face mapped to one spot of a palette) takes the texel at its
    /// centroid.
    fn triangle_mean(&self, uv: [Vec2; 3]) -> Rgb {
        let (w, h) = self.texture.size();
        let t = uv.map(|p| DVec2::new(f64::from(p.x) * w as f64, f64::from(p.y) * h as f64));
        let lo = t[0].min(t[1]).min(t[2]);
        let hi = t[0].max(t[1]).max(t[2]);
        if !(lo.is_finite() && hi.is_finite()) || (hi - lo).max_element() > MAX_SPAN {
            return self.texture.mean();
        }
        if footprint::polygon_area(&t) < 1e-9 {
            let c = (t[0] + t[1] + t[2]) / 3.0;
            return self.texel(c.x.floor() as i64, c.y.floor() as i64);
        }
        let (sum, area) = footprint::triangle_integral(
            t,
            |i, j| self.texel(i, j),
            |j, i0, i1| self.run(j, i0, i1),
        );
        sum / area
    }

    /// The texel of cell (i, j), wrapped.
    fn texel(&self, i: i64, j: i64) -> Rgb {
        let (w, h) = self.texture.size();
        self.texture
            .texel(self.wrap[0].index(i, w), self.wrap[1].index(j, h))
    }

    /// The sum of cells i0..i1 of row j, wrapped: whole periods from the row's total.
    fn run(&self, j: i64, i0: i64, i1: i64) -> Rgb {
        let (w, h) = self.texture.size();
        let row = self.wrap[1].index(j, h);
        let texel = |i: i64| self.texture.texel(self.wrap[0].index(i, w), row);
        let wide = w as i64;
        match self.wrap[0] {
            Wrap::Repeat | Wrap::MirroredRepeat => {
                let period = if self.wrap[0] == Wrap::Repeat {
                    wide
                } else {
                    2 * wide
                };
                let periods = (i1 - i0) / period;
                let whole = self.texture.row_sums[row] * (periods * period / wide) as f64;
                whole + (i0 + periods * period..i1).map(texel).sum::<Rgb>()
            }
            Wrap::ClampToEdge => {
                let left = (i1.min(0) - i0).max(0) as f64;
                let right = (i1 - i0.max(wide)).max(0) as f64;
                let inner: Rgb = (i0.max(0)..i1.min(wide)).map(texel).sum();
                left * texel(0) + inner + right * texel(wide - 1)
            }
        }
    }
}

/// ρ clamped to [0, [`MAX_REFLECTANCE`]] per channel.
fn clamped(rho: Rgb) -> Rgb {
    rho.clamp(Rgb::ZERO, Rgb::splat(MAX_REFLECTANCE))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(image: &image::RgbImage) -> Vec<u8> {
        let mut bytes = Vec::new();
        image
            .write_to(
                &mut std::io::Cursor::new(&mut bytes),
                image::ImageFormat::Png,
            )
            .unwrap();
        bytes
    }

    /// A 2 × 2 checker, white at top-left and bottom-right.
    fn checker() -> Texture {
        let img = image::RgbImage::from_fn(2, 2, |x, y| {
            image::Rgb(if (x + y) % 2 == 0 { [255; 3] } else { [0; 3] })
        });
        Texture::decode(&png(&img), false).unwrap()
    }

    fn map(texture: Texture, wrap: Wrap) -> TextureMap {
        TextureMap {
            texture: Arc::new(texture),
            wrap: [wrap; 2],
            factor: Rgb::splat(0.5),
        }
    }

    #[test]
    fn images_average_in_linear_light() {
        let t = checker();
        assert_eq!(t.mean(), Rgb::splat(0.5));
        // sRGB 128 is linear 0.2158; read raw it is 128/255.
        let grey = png(&image::RgbImage::from_pixel(2, 2, image::Rgb([128; 3])));
        let srgb = Texture::decode(&grey, false).unwrap().mean().x;
        assert!((srgb - 0.215_861).abs() < 1e-6, "{srgb}");
        let raw = Texture::decode(&grey, true).unwrap().mean().x;
        assert!((raw - 128.0 / 255.0).abs() < 1e-12);
        assert!(Texture::decode(b"not an image", false).is_err());
        assert!(Texture::open(Path::new("/nonexistent/t.png"), false).is_err());
    }

    #[test]
    fn wrap_modes_index_cells() {
        let idx = |w: Wrap| [-3, -1, 0, 2, 3, 4, 7].map(|i| w.index(i, 3));
        assert_eq!(idx(Wrap::Repeat), [0, 2, 0, 2, 0, 1, 1]);
        assert_eq!(idx(Wrap::MirroredRepeat), [2, 0, 0, 2, 2, 1, 1]);
        assert_eq!(idx(Wrap::ClampToEdge), [0, 0, 0, 2, 2, 2, 2]);
    }

    /// Runs of whole periods add row totals; they equal the texel-by-texel sum.
    #[test]
    fn runs_equal_texel_sums() {
        let img = image::RgbImage::from_fn(3, 2, |x, y| image::Rgb([(40 * x + 90 * y) as u8; 3]));
        let t = Texture::decode(&png(&img), false).unwrap();
        for wrap in [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge] {
            let m = map(t.clone(), wrap);
            for (i0, i1) in [(-7, 11), (0, 3), (2, 2), (-1, 0), (4, 17)] {
                let slow: Rgb = (i0..i1).map(|i| m.texel(i, 1)).sum();
                assert!(
                    (m.run(1, i0, i1) - slow).length() < 1e-12,
                    "{wrap:?} {i0}..{i1}"
                );
            }
        }
    }

    /// A unit square with UVs over the whole checker averages to its mean; over the white
    /// top-left quarter, white; repeated 3½ times, by the share of white it covers.
    #[test]
    fn polygon_means_over_footprints() {
        let square = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, 1.0), Vec3::Z];
        let uv = |s: f32, o: f32| {
            [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
                .map(|(u, v)| Vec2::new(o + s * u, o + s * v))
        };
        let m = map(checker(), Wrap::Repeat);
        let half = Rgb::splat(0.25);
        assert!((m.mean_over(&square, &uv(1.0, 0.0)) - half).length() < 1e-12);
        assert!((m.mean_over(&square, &uv(0.5, 0.0)) - 2.0 * half).length() < 1e-12);
        assert!((m.mean_over(&square, &uv(0.5, 0.5)) - 2.0 * half).length() < 1e-12);
        // 7 × 7 half-texel cells: 25 white ones and 24 black.
        let mixed = m.mean_over(&square, &uv(3.5, 0.0));
        assert!(
            (mixed - Rgb::splat(0.5 * 25.0 / 49.0)).length() < 1e-12,
            "{mixed}"
        );
        // Clamped outward from the white corner texel.
        let clamp = map(checker(), Wrap::ClampToEdge);
        assert!((clamp.mean_over(&square, &uv(5.0, -10.0)) - 2.0 * half).length() < 1e-12);
        // One UV point: the texel there; no UVs, NaN or absurd ones: the whole mean.
        let point = [Vec2::splat(0.75); 4];
        assert_eq!(m.mean_over(&square, &point), 2.0 * half);
        assert_eq!(m.mean_over(&square, &[]), half);
        assert_eq!(m.mean_over(&square, &[Vec2::NAN; 4]), half);
        assert_eq!(m.mean_over(&square, &uv(1e9, 0.0)), half);
    }

    /// White texels at factor 1 are clamped below 1.
    #[test]
    fn reflectance_stays_below_one() {
        let white = png(&image::RgbImage::from_pixel(1, 1, image::Rgb([255; 3])));
        let m = TextureMap {
            texture: Arc::new(Texture::decode(&white, false).unwrap()),
            wrap: [Wrap::Repeat; 2],
            factor: Rgb::ONE,
        };
        assert_eq!(m.mean(), Rgb::splat(MAX_REFLECTANCE));
    }
}
