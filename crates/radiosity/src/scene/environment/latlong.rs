//! Latitude-longitude radiance maps in Mitsuba 3's `envmap` convention: reading one as
//! L_env(ω), and writing any L_env(ω) as one.
//!
//! ## The mapping
//!
//! A world direction d is taken into the map's frame, v = normalize(M⁻¹ d) with M the linear
//! part of `to_world`, and then to
//!
//! ```text
//! u = atan2(v_x, −v_z) / 2π  (mod 1),     θ = acos(v_y)
//! ```
//!
//! so +y is the top row, −z the left edge and +x a quarter of the way across. The W × H pixels
//! are *samples*: column i at u = (i + ½)/W, row j at θ = π j/(H − 1), so the first and last
//! rows sit on the poles. Between them the radiance is bilinear, the last column joined to the
//! first across the seam:
//!
//! ```text
//! x = (u − ½/W) W  (mod W),   y = (H − 1) θ/π,   L(d) = scale · bilerp(x, y)
//! ```
//!
//! This is Mitsuba 3's `envmap` emitter (`direction_to_uv`, `eval_spectrum` in its
//! `envmap.cpp`), checked against the `mitsuba` 3.9 Python package in `scalar_rgb`: its
//! `eval` in the six axis directions, at a pixel's own direction and across the seam, with a
//! rotating `to_world` and a `scale`, gives the values this module does.
//!
//! ## Writing a map
//!
//! [`rasterize`] samples L_env(ω) into a W × W/2 map in that convention, in world space (for an
//! `envmap` without `to_world`). A pixel is not L at its direction but the mean of L weighted by
//! the pixel's bilinear hat h_ij, the function the reader's interpolation spreads it with:
//!
//! ```text
//! p_ij = ∫ L h_ij dω / ∫ h_ij dω
//! ```
//!
//! The hats add up to one everywhere, so the interpolated map carries the power ∫ L dω of the
//! original to quadrature, however small a bright disc is against the pixels. The integrals
//! are sums over 4 × 4 sub-cells of each cell between four samples (sub-cell solid angles
//! exact: Δφ (cos θ₀ − cos θ₁)); a [`Disc`] is left out of them and sampled on its own, its
//! solid angle in [`DISC_SAMPLES`] equal parts, each splatted with the same hats.

use std::f64::consts::{PI, TAU};
use std::path::Path;

use glam::{DMat3, DVec3, Mat4};

use super::Disc;
use crate::io::image_file::read_image;
use crate::render::Image;
use crate::scene::SceneError;
use crate::Rgb;

/// Sub-cells per side of each cell in [`rasterize`].
pub const SUBCELLS: u32 = 4;

/// Samples of a disc in [`rasterize`] (a 64 × 64 stratified grid over its solid angle).
pub const DISC_SAMPLES: u32 = 64 * 64;

/// A map as a radiance function of direction.
#[derive(Clone, Debug, PartialEq)]
pub struct LatLong {
    /// The pixels, negative and non-finite values set to 0.
    image: Image,
    /// How many pixels were set to 0.
    repaired: usize,
    /// The multiplier of the pixels.
    scale: f64,
    /// World → map frame: M⁻¹.
    from_world: DMat3,
}

/// The (u, θ/π) of a unit direction in the map's frame; u in (−½, ½].
#[must_use]
pub fn direction_to_uv(v: DVec3) -> (f64, f64) {
    (v.x.atan2(-v.z) / TAU, v.y.clamp(-1.0, 1.0).acos() / PI)
}

/// The unit direction in the map's frame of (u, θ/π).
#[must_use]
pub fn uv_to_direction(u: f64, t: f64) -> DVec3 {
    let (sin_phi, cos_phi) = (TAU * u).sin_cos();
    let (sin_theta, cos_theta) = (PI * t).sin_cos();
    DVec3::new(sin_phi * sin_theta, cos_theta, -cos_phi * sin_theta)
}

