//! Scenes: what is lit, what it is made of, and where it is seen from.
//!
//! Loading runs in three stages (as pbrt-v4 and Tungsten do): [`parse`] reads the TOML into plain
//! description structs that keep the source location of every value, [`check`] checks them
//! and reports the first problem with `file:line:col` and the key, and [`build`] turns them into
//! the frozen [`Scene`] below: planar polygons with materials, objects and cameras. A bare
//! `.obj` file is a scene too (see [`crate::scene::import::obj`]).

pub mod build;
pub mod builtin;
pub mod check;
pub(crate) mod coincident;
pub mod description;
pub mod enclosure;
pub mod environment;
pub mod error;
pub mod facing_emitters;
pub mod frame;
pub mod grid;
pub mod import;
pub mod luminaire;
pub mod parse;
pub mod sky;
pub mod texture;
pub mod units;

use glam::{Vec2, Vec3};

use crate::Rgb;
pub use error::{Loc, SceneError};
pub use luminaire::Luminaire;

/// A loaded scene: planar polygons, each with a material and an owning object.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// A short name (the file stem or the built-in's name), used for default output names.
    pub name: String,
    /// Materials; polygons refer to them by index.
    pub materials: Vec<Material>,
    /// Named objects; polygons refer to them by index.
    pub objects: Vec<Object>,
    /// Planar polygons (the patches of the radiosity method), counter-clockwise seen from the
    /// front.
    pub polygons: Vec<Polygon>,
    /// Cameras; the first is the default. Never empty after loading (one is framed if needed).
    pub cameras: Vec<Camera>,
    /// Image size defaults.
    pub render: RenderDefaults,
    /// The length unit of the coordinates (`units`; metres by default).
    pub units: units::Units,
    /// Calculation grids (`[[grids]]`), where illuminance is measured.
    pub grids: Vec<grid::Grid>,
    /// Point luminaires (`shape = "luminaire"`, `"point"`, `"spot"`): light from a point with
    /// a distribution of intensity, which no ray sees.
    pub luminaires: Vec<Luminaire>,
    /// The unobstructed horizontal illuminance of the scene's CIE sky (`[sky]`), lx: what
    /// daylight factors are relative to.
    pub sky_illuminance: Option<f64>,
    /// Problems repaired while loading (e.g. a missing MTL file), one line each.
    pub warnings: Vec<String>,
}

/// The largest reflectance an imported material keeps per channel: files say ρ = 1 (glTF's
/// default base colour, white texels), and ρ ≥ 1 would make a closed scene's light grow
/// without bound.
pub const MAX_REFLECTANCE: f64 = 0.99;

/// A diffuse material, with the specular and transmissive parts used by the ray tracer.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The name in the scene (or in the MTL file).
    pub name: String,
    /// Diffuse reflectance ρ per channel, in [0, 1); for a textured material, the mean of its
    /// texture ([`texture::TextureMap::mean`]).
    pub reflectance: Rgb,
    /// The texture that varies ρ over a polygon with texture coordinates (glTF
    /// `baseColorTexture`, MTL `map_Kd`); see [`Material::reflectance_of`].
    pub texture: Option<texture::TextureMap>,
    /// Emitted radiance L_e (W·m⁻²·sr⁻¹); emitted exitance is E = π·L_e, from the front only.
    pub emission: Rgb,
    /// Whether the back reflects too (with the same ρ).
    pub two_sided: bool,
    /// Mirror reflectance (ray tracing only).
    pub specular: Rgb,
    /// Transmittance (ray tracing only).
    pub transmission: Rgb,
    /// Index of refraction (ray tracing only).
    pub ior: f64,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: "default".into(),
            reflectance: Rgb::splat(0.5),
            texture: None,
            emission: Rgb::ZERO,
            two_sided: false,
            specular: Rgb::ZERO,
            transmission: Rgb::ZERO,
            ior: 1.5,
        }
    }
}

impl Material {
    /// The reflectance the solve gives `polygon`: its texture's mean over the polygon's
    /// footprint when both are present ([`texture::TextureMap::mean_over`]), else
    /// [`Material::reflectance`].
    #[must_use]
    pub fn reflectance_of(&self, polygon: &Polygon) -> Rgb {
        match (&self.texture, &polygon.uv) {
            (Some(map), Some(uv)) => map.mean_over(&polygon.vertices, uv),
            _ => self.reflectance,
        }
    }

    /// Whether the material emits light.
    #[must_use]
    pub fn is_emitter(&self) -> bool {
        self.emission.max_element() > 0.0
    }

    /// Whether the material reflects specularly or transmits: ray tracing follows it, where
    /// radiosity sees only its diffuse part.
    #[must_use]
    pub fn is_specular(&self) -> bool {
        self.specular.max_element() > 0.0 || self.transmission.max_element() > 0.0
    }
}

/// A named object: what stats and exports report per name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Object {
    /// The name from the scene file (or the OBJ object/group name).
    pub name: String,
}

/// A planar polygon with three or more corners, convex or not.
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    /// Corners, counter-clockwise seen from the front.
    pub vertices: Vec<Vec3>,
    /// Index into [`Scene::materials`].
    pub material: usize,
    /// Index into [`Scene::objects`].
    pub object: usize,
    /// Texture coordinates, one per corner (see [`texture`] for their convention), when the
    /// polygon comes from a file that gives them.
    pub uv: Option<Vec<Vec2>>,
}

/// A perspective camera.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Name (for `--camera`).
    pub name: String,
    /// Position of the eye.
    pub eye: Vec3,
    /// A point the camera looks at.
    pub target: Vec3,
    /// Up direction (need not be orthogonal to the view direction).
    pub up: Vec3,
    /// Vertical field of view in degrees.
    pub fov_y: f32,
}

/// Render defaults from the scene's `[render]` table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderDefaults {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl Default for RenderDefaults {
    fn default() -> Self {
        Self {
            width: 512,
            height: 512,
        }
    }
}
