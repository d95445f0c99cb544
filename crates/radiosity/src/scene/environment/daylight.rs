//! Daylight: the clear sky and the sun of Preetham, Shirley & Smits 1999, "A Practical
//! Analytic Model for Daylight" (SIGGRAPH 99), from the sun's position and the atmosphere's
//! turbidity T.
//!
//! ## The sky
//!
//! The luminance Y and the CIE chromaticity x, y of the sky in a direction at angle θ from the
//! zenith and γ from the sun follow Perez, Seals & Michalsky's (1993) distribution, relative to
//! the zenith:
//!
//! ```text
//! F(θ, γ) = (1 + A e^(B / cos θ)) (1 + C e^(D γ) + E cos² γ)
//! Y(θ, γ) = Y_z F(θ, γ) / F(0, θ_s)         (θ_s the sun's angle from the zenith)
//! ```
//!
//! and the same for x and y with their own A…E, each linear in T (the paper's appendix):
//!
//! | | A | B | C | D | E |
//! |---|---|---|---|---|---|
//! | Y | 0.1787 T − 1.4630 | −0.3554 T + 0.4275 | −0.0227 T + 5.3251 | 0.1206 T − 2.5771 | −0.0670 T + 0.3703 |
//! | x | −0.0193 T − 0.2592 | −0.0665 T + 0.0008 | −0.0004 T + 0.2125 | −0.0641 T − 0.8989 | −0.0033 T + 0.0452 |
//! | y | −0.0167 T − 0.2608 | −0.0950 T + 0.0092 | −0.0079 T + 0.2102 | −0.0441 T − 1.6537 | −0.0109 T + 0.0529 |
//!
//! The zenith's luminance (kcd·m⁻²) and chromaticity:
//!
//! ```text
//! Y_z = (4.0453 T − 4.9710) tan χ − 0.2155 T + 2.4192,   χ = (4/9 − T/120)(π − 2 θ_s)
//! x_z = [T² T 1] M_x [θ_s³ θ_s² θ_s 1]ᵀ,   y_z = [T² T 1] M_y [θ_s³ θ_s² θ_s 1]ᵀ
//! ```
//!
//! with the matrices [`ZENITH_X`] and [`ZENITH_Y`]. Then xyY → XYZ (X = x Y / y,
//! Z = (1 − x − y) Y / y) → linear sRGB ([`crate::color::xyz_to_linear_srgb`]). Below the
//! horizon the sky is black: the model has no ground, and neither Mitsuba's `sky` plugin (0.6)
//! nor its `sunsky` (3) emits there. The ground albedo of the scene formats is therefore not
//! used.
//!
//! ## The sun
//!
//! The sun's spectral radiance outside the atmosphere L₀(λ) (the paper's table, 380–750 nm
//! every 10 nm, [`SOLAR`]) is attenuated along the relative optical air mass
//! m = 1 / (cos θ_s + 0.15 (93.885 − θ_s[°])^−1.253) (Kasten 1966) by Rayleigh scattering,
//! aerosols and ozone (the paper's appendix, after Iqbal 1983; λ in µm):
//!
//! ```text
//! τ_R = exp(−0.008735 λ^−4.08 m)
//! τ_a = exp(−β λ^−α m),   α = 1.3,  β = 0.04608 T − 0.04586
//! τ_o = exp(−k_o(λ) l m), l = 0.35 cm  (k_o: [`OZONE`])
//! ```
//!
//! Mixed gases and water vapour absorb only above 689 nm, where the colour-matching functions
//! are below 1 % of their peaks: leaving them out changes the sun's RGB by less than 0.03 %
//! down to 5° above the horizon. The spectrum becomes XYZ = ∫ L (x̄, ȳ, z̄) dλ / ∫ ȳ dλ
//! ([`crate::color::cie_1931`]) and then linear sRGB.
//!
//! ## Units and magnitudes
//!
//! Both parts are in the units of Mitsuba 0.6's `sun` and `sky` plugins (RGB mode), which the
//! published scenes' `sunScale` and `skyScale` were set against: W·m⁻²·sr⁻¹·nm⁻¹, the spectral
//! radiance averaged over the visible with the weight ȳ. Mitsuba 0.6's `sun` is this sun
//! model, and its `sky` (Hošek & Wilkie 2012) divides the model's ∫ L ȳ dλ by
//! ∫ ȳ dλ = 106.857 nm; a Preetham luminance Y (kcd·m⁻²) is ∫ L ȳ dλ · 683 lm·W⁻¹, so the sky
//! here is Y · 1000 / (683 · 106.857) ([`KCD`]). The sun's disc keeps the sun's power: the sun
//! of angular radius [`SUN_RADIUS_DEG`] emits L_sun; a disc of radius r (Mitsuba 0.6
//! `sunRadiusScale`, Mitsuba 3 `sun_aperture`) emits L_sun (1 − cos 0.2679°) / (1 − cos r),
//! the same irradiance.

