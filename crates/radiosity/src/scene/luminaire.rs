//! Luminaires: light that leaves a point with a measured distribution of intensity.
//!
//! A luminaire far from what it lights (a few times its own size away, the photometric
//! distance of CIE 121) acts as a point source of luminous intensity I(ω), candela = lm/sr,
//! which falls on a surface at distance r, seen under the angle θ from its normal, as
//!
//! ```text
//! E = I(ω) · cos θ / r²            (the inverse-square and cosine laws)
//! ```
//!
//! I(ω) is the table of a photometric file ([`crate::photometry::Distribution`], IES LM-63 or
//! EULUMDAT) in the luminaire's own frame: −Z the nadir (the scene's `aim`), +X the C0 plane,
//! +Y the C90 plane. The shorthand `point` and `spot` lights are distributions too, written
//! here: a point light I(ω) = I₀ in every direction, a spot I₀ inside its beam, falling to 0 at
//! its cone's edge ([`Falloff`]: as the square of a linear ramp in cos γ, the attenuation glTF's
//! `KHR_lights_punctual` specifies, or linearly in γ, as Mitsuba's `spot`).
//!
//! A luminaire close to what it lights is better taken by its *luminous opening*, the
//! emitting rectangle its photometric file declares: the intensity is then shared among
//! [`OPENING_SIDE`]² points stratified over the opening (each I(ω)/N from its own place, with
//! its own shadow ray), which gives soft shadows and the near field's falloff. A round opening
//! is sampled as the ellipse inscribed in its rectangle (the points of the square grid mapped to
//! the disc by Shirley & Chiu's concentric map, 1997).
//!
//! A white luminaire's candela fill the three channels, so its radiometric numbers read
//! directly as photometric ones (cd, lm, lx); a colour tints the channels at a luminance of 1.
//! The distances of the inverse-square law are in metres, whatever the scene's length unit.
//!
//! ## Directional light
//!
//! A source so far away that its rays arrive parallel (the sun's beam; glTF's and Mitsuba's
//! `directional` lights) has no position and no finite intensity: it is given by the
//! illuminance E⊥ it makes on a plane facing it, and lights a surface turned θ from it with
//!
//! ```text
//! E = E⊥ · cos θ                   (no falloff with distance)
//! ```
//!
//! where nothing stands between the surface and the light. Its shadow ray leaves the scene:
//! it runs the length of the bounds' diagonal towards the light ([`Luminaire::within`]), far
//! enough to cross every object and short of a far environment's enclosure. What it emits is
//! counted as what crosses the disc of the sphere around the bounds, E⊥ · π R², the most the
//! scene can take from it.

use std::sync::Arc;

use glam::{DVec3, Vec3};

use crate::photometry::{Distribution, Symmetry};
use crate::Rgb;

/// Side of the grid of points over a luminous opening (64 points).
pub const OPENING_SIDE: u32 = 8;

/// Steps of the γ table of a spot's falloff, between its beam and its cone.
const SPOT_STEPS: usize = 64;

/// A luminaire placed in the scene: a point source (its position or its opening) or a
/// directional light.
#[derive(Clone, Debug, PartialEq)]
pub struct Luminaire {
    /// The object's name.
    pub name: String,
    /// How its light travels.
    throw: Throw,
    /// The colour tint (luminance 1) times the light-loss multiplier, per channel.
    tint: Rgb,
}

/// How a luminaire's light reaches what it lights (module docs).
#[derive(Clone, Debug, PartialEq)]
enum Throw {
    /// From points in the scene, falling off by the inverse-square law.
    Radial {
        /// Where the light leaves (the opening's centre), scene units.
        position: Vec3,
        /// The points the light leaves from: the position alone, or points over the opening.
        sources: Vec<Vec3>,
        /// The luminaire frame in scene axes: the C0 axis (+X), the C90 axis (+Y) and the
        /// zenith (+Z, opposite the aim).
        axes: [DVec3; 3],
        /// I(C, γ) of a white luminaire, cd.
        distribution: Arc<Distribution>,
        /// 1 / (metres per scene unit)²: turns 1/r² in scene units into 1/r² in metres.
        per_square_unit: f64,
    },
    /// In parallel from far away.
    Parallel {
        /// Towards the light (unit).
        toward: Vec3,
        /// The length of a shadow ray, scene units (infinite until [`Luminaire::within`]).
        reach: f32,
        /// The area its flux is counted on, scene units² (0 until [`Luminaire::within`]).
        section: f64,
        /// Metres per scene unit.
        metres: f64,
    },
}

