//! Mitsuba scene files (`.xml`), Mitsuba 3's format and Mitsuba 0.6's as Mitsuba 3 upgrades it:
//! the format the research community publishes its test scenes in (Bitterli's rendering
//! resources, McGuire's archive in its Mitsuba versions).
//!
//! [`xml`] reads the file into plugins with typed, located properties; [`bsdf`] maps every BSDF
//! to the diffuse surface a radiosity solve sees; [`shapes`] makes Mitsuba's built-in shapes
//! into polygons; this module turns sensors and emitters into cameras and light; the scene
//! builder ([`crate::Scene::load`]) puts them together. What is read (docs/mitsuba.md has the
//! whole table):
//!
//! | element | read as |
//! |---|---|
//! | `shape` `obj`, `ply`, `rectangle`, `cube`, `disk`, `sphere`, `cylinder` | polygons, with `to_world` and `flip_normals` |
//! | `shape` `shapegroup` + `instance` | the group's shapes again, under the instance's `to_world` |
//! | `bsdf` | a diffuse reflectance ([`bsdf`]'s table) |
//! | `emitter` `area` in a shape | the shape's emitted radiance (`radiance`), from its front |
//! | `emitter` `constant`, `envmap`, `sunsky` (0.6 also `sun`, `sky`) | distant light ([`Environment`]) |
//! | `emitter` `point`, `spot`, `directional` | a luminaire ([`crate::scene::luminaire`], [`luminaire`]) |
//! | `sensor` `perspective`, `thinlens` | the scene's camera (`fov`, `fov_axis`, the film's size) |
//! | `integrator`, `sampler`, `rfilter`, `film` (but its size) | ignored: a radiosity renderer has its own |
//!
//! Plugins Mitsuba does not have are errors at their `file:line:col`; plugins it has that a
//! radiosity renderer cannot stand for (participating media, projector lights,
//! curves, `serialized` meshes) are errors too, saying so, never silent drops.

pub mod bsdf;
pub mod shapes;
pub mod xml;

use glam::Vec3;

use std::sync::Arc;

use crate::scene::environment::{Environment, SunSky};
use crate::scene::luminaire::{isotropic, spot, Falloff, Luminaire};
use crate::scene::{Camera, RenderDefaults, SceneError};
use xml::{resolve, Class, Object, Value};

/// Mitsuba's default film size.
const FILM: RenderDefaults = RenderDefaults {
    width: 768,
    height: 576,
};

/// The camera and image size of a `perspective` (or `thinlens`) sensor.
///
/// The sensor looks down its `to_world`'s +z with +y up (Mitsuba's convention), from
/// `to_world`·(0, 0, 0). Its `fov` (degrees) spans the axis `fov_axis` names — `x` (the
/// default), `y`, `diagonal`, `smaller` or `larger` — of the film, so the vertical field of
/// view is θ_y = 2·atan(tan(θ/2)·h/s), s the film's extent along that axis. Without `fov`, a
/// `focal_length` in 35 mm equivalent (default 50 mm) gives θ_x = 2·atan(36 / (2f)).
///
/// # Errors
/// A sensor of another type, or properties of the wrong type.
pub fn camera(sensor: &Object, name: &str) -> Result<(Camera, RenderDefaults), SceneError> {
    if !matches!(sensor.kind.as_str(), "perspective" | "thinlens") {
        return Err(sensor.error(format!(
            "a `{}` sensor cannot be the scene's camera (perspective or thinlens)",
            sensor.kind
        )));
    }
    let film = sensor.children(Class::Film).next();
    let size =
        |o: Option<&std::sync::Arc<Object>>, key: &str, default: u32| -> Result<u32, SceneError> {
            let Some(o) = o else { return Ok(default) };
            let v = o.float(key, f64::from(default))?;
            if (1.0..=65_536.0).contains(&v) {
                Ok(v as u32)
            } else {
                Err(o.error(format!("`{key}` = {v} is not an image size")))
            }
        };
    let film_size = RenderDefaults {
        width: size(film, "width", FILM.width)?,
        height: size(film, "height", FILM.height)?,
    };
    let (w, h) = (f64::from(film_size.width), f64::from(film_size.height));
    let (fov, axis_extent) = if sensor.get("fov").is_some() {
        let fov = sensor.float("fov", 0.0)?;
        let axis = sensor.string("fov_axis")?.unwrap_or("x");
        let extent = match axis {
            "x" => w,
            "y" => h,
            "diagonal" => w.hypot(h),
            "smaller" => w.min(h),
            "larger" => w.max(h),
            other => {
                return Err(sensor.get("fov_axis").map_or_else(
                    || sensor.error("bad fov_axis"),
                    |p| {
                        p.error(format!(
                            "`{other}` is not x, y, diagonal, smaller or larger"
                        ))
                    },
                ))
            }
        };
        (fov, extent)
    } else {
        let f =
            match sensor.get("focal_length") {
                None => 50.0,
                Some(p) => match &p.value {
                    Value::Str(s) => s.trim_end_matches("mm").trim().parse().map_err(|_| {
                        p.error(format!("`{s}` is not a focal length such as 50mm"))
                    })?,
                    Value::Float(x) => *x,
                    _ => return Err(p.error("expected a focal length such as 50mm")),
                },
            };
        ((2.0 * (36.0 / (2.0 * f)).atan()).to_degrees(), w)
    };
    if !(fov > 0.0 && fov < 180.0) {
        return Err(sensor.error(format!("`fov` = {fov} is not between 0 and 180 degrees")));
    }
    let fov_y = 2.0 * ((fov.to_radians() / 2.0).tan() * h / axis_extent).atan();
    let m = sensor.transform("to_world")?;
    let eye = m.transform_point3(Vec3::ZERO);
    let forward = m.transform_vector3(Vec3::Z);
    let up = m.transform_vector3(Vec3::Y);
    if forward.length_squared() == 0.0 || up.cross(forward).length_squared() == 0.0 {
        return Err(sensor.error("`to_world` does not give the camera a direction and an up"));
    }
    let camera = Camera {
        name: name.to_string(),
        eye,
        target: eye + forward.normalize(),
        up: up.normalize(),
        fov_y: fov_y.to_degrees() as f32,
    };
    Ok((camera, film_size))
}

