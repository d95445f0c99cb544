//! Parsing: TOML text → [`SceneDesc`], with the line, column and key path of every value.
//!
//! Two steps. First serde and the `toml` crate read the text into a small tree in which every
//! key and value keeps its byte span (the `toml` crate's `Spanned` protocol, see [`Value`]).
//! Then a reader walks the tree table by table: it rejects unknown keys (the TOML analogue of
//! serde's `deny_unknown_fields`), checks types, rejects the `nan`/`inf` literals TOML allows,
//! and fills the description structs. Serde's derive cannot do the second step alone: the
//! `shape` key selects which other keys an object has, and internally tagged enums lose spans.
//!
//! Meaning (ranges, material names, polygon shapes) is checked later, in [`super::check`].

mod grid;
mod sdf;
mod shape;
mod source;
mod table;
mod transform;
mod value;

use std::path::Path;

use glam::Vec3;

use super::description::{CameraDesc, Field, MaterialDesc, RenderDesc, SceneDesc, SkyDesc};
use super::units::UnknownUnit;
use super::SceneError;
use crate::Rgb;
use shape::parse_object;
use source::Source;
use table::Table;
use value::Value;

/// Default marching-cubes `resolution` of an implicit shape.
pub const DEFAULT_IMPLICIT_RESOLUTION: u32 = 48;

/// Default subdivision `levels`.
pub const DEFAULT_SUBDIVISION_LEVELS: u32 = 3;

/// Default `subdivisions` of a sphere (20·4³ = 1280 triangles).
pub const DEFAULT_SPHERE_SUBDIVISIONS: u32 = 3;

/// Default vertical field of view, degrees.
pub const DEFAULT_FOV_Y: f32 = 40.0;

/// Parses a TOML scene. `file` names the text in messages.
///
/// # Errors
/// Malformed TOML, an unknown key, a value of the wrong type, a missing required key, or a
/// `nan`/`inf` number, each with `file:line:col` and the key.
pub fn parse(text: &str, file: &Path) -> Result<SceneDesc, SceneError> {
    let src = Source::new(text, file);
    let root: Value = toml::from_str(text).map_err(|e| {
        let at = e.span().map_or(0, |s| s.start);
        SceneError::at(src.loc(at), e.message().to_string())
    })?;
    let mut top = Table::new(&src, String::new(), root)?;
    top.check_keys(&[
        "units",
        "camera",
        "cameras",
        "render",
        "materials",
        "objects",
        "grids",
        "sky",
    ])?;
    let mut desc = SceneDesc {
        file: file.to_path_buf(),
        ..SceneDesc::default()
    };
    if let Some((k, v)) = top.take("units") {
        let name = src.string("units", v)?;
        let units = name
            .value
            .parse()
            .map_err(|e: UnknownUnit| src.error(&k.span, "units", e.to_string()))?;
        desc.units = Some(name.map(|_| units));
    }
    match (top.take("camera"), top.take("cameras")) {
        (Some(_), Some((k, _))) => {
            return Err(src.error(&k.span, "cameras", "use either [camera] or [[cameras]]"))
        }
        (Some((_, v)), None) => {
            let t = Table::new(&src, "camera".into(), v)?;
            desc.cameras.push(parse_camera(t, None)?);
        }
        (None, Some((_, v))) => {
            for (i, item) in src.array(v, "cameras")?.into_iter().enumerate() {
                let t = Table::new(&src, format!("cameras[{i}]"), item)?;
                let name = t.span.start;
                desc.cameras.push(parse_camera(t, Some(name))?);
            }
        }
        (None, None) => {}
    }
    if let Some((_, v)) = top.take("render") {
        let mut t = Table::new(&src, "render".into(), v)?;
        t.check_keys(&["width", "height"])?;
        desc.render = RenderDesc {
            width: t.optional("width", |k, v| src.u32(k, v))?,
            height: t.optional("height", |k, v| src.u32(k, v))?,
        };
    }
    if let Some((_, v)) = top.take("materials") {
        let t = Table::new(&src, "materials".into(), v)?;
        for (key, value) in t.entries {
            let path = format!("materials.{}", key.name);
            let name = Field {
                value: key.name,
                pos: src.pos(key.span.start),
                key: path.clone(),
            };
            desc.materials
                .push(parse_material(Table::new(&src, path, value)?, name)?);
        }
    }
    if let Some((_, v)) = top.take("objects") {
        for (i, item) in src.array(v, "objects")?.into_iter().enumerate() {
            let t = Table::new(&src, format!("objects[{i}]"), item)?;
            desc.objects.push(parse_object(t, i)?);
        }
    }
    if let Some((_, v)) = top.take("sky") {
        let mut t = Table::new(&src, "sky".into(), v)?;
        t.check_keys(&[
            "type",
            "zenith_luminance",
            "sun",
            "latitude",
            "longitude",
            "date",
            "time",
            "utc_offset",
            "north",
            "sun_illuminance",
        ])?;
        desc.sky = Some(SkyDesc {
            kind: t.required_with("type", |k, v| src.string(k, v))?,
            zenith_luminance: t.required_with("zenith_luminance", |k, v| src.f64(k, v))?,
            sun: t.optional("sun", |k, v| src.vec3(k, v))?,
            latitude: t.optional("latitude", |k, v| src.f64(k, v))?,
            longitude: t.optional("longitude", |k, v| src.f64(k, v))?,
            date: t.optional("date", |k, v| src.string(k, v))?,
            time: t.optional("time", |k, v| src.string(k, v))?,
            utc_offset: t.optional("utc_offset", |k, v| src.f64(k, v))?,
            north: t.optional("north", |k, v| src.vec3(k, v))?,
            sun_illuminance: t.optional("sun_illuminance", |k, v| src.f64(k, v))?,
        });
    }
    if let Some((_, v)) = top.take("grids") {
        for (i, item) in src.array(v, "grids")?.into_iter().enumerate() {
            let t = Table::new(&src, format!("grids[{i}]"), item)?;
            desc.grids.push(grid::parse_grid(t)?);
        }
    }
    Ok(desc)
}

