//! # The luminous intensity distribution I(C, γ)
//!
//! **Type C photometry** (CIE 121:1996, IES LM-63 "type C", EULUMDAT) describes a direction
//! from the luminaire's photometric centre by two angles: the polar angle γ from the nadir
//! (0° straight down, 90° in the horizontal plane, 180° straight up) and the azimuth C of the
//! vertical half-plane it lies in (0°–360°, counter-clockwise seen from above). The file gives
//! the luminous intensity I (cd) on a grid of C planes and γ angles.
//!
//! ## The luminaire frame
//!
//! [`Distribution::intensity`] takes a direction in the *luminaire frame*, right-handed:
//!
//! | axis | photometric meaning |
//! |---|---|
//! | −Z | the nadir, γ = 0° (the direction a scene's `aim` names) |
//! | +X | the C0 half-plane at γ = 90° (the luminaire's length axis in LM-63) |
//! | +Y | the C90 half-plane at γ = 90° |
//!
//! so d = (sin γ cos C, sin γ sin C, −cos γ). Seen from above (+Z), C turns from +X towards +Y,
//! counter-clockwise as both standards require. A scene object places a luminaire by mapping
//! −Z onto its `aim` and +X onto a direction perpendicular to it, turned by its `rotation`
//! about the aim.
//!
//! ## Symmetry
//!
//! A file may store part of the sphere ([`Symmetry`]); the constructor expands it by mirroring
//! each stored plane C onto its images: −C about the C0–C180 plane, 180° − C about the C90–C270
//! plane, both for a quadrant-symmetric file, and one plane for all C when the distribution is
//! rotationally symmetric. The expanded table holds every C in [0°, 360°) once and is periodic
//! in C.
//!
//! ## Interpolation
//!
//! Between grid points I is interpolated **bilinearly** in (C, γ), periodically in C. Outside
//! the γ range of the file (beyond the last γ of a downlight that stops at 90°, below the
//! first of an uplight that starts at 90°) I is zero.
//!
//! ## Flux
//!
//! The luminous flux is Φ = ∫ I dΩ = ∫∫ I(C, γ) sin γ dγ dC. On a grid cell [C₁, C₂] × [γ₁, γ₂]
//! the bilinear interpolant is integrated exactly: its mean over C at each γ edge, Ī₁ and Ī₂,
//! is weighted by
//!
//! w₂ = (sin γ₂ − sin γ₁)/(γ₂ − γ₁) − cos γ₂,  w₁ = (cos γ₁ − cos γ₂) − w₂,
//!
//! so Φ_cell = ΔC (w₁ Ī₁ + w₂ Ī₂), ΔC in radians. The two weights add up to the zone's
//! exact solid angle per radian of C, cos γ₁ − cos γ₂; the solid angle of the cell is
//! 2π (cos γ₁ − cos γ₂) · ΔC/360°. A constant I therefore integrates to exactly 4πI, and the
//! flux is the flux of the same function [`Distribution::intensity`] evaluates.
//!
//! ## Beam and field angles
//!
//! The **beam angle** is the full angle of the cone within which I stays at or above 50 % of
//! the maximum intensity I_max, the **field angle** the same at 10 % (CIE 121, IES
//! LM-79's definitions relative to I_max). It is measured in the two principal planes, C0–C180
//! and C90–C270, from the beam axis — the nadir when the maximum lies in the lower hemisphere,
//! the zenith otherwise — to the outermost angle on each half-plane where I still reaches the
//! threshold; the two half-angles add up to the full angle ([`Spread`]). For a rotationally
//! symmetric distribution the two planes agree.

use glam::DVec3;

/// Which part of the sphere a file stores and how the rest follows from it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Symmetry {
    /// Every C plane is stored.
    None,
    /// I does not depend on C: one plane stands for all (IES: a single horizontal angle; LDT
    /// Isym 1).
    Rotational,
    /// Mirror symmetric about the C0–C180 plane, I(C) = I(−C): planes 0°–180° are stored
    /// (IES: horizontal angles 0–180; LDT Isym 2).
    PlaneC0C180,
    /// Mirror symmetric about the C90–C270 plane, I(C) = I(180° − C) (IES 1995: horizontal
    /// angles 90–270; LDT Isym 3).
    PlaneC90C270,
    /// Symmetric about both planes: planes 0°–90° are stored (IES: horizontal angles 0–90; LDT
    /// Isym 4).
    Quadrant,
}