use glam::DVec3;

use super::{Disc, SunSky};
use crate::color::{cie_1931, xyz_to_linear_srgb};
use crate::scene::SceneError;
use crate::Rgb;

/// The sun's angular radius in degrees: half of the apparent diameter 0.5358° of Mitsuba's
/// sun (`SUN_APP_RADIUS`, 0.6 and 3), the mean of the year's 0.526°–0.545°.
pub const SUN_RADIUS_DEG: f64 = 0.5358 / 2.0;

/// kcd·m⁻² of luminance → W·m⁻²·sr⁻¹·nm⁻¹ of ȳ-weighted spectral radiance:
/// 1000 / (683 lm·W⁻¹ · 106.857 nm).
pub const KCD: f64 = 1000.0 / (683.0 * 106.857);

/// Perez coefficients A…E of the luminance Y as (slope, intercept) in T.
pub const PEREZ_Y: [(f64, f64); 5] = [
    (0.1787, -1.4630),
    (-0.3554, 0.4275),
    (-0.0227, 5.3251),
    (0.1206, -2.5771),
    (-0.0670, 0.3703),
];

/// Perez coefficients A…E of the chromaticity x.
pub const PEREZ_X: [(f64, f64); 5] = [
    (-0.0193, -0.2592),
    (-0.0665, 0.0008),
    (-0.0004, 0.2125),
    (-0.0641, -0.8989),
    (-0.0033, 0.0452),
];

/// Perez coefficients A…E of the chromaticity y.
pub const PEREZ_CY: [(f64, f64); 5] = [
    (-0.0167, -0.2608),
    (-0.0950, 0.0092),
    (-0.0079, 0.2102),
    (-0.0441, -1.6537),
    (-0.0109, 0.0529),
];

/// The zenith's chromaticity x: rows T², T, 1; columns θ_s³, θ_s², θ_s, 1.
pub const ZENITH_X: [[f64; 4]; 3] = [
    [0.00166, -0.00375, 0.00209, 0.0],
    [-0.02903, 0.06377, -0.03202, 0.00394],
    [0.11693, -0.21196, 0.06052, 0.25886],
];

/// The zenith's chromaticity y, as [`ZENITH_X`].
pub const ZENITH_Y: [[f64; 4]; 3] = [
    [0.00275, -0.00610, 0.00317, 0.0],
    [-0.04214, 0.08970, -0.04153, 0.00516],
    [0.15346, -0.26756, 0.06670, 0.26688],
];

/// The sun's spectral radiance outside the atmosphere, W·m⁻²·sr⁻¹·nm⁻¹, at 380, 390, …,
/// 750 nm (the paper's table, given there in W·cm⁻²·µm⁻¹·sr⁻¹, ×10 here).
pub const SOLAR: [f64; 38] = [
    16559.0, 16233.7, 21127.5, 25888.2, 25829.1, 24232.3, 26760.5, 29658.3, 30545.4, 30057.5,
    30663.7, 28830.4, 28712.1, 27825.0, 27100.6, 27233.6, 26361.3, 25503.8, 25060.2, 25311.6,
    25355.9, 25134.2, 24631.5, 24173.2, 23685.3, 23212.1, 22827.7, 22339.8, 21970.2, 21526.7,
    21097.9, 20728.3, 20240.4, 19870.8, 19427.2, 19072.4, 18628.9, 18259.2,
];

/// Ozone's absorption coefficient k_o, cm⁻¹, at 450, 460, …, 770 nm (Iqbal 1983, as the
/// paper uses it); 0 outside (its visible band, Chappuis', starts near 450 nm).
pub const OZONE: [f64; 33] = [
    0.003, 0.006, 0.009, 0.014, 0.021, 0.03, 0.04, 0.048, 0.063, 0.075, 0.085, 0.103, 0.12, 0.12,
    0.115, 0.125, 0.12, 0.105, 0.09, 0.079, 0.067, 0.057, 0.048, 0.036, 0.028, 0.023, 0.018, 0.014,
    0.011, 0.01, 0.009, 0.007, 0.004,
];