/// Distant light from a `constant`, `envmap`, `sunsky`, `sun` or `sky` emitter; `version6`
/// for a Mitsuba 0.6 file (its sky's zenith is +y; Mitsuba 3's is `to_world`·+z).
///
/// # Errors
/// Another emitter type (with what to do instead), or bad properties.
pub fn environment(emitter: &Object, version6: bool) -> Result<Environment, SceneError> {
    match emitter.kind.as_str() {
        "constant" => Ok(Environment::Constant {
            radiance: colour(emitter, "radiance", 1.0)?,
        }),
        "envmap" => {
            let name = emitter
                .string("filename")?
                .ok_or_else(|| emitter.error("an envmap needs `filename`"))?;
            let path = resolve(&emitter.loc, name);
            if !path.is_file() {
                return Err(emitter.error(format!("cannot read `{}`", path.display())));
            }
            Ok(Environment::Map {
                path,
                scale: emitter.float("scale", 1.0)?,
                to_world: emitter.transform("to_world")?,
            })
        }
        kind @ ("sunsky" | "sun" | "sky") => {
            let to_world = emitter.transform("to_world")?;
            let up = if version6 {
                to_world.transform_vector3(Vec3::Y)
            } else {
                to_world.transform_vector3(Vec3::Z)
            }
            .try_normalize()
            .ok_or_else(|| emitter.error("`to_world` has no up"))?;
            let sun = emitter
                .vector("sun_direction", Vec3::ZERO)?
                .try_normalize()
                .ok_or_else(|| {
                    emitter.error("give `sun_direction` (the sun's position from a date, time and place is not computed)")
                })?;
            let sun_radius_deg = if version6 {
                0.2667 * emitter.float("sun_radius_scale", 1.0)?
            } else {
                0.5 * emitter.float("sun_aperture", 0.5338)?
            };
            Ok(Environment::SunSky(SunSky {
                sun_direction: sun,
                up,
                turbidity: emitter.float("turbidity", 3.0)?,
                albedo: emitter.float("albedo", 0.15)?,
                sky_scale: if kind == "sun" {
                    0.0
                } else {
                    emitter.float("sky_scale", 1.0)?
                },
                sun_scale: if kind == "sky" {
                    0.0
                } else {
                    emitter.float("sun_scale", 1.0)?
                },
                sun_radius_deg,
                sky: kind != "sun",
            }))
        }
        "area" => Err(emitter.error("an area emitter belongs inside the <shape> that emits")),
        kind @ ("point" | "spot" | "directional") => Err(emitter.error(format!(
            "a `{kind}` emitter is a luminaire, not an environment"
        ))),
        kind @ ("projector" | "collimated" | "directionalarea") => {
            Err(emitter.error(format!(
                "`{kind}` emitters are not read yet: model the light as a small emitting shape, a point or spot light, or a sunsky"
            )))
        }
        kind => Err(emitter.error(format!("unknown emitter plugin `{kind}`"))),
    }
}

