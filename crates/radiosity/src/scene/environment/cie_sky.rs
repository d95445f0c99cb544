//! The CIE standard skies: the sky luminance distributions daylighting standards compute with.
//!
//! - **CIE standard overcast sky** (Moon & Spencer 1942, adopted by the CIE in 1955): brightest
//!   at the zenith, a third of that at the horizon, the same in every azimuth,
//!
//!   ```text
//!   L(Z) = L_z (1 + 2 cos Z) / 3,
//!   ```
//!
//!   Z the angle from the zenith. Its unobstructed horizontal illuminance has a closed form,
//!   E_h = ∫ L cos Z dω = 2π L_z ∫₀^{π/2} (1 + 2 cos Z)/3 · cos Z sin Z dZ = 7π L_z / 9; the
//!   *daylight factor* of a point is its illuminance over E_h.
//! - **CIE standard general sky** (ISO 15469:2004 / CIE S 011/E:2003; Kittler, Perez & Darula
//!   1998): fifteen types, each a *gradation* φ(Z) of luminance with height and an *indicatrix*
//!   f(χ) of scattering around the sun, χ the angle between the sky element and the sun, Z_s
//!   the sun's angle from the zenith:
//!
//!   ```text
//!   L / L_z = f(χ) φ(Z) / (f(Z_s) φ(0)),
//!   φ(Z) = 1 + a exp(b / cos Z)                 (φ = 1 at the horizon),
//!   f(χ) = 1 + c (exp(d χ) − exp(d π/2)) + e cos² χ.
//!   ```
//!
//!   | type | description | a | b | c | d | e |
//!   |---|---|---|---|---|---|---|
//!   | 1 | overcast, steep gradation towards the zenith, azimuthal uniformity | 4.0 | −0.70 | 0 | −1.0 | 0 |
//!   | 12 | CIE standard clear sky, low illuminance turbidity | −1.0 | −0.32 | 10 | −3.0 | 0.45 |
//!
//! The luminance is white (the same on the three channels) in cd·m⁻², so the illuminances the
//! grids read are in lx. Below the horizon the sky sends nothing: the ground is the scene's.

use glam::{DVec3, Vec3};

/// Which CIE sky.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CieSkyKind {
    /// The CIE standard overcast sky (1 + 2 cos Z)/3.
    Overcast,
    /// General sky type 1 (overcast, azimuthally uniform).
    Type1,
    /// General sky type 12 (CIE standard clear sky, low turbidity): needs the sun's position.
    Type12,
}

impl CieSkyKind {
    /// The scene-file names, in order.
    pub const NAMES: [&'static str; 3] = ["cie-overcast", "cie-1", "cie-12"];

    /// The kind named `name` in a scene file.
    #[must_use]
    pub fn named(name: &str) -> Option<Self> {
        match name {
            "cie-overcast" => Some(Self::Overcast),
            "cie-1" => Some(Self::Type1),
            "cie-12" => Some(Self::Type12),
            _ => None,
        }
    }

    /// Gradation a, b and indicatrix c, d, e of a general sky type (module docs).
    fn parameters(self) -> Option<[f64; 5]> {
        match self {
            Self::Overcast => None,
            Self::Type1 => Some([4.0, -0.70, 0.0, -1.0, 0.0]),
            Self::Type12 => Some([-1.0, -0.32, 10.0, -3.0, 0.45]),
        }
    }
}

/// A CIE sky in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct CieSky {
    /// Which distribution.
    pub kind: CieSkyKind,
    /// The zenith's luminance L_z, cd·m⁻².
    pub zenith_luminance: f64,
    /// Unit vector towards the sun (used by the types whose indicatrix is not uniform).
    pub sun_direction: Vec3,
    /// The zenith (unit).
    pub up: Vec3,
}

impl CieSky {
    /// The luminance towards unit `dir`, cd·m⁻² (0 below the horizon).
    #[must_use]
    pub fn luminance(&self, dir: DVec3) -> f64 {
        let cos_z = dir.dot(self.up.as_dvec3());
        if cos_z <= 0.0 {
            return 0.0;
        }
        self.zenith_luminance * self.relative(cos_z.min(1.0), dir)
    }

    /// L / L_z at zenith-angle cosine `cos_z` in unit direction `dir`.
    fn relative(&self, cos_z: f64, dir: DVec3) -> f64 {
        let Some([a, b, c, d, e]) = self.kind.parameters() else {
            return (1.0 + 2.0 * cos_z) / 3.0;
        };
        let gradation = |cos: f64| {
            if cos <= 0.0 {
                1.0
            } else {
                1.0 + a * (b / cos).exp()
            }
        };
        let indicatrix = |chi: f64| {
            1.0 + c * ((d * chi).exp() - (d * std::f64::consts::FRAC_PI_2).exp())
                + e * chi.cos().powi(2)
        };
        let sun = self.sun_direction.as_dvec3();
        let chi = dir.dot(sun).clamp(-1.0, 1.0).acos();
        let z_sun = self.up.as_dvec3().dot(sun).clamp(-1.0, 1.0).acos();
        indicatrix(chi) * gradation(cos_z) / (indicatrix(z_sun) * gradation(1.0))
    }