/// The cell of a W × H map that holds (u, θ/π) and the position in it: the columns i and
/// i + 1 (mod W), the rows j and j + 1, and the fractions (tx, ty) towards the second of each.
fn cell(width: usize, height: usize, (u, t): (f64, f64)) -> (usize, usize, f64, f64) {
    let x = (u - 0.5 / width as f64).rem_euclid(1.0) * width as f64;
    let y = t.clamp(0.0, 1.0) * (height - 1) as f64;
    let i = (x.floor() as usize).min(width - 1);
    let j = (y.floor() as usize).min(height - 2);
    (i, j, x - i as f64, y - j as f64)
}

impl LatLong {
    /// The map of `image` times `scale`, placed by `to_world`.
    ///
    /// # Errors
    /// An image smaller than 2 × 3 (Mitsuba's minimum), a scale that is negative or not finite,
    /// or a `to_world` whose linear part cannot be inverted.
    pub fn new(mut image: Image, scale: f64, to_world: Mat4) -> Result<Self, SceneError> {
        if image.width < 2 || image.height < 3 {
            return Err(SceneError::new(format!(
                "a {}×{} map is smaller than 2×3",
                image.width, image.height
            )));
        }
        if !(scale >= 0.0 && scale.is_finite()) {
            return Err(SceneError::new(format!("{scale} is not a scale")).with_key("scale"));
        }
        let linear = to_world.as_dmat4();
        let m = DMat3::from_cols(
            linear.x_axis.truncate(),
            linear.y_axis.truncate(),
            linear.z_axis.truncate(),
        );
        let det = m.determinant();
        if !(det.is_finite() && det.abs() > 1e-12) {
            return Err(SceneError::new("`to_world` cannot be inverted").with_key("to_world"));
        }
        let mut repaired = 0;
        for p in &mut image.pixels {
            let fixed =
                Rgb::from_array(
                    p.to_array()
                        .map(|c| if c >= 0.0 && c.is_finite() { c } else { 0.0 }),
                );
            repaired += usize::from(fixed != *p);
            *p = fixed;
        }
        Ok(Self {
            image,
            repaired,
            scale,
            from_world: m.inverse(),
        })
    }

    /// The map in the file at `path` (any format of [`read_image`]).
    ///
    /// # Errors
    /// A file that cannot be read (the message names it), and those of [`Self::new`].
    pub fn read(path: &Path, scale: f64, to_world: Mat4) -> Result<Self, SceneError> {
        let image = read_image(path).map_err(|e| SceneError::new(e.to_string()))?;
        Self::new(image, scale, to_world).map_err(|mut e| {
            e.message = format!("{}: {}", path.display(), e.message);
            e
        })
    }

    /// A warning if pixels were negative or not finite (they count as black).
    #[must_use]
    pub fn warning(&self) -> Option<String> {
        (self.repaired > 0).then(|| {
            format!(
                "environment map: {} pixels negative or not finite, taken as black",
                self.repaired
            )
        })
    }

    /// The angle between neighbouring samples, the smaller of 2π/W and π/(H − 1): how finely
    /// the map varies.
    #[must_use]
    pub fn pixel_angle(&self) -> f64 {
        (TAU / f64::from(self.image.width)).min(PI / f64::from(self.image.height - 1))
    }

    /// L towards unit world direction `dir` (module docs).
    #[must_use]
    pub fn radiance(&self, dir: DVec3) -> Rgb {
        let v = (self.from_world * dir).normalize_or_zero();
        let (w, h) = (self.image.width as usize, self.image.height as usize);
        let (i, j, tx, ty) = cell(w, h, direction_to_uv(v));
        let p = |i: usize, j: usize| self.image.pixels[j * w + i % w];
        let top = p(i, j) * (1.0 - tx) + p(i + 1, j) * tx;
        let bottom = p(i, j + 1) * (1.0 - tx) + p(i + 1, j + 1) * tx;
        (top * (1.0 - ty) + bottom * ty) * self.scale
    }
}