/// A `point`, `spot` or `directional` emitter as the luminaire `name` (`None` for other
/// emitters).
///
/// A point and a spot shine `intensity` (W·sr⁻¹ per channel, default 1) from
/// `to_world`·(0, 0, 0) (a point light's `position` instead, when given); a spot along
/// `to_world`·+z, fully out to `beam_width` and falling linearly in angle to 0 at
/// `cutoff_angle` (degrees, default 20 and ¾ of it, as Mitsuba 3). A directional light's rays
/// travel along `direction` (else `to_world`·+z) with the `irradiance` (W·m⁻² per channel,
/// default 1) on a plane facing them. Mitsuba scenes have no length unit: metres.
///
/// # Errors
/// A textured spot, angles out of order, or properties of the wrong type.
pub fn luminaire(emitter: &Object, name: &str) -> Result<Option<Luminaire>, SceneError> {
    let to_world = emitter.transform("to_world")?;
    if emitter.kind == "directional" {
        let along = to_world.transform_vector3(Vec3::Z);
        let aim = emitter
            .vector("direction", along)?
            .try_normalize()
            .ok_or_else(|| emitter.error("a directional light needs a non-zero direction"))?;
        let irradiance = colour(emitter, "irradiance", 1.0)?;
        return Ok(Some(Luminaire::directional(name, aim, irradiance, 1.0)));
    }
    let intensity = colour(emitter, "intensity", 1.0)?;
    let origin = to_world.transform_point3(Vec3::ZERO);
    let (position, aim, distribution) = match emitter.kind.as_str() {
        "point" => (
            emitter.vector("position", origin)?,
            Vec3::NEG_Y,
            isotropic(1.0),
        ),
        "spot" => {
            if emitter.get("texture").is_some() {
                return Err(emitter.error("a textured spot is not read"));
            }
            let cone = emitter.float("cutoff_angle", 20.0)?;
            let beam = emitter.float("beam_width", 0.75 * cone)?;
            if !(cone > 0.0 && cone <= 180.0 && beam >= 0.0 && beam < cone) {
                return Err(emitter.error(format!(
                    "a spot needs 0 ≤ beam_width < cutoff_angle ≤ 180 (got {beam} and {cone})"
                )));
            }
            let aim = to_world
                .transform_vector3(Vec3::Z)
                .try_normalize()
                .ok_or_else(|| emitter.error("`to_world` gives the spot no direction"))?;
            (origin, aim, spot(1.0, beam, cone, Falloff::LinearAngle))
        }
        _ => return Ok(None),
    };
    Ok(Some(Luminaire::new(
        name,
        position,
        aim,
        0.0,
        Arc::new(distribution),
        intensity,
        1.0,
    )))
}

/// An area emitter's radiance (default 1, as Mitsuba 0.6).
///
/// # Errors
/// Another emitter type inside a shape, or a `radiance` that is not a colour.
pub fn area_radiance(emitter: &Object) -> Result<crate::Rgb, SceneError> {
    if emitter.kind != "area" {
        return Err(emitter.error(format!(
            "a shape's emitter must be `area`, not `{}`",
            emitter.kind
        )));
    }
    colour(emitter, "radiance", 1.0)
}