/// `[camera]` (no name: `default`) or one of `[[cameras]]` (a `name` is required).
fn parse_camera(mut t: Table<'_>, named: Option<usize>) -> Result<CameraDesc, SceneError> {
    let src = t.src;
    if named.is_some() {
        t.check_keys(&["name", "eye", "target", "up", "fov_y"])?;
    } else {
        t.check_keys(&["eye", "target", "up", "fov_y"])?;
    }
    let name = match named {
        Some(_) => t.required_with("name", |k, v| src.string(k, v))?,
        None => t.default_field("default".to_string()),
    };
    Ok(CameraDesc {
        name,
        eye: t.required_with("eye", |k, v| src.vec3(k, v))?,
        target: t.required_with("target", |k, v| src.vec3(k, v))?,
        up: t.optional_with("up", Vec3::Y, |k, v| src.vec3(k, v))?,
        fov_y: t.optional_with("fov_y", DEFAULT_FOV_Y, |k, v| src.f32(k, v))?,
    })
}

/// `[materials.NAME]`.
fn parse_material(mut t: Table<'_>, name: Field<String>) -> Result<MaterialDesc, SceneError> {
    let src = t.src;
    t.check_keys(&[
        "reflectance",
        "emission",
        "two_sided",
        "specular",
        "transmission",
        "ior",
    ])?;
    Ok(MaterialDesc {
        name,
        reflectance: t.optional_with("reflectance", Rgb::ZERO, |k, v| src.rgb(k, v))?,
        emission: t.optional_with("emission", Rgb::ZERO, |k, v| src.rgb(k, v))?,
        two_sided: t
            .optional_with("two_sided", false, |k, v| src.boolean(k, v))?
            .value,
        specular: t.optional_with("specular", Rgb::ZERO, |k, v| src.rgb(k, v))?,
        transmission: t.optional_with("transmission", Rgb::ZERO, |k, v| src.rgb(k, v))?,
        ior: t.optional_with("ior", 1.5, |k, v| src.f64(k, v))?,
    })
}