/// The Perez coefficients of one turbidity.
fn perez_coefficients(table: &[(f64, f64); 5], turbidity: f64) -> [f64; 5] {
    table.map(|(slope, intercept)| slope * turbidity + intercept)
}

/// The Perez distribution F(θ, γ) = (1 + A e^(B / cos θ)) (1 + C e^(D γ) + E cos² γ) for
/// coefficients `c` = [A, B, C, D, E], at cos θ ≥ 0 (the horizon, cos θ = 0, is its limit
/// 1 + A·0 for B < 0).
#[must_use]
pub fn perez(c: &[f64; 5], cos_theta: f64, gamma: f64) -> f64 {
    let [a, b, cc, d, e] = *c;
    let vertical = if cos_theta > 0.0 {
        1.0 + a * (b / cos_theta).exp()
    } else if b < 0.0 {
        1.0
    } else {
        f64::INFINITY
    };
    let cos_gamma = gamma.cos();
    vertical * (1.0 + cc * (d * gamma).exp() + e * cos_gamma * cos_gamma)
}

/// The zenith's luminance Y_z, kcd·m⁻², for the sun at `theta_s` radians from the zenith.
#[must_use]
pub fn zenith_luminance(turbidity: f64, theta_s: f64) -> f64 {
    let chi = (4.0 / 9.0 - turbidity / 120.0) * (std::f64::consts::PI - 2.0 * theta_s);
    (4.0453 * turbidity - 4.9710) * chi.tan() - 0.2155 * turbidity + 2.4192
}

/// The zenith's chromaticity (x_z, y_z) for the sun at `theta_s` radians from the zenith.
#[must_use]
pub fn zenith_chromaticity(turbidity: f64, theta_s: f64) -> (f64, f64) {
    let t = [turbidity * turbidity, turbidity, 1.0];
    let s = [theta_s.powi(3), theta_s * theta_s, theta_s, 1.0];
    let form = |m: &[[f64; 4]; 3]| -> f64 {
        (0..3)
            .map(|i| t[i] * (0..4).map(|j| m[i][j] * s[j]).sum::<f64>())
            .sum()
    };
    (form(&ZENITH_X), form(&ZENITH_Y))
}

/// Linear interpolation in a table sampled every `step` nm from `first` nm; 0 outside.
fn tabulated(table: &[f64], first: f64, step: f64, nm: f64) -> f64 {
    let x = (nm - first) / step;
    if x < 0.0 || x > (table.len() - 1) as f64 {
        return 0.0;
    }
    let i = (x.floor() as usize).min(table.len() - 2);
    let t = x - i as f64;
    table[i] * (1.0 - t) + table[i + 1] * t
}

/// The sun's radiance seen from the ground (module docs), linear sRGB in W·m⁻²·sr⁻¹·nm⁻¹, for
/// the sun at `theta_s` radians from the zenith (at most π/2).
#[must_use]
pub fn sun_radiance(theta_s: f64, turbidity: f64) -> Rgb {
    let m = 1.0 / (theta_s.cos() + 0.15 * (93.885 - theta_s.to_degrees()).powf(-1.253));
    let beta = 0.04608 * turbidity - 0.04586;
    let (alpha, ozone_cm) = (1.3, 0.35);
    // ∫ L (x̄, ȳ, z̄) dλ by 1 nm steps over the table's range, then / ∫ ȳ dλ (360–830 nm).
    let xyz: DVec3 = (380..=750)
        .map(|nm| {
            let nm = f64::from(nm);
            let um = nm / 1000.0;
            let rayleigh = (-m * 0.008735 * um.powf(-4.08)).exp();
            let aerosol = (-m * beta * um.powf(-alpha)).exp();
            let ozone = (-m * tabulated(&OZONE, 450.0, 10.0, nm) * ozone_cm).exp();
            let l = tabulated(&SOLAR, 380.0, 10.0, nm) * rayleigh * aerosol * ozone;
            cie_1931(nm) * l
        })
        .sum();
    let y_area: f64 = (360..=830).map(|nm| cie_1931(f64::from(nm)).y).sum();
    xyz_to_linear_srgb(xyz / y_area)
}