impl Luminaire {
    /// A luminaire of distribution `distribution` at `position`, its nadir along `aim` and its
    /// C0 plane turned `rotation` degrees about it (counter-clockwise seen from above, against
    /// the aim) from the plane that holds the scene's +X (+Z when the aim is along X); `tint`
    /// scales the channels; `metres` is the scene's length unit in metres.
    #[must_use]
    pub fn new(
        name: &str,
        position: Vec3,
        aim: Vec3,
        rotation: f64,
        distribution: Arc<Distribution>,
        tint: Rgb,
        metres: f64,
    ) -> Self {
        let zenith = -aim.as_dvec3().normalize();
        let reference = if zenith.x.abs() > 0.9 {
            DVec3::Z
        } else {
            DVec3::X
        };
        let c0 = (reference - zenith * reference.dot(zenith)).normalize();
        let c90 = zenith.cross(c0);
        let (s, c) = rotation.to_radians().sin_cos();
        let x = c0 * c + c90 * s;
        let y = zenith.cross(x);
        Self {
            name: name.to_string(),
            throw: Throw::Radial {
                position,
                sources: vec![position],
                axes: [x, y, zenith],
                distribution,
                per_square_unit: 1.0 / (metres * metres),
            },
            tint,
        }
    }

    /// A directional light whose rays travel along `aim`, making the illuminance
    /// `illuminance` (lx, or W·m⁻² per channel) on a plane facing it; `metres` is the scene's
    /// length unit in metres. Its shadows need the scene's bounds: [`Luminaire::within`].
    #[must_use]
    pub fn directional(name: &str, aim: Vec3, illuminance: Rgb, metres: f64) -> Self {
        Self {
            name: name.to_string(),
            throw: Throw::Parallel {
                toward: -aim.normalize(),
                reach: f32::INFINITY,
                section: 0.0,
                metres,
            },
            tint: illuminance,
        }
    }

    /// The same luminaire shining from its luminous opening instead of its centre: a `length`
    /// × `width` rectangle (scene units) along its C0 and C90 axes about the position,
    /// `round` for the ellipse inscribed in it (module docs). A directional light is left as
    /// it is.
    #[must_use]
    pub fn with_opening(mut self, length: f64, width: f64, round: bool) -> Self {
        if let Throw::Radial {
            position,
            sources,
            axes,
            ..
        } = &mut self.throw
        {
            let n = OPENING_SIDE;
            *sources = (0..n * n)
                .map(|k| {
                    let u = 2.0 * ((k % n) as f64 + 0.5) / f64::from(n) - 1.0;
                    let v = 2.0 * ((k / n) as f64 + 0.5) / f64::from(n) - 1.0;
                    let (a, b) = if round { concentric(u, v) } else { (u, v) };
                    let offset = axes[0] * (0.5 * length * a) + axes[1] * (0.5 * width * b);
                    *position + offset.as_vec3()
                })
                .collect();
        }
        self
    }

    /// Fits a directional light to the scene's bounds `[lo, hi]` (the objects it lights, no
    /// far environment): its shadow rays run the bounds' diagonal, its flux is counted on the
    /// disc of the sphere around them (module docs). A point luminaire is left as it is.
    pub fn within(&mut self, lo: Vec3, hi: Vec3) {
        if let Throw::Parallel { reach, section, .. } = &mut self.throw {
            let diagonal = (hi - lo).length();
            *reach = diagonal.max(f32::MIN_POSITIVE.sqrt());
            *section = std::f64::consts::PI * f64::from(0.5 * diagonal).powi(2);
        }
    }

    /// Where the light leaves, scene units; `None` for a directional light.
    #[must_use]
    pub fn position(&self) -> Option<Vec3> {
        match &self.throw {
            Throw::Radial { position, .. } => Some(*position),
            Throw::Parallel { .. } => None,
        }
    }

