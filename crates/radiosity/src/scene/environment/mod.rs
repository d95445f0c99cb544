//! Light from far away: a uniform environment, a radiance map, or the sun and sky, as the
//! published scene formats declare them (Mitsuba's `constant`, `envmap` and `sunsky` emitters).
//!
//! A radiosity solver exchanges light between surfaces, so distant light enters the scene as
//! one more surface: an inward-facing, non-reflecting box around the scene (as the default sky,
//! [`super::sky`], does), whose faces emit, in every direction ω they are seen from, the
//! environment's radiance L_env(ω). A uniform environment is exact on a box of any size; a map
//! or a sun is carried by tiles of the box, each emitting the map's mean radiance over the solid
//! angle it covers as seen from the scene's centre.
//!
//! | variant | enclosure | radiance |
//! |---|---|---|
//! | [`Environment::Constant`] | the default sky's box ([`super::enclosure`]), one material | exact |
//! | [`Environment::Map`] | a far cube split into tiles ([`tiles`]) | the map's mean over each tile, Mitsuba 3's mapping ([`latlong`]) |
//! | [`Environment::SunSky`] | tiles, and the sun as a disc ([`Disc`]) in front of them | Preetham et al. 1999 ([`daylight`]) |
//! | [`Environment::Cie`] | tiles | the CIE standard skies ([`cie_sky`]) |
//!
//! One function, [`Distant::radiance`], is L_env(ω): the tiles integrate it, and
//! [`latlong::rasterize`] writes it as a map a path tracer can use in place of the scene's own
//! emitter, so both see the same light.

pub mod cie_sky;
pub mod daylight;
pub mod latlong;
pub mod solar;
pub mod tiles;

use std::path::PathBuf;

use glam::{DVec3, Mat4, Vec3};

use super::{enclosure, sky, Scene, SceneError};
use crate::Rgb;
pub use cie_sky::{CieSky, CieSkyKind};
pub use daylight::Daylight;
pub use latlong::LatLong;

/// The name of the environment's object and materials.
pub const NAME: &str = "environment";

/// Distant light declared by a scene file.
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    /// The same radiance from every direction (Mitsuba `constant`, `radiance`).
    Constant {
        /// Radiance, W·m⁻²·sr⁻¹ per channel.
        radiance: Rgb,
    },
    /// A latitude-longitude radiance map (Mitsuba `envmap`).
    Map {
        /// The image (EXR, HDR, PFM or PNG), already resolved against the scene's folder.
        path: PathBuf,
        /// `scale`, multiplying the map's values.
        scale: f64,
        /// `to_world`: the map's frame (its +y is the map's up) in world space.
        to_world: Mat4,
    },
    /// The sun and a clear sky (Mitsuba 0.6 `sunsky`/`sun`/`sky`, Mitsuba 3 `sunsky`).
    SunSky(SunSky),
    /// A CIE standard sky (a scene file's `[sky]`).
    Cie(CieSky),
}

/// The parameters of a sun and sky, in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct SunSky {
    /// Unit vector from the scene towards the sun.
    pub sun_direction: Vec3,
    /// The world's up (the sky's zenith): +y for Mitsuba 0.6 files, the `to_world` image of +z
    /// for Mitsuba 3 files.
    pub up: Vec3,
    /// Atmospheric turbidity (2 = very clear, 10 = hazy).
    pub turbidity: f64,
    /// Ground albedo.
    pub albedo: f64,
    /// Multiplier of the sky's radiance (0.6 `skyScale`, 3 `sky_scale`).
    pub sky_scale: f64,
    /// Multiplier of the sun's radiance (0.6 `sunScale`, 3 `sun_scale`); 0 for a sky alone.
    pub sun_scale: f64,
    /// The sun's angular radius in degrees (0.6: [`daylight::SUN_RADIUS_DEG`] = 0.2679 ×
    /// `sunRadiusScale`; 3: `sun_aperture` / 2); 0 for the sun's own.
    pub sun_radius_deg: f64,
    /// Whether the sky is drawn (false for a sun alone).
    pub sky: bool,
}

/// A bright disc of directions: the sun.
#[derive(Clone, Debug, PartialEq)]
pub struct Disc {
    /// Its centre (unit).
    pub axis: DVec3,
    /// Its angular radius, radians.
    pub radius: f64,
    /// The radiance it adds inside, W·m⁻²·sr⁻¹ per channel.
    pub radiance: Rgb,
}