/// Linear sRGB of luminance `y` with chromaticity (`cx`, `cy`).
fn xyy_to_rgb(cx: f64, cy: f64, y: f64) -> Rgb {
    if cy <= 0.0 {
        return Rgb::ZERO;
    }
    xyz_to_linear_srgb(DVec3::new(cx * y / cy, y, (1.0 - cx - cy) * y / cy))
}

/// The clear sky of one sun position and turbidity, ready to evaluate in any direction.
#[derive(Clone, Debug, PartialEq)]
pub struct Sky {
    /// The zenith (unit).
    up: DVec3,
    /// Towards the sun (unit).
    sun: DVec3,
    /// Perez coefficients of Y, x and y.
    coefficients: [[f64; 5]; 3],
    /// Y_z (kcd·m⁻²), x_z, y_z over F(0, θ_s) of each: the factors of F(θ, γ).
    scale: [f64; 3],
}

impl Sky {
    /// The sky for unit vectors `up` (the zenith) and `sun`, the sun above the horizon.
    #[must_use]
    pub fn new(up: DVec3, sun: DVec3, turbidity: f64) -> Self {
        let theta_s = up.dot(sun).clamp(-1.0, 1.0).acos();
        let coefficients = [PEREZ_Y, PEREZ_X, PEREZ_CY].map(|t| perez_coefficients(&t, turbidity));
        let (x_z, y_z) = zenith_chromaticity(turbidity, theta_s);
        let zenith = [zenith_luminance(turbidity, theta_s), x_z, y_z];
        let scale = [0, 1, 2].map(|k| zenith[k] / perez(&coefficients[k], 1.0, theta_s));
        Self {
            up,
            sun,
            coefficients,
            scale,
        }
    }

    /// The luminance Y (kcd·m⁻²) and chromaticity (x, y) towards unit `dir`, or `None` below
    /// the horizon.
    #[must_use]
    pub fn luminance_xy(&self, dir: DVec3) -> Option<(f64, f64, f64)> {
        let cos_theta = self.up.dot(dir);
        if cos_theta < 0.0 {
            return None;
        }
        let gamma = self.sun.dot(dir).clamp(-1.0, 1.0).acos();
        let [y, x, cy] =
            [0, 1, 2].map(|k| self.scale[k] * perez(&self.coefficients[k], cos_theta, gamma));
        Some((y, x, cy))
    }

    /// The radiance towards unit `dir`, linear sRGB in W·m⁻²·sr⁻¹·nm⁻¹ (module docs); black
    /// below the horizon.
    #[must_use]
    pub fn radiance(&self, dir: DVec3) -> Rgb {
        self.luminance_xy(dir).map_or(Rgb::ZERO, |(y, cx, cy)| {
            xyy_to_rgb(cx, cy, y * KCD).max(Rgb::ZERO)
        })
    }
}

/// A [`SunSky`]'s radiance in every direction: the sky times its scale, and the sun's disc.
#[derive(Clone, Debug, PartialEq)]
pub struct Daylight {
    /// The sky, unless it is off.
    sky: Option<Sky>,
    /// Its multiplier.
    sky_scale: f64,
    /// The sun's disc, unless the sun is off.
    disc: Option<Disc>,
}