    /// The points the light leaves from, each with 1/N of the intensity (none for a
    /// directional light).
    #[must_use]
    pub fn sources(&self) -> &[Vec3] {
        match &self.throw {
            Throw::Radial { sources, .. } => sources,
            Throw::Parallel { .. } => &[],
        }
    }

    /// The light that may reach a surface at `point` of unit normal `normal`: for each of
    /// its sources, the far end of the shadow ray that decides whether it arrives (a source
    /// point, or the end of the ray towards a directional light) and the irradiance it
    /// brings if it does. Zero where the surface faces away.
    pub fn arrivals(&self, point: Vec3, normal: Vec3) -> impl Iterator<Item = (Vec3, Rgb)> + '_ {
        let parallel = match &self.throw {
            Throw::Radial { .. } => None,
            Throw::Parallel { toward, reach, .. } => {
                let cos = f64::from(normal.dot(*toward)).max(0.0);
                Some((point + *toward * *reach, self.tint * cos))
            }
        };
        self.sources()
            .iter()
            .map(move |&from| (from, self.irradiance_from(from, point, normal)))
            .chain(parallel)
    }

    /// The irradiance that source point `from` (one of [`Luminaire::sources`]) sends to a
    /// surface at `point` of unit normal `normal`, shadows aside.
    #[must_use]
    pub fn irradiance_from(&self, from: Vec3, point: Vec3, normal: Vec3) -> Rgb {
        let Throw::Radial {
            sources,
            per_square_unit,
            ..
        } = &self.throw
        else {
            return Rgb::ZERO;
        };
        let w = from - point;
        let r2 = f64::from(w.length_squared());
        let cos = f64::from(normal.dot(w)) / r2.sqrt();
        if !(r2 > 0.0 && cos > 0.0) {
            return Rgb::ZERO;
        }
        self.intensity(-w) * (cos / r2 * per_square_unit / sources.len() as f64)
    }

    /// The intensity towards the direction `dir` (scene axes, from the luminaire; need not be
    /// normalized), per channel; zero for a directional light, which has no finite one.
    #[must_use]
    pub fn intensity(&self, dir: Vec3) -> Rgb {
        let Throw::Radial {
            axes, distribution, ..
        } = &self.throw
        else {
            return Rgb::ZERO;
        };
        let d = dir.as_dvec3();
        let local = DVec3::new(axes[0].dot(d), axes[1].dot(d), axes[2].dot(d));
        self.tint * distribution.intensity(local)
    }

    /// The irradiance it sends to a surface at `point` of unit normal `normal`, shadows
    /// aside: Σ over its sources of I(ω) cos θ / (N r²), r in metres, or E⊥ cos θ for a
    /// directional light; zero behind the surface.
    #[must_use]
    pub fn irradiance(&self, point: Vec3, normal: Vec3) -> Rgb {
        self.arrivals(point, normal).map(|(_, e)| e).sum()
    }

    /// The luminous (or radiant) flux it emits, per channel: Φ = ∫ I dΩ (lm for a white
    /// luminaire), or E⊥ · π R² for a directional light (module docs).
    #[must_use]
    pub fn flux(&self) -> Rgb {
        match &self.throw {
            Throw::Radial { distribution, .. } => self.tint * distribution.flux(),
            Throw::Parallel {
                section, metres, ..
            } => self.tint * (section * metres * metres),
        }
    }

    /// The flux in the scene's power units (Φ over the square of metres per unit), which
    /// the radiosity's Σ A·B is measured in.
    #[must_use]
    pub fn scene_power(&self) -> Rgb {
        match &self.throw {
            Throw::Radial {
                per_square_unit, ..
            } => self.flux() * *per_square_unit,
            Throw::Parallel { section, .. } => self.tint * *section,
        }
    }
}

/// Shirley & Chiu's concentric map of the square [−1, 1]² onto the unit disc.
fn concentric(u: f64, v: f64) -> (f64, f64) {
    use std::f64::consts::FRAC_PI_4;
    if u == 0.0 && v == 0.0 {
        return (0.0, 0.0);
    }
    let (r, phi) = if u.abs() > v.abs() {
        (u, FRAC_PI_4 * (v / u))
    } else {
        (v, 2.0 * FRAC_PI_4 - FRAC_PI_4 * (u / v))
    };
    (r * phi.cos(), r * phi.sin())
}