/// A `width` × `width`/2 map of `radiance` in world space (module docs), `disc` sampled on its
/// own.
///
/// # Panics
/// If `width` is below 4.
#[must_use]
pub fn rasterize(
    width: u32,
    radiance: &(dyn Fn(DVec3) -> Rgb + Sync),
    disc: Option<&Disc>,
) -> Image {
    use rayon::prelude::*;
    assert!(width >= 4, "a map at least 4 pixels wide");
    let (w, h) = (width as usize, width as usize / 2);
    let s = SUBCELLS as usize;
    let d_phi = TAU / (w * s) as f64;
    let d_t = 1.0 / ((h - 1) * s) as f64;
    let outside = |dir: DVec3| disc.is_none_or(|d| !d.contains(dir));
    // Σ w L dω and Σ w dω per pixel, over the cells of each band of rows [j, j + 1] (a band's
    // cells touch rows j and j + 1 only, so bands are summed apart and then added).
    let bands: Vec<(Vec<Rgb>, Vec<f64>)> = (0..h - 1)
        .into_par_iter()
        .map(|j| {
            let mut num = vec![Rgb::ZERO; 2 * w];
            let mut den = vec![0.0; 2 * w];
            for b in 0..s {
                let t0 = (j * s + b) as f64 * d_t;
                let t1 = t0 + d_t;
                let d_omega = d_phi * ((PI * t0).cos() - (PI * t1).cos());
                let ty = (b as f64 + 0.5) / s as f64;
                let t = 0.5 * (t0 + t1);
                for i in 0..w {
                    for a in 0..s {
                        let tx = (a as f64 + 0.5) / s as f64;
                        let u = (i as f64 + tx + 0.5) / w as f64;
                        let dir = uv_to_direction(u, t);
                        let l = if outside(dir) {
                            radiance(dir)
                        } else {
                            Rgb::ZERO
                        };
                        let corners = [
                            (i, (1.0 - tx) * (1.0 - ty)),
                            ((i + 1) % w, tx * (1.0 - ty)),
                            (w + i, (1.0 - tx) * ty),
                            (w + (i + 1) % w, tx * ty),
                        ];
                        for (k, weight) in corners {
                            num[k] += l * (weight * d_omega);
                            den[k] += weight * d_omega;
                        }
                    }
                }
            }
            (num, den)
        })
        .collect();
    let mut num = vec![Rgb::ZERO; w * h];
    let mut den = vec![0.0; w * h];
    for (j, (n, d)) in bands.into_iter().enumerate() {
        for k in 0..2 * w {
            num[j * w + k] += n[k];
            den[j * w + k] += d[k];
        }
    }
    // The disc: equal solid angles, stratified in (cos θ, φ) about its axis.
    if let Some(disc) = disc {
        let side = f64::from(DISC_SAMPLES).sqrt() as usize;
        let (e1, e2) = disc.axis.any_orthonormal_pair();
        let d_omega = disc.solid_angle() / (side * side) as f64;
        let cos_r = disc.radius.cos();
        for a in 0..side {
            for b in 0..side {
                let cos_t = 1.0 - (1.0 - cos_r) * (a as f64 + 0.5) / side as f64;
                let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                let (sin_p, cos_p) = (TAU * (b as f64 + 0.5) / side as f64).sin_cos();
                let dir = disc.axis * cos_t + (e1 * cos_p + e2 * sin_p) * sin_t;
                let l = radiance(dir) * d_omega;
                let (i, j, tx, ty) = cell(w, h, direction_to_uv(dir));
                for (k, weight) in [
                    (j * w + i, (1.0 - tx) * (1.0 - ty)),
                    (j * w + (i + 1) % w, tx * (1.0 - ty)),
                    ((j + 1) * w + i, (1.0 - tx) * ty),
                    ((j + 1) * w + (i + 1) % w, tx * ty),
                ] {
                    num[k] += l * weight;
                }
            }
        }
    }
    Image {
        width,
        height: h as u32,
        pixels: num
            .iter()
            .zip(&den)
            .map(|(n, &d)| if d > 0.0 { *n / d } else { Rgb::ZERO })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An 8 × 5 map whose pixel (i, j) is (i, j, 100 + 10 i + j), as in the Mitsuba check.
    fn probe() -> Image {
        let mut image = Image::new(8, 5);
        for j in 0..5 {
            for i in 0..8 {
                image.pixels[j * 8 + i] =
                    Rgb::new(i as f64, j as f64, 100.0 + 10.0 * i as f64 + j as f64);
            }
        }
        image
    }

    #[test]
    fn lookups_match_mitsuba_3() {
        // Values printed by mitsuba 3.9 (scalar_rgb) for this map: `envmap` `eval` with
        // si.wi = −d.
        let map = LatLong::new(probe(), 1.0, Mat4::IDENTITY).expect("map");
        let cases = [
            (DVec3::Y, Rgb::new(3.5, 0.0, 135.0)),
            (DVec3::NEG_Z, Rgb::new(3.5, 2.0, 137.0)),
            (DVec3::X, Rgb::new(1.5, 2.0, 117.0)),
            (DVec3::Z, Rgb::new(3.5, 2.0, 137.0)),
            (DVec3::NEG_X, Rgb::new(5.5, 2.0, 157.0)),
            (DVec3::NEG_Y, Rgb::new(3.5, 4.0, 139.0)),
            // Pixel (2, 1)'s own direction, and u = 0 between rows 1 and 2 (across the seam).
            (uv_to_direction(2.5 / 8.0, 0.25), Rgb::new(2.0, 1.0, 121.0)),
            (uv_to_direction(0.0, 1.5 / 4.0), Rgb::new(3.5, 1.5, 136.5)),
        ];
        for (d, expected) in cases {
            let got = map.radiance(d);
            assert!((got - expected).abs().max_element() < 1e-9, "{d}: {got}");
        }
        // rotate x −90° and scale 2: world +z is the map's −y, world +y its +z.
        let rotated = LatLong::new(
            probe(),
            2.0,
            Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2),
        )
        .expect("map");
        assert!(
            (rotated.radiance(DVec3::Z) - Rgb::new(7.0, 8.0, 278.0))
                .abs()
                .max_element()
                < 1e-4
        );
        assert!(
            (rotated.radiance(DVec3::Y) - Rgb::new(7.0, 4.0, 274.0))
                .abs()
                .max_element()
                < 1e-4
        );
    }

    #[test]
    fn directions_and_uv_are_inverse() {
        for (u, t) in [(0.1, 0.3), (0.45, 0.9), (-0.3, 0.5)] {
            let (u2, t2) = direction_to_uv(uv_to_direction(u, t));
            assert!((u2 - u).abs() < 1e-12 && (t2 - t).abs() < 1e-12, "{u} {t}");
        }
    }

    /// ∫ L dω of a map by a fine (φ, θ) grid with exact band solid angles.
    fn integral(f: &dyn Fn(DVec3) -> Rgb, n: usize) -> Rgb {
        let mut sum = Rgb::ZERO;
        for j in 0..n {
            let (t0, t1) = (j as f64 / n as f64, (j + 1) as f64 / n as f64);
            let d_omega = TAU / (2 * n) as f64 * ((PI * t0).cos() - (PI * t1).cos());
            for i in 0..2 * n {
                sum += f(uv_to_direction(
                    (i as f64 + 0.5) / (2 * n) as f64,
                    0.5 * (t0 + t1),
                )) * d_omega;
            }
        }
        sum
    }

    #[test]
    fn a_written_map_keeps_the_power_of_a_small_bright_disc() {
        // A sky gradient and a sun 0.4° across (a fifth of a pixel at 128 wide), 10⁵ times
        // brighter: the map read back through the bilinear lookup holds both powers.
        let axis = DVec3::new(0.3, 0.5, -0.8).normalize();
        let disc = Disc {
            axis,
            radius: 0.2f64.to_radians(),
            radiance: Rgb::new(1e5, 8e4, 6e4),
        };
        let sky = |d: DVec3| Rgb::new(0.2, 0.3, 0.5) * (1.0 + d.y).max(0.0);
        let env = |d: DVec3| {
            sky(d)
                + if disc.contains(d) {
                    disc.radiance
                } else {
                    Rgb::ZERO
                }
        };
        let image = rasterize(128, &env, Some(&disc));
        assert_eq!((image.width, image.height), (128, 64));
        let map = LatLong::new(image, 1.0, Mat4::IDENTITY).expect("map");
        let expected = integral(&sky, 512) + disc.radiance * disc.solid_angle();
        let got = integral(&|d| map.radiance(d), 512);
        // The quadrature of the read-back map resolves its pixels (4 × 4 per pixel): the
        // hat integrals differ from the grid's at second order, ~10⁻⁴.
        let rel = ((got - expected) / expected).abs().max_element();
        assert!(rel < 2e-3, "{got} vs {expected}");
    }
}