impl Daylight {
    /// The daylight of `s`.
    ///
    /// # Errors
    /// A direction that is zero or not finite, the sun below the horizon (the model covers the
    /// day only), a turbidity outside [1, 10], a negative or non-finite scale, or a sun radius
    /// not below 45°; each names its parameter. A radius of 0 or less (Mitsuba 0.6
    /// `sunRadiusScale` 0, a directional sun) is the sun's own, [`SUN_RADIUS_DEG`], which
    /// carries the same power.
    pub fn new(s: &SunSky) -> Result<Self, SceneError> {
        let unit = |v: glam::Vec3, key: &str| {
            v.as_dvec3()
                .try_normalize()
                .ok_or_else(|| SceneError::new(format!("not a direction: {v}")).with_key(key))
        };
        let up = unit(s.up, "up")?;
        let sun = unit(s.sun_direction, "sun_direction")?;
        if up.dot(sun) < 0.0 {
            return Err(SceneError::new(format!(
                "the sun is {:.1}° below the horizon; the daylight model covers the day only",
                up.dot(sun).asin().to_degrees().abs()
            ))
            .with_key("sun_direction"));
        }
        if !(1.0..=10.0).contains(&s.turbidity) {
            return Err(
                SceneError::new(format!("turbidity {} is outside [1, 10]", s.turbidity))
                    .with_key("turbidity"),
            );
        }
        for (value, key) in [(s.sky_scale, "sky_scale"), (s.sun_scale, "sun_scale")] {
            if !(value >= 0.0 && value.is_finite()) {
                return Err(SceneError::new(format!("{value} is not a scale")).with_key(key));
            }
        }
        if s.sun_radius_deg.is_nan() || s.sun_radius_deg >= 45.0 {
            return Err(SceneError::new(format!(
                "a sun of radius {}° is not a sun",
                s.sun_radius_deg
            ))
            .with_key("sun_radius_deg"));
        }
        let theta_s = up.dot(sun).clamp(0.0, 1.0).acos();
        let radius = if s.sun_radius_deg > 0.0 {
            s.sun_radius_deg
        } else {
            SUN_RADIUS_DEG
        }
        .to_radians();
        let keep_power = (1.0 - SUN_RADIUS_DEG.to_radians().cos()) / (1.0 - radius.cos());
        let disc = (s.sun_scale > 0.0).then(|| Disc {
            axis: sun,
            radius,
            radiance: sun_radiance(theta_s, s.turbidity) * keep_power * s.sun_scale,
        });
        Ok(Self {
            sky: (s.sky && s.sky_scale > 0.0).then(|| Sky::new(up, sun, s.turbidity)),
            sky_scale: s.sky_scale,
            disc,
        })
    }

    /// The sky alone towards unit `dir` (scaled).
    #[must_use]
    pub fn sky_radiance(&self, dir: DVec3) -> Rgb {
        self.sky
            .as_ref()
            .map_or(Rgb::ZERO, |sky| sky.radiance(dir) * self.sky_scale)
    }

    /// L_env towards unit `dir`: the sky, plus the sun inside its disc.
    #[must_use]
    pub fn radiance(&self, dir: DVec3) -> Rgb {
        let sun = self
            .disc
            .as_ref()
            .filter(|d| d.contains(dir))
            .map_or(Rgb::ZERO, |d| d.radiance);
        self.sky_radiance(dir) + sun
    }

    /// The sun's disc, with the sun's own radiance (the sky's is added by [`Self::radiance`]).
    #[must_use]
    pub fn disc(&self) -> Option<&Disc> {
        self.disc.as_ref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::luminance;
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};

    fn sun_sky(elevation_deg: f64) -> SunSky {
        let e = elevation_deg.to_radians();
        SunSky {
            sun_direction: glam::Vec3::new(e.cos() as f32, e.sin() as f32, 0.0),
            up: glam::Vec3::Y,
            turbidity: 3.0,
            albedo: 0.2,
            sky_scale: 1.0,
            sun_scale: 1.0,
            sun_radius_deg: 0.0,
            sky: true,
        }
    }

    #[test]
    fn the_zenith_luminance_is_the_papers_formula() {
        // T = 3, θ_s = π/4: χ = (4/9 − 3/120)·π/2 = 0.658862, tan χ = 0.774283,
        // Y_z = (4.0453·3 − 4.9710)·0.774283 − 0.2155·3 + 2.4192 = 7.3204 kcd·m⁻².
        assert!((zenith_luminance(3.0, FRAC_PI_4) - 7.3204).abs() < 1e-4);
        // At the horizon χ = 0: Y_z = −0.2155 T + 2.4192.
        assert!((zenith_luminance(2.0, FRAC_PI_2) - (2.4192 - 0.431)).abs() < 1e-12);
        // x_z, y_z at T = 3, θ_s = π/4 from the matrices: 0.24568, 0.25148 (a bluish white).
        let (x, y) = zenith_chromaticity(3.0, FRAC_PI_4);
        assert!(
            (x - 0.245678).abs() < 1e-5 && (y - 0.251476).abs() < 1e-5,
            "{x} {y}"
        );
    }