/// The distribution of a point light of intensity `candela` in every direction.
///
/// # Panics
/// Never for a finite, non-negative intensity (checked when the scene is).
#[must_use]
pub fn isotropic(candela: f64) -> Distribution {
    Distribution::new(
        Symmetry::Rotational,
        &[0.0],
        &[0.0, 180.0],
        vec![candela; 2],
    )
    .expect("a finite, non-negative intensity")
}

/// How a spot's intensity falls from its beam (half-angle β) to its cone's edge (κ).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Falloff {
    /// ((cos γ − cos κ) / (cos β − cos κ))², glTF's `KHR_lights_punctual`.
    SquaredCosineRamp,
    /// (κ − γ) / (κ − β), Mitsuba 3's `spot`.
    LinearAngle,
}

impl Falloff {
    /// The factor at angle `gamma` between `beam` and `cone` (degrees), in [0, 1].
    fn at(self, gamma: f64, beam: f64, cone: f64) -> f64 {
        let t = match self {
            Self::SquaredCosineRamp => {
                let c = |a: f64| a.to_radians().cos();
                ((c(gamma) - c(cone)) / (c(beam) - c(cone)))
                    .clamp(0.0, 1.0)
                    .powi(2)
            }
            Self::LinearAngle => (cone - gamma) / (cone - beam),
        };
        t.clamp(0.0, 1.0)
    }
}