impl Disc {
    /// Whether unit `dir` is inside.
    #[must_use]
    pub fn contains(&self, dir: DVec3) -> bool {
        self.axis.dot(dir) >= self.radius.cos()
    }

    /// Its solid angle, 2π (1 − cos r).
    #[must_use]
    pub fn solid_angle(&self) -> f64 {
        std::f64::consts::TAU * (1.0 - self.radius.cos())
    }
}

/// An environment's radiance in every direction, L_env(ω), the map read and the sky model
/// prepared.
#[derive(Clone, Debug, PartialEq)]
pub enum Distant {
    /// The same radiance everywhere.
    Constant(Rgb),
    /// A latitude-longitude map.
    Map(LatLong),
    /// The sun and sky.
    Daylight(Daylight),
    /// A CIE standard sky, its luminance on the three channels.
    Cie(CieSky),
}

impl Distant {
    /// L_env towards unit `dir` (world space), W·m⁻²·sr⁻¹ per channel.
    #[must_use]
    pub fn radiance(&self, dir: DVec3) -> Rgb {
        match self {
            Self::Constant(l) => *l,
            Self::Map(map) => map.radiance(dir),
            Self::Daylight(daylight) => daylight.radiance(dir),
            Self::Cie(sky) => Rgb::splat(sky.luminance(dir)),
        }
    }

    /// The disc that holds a concentrated source (the sun), if any.
    #[must_use]
    pub fn disc(&self) -> Option<&Disc> {
        match self {
            Self::Constant(_) | Self::Map(_) | Self::Cie(_) => None,
            Self::Daylight(daylight) => daylight.disc(),
        }
    }
}

impl Environment {
    /// The environment's radiance function: the map read from its file, the sky model set up.
    ///
    /// # Errors
    /// A map that cannot be read (named with its file), a radiance, scale or transform that is
    /// negative or not finite, or sun and sky parameters out of range (named by their key).
    pub fn distant(&self) -> Result<Distant, SceneError> {
        match self {
            Self::Constant { radiance } => {
                if !(radiance.is_finite() && radiance.min_element() >= 0.0) {
                    return Err(SceneError::new(format!("{radiance} is not a radiance"))
                        .with_key("radiance"));
                }
                Ok(Distant::Constant(*radiance))
            }
            Self::Map {
                path,
                scale,
                to_world,
            } => LatLong::read(path, *scale, *to_world).map(Distant::Map),
            Self::SunSky(s) => Daylight::new(s).map(Distant::Daylight),
            Self::Cie(sky) => {
                let l = sky.zenith_luminance;
                if !(l.is_finite() && l >= 0.0) {
                    return Err(SceneError::new(format!("{l} is not a luminance"))
                        .with_key("zenith_luminance"));
                }
                Ok(Distant::Cie(sky.clone()))
            }
        }
    }
}

impl Scene {
    /// Encloses the scene in `env` (module docs): one object named [`NAME`], its polygons
    /// inward-facing, reflecting nothing, each tile with its own material (also [`NAME`]).
    /// Warnings (a map's negative pixels) go to [`Scene::warnings`].
    ///
    /// # Errors
    /// Those of [`Environment::distant`], and a scene with nothing to enclose.
    pub fn add_environment(&mut self, env: &Environment) -> Result<(), SceneError> {
        let distant = env.distant()?;
        let Some(bounds) = enclosure::bounds(self) else {
            return Err(SceneError::new(
                "the scene has no polygons and no camera: nothing for the environment to light",
            ));
        };
        if let Distant::Map(map) = &distant {
            if let Some(warning) = map.warning() {
                self.warnings.push(warning);
            }
        }
        let polygons = match (env, &distant) {
            (Environment::Constant { .. }, Distant::Constant(radiance)) => {
                // Exact on any closed box: the default sky's, close around the scene.
                let (lo, hi) = enclosure::grown(bounds, sky::MARGIN);
                enclosure::box_faces_inward(lo, hi)
                    .iter()
                    .map(|f| (f.to_vec(), *radiance))
                    .collect()
            }
            _ => tiles::Cube::around(bounds, env)
                .tile(&distant)
                .into_iter()
                .map(|t| (t.vertices, t.radiance))
                .collect(),
        };
        self.add_enclosure(NAME, polygons);
        Ok(())
    }
}