    /// The unobstructed horizontal illuminance E_h = ∫ L cos Z dω over the sky, lx: 7π L_z / 9
    /// for the overcast sky, else by the midpoint rule on 360 × 720 cells of (cos² Z, azimuth)
    /// (uniform in the cosine-weighted measure, so each cell weighs alike).
    #[must_use]
    pub fn horizontal_illuminance(&self) -> f64 {
        if self.kind == CieSkyKind::Overcast {
            return 7.0 * std::f64::consts::PI * self.zenith_luminance / 9.0;
        }
        self.quadrature()
    }

    /// E_h by the midpoint rule ([`CieSky::horizontal_illuminance`]).
    fn quadrature(&self) -> f64 {
        let up = self.up.as_dvec3();
        let (t, b) = up.any_orthonormal_pair();
        let (rings, sectors) = (360, 720);
        let mut sum = 0.0;
        for i in 0..rings {
            // cos² Z uniform: dω cos Z = π d(sin² Z) / (2π) dφ.
            let s2 = (f64::from(i) + 0.5) / f64::from(rings);
            let (sin_z, cos_z) = (s2.sqrt(), (1.0 - s2).sqrt());
            for k in 0..sectors {
                let phi = std::f64::consts::TAU * (f64::from(k) + 0.5) / f64::from(sectors);
                let dir = up * cos_z + (t * phi.cos() + b * phi.sin()) * sin_z;
                sum += self.luminance(dir);
            }
        }
        std::f64::consts::PI * sum / f64::from(rings * sectors)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sky(kind: CieSkyKind, sun: Vec3) -> CieSky {
        CieSky {
            kind,
            zenith_luminance: 1000.0,
            sun_direction: sun.normalize(),
            up: Vec3::Y,
        }
    }

    /// Every type is L_z at the zenith; the overcast sky a third of it at the horizon, and
    /// type 1, its general-sky counterpart, 1/(1 + 4 e^-0.7) = 0.3349 of it there.
    #[test]
    fn zenith_and_horizon_follow_the_formulas() {
        let sun = Vec3::new(0.0, 0.6, 0.8);
        for kind in [CieSkyKind::Overcast, CieSkyKind::Type1, CieSkyKind::Type12] {
            let l = sky(kind, sun).luminance(DVec3::Y);
            assert!((l - 1000.0).abs() < 1e-9, "{kind:?}: {l}");
        }
        let horizon = DVec3::new(1.0, 1e-12, 0.0).normalize();
        let overcast = sky(CieSkyKind::Overcast, sun).luminance(horizon);
        assert!((overcast - 1000.0 / 3.0).abs() < 1e-6);
        let type1 = sky(CieSkyKind::Type1, sun).luminance(horizon);
        assert!((type1 / 1000.0 - 1.0 / (1.0 + 4.0 * (-0.7f64).exp())).abs() < 1e-9);
        assert_eq!(sky(CieSkyKind::Overcast, sun).luminance(-DVec3::Y), 0.0);
    }

    /// The quadrature of the general types, run on the overcast sky, meets its closed form
    /// 7π L_z/9; the clear sky is brighter towards the sun than away from it.
    #[test]
    fn the_horizontal_illuminance_meets_the_closed_form() {
        let s = sky(CieSkyKind::Overcast, Vec3::Y);
        let exact = 7.0 * std::f64::consts::PI * 1000.0 / 9.0;
        assert_eq!(s.horizontal_illuminance(), exact);
        assert!(
            (s.quadrature() / exact - 1.0).abs() < 1e-5,
            "{}",
            s.quadrature()
        );
        // Type 1 integrates to within a few per cent of the overcast sky it approximates.
        let t1 = sky(CieSkyKind::Type1, Vec3::Y).horizontal_illuminance();
        assert!((t1 / exact - 1.0).abs() < 0.05, "{t1} {exact}");
        let clear = sky(CieSkyKind::Type12, Vec3::new(0.0, 0.5, 0.866));
        let towards = clear.luminance(DVec3::new(0.0, 0.5, 0.866));
        let away = clear.luminance(DVec3::new(0.0, 0.5, -0.866));
        assert!(towards > 3.0 * away, "{towards} {away}");
    }
}