fn colour(o: &Object, name: &str, default: f64) -> Result<crate::Rgb, SceneError> {
    match o.get(name) {
        None => Ok(crate::Rgb::splat(default)),
        Some(p) => match &p.value {
            Value::Rgb(c) => Ok(*c),
            Value::Float(x) => Ok(crate::Rgb::splat(*x)),
            _ => Err(p.error("expected a colour (textured emission is not read)")),
        },
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    fn first(xml: &str) -> std::sync::Arc<Object> {
        let d = xml::parse(
            &format!("<scene version=\"3.0.0\">{xml}</scene>"),
            Path::new("c.xml"),
        )
        .unwrap();
        d.objects[0].clone()
    }

    #[test]
    fn a_horizontal_fov_on_a_wide_film_gives_the_vertical_one() {
        let s = first(
            r#"<sensor type="perspective"><float name="fov" value="90"/>
               <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, -1" up="0, 1, 0"/></transform>
               <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/></film></sensor>"#,
        );
        let (c, size) = camera(&s, "default").unwrap();
        assert_eq!((size.width, size.height), (200, 100));
        // tan(θy/2) = tan(45°)·100/200.
        assert!(
            (c.fov_y - 2.0 * 0.5f32.atan().to_degrees()).abs() < 1e-4,
            "{}",
            c.fov_y
        );
        assert!((c.target - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
        assert!((c.up - Vec3::Y).length() < 1e-6);
    }

    #[test]
    fn point_and_spot_emitters_are_luminaires() {
        let o = first(
            r#"<emitter type="point"><point name="position" x="1" y="2" z="3"/>
               <rgb name="intensity" value="4, 5, 6"/></emitter>"#,
        );
        let l = luminaire(&o, "bulb").unwrap().unwrap();
        assert_eq!(l.position(), Some(Vec3::new(1.0, 2.0, 3.0)));
        // 2 m straight above a floor point: I / 4.
        let e = l.irradiance(Vec3::new(1.0, 0.0, 3.0), Vec3::Y);
        assert!((e - crate::Rgb::new(1.0, 1.25, 1.5)).abs().max_element() < 1e-9);
        // A spot at the origin looking down −y (to_world turns +z there), cutoff 40°, beam
        // 20°: full at 10° off its axis, half-way down in angle at 30°, dark at 45°.
        let o = first(
            r#"<emitter type="spot"><float name="intensity" value="100"/>
               <float name="cutoff_angle" value="40"/><float name="beam_width" value="20"/>
               <transform name="to_world"><rotate x="1" angle="90"/></transform></emitter>"#,
        );
        let l = luminaire(&o, "spot").unwrap().unwrap();
        let towards = |deg: f32| {
            let r = deg.to_radians();
            Vec3::new(r.sin(), -r.cos(), 0.0)
        };
        assert!((l.intensity(towards(10.0)).x - 100.0).abs() < 1e-6);
        assert!((l.intensity(towards(30.0)).x - 50.0).abs() < 0.5);
        assert_eq!(l.intensity(towards(45.0)).x, 0.0);
        assert!(luminaire(&first("<emitter type=\"constant\"/>"), "sky")
            .unwrap()
            .is_none());
    }

    #[test]
    fn a_directional_emitter_is_parallel_light() {
        // Rays travelling down and along +x at 45°, 2 W/m² facing them: a floor takes
        // 2 cos 45°, a wall facing −x the same, a wall facing +x nothing.
        let o = first(
            r#"<emitter type="directional"><vector name="direction" x="1" y="-1" z="0"/>
               <rgb name="irradiance" value="2, 2, 2"/></emitter>"#,
        );
        let l = luminaire(&o, "sun").unwrap().unwrap();
        assert_eq!(l.position(), None);
        let c = std::f64::consts::FRAC_1_SQRT_2;
        let floor = l.irradiance(Vec3::new(5.0, 0.0, 7.0), Vec3::Y);
        assert!((floor.x - 2.0 * c).abs() < 1e-6, "{floor}");
        assert!((l.irradiance(Vec3::ZERO, Vec3::NEG_X).y - 2.0 * c).abs() < 1e-6);
        assert_eq!(l.irradiance(Vec3::ZERO, Vec3::X), crate::Rgb::ZERO);
        // Its default: along to_world's +z.
        let o = first(
            r#"<emitter type="directional"><transform name="to_world">
               <rotate x="1" angle="90"/></transform></emitter>"#,
        );
        let l = luminaire(&o, "sun").unwrap().unwrap();
        assert!((l.irradiance(Vec3::ZERO, Vec3::Y).x - 1.0).abs() < 1e-6);
    }

    #[test]
    fn projectors_and_unknown_emitters_are_located_errors() {
        let e = environment(&first("<emitter type=\"projector\"/>"), false).unwrap_err();
        assert!(e.message.contains("not read yet"), "{e}");
        let e = environment(&first("<emitter type=\"laser\"/>"), false).unwrap_err();
        assert!(e.message.contains("unknown emitter plugin `laser`"), "{e}");
        assert!(e.line_col.is_some());
    }

    #[test]
    fn a_mitsuba_06_sunsky_has_its_zenith_on_y() {
        let o = first(
            r#"<emitter type="sunsky"><vector name="sunDirection" x="0" y="1" z="1"/>
               <float name="sunRadiusScale" value="2"/><float name="skyScale" value="3"/></emitter>"#,
        );
        let Environment::SunSky(s) = environment(&o, true).unwrap() else {
            panic!()
        };
        assert_eq!(s.up, Vec3::Y);
        assert!((s.sun_radius_deg - 0.5334).abs() < 1e-9);
        assert_eq!((s.sky_scale, s.sun_scale, s.sky), (3.0, 1.0, true));
        assert!((s.sun_direction.length() - 1.0).abs() < 1e-6);
    }
}