impl Symmetry {
    /// The images of a plane at C (degrees) under the symmetry, C itself first.
    fn images(self, c: f64) -> Vec<f64> {
        match self {
            Self::None | Self::Rotational => vec![c],
            Self::PlaneC0C180 => vec![c, -c],
            Self::PlaneC90C270 => vec![c, 180.0 - c],
            Self::Quadrant => vec![c, -c, 180.0 - c, 180.0 + c],
        }
    }

    /// A short description for reports.
    #[must_use]
    pub fn describe(self) -> &'static str {
        match self {
            Self::None => "none (all C planes stored)",
            Self::Rotational => "rotational (one C plane for all)",
            Self::PlaneC0C180 => "about the C0–C180 plane",
            Self::PlaneC90C270 => "about the C90–C270 plane",
            Self::Quadrant => "about the C0–C180 and C90–C270 planes",
        }
    }
}

/// A table that cannot make a distribution.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TableError {
    /// No C plane or no γ angle.
    #[error("the table is empty: {c} C planes, {gamma} γ angles")]
    Empty {
        /// C planes given.
        c: usize,
        /// γ angles given.
        gamma: usize,
    },
    /// A rotationally symmetric table must have exactly one C plane.
    #[error("a rotationally symmetric distribution has one C plane, not {0}")]
    RotationalPlanes(usize),
    /// The number of values is not (C planes) × (γ angles).
    #[error("expected {expected} intensities ({c} C planes × {gamma} γ angles), found {found}")]
    Size {
        /// C planes.
        c: usize,
        /// γ angles.
        gamma: usize,
        /// c × gamma.
        expected: usize,
        /// Values given.
        found: usize,
    },
    /// γ angles must rise strictly within [0°, 180°].
    #[error("the γ angles must rise strictly from 0° to at most 180°, found {0}° after {1}°")]
    Gamma(f64, f64),
    /// C angles must rise strictly within [0°, 360°].
    #[error("the C angles must rise strictly from 0° to at most 360°, found {0}° after {1}°")]
    C(f64, f64),
    /// Intensities must be finite and not negative.
    #[error("intensities must be finite and not negative, found {value} cd at C {c}°, γ {gamma}°")]
    Intensity {
        /// The value.
        value: f64,
        /// Its C plane.
        c: f64,
        /// Its γ angle.
        gamma: f64,
    },
}

/// The maximum intensity and its direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    /// I_max, cd.
    pub candela: f64,
    /// Its C plane, degrees.
    pub c: f64,
    /// Its γ angle, degrees.
    pub gamma: f64,
}

/// A full angle of the beam in the two principal planes, degrees (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spread {
    /// In the C0–C180 plane.
    pub c0_c180: f64,
    /// In the C90–C270 plane.
    pub c90_c270: f64,
}

/// The luminous intensity distribution I(C, γ) of a luminaire, in candela, over the whole
/// sphere (see the module docs for the frame, interpolation and integration).
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution {
    /// C angles, degrees, strictly rising in [0, 360); periodic.
    c: Vec<f64>,
    /// γ angles, degrees, strictly rising in [0, 180].
    gamma: Vec<f64>,
    /// I in cd, C-major: `values[i * gamma.len() + j]` is I(c[i], gamma[j]).
    values: Vec<f64>,
}

/// The tolerance under which two angles (degrees) are the same grid angle.
const SAME_ANGLE: f64 = 1e-9;

impl Distribution {
    /// A distribution from a table: `candela[i * gamma.len() + j]` is `I(c[i], gamma[j])` in cd,
    /// for the stored planes `c` (degrees, rising in [0, 360]) and angles `gamma` (degrees,
    /// rising in [0, 180]); the planes not stored follow from `symmetry`.
    ///
    /// A plane at 360° is the plane at 0° (the first one given is kept).
    ///
    /// # Errors
    /// [`TableError`] when the table is empty, of the wrong size, its angles do not rise within
    /// their ranges, or an intensity is negative or not finite.
    pub fn new(
        symmetry: Symmetry,
        c: &[f64],
        gamma: &[f64],
        candela: Vec<f64>,
    ) -> Result<Self, TableError> {
        // Check the table's shape and values.
        if c.is_empty() || gamma.is_empty() {
            return Err(TableError::Empty {
                c: c.len(),
                gamma: gamma.len(),
            });
        }
        if symmetry == Symmetry::Rotational && c.len() != 1 {
            return Err(TableError::RotationalPlanes(c.len()));
        }
        let n = gamma.len();
        if candela.len() != c.len() * n {
            return Err(TableError::Size {
                c: c.len(),
                gamma: n,
                expected: c.len() * n,
                found: candela.len(),
            });
        }
        rising(gamma, 180.0).map_err(|(a, b)| TableError::Gamma(a, b))?;
        rising(c, 360.0).map_err(|(a, b)| TableError::C(a, b))?;
        if let Some(k) = candela.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(TableError::Intensity {
                value: candela[k],
                c: c[k / n],
                gamma: gamma[k % n],
            });
        }