/// The distribution of a spot of intensity `candela` on its axis, full out to the half-angle
/// `beam` and falling to 0 at the half-angle `cone` (degrees, 0 ≤ beam < cone ≤ 180) as
/// `falloff` says.
///
/// # Panics
/// Never for a finite, non-negative intensity and angles in order (checked when the scene
/// is).
#[must_use]
pub fn spot(candela: f64, beam: f64, cone: f64, falloff: Falloff) -> Distribution {
    let mut gamma = vec![0.0];
    gamma.extend((0..=SPOT_STEPS).map(|k| beam + (cone - beam) * k as f64 / SPOT_STEPS as f64));
    if cone < 180.0 {
        gamma.push(180.0);
    }
    gamma.dedup();
    let values = gamma
        .iter()
        .map(|&g| candela * falloff.at(g, beam, cone))
        .collect();
    Distribution::new(Symmetry::Rotational, &[0.0], &gamma, values)
        .expect("a finite, non-negative intensity and rising angles")
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;

    fn lamp(distribution: Distribution, aim: Vec3, metres: f64) -> Luminaire {
        Luminaire::new(
            "lamp",
            Vec3::new(0.0, 2.0, 0.0),
            aim,
            0.0,
            Arc::new(distribution),
            Rgb::ONE,
            metres,
        )
    }

    #[test]
    fn a_point_light_follows_the_inverse_square_and_cosine_laws() {
        let l = lamp(isotropic(100.0), Vec3::NEG_Y, 1.0);
        // Straight below at 2 m: 100 / 4 = 25 lx.
        let below = l.irradiance(Vec3::ZERO, Vec3::Y);
        assert!(
            (below - Rgb::splat(25.0)).abs().max_element() < 1e-9,
            "{below}"
        );
        // 2 m aside: r² = 8, cos θ = 2/√8.
        let aside = l.irradiance(Vec3::new(2.0, 0.0, 0.0), Vec3::Y).x;
        assert!(
            (aside - 100.0 / 8.0 * (2.0 / 8f64.sqrt())).abs() < 1e-9,
            "{aside}"
        );
        // Behind the surface: nothing.
        assert_eq!(l.irradiance(Vec3::ZERO, Vec3::NEG_Y), Rgb::ZERO);
        // Φ = 4π I.
        assert!((l.flux().y - 400.0 * PI).abs() < 1e-9);
        // In millimetres the same lamp 2 mm up gives 10⁶ times as much.
        let mm = lamp(isotropic(100.0), Vec3::NEG_Y, 1e-3);
        assert!((mm.irradiance(Vec3::ZERO, Vec3::Y).x / 25e6 - 1.0).abs() < 1e-9);
    }

    #[test]
    fn a_spot_lights_its_cone_only_and_its_flux_is_the_closed_form() {
        let l = lamp(
            spot(1000.0, 20.0, 30.0, Falloff::SquaredCosineRamp),
            Vec3::NEG_Y,
            1.0,
        );
        let at = |deg: f64| {
            l.intensity(Vec3::new(
                deg.to_radians().sin() as f32,
                -(deg.to_radians().cos() as f32),
                0.0,
            ))
            .x
        };
        assert!((at(0.0) - 1000.0).abs() < 1e-9);
        assert!((at(19.0) - 1000.0).abs() < 1e-6);
        assert!(at(31.0) == 0.0 && at(90.0) == 0.0);
        let mid = at(25.0);
        let ramp = (25f64.to_radians().cos() - 30f64.to_radians().cos())
            / (20f64.to_radians().cos() - 30f64.to_radians().cos());
        assert!((mid / (1000.0 * ramp * ramp) - 1.0).abs() < 2e-3, "{mid}");
        // Φ = 2π I₀ [(1 − cos β) + ∫ ramp² d(cos γ)], the ramp's integral (cos β − cos κ) / 3.
        let (cb, ck) = (20f64.to_radians().cos(), 30f64.to_radians().cos());
        let exact = 2.0 * PI * 1000.0 * ((1.0 - cb) + (cb - ck) / 3.0);
        assert!(
            (l.flux().x / exact - 1.0).abs() < 2e-3,
            "{} {exact}",
            l.flux().x
        );
    }

    #[test]
    fn an_opening_keeps_the_far_field_and_softens_the_near_one() {
        let point = lamp(isotropic(100.0), Vec3::NEG_Y, 1.0);
        let panel = lamp(isotropic(100.0), Vec3::NEG_Y, 1.0).with_opening(0.6, 0.6, false);
        assert_eq!(panel.sources().len(), 64);
        // Far away the opening is a point: within (0.3 / 40)² of it.
        let far = Vec3::new(40.0, 2.0, 0.0);
        let (p, q) = (
            point.irradiance(far, Vec3::NEG_X),
            panel.irradiance(far, Vec3::NEG_X),
        );
        assert!((q.x / p.x - 1.0).abs() < 1e-4, "{p} {q}");
        // The flux is the distribution's, wherever it leaves from.
        assert_eq!(panel.flux(), point.flux());
        // Close under it, the spread points are farther on average: less light.
        let near = Vec3::new(0.0, 1.8, 0.0);
        assert!(panel.irradiance(near, Vec3::Y).x < point.irradiance(near, Vec3::Y).x);
        // A round opening's points lie in the inscribed disc.
        let round = lamp(isotropic(1.0), Vec3::NEG_Y, 1.0).with_opening(0.6, 0.6, true);
        let c = round.position().unwrap();
        assert!(round
            .sources()
            .iter()
            .all(|s| (*s - c).length() <= 0.3 + 1e-6));
    }

    #[test]
    fn the_frame_follows_the_aim_and_the_rotation() {
        // A table lit only in the C0 half-space (I = 100 at C 0°, 0 at C 180°), aimed down:
        // the C0 plane holds +X, so a point below and to +X is lit, one to −X is not.
        let d = Distribution::new(
            Symmetry::None,
            &[0.0, 90.0, 180.0, 270.0],
            &[0.0, 90.0],
            vec![100.0, 100.0, 50.0, 50.0, 0.0, 0.0, 50.0, 50.0],
        )
        .unwrap();
        let l = lamp(d.clone(), Vec3::NEG_Y, 1.0);
        assert!(l.irradiance(Vec3::new(1.0, 0.0, 0.0), Vec3::Y).x > 10.0);
        assert!(l.irradiance(Vec3::new(-1.0, 0.0, 0.0), Vec3::Y).x < 1e-9);
        // Turned 180° about the aim, the other way round.
        let turned = Luminaire::new(
            "lamp",
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::NEG_Y,
            180.0,
            Arc::new(d),
            Rgb::ONE,
            1.0,
        );
        assert!(turned.irradiance(Vec3::new(1.0, 0.0, 0.0), Vec3::Y).x < 1e-9);
        assert!(turned.irradiance(Vec3::new(-1.0, 0.0, 0.0), Vec3::Y).x > 10.0);
    }
}