    #[test]
    fn the_perez_ratio_is_one_at_the_zenith() {
        // Y(0, θ_s) = Y_z F(0, θ_s)/F(0, θ_s): the sky's zenith is the zenith's formula, for
        // every turbidity and sun height.
        for turbidity in [2.0, 3.0, 6.5, 10.0] {
            for elevation in [5.0f64, 30.0, 60.0, 89.0] {
                let e = elevation.to_radians();
                let sun = DVec3::new(e.cos(), e.sin(), 0.0);
                let sky = Sky::new(DVec3::Y, sun, turbidity);
                let (y, x, cy) = sky.luminance_xy(DVec3::Y).expect("above the horizon");
                let theta_s = FRAC_PI_2 - e;
                let (x_z, y_z) = zenith_chromaticity(turbidity, theta_s);
                assert!((y / zenith_luminance(turbidity, theta_s) - 1.0).abs() < 1e-12);
                assert!((x - x_z).abs() < 1e-12 && (cy - y_z).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn the_sky_is_brightest_near_the_sun_and_black_below_the_horizon() {
        let daylight = Daylight::new(&sun_sky(30.0)).expect("valid");
        let e = 30f64.to_radians();
        let near_sun = DVec3::new(e.cos(), e.sin() + 0.1, 0.0).normalize();
        let away = DVec3::new(-e.cos(), e.sin(), 0.0);
        let lum = |d| luminance(daylight.sky_radiance(d));
        assert!(
            lum(near_sun) > 3.0 * lum(away),
            "{} {}",
            lum(near_sun),
            lum(away)
        );
        assert_eq!(
            daylight.radiance(DVec3::new(0.3, -0.1, 0.9).normalize()),
            Rgb::ZERO
        );
        // Blue overhead: the clear sky's zenith.
        let zenith = daylight.sky_radiance(DVec3::Y);
        assert!(zenith.z > zenith.x, "{zenith}");
        // Its luminance is Y_z in the Mitsuba unit.
        let y_z = zenith_luminance(3.0, FRAC_PI_2 - e) * KCD;
        assert!((luminance(zenith) / y_z - 1.0).abs() < 1e-3);
    }

    #[test]
    fn the_sun_dims_and_reddens_towards_the_horizon() {
        // Overhead the attenuated sun is near 18 600 W·m⁻²·sr⁻¹·nm⁻¹ in ȳ (the table's
        // visible mean is ~25 000, the clear air passes ~75 %); low, it reddens.
        let high = sun_radiance(0.0, 3.0);
        let low = sun_radiance(85f64.to_radians(), 3.0);
        assert!((luminance(high) - 18_600.0).abs() < 200.0, "{high}");
        assert!(luminance(low) < 0.1 * luminance(high));
        assert!(low.x / low.z > 4.0 * high.x / high.z, "{low} {high}");
        // More haze, less sun.
        assert!(luminance(sun_radiance(0.5, 8.0)) < 0.8 * luminance(sun_radiance(0.5, 2.0)));
    }

    #[test]
    fn a_larger_disc_keeps_the_suns_power() {
        let power = |radius_deg: f64| {
            let d = Daylight::new(&SunSky {
                sun_radius_deg: radius_deg,
                ..sun_sky(40.0)
            })
            .expect("valid");
            let disc = d.disc().expect("a sun").clone();
            luminance(disc.radiance) * disc.solid_angle()
        };
        let natural = power(0.0);
        for r in [SUN_RADIUS_DEG, 1.0, 5.0] {
            assert!((power(r) / natural - 1.0).abs() < 1e-9, "{r}");
        }
    }

    #[test]
    fn bad_parameters_name_their_key() {
        let cases = [
            (
                SunSky {
                    turbidity: 0.5,
                    ..sun_sky(30.0)
                },
                "turbidity",
            ),
            (
                SunSky {
                    sky_scale: -1.0,
                    ..sun_sky(30.0)
                },
                "sky_scale",
            ),
            (
                SunSky {
                    sun_scale: f64::NAN,
                    ..sun_sky(30.0)
                },
                "sun_scale",
            ),
            (
                SunSky {
                    sun_radius_deg: 60.0,
                    ..sun_sky(30.0)
                },
                "sun_radius_deg",
            ),
            (
                SunSky {
                    up: glam::Vec3::ZERO,
                    ..sun_sky(30.0)
                },
                "up",
            ),
            (sun_sky(-5.0), "sun_direction"),
        ];
        for (s, key) in cases {
            let err = Daylight::new(&s).expect_err(key);
            assert_eq!(err.key.as_deref(), Some(key), "{err}");
        }
    }
}