        // Expand the symmetry: every image of every stored plane, in [0, 360), sorted, once.
        let mut planes: Vec<(f64, usize)> = c
            .iter()
            .enumerate()
            .flat_map(|(i, &ci)| {
                symmetry
                    .images(ci)
                    .into_iter()
                    // `+ 0.0` turns the image −0° of the plane 0° into 0°.
                    .map(move |a| (a.rem_euclid(360.0) + 0.0, i))
            })
            .map(|(a, i)| (if a >= 360.0 - SAME_ANGLE { 0.0 } else { a }, i))
            .collect();
        // A stable sort keeps a stored plane ahead of the images that fall on it.
        planes.sort_by(|a, b| a.0.total_cmp(&b.0));
        planes.dedup_by(|b, a| (b.0 - a.0).abs() < SAME_ANGLE);
        let values = planes
            .iter()
            .flat_map(|&(_, i)| candela[i * n..(i + 1) * n].iter().copied())
            .collect();
        let d = Self {
            c: planes.iter().map(|p| p.0).collect(),
            gamma: gamma.to_vec(),
            values,
        };
        debug_assert_eq!(d.validate(), Ok(()));
        Ok(d)
    }

    /// Checks the invariants: C rising in [0, 360), γ rising in [0, 180], one finite
    /// non-negative value per grid point.
    ///
    /// # Errors
    /// The first invariant broken, as a sentence.
    pub fn validate(&self) -> Result<(), String> {
        if self.c.is_empty() || self.gamma.is_empty() {
            return Err("empty grid".into());
        }
        if self.c.windows(2).any(|w| w[0] >= w[1])
            || self.c[0] < 0.0
            || self.c[self.c.len() - 1] >= 360.0
        {
            return Err(format!("C angles not rising in [0, 360): {:?}", self.c));
        }
        rising(&self.gamma, 180.0).map_err(|e| format!("γ angles not rising: {e:?}"))?;
        if self.values.len() != self.c.len() * self.gamma.len() {
            return Err("values do not fill the grid".into());
        }
        if self.values.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err("a value is negative or not finite".into());
        }
        Ok(())
    }

    /// The C angles of the expanded grid, degrees, rising in [0, 360).
    #[must_use]
    pub fn c_angles(&self) -> &[f64] {
        &self.c
    }

    /// The γ angles of the grid, degrees, rising in [0, 180].
    #[must_use]
    pub fn gamma_angles(&self) -> &[f64] {
        &self.gamma
    }

    /// I at grid point (C index `i`, γ index `j`).
    fn at(&self, i: usize, j: usize) -> f64 {
        self.values[i * self.gamma.len() + j]
    }

    /// The two planes around `c` (degrees, any value) and the weight of the second: periodic
    /// linear interpolation in C.
    fn c_weights(&self, c: f64) -> (usize, usize, f64) {
        let m = self.c.len();
        if m == 1 {
            return (0, 0, 0.0);
        }
        let c = c.rem_euclid(360.0);
        // The first plane above c; the segment before it holds c (wrapping past 360°).
        let k = self.c.partition_point(|&a| a <= c);
        let (lo, hi) = if k == 0 || k == m {
            (m - 1, 0)
        } else {
            (k - 1, k)
        };
        let a = self.c[lo];
        let mut span = self.c[hi] - a;
        let mut offset = c - a;
        if span <= 0.0 {
            span += 360.0;
        }
        if offset < 0.0 {
            offset += 360.0;
        }
        (lo, hi, (offset / span).clamp(0.0, 1.0))
    }

    /// I(C, γ) in cd, interpolated on the C plane at `c` for every grid γ.
    fn plane(&self, c: f64) -> Vec<f64> {
        let (a, b, t) = self.c_weights(c);
        (0..self.gamma.len())
            .map(|j| self.at(a, j) * (1.0 - t) + self.at(b, j) * t)
            .collect()
    }

    /// I(C, γ) in cd at the angles `c` and `gamma` in degrees: bilinear on the grid, periodic in
    /// C, zero outside the γ range of the file.
    ///
    /// See also [`Distribution::intensity`] for a direction.
    #[must_use]
    pub fn intensity_at(&self, c: f64, gamma: f64) -> f64 {
        let g = &self.gamma;
        let (first, last) = (g[0], g[g.len() - 1]);
        if !(gamma >= first - SAME_ANGLE && gamma <= last + SAME_ANGLE) {
            return 0.0;
        }
        let (a, b, t) = self.c_weights(c);
        let row = |j: usize| self.at(a, j) * (1.0 - t) + self.at(b, j) * t;
        if g.len() == 1 {
            return row(0);
        }
        let k = g.partition_point(|&x| x <= gamma).clamp(1, g.len() - 1);
        let s = ((gamma - g[k - 1]) / (g[k] - g[k - 1])).clamp(0.0, 1.0);
        row(k - 1) * (1.0 - s) + row(k) * s
    }

    /// I in cd towards `direction` in the luminaire frame (−Z the nadir, +X the C0 plane, +Y the
    /// C90 plane; see the module docs). The direction need not be normalized; a zero or
    /// non-finite vector gets 0.
    #[must_use]
    pub fn intensity(&self, direction: DVec3) -> f64 {
        let Some(d) = direction.try_normalize() else {
            return 0.0;
        };
        let gamma = (-d.z).clamp(-1.0, 1.0).acos().to_degrees();
        let c = d.y.atan2(d.x).to_degrees();
        self.intensity_at(c, gamma)
    }

    /// The unit vector of the direction (C, γ), degrees, in the luminaire frame: the inverse of
    /// the angles [`Distribution::intensity`] finds.
    #[must_use]
    pub fn direction(c: f64, gamma: f64) -> DVec3 {
        let (c, g) = (c.to_radians(), gamma.to_radians());
        DVec3::new(g.sin() * c.cos(), g.sin() * c.sin(), -g.cos())
    }

    /// The luminous flux Φ = ∫ I dΩ in lm, the exact integral of the interpolated distribution
    /// (module docs).
    #[must_use]
    pub fn flux(&self) -> f64 {
        let m = self.c.len();
        let g = &self.gamma;
        // The C segments, periodic: each plane to the next, the last to the first + 360°.
        let segments: Vec<(usize, usize, f64)> = if m == 1 {
            vec![(0, 0, 360.0)]
        } else {
            (0..m)
                .map(|i| {
                    let k = (i + 1) % m;
                    let span = if k == 0 {
                        self.c[0] + 360.0 - self.c[i]
                    } else {
                        self.c[k] - self.c[i]
                    };
                    (i, k, span)
                })
                .collect()
        };
        let mut flux = 0.0;
        for (a, b, span) in segments {
            let dc = span.to_radians();
            for j in 1..g.len() {
                // The zone's weights of its lower and upper edge (module docs).
                let (g1, g2) = (g[j - 1].to_radians(), g[j].to_radians());
                let w2 = (g2.sin() - g1.sin()) / (g2 - g1) - g2.cos();
                let w1 = (g1.cos() - g2.cos()) - w2;
                let mean1 = 0.5 * (self.at(a, j - 1) + self.at(b, j - 1));
                let mean2 = 0.5 * (self.at(a, j) + self.at(b, j));
                flux += dc * (w1 * mean1 + w2 * mean2);
            }
        }
        flux
    }

    /// The maximum intensity and its direction (the first grid point that holds it). The
    /// bilinear interpolant takes its maximum on the grid.
    #[must_use]
    pub fn peak(&self) -> Peak {
        let n = self.gamma.len();
        let (k, candela) =
            self.values
                .iter()
                .copied()
                .enumerate()
                .fold((0, f64::NEG_INFINITY), |best, (k, v)| {
                    if v > best.1 {
                        (k, v)
                    } else {
                        best
                    }
                });
        Peak {
            candela,
            c: self.c[k / n],
            gamma: self.gamma[k % n],
        }
    }

    /// The full angle, in the two principal planes, of the cone within which I reaches
    /// `fraction` of I_max (module docs); 0 where no direction does.
    #[must_use]
    pub fn spread(&self, fraction: f64) -> Spread {
        let peak = self.peak();
        let threshold = fraction * peak.candela;
        let from_zenith = peak.gamma > 90.0;
        let half = |c: f64| self.half_angle(c, threshold, from_zenith);
        Spread {
            c0_c180: half(0.0) + half(180.0),
            c90_c270: half(90.0) + half(270.0),
        }
    }

    /// The beam angle: [`Distribution::spread`] at 50 % of I_max.
    #[must_use]
    pub fn beam_angle(&self) -> Spread {
        self.spread(0.5)
    }

    /// The field angle: [`Distribution::spread`] at 10 % of I_max.
    #[must_use]
    pub fn field_angle(&self) -> Spread {
        self.spread(0.1)
    }

    /// On the half-plane at `c`, the largest angle from the beam axis (the nadir, or the zenith
    /// when `from_zenith`) at which I still reaches `threshold`, degrees.
    fn half_angle(&self, c: f64, threshold: f64, from_zenith: bool) -> f64 {
        if threshold.is_nan() || threshold <= 0.0 {
            return 0.0;
        }
        // (angle from the axis, I) along the half-plane, rising in angle; I is piecewise
        // linear in γ between grid angles.
        let row = self.plane(c);
        let mut points: Vec<(f64, f64)> = self.gamma.iter().copied().zip(row).collect();
        if from_zenith {
            points = points
                .into_iter()
                .rev()
                .map(|(g, v)| (180.0 - g, v))
                .collect();
        }
        let Some(k) = points.iter().rposition(|p| p.1 >= threshold) else {
            return 0.0;
        };
        match points.get(k + 1) {
            // I reaches the threshold up to the end of the table, where it drops to zero.
            None => points[k].0,
            Some(&(a2, v2)) => {
                let (a1, v1) = points[k];
                a1 + (v1 - threshold) / (v1 - v2) * (a2 - a1)
            }
        }
    }
}

