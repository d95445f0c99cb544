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
//! Status: the interface is fixed; [`Scene::add_environment`] is filled in by the environment
//! work (tiles, the sun disc and the sky model).

use std::path::PathBuf;

use glam::{Mat4, Vec3};

use super::{Scene, SceneError};
use crate::Rgb;

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
    /// The sun's angular radius in degrees (0.6: 0.2667 × `sunRadiusScale`; 3: `sun_aperture`
    /// / 2).
    pub sun_radius_deg: f64,
    /// Whether the sky is drawn (false for a sun alone).
    pub sky: bool,
}

impl Scene {
    /// Encloses the scene in `env` (module docs): one object named `environment`, its polygons
    /// inward-facing, reflecting nothing.
    ///
    /// # Errors
    /// A map that cannot be read, named with its file.
    pub fn add_environment(&mut self, env: &Environment) -> Result<(), SceneError> {
        let _ = env;
        Err(SceneError::new("environment light is not implemented yet"))
    }
}