/// Checks that `angles` rise strictly from 0 or more to `max` or less; else the offending pair
/// (angle, the one before it; the one before the first is 0).
fn rising(angles: &[f64], max: f64) -> Result<(), (f64, f64)> {
    let mut before = 0.0;
    for (k, &a) in angles.iter().enumerate() {
        if !(a.is_finite() && a >= 0.0 && a <= max) || (k > 0 && a <= before) {
            return Err((a, before));
        }
        before = a;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// γ from 0 to 180° in steps of `step`.
    fn gammas(step: f64, last: f64) -> Vec<f64> {
        (0..=(last / step).round() as usize)
            .map(|k| k as f64 * step)
            .collect()
    }

    /// A distribution tabulated from `f(C, γ)` on the planes `c` and angles `g`.
    fn table(
        symmetry: Symmetry,
        c: &[f64],
        g: &[f64],
        f: impl Fn(f64, f64) -> f64,
    ) -> Distribution {
        let values = c
            .iter()
            .flat_map(|&ci| g.iter().map(move |&gj| (ci, gj)))
            .map(|(ci, gj)| f(ci, gj))
            .collect();
        Distribution::new(symmetry, c, g, values).expect("valid table")
    }

    #[test]
    fn an_isotropic_source_integrates_to_four_pi_i() {
        // The weights are exact for a constant, so only rounding remains.
        for step in [1.0, 5.0, 22.5, 90.0, 180.0] {
            let d = table(
                Symmetry::Rotational,
                &[0.0],
                &gammas(step, 180.0),
                |_, _| 250.0,
            );
            assert!(
                (d.flux() - 4.0 * PI * 250.0).abs() < 1e-9,
                "step {step}: {}",
                d.flux()
            );
        }
        // Written in full, with uneven C planes, the same.
        let c = [0.0, 10.0, 45.0, 100.0, 200.0, 300.0, 355.0];
        let d = table(Symmetry::None, &c, &gammas(5.0, 180.0), |_, _| 250.0);
        assert!((d.flux() - 4.0 * PI * 250.0).abs() < 1e-9);
    }

    #[test]
    fn a_lambertian_downlight_integrates_to_pi_i0() {
        // I(γ) = I₀ cos γ for γ ≤ 90°: Φ = 2π I₀ ∫ cos γ sin γ dγ = π I₀. The interpolant of
        // cos on steps h errs by at most h²/8 · I₀, so Φ by at most 2π · h²/8 · I₀, a relative
        // error h²/4 (1.9e-3 at 5°); the chord of a concave function lies below it, so the
        // integral is low.
        let i0 = 1000.0;
        for step in [1.0, 2.5, 5.0] {
            let d = table(Symmetry::Rotational, &[0.0], &gammas(step, 90.0), |_, g| {
                i0 * g.to_radians().cos()
            });
            let h = f64::to_radians(step);
            let exact = PI * i0;
            assert!(
                d.flux() <= exact && d.flux() > exact * (1.0 - h * h / 4.0),
                "{step}: {}",
                d.flux()
            );
        }
    }

    #[test]
    fn interpolation_returns_the_table_at_grid_points_and_between_them_linearly() {
        let c = [0.0, 30.0, 90.0, 180.0, 270.0];
        let g = gammas(15.0, 180.0);
        let f = |c: f64, g: f64| 1.0 + c + 1000.0 * g;
        let d = table(Symmetry::None, &c, &g, f);
        for &ci in &c {
            for &gj in &g {
                assert_eq!(d.intensity_at(ci, gj), f(ci, gj));
                let dir = Distribution::direction(ci, gj);
                if gj > 0.0 && gj < 180.0 {
                    assert!(
                        (d.intensity(dir) - f(ci, gj)).abs() < 1e-6 * f(ci, gj),
                        "{ci} {gj}"
                    );
                }
            }
        }
        // Bilinear inside a cell: at its centre, the mean of its corners.
        assert!((d.intensity_at(15.0, 7.5) - (f(0.0, 0.0) + f(30.0, 15.0)) / 2.0).abs() < 1e-9);
        // Periodic past the last plane: halfway from 270° to 360° = 0°.
        let mid = 0.5 * (d.intensity_at(270.0, 45.0) + d.intensity_at(0.0, 45.0));
        assert!((d.intensity_at(315.0, 45.0) - mid).abs() < 1e-9);
        assert_eq!(d.intensity_at(-45.0, 45.0), d.intensity_at(315.0, 45.0));
    }

    #[test]
    fn the_frame_puts_the_nadir_down_c0_on_x_and_c90_on_y() {
        let d = table(
            Symmetry::None,
            &[0.0, 90.0, 180.0, 270.0],
            &[0.0, 90.0, 180.0],
            |c, g| {
                if g == 90.0 {
                    10.0 + c
                } else if g == 0.0 {
                    1.0
                } else {
                    2.0
                }
            },
        );
        assert_eq!(d.intensity(DVec3::NEG_Z), 1.0);
        assert_eq!(d.intensity(DVec3::Z), 2.0);
        assert_eq!(d.intensity(DVec3::X), 10.0);
        assert_eq!(d.intensity(DVec3::Y), 100.0);
        assert_eq!(d.intensity(DVec3::NEG_X), 190.0);
        assert_eq!(d.intensity(DVec3::NEG_Y * 3.0), 280.0);
        assert_eq!(d.intensity(DVec3::ZERO), 0.0);
        assert_eq!(d.intensity(DVec3::NAN), 0.0);
    }

    #[test]
    fn beyond_the_last_gamma_is_dark() {
        let d = table(Symmetry::Rotational, &[0.0], &gammas(10.0, 90.0), |_, _| {
            5.0
        });
        assert_eq!(d.intensity_at(0.0, 90.0), 5.0);
        assert_eq!(d.intensity_at(0.0, 90.5), 0.0);
        assert_eq!(d.intensity(DVec3::Z), 0.0);
        // Half the isotropic flux.
        assert!((d.flux() - 2.0 * PI * 5.0).abs() < 1e-9);
        let up = table(Symmetry::Rotational, &[0.0], &[90.0, 180.0], |_, _| 5.0);
        assert_eq!(up.intensity(DVec3::NEG_Z), 0.0);
        assert_eq!(up.intensity(DVec3::Z), 5.0);
    }

    #[test]
    fn every_symmetry_expands_to_the_full_table() {
        // A distribution symmetric about both planes, stored each way the symmetries allow.
        let f = |c: f64, g: f64| {
            let (c, g) = (c.to_radians(), g.to_radians());
            100.0 + 40.0 * (2.0 * c).cos() * g.sin() + 20.0 * (4.0 * c).cos() + 10.0 * g.cos()
        };
        let g = gammas(10.0, 180.0);
        let steps = |a: f64, b: f64| -> Vec<f64> {
            (0..=((b - a) / 15.0) as usize)
                .map(|k| a + 15.0 * k as f64)
                .collect()
        };
        let full = table(Symmetry::None, &steps(0.0, 345.0), &g, f);
        let cases = [
            (Symmetry::PlaneC0C180, steps(0.0, 180.0)),
            (Symmetry::PlaneC90C270, steps(90.0, 270.0)),
            (Symmetry::Quadrant, steps(0.0, 90.0)),
        ];
        for (s, c) in cases {
            let d = table(s, &c, &g, f);
            assert_eq!(d.c_angles(), full.c_angles(), "{s:?}");
            // The image −0° of the plane 0° is the plane 0° itself, not a −0° before it.
            assert!(d.c_angles().iter().all(|c| c.is_sign_positive()), "{s:?}");
            // f(C) and f(−C) may differ in the last bit.
            for &c in full.c_angles() {
                for &gj in &g {
                    let (a, b) = (d.intensity_at(c, gj), full.intensity_at(c, gj));
                    assert!((a - b).abs() < 1e-9, "{s:?} at C {c}, γ {gj}: {a} vs {b}");
                }
            }
        }
        // The images of a C90–C270 half that wraps through 0° (EULUMDAT Isym 3).
        let wrap: Vec<f64> = steps(270.0, 345.0)
            .into_iter()
            .chain(steps(0.0, 90.0))
            .collect();
        // Not rising as given: the EULUMDAT reader rotates such a list first.
        assert!(Distribution::new(
            Symmetry::PlaneC90C270,
            &wrap,
            &g,
            vec![0.0; wrap.len() * g.len()]
        )
        .is_err());
    }

    #[test]
    fn peak_beam_and_field_of_a_cosine_power_spot() {
        // I = I₀ cosⁿ γ: I/I₀ = 1/2 at γ = acos(2^(−1/n)), the beam half-angle.
        let n = 8.0;
        let d = table(Symmetry::Rotational, &[0.0], &gammas(0.5, 90.0), |_, g| {
            500.0 * g.to_radians().cos().powf(n)
        });
        let p = d.peak();
        assert_eq!((p.candela, p.gamma), (500.0, 0.0));
        let beam = d.beam_angle();
        let exact = 2.0 * 0.5f64.powf(1.0 / n).acos().to_degrees();
        // Linear interpolation between 0.5° steps: well inside 0.05°.
        assert!((beam.c0_c180 - exact).abs() < 0.05, "{beam:?} vs {exact}");
        assert_eq!(beam.c0_c180, beam.c90_c270);
        let field = d.field_angle();
        let exact = 2.0 * 0.1f64.powf(1.0 / n).acos().to_degrees();
        assert!((field.c0_c180 - exact).abs() < 0.05, "{field:?} vs {exact}");
        // An uplight's beam is measured from the zenith.
        let up = table(Symmetry::Rotational, &[0.0], &gammas(0.5, 180.0), |_, g| {
            500.0 * (-g.to_radians().cos()).max(0.0).powf(n)
        });
        assert!((up.beam_angle().c0_c180 - beam.c0_c180).abs() < 1e-9);
    }

    #[test]
    fn malformed_tables_are_errors() {
        let g = [0.0, 90.0];
        let bad = |s, c: &[f64], g: &[f64], v: Vec<f64>| Distribution::new(s, c, g, v).is_err();
        assert!(bad(Symmetry::None, &[], &g, vec![]));
        assert!(bad(Symmetry::Rotational, &[0.0, 90.0], &g, vec![1.0; 4]));
        assert!(bad(Symmetry::None, &[0.0], &g, vec![1.0; 3]));
        assert!(bad(Symmetry::None, &[0.0], &[0.0, 0.0], vec![1.0; 2]));
        assert!(bad(Symmetry::None, &[0.0], &[0.0, 190.0], vec![1.0; 2]));
        assert!(bad(Symmetry::None, &[0.0, 400.0], &g, vec![1.0; 4]));
        assert!(bad(Symmetry::None, &[0.0], &g, vec![1.0, -1.0]));
        assert!(bad(Symmetry::None, &[0.0], &g, vec![1.0, f64::NAN]));
        assert!(bad(Symmetry::None, &[0.0], &[f64::NAN, 1.0], vec![1.0; 2]));
    }
}
