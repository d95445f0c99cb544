//! Objects and their shapes: the keys every `[[objects]]` entry may have, then the keys the
//! `shape` selects (see [`SHAPES`]), and the `csg` operands they hold.

use std::path::PathBuf;

use glam::Vec3;
use model::csg::CsgOp;
use model::surface::subdivision::Scheme;

use super::sdf::parse_sdf;
use super::table::Table;
use super::transform::take_transform;
use super::{DEFAULT_IMPLICIT_RESOLUTION, DEFAULT_SPHERE_SUBDIVISIONS, DEFAULT_SUBDIVISION_LEVELS};
use crate::scene::description::{
    BaseMesh, LightDesc, LuminaireDesc, ObjectDesc, OperandDesc, ShapeDesc, Strength,
};
use crate::scene::SceneError;

/// A spot's default cone half-angle, degrees.
const DEFAULT_SPOT_CONE: f64 = 30.0;

/// The keys every object may have, whatever its shape.
const OBJECT_KEYS: &[&str] = &["name", "material", "shape", "transform"];

/// Every shape with its own keys. A new shape adds a line here, a [`ShapeDesc`] variant, an arm
/// in [`parse_shape`] and a build function.
const SHAPES: &[(&str, &[&str])] = &[
    ("polygon", &["vertices"]),
    ("box", &["min", "max"]),
    ("sphere", &["center", "radius", "subdivisions"]),
    ("mesh", &["path"]),
    ("bezier_patch", &["points", "path", "tolerance"]),
    (
        "nurbs_surface",
        &[
            "points",
            "weights",
            "degree",
            "knots_u",
            "knots_v",
            "tolerance",
        ],
    ),
    (
        "revolve",
        &[
            "profile",
            "weights",
            "degree",
            "knots",
            "origin",
            "axis",
            "angle",
            "tolerance",
        ],
    ),
    (
        "subdivision",
        &["base", "vertices", "faces", "scheme", "levels"],
    ),
    ("teapot", &["tolerance"]),
    ("implicit", &["sdf", "resolution"]),
    ("csg", &["op", "operands"]),
    ("instance", &["of"]),
    (
        "luminaire",
        &[
            "file",
            "opening",
            "position",
            "aim",
            "rotation",
            "multiplier",
            "colour",
        ],
    ),
    (
        "point",
        &["position", "intensity", "flux", "multiplier", "colour"],
    ),
    (
        "directional",
        &["aim", "illuminance", "multiplier", "colour"],
    ),
    (
        "spot",
        &[
            "position",
            "aim",
            "rotation",
            "intensity",
            "flux",
            "cone",
            "beam",
            "multiplier",
            "colour",
        ],
    ),
];

/// One `[[objects]]` entry: the common keys, then the shape's own.
pub(super) fn parse_object(mut t: Table<'_>, index: usize) -> Result<ObjectDesc, SceneError> {
    let src = t.src;
    let shape = t.required_with("shape", |k, v| src.string(k, v))?;
    let Some(allowed) = allowed_keys(&shape.value, OBJECT_KEYS) else {
        let known: Vec<&str> = SHAPES.iter().map(|(s, _)| *s).collect();
        return Err(src.error_at(
            &shape,
            format!(
                "unknown shape `{}` (expected one of: {})",
                shape.value,
                known.join(", ")
            ),
        ));
    };
    t.check_keys(&allowed)?;
    let name = t.optional("name", |k, v| src.string(k, v))?;
    let material = t.optional("material", |k, v| src.string(k, v))?;
    let transform = take_transform(&mut t)?;
    let shape = parse_shape(&shape.value, &mut t)?;
    Ok(ObjectDesc {
        index,
        pos: src.pos(t.span.start),
        name,
        material,
        transform,
        shape,
    })
}

/// The keys of shape `kind` (one of [`SHAPES`]).
fn parse_shape(kind: &str, t: &mut Table<'_>) -> Result<ShapeDesc, SceneError> {
    let src = t.src;
    Ok(match kind {
        "polygon" => ShapeDesc::Polygon {
            vertices: t.required_with("vertices", |k, v| {
                let at = src.field(k, &v, ());
                let points = src
                    .array(v, k)?
                    .into_iter()
                    .enumerate()
                    .map(|(i, p)| Ok(src.vec3(&format!("{k}[{i}]"), p)?.value))
                    .collect::<Result<Vec<_>, SceneError>>()?;
                Ok(at.map(|()| points))
            })?,
        },
        "box" => ShapeDesc::Box {
            min: t.required_with("min", |k, v| src.vec3(k, v))?,
            max: t.required_with("max", |k, v| src.vec3(k, v))?,
        },
        "sphere" => ShapeDesc::Sphere {
            center: t.required_with("center", |k, v| src.vec3(k, v))?,
            radius: t.required_with("radius", |k, v| src.f32(k, v))?,
            subdivisions: t.optional_with(
                "subdivisions",
                DEFAULT_SPHERE_SUBDIVISIONS,
                |k, v| src.u32(k, v),
            )?,
        },
        "bezier_patch" => ShapeDesc::BezierPatch {
            points: t.optional("points", |k, v| src.list(k, v, |k, v| src.vec3_list(k, v)))?,
            path: t.optional("path", |k, v| Ok(src.string(k, v)?.map(PathBuf::from)))?,
            tolerance: t.optional("tolerance", |k, v| src.f64(k, v))?,
        },
        "nurbs_surface" => ShapeDesc::NurbsSurface {
            points: t.required_with("points", |k, v| src.list(k, v, |k, v| src.vec3_list(k, v)))?,
            weights: t.optional("weights", |k, v| src.list(k, v, |k, v| src.f64_list(k, v)))?,
            degree: t.optional("degree", |k, v| src.list(k, v, |k, v| src.u32(k, v)))?,
            knots_u: t.optional("knots_u", |k, v| src.f64_list(k, v))?,
            knots_v: t.optional("knots_v", |k, v| src.f64_list(k, v))?,
            tolerance: t.optional("tolerance", |k, v| src.f64(k, v))?,
        },
        "revolve" => ShapeDesc::Revolve {
            profile: t.required_with("profile", |k, v| src.vec3_list(k, v))?,
            weights: t.optional("weights", |k, v| src.f64_list(k, v))?,
            degree: t.optional("degree", |k, v| src.u32(k, v))?,
            knots: t.optional("knots", |k, v| src.f64_list(k, v))?,
            origin: t.optional_with("origin", Vec3::ZERO, |k, v| src.vec3(k, v))?,
            axis: t.optional_with("axis", Vec3::Y, |k, v| src.vec3(k, v))?,
            angle: t.optional_with("angle", 360.0, |k, v| src.f64(k, v))?,
            tolerance: t.optional("tolerance", |k, v| src.f64(k, v))?,
        },
        "subdivision" => ShapeDesc::Subdivision {
            base: t.optional("base", |k, v| {
                let bases = [
                    ("cube", BaseMesh::Cube),
                    ("tetrahedron", BaseMesh::Tetrahedron),
                ];
                src.keyword(k, v, &bases, |other| {
                    format!("unknown base `{other}` (expected cube or tetrahedron)")
                })
            })?,
            vertices: t.optional("vertices", |k, v| src.vec3_list(k, v))?,
            faces: t.optional("faces", |k, v| {
                src.list(k, v, |k, v| src.list(k, v, |k, v| src.u32(k, v)))
            })?,
            scheme: t.optional_with("scheme", Scheme::CatmullClark, |k, v| {
                let schemes = [
                    ("catmull_clark", Scheme::CatmullClark),
                    ("loop", Scheme::Loop),
                ];
                src.keyword(k, v, &schemes, |other| {
                    format!("unknown scheme `{other}` (expected catmull_clark or loop)")
                })
            })?,
            levels: t.optional_with("levels", DEFAULT_SUBDIVISION_LEVELS, |k, v| src.u32(k, v))?,
        },
        "teapot" => ShapeDesc::Teapot {
            tolerance: t.optional("tolerance", |k, v| src.f64(k, v))?,
        },
        "implicit" => ShapeDesc::Implicit {
            sdf: t.required_with("sdf", |k, v| {
                let at = src.field(k, &v, ());
                let sdf = parse_sdf(src, k, v)?;
                Ok(at.map(|()| sdf))
            })?,
            resolution: t.optional_with("resolution", DEFAULT_IMPLICIT_RESOLUTION, |k, v| {
                src.u32(k, v)
            })?,
        },
        "csg" => ShapeDesc::Csg {
            op: t.required_with("op", |k, v| {
                let ops = [
                    ("union", CsgOp::Union),
                    ("intersection", CsgOp::Intersection),
                    ("difference", CsgOp::Difference),
                ];
                src.keyword(k, v, &ops, |_| {
                    "expected `union`, `intersection` or `difference`".into()
                })
            })?,
            operands: t.required_with("operands", |k, v| {
                let at = src.field(k, &v, ());
                let items = src
                    .array(v, k)?
                    .into_iter()
                    .enumerate()
                    .map(|(i, item)| {
                        let t = Table::new(src, format!("{k}[{i}]"), item)?;
                        parse_operand(t)
                    })
                    .collect::<Result<Vec<_>, SceneError>>()?;
                Ok(at.map(|()| items))
            })?,
        },
        "instance" => ShapeDesc::Instance {
            of: t.required_with("of", |k, v| src.string(k, v))?,
        },
        "mesh" => ShapeDesc::Mesh {
            path: t.required_with("path", |k, v| Ok(src.string(k, v)?.map(PathBuf::from)))?,
        },
        "luminaire" | "point" | "spot" | "directional" => {
            ShapeDesc::Luminaire(parse_luminaire(kind, t)?)
        }
        // Every name of SHAPES has its arm above; `allowed_keys` let no other through.
        other => {
            return Err(SceneError::at(
                src.loc_of(src.pos(t.span.start)),
                format!("unknown shape `{other}`"),
            ))
        }
    })
}

/// The keys of a luminaire of shape `kind` (`luminaire`, `point`, `spot` or `directional`).
fn parse_luminaire(kind: &str, t: &mut Table<'_>) -> Result<LuminaireDesc, SceneError> {
    let src = t.src;
    let light = match kind {
        "point" => LightDesc::Point(strength(kind, t)?),
        "spot" => LightDesc::Spot {
            strength: strength(kind, t)?,
            cone: t.optional_with("cone", DEFAULT_SPOT_CONE, |k, v| src.f64(k, v))?,
            beam: t.optional("beam", |k, v| src.f64(k, v))?,
        },
        "directional" => {
            LightDesc::Directional(t.required_with("illuminance", |k, v| src.f64(k, v))?)
        }
        _ => LightDesc::File(
            t.required_with("file", |k, v| Ok(src.string(k, v)?.map(PathBuf::from)))?,
            t.optional_with("opening", false, |k, v| src.boolean(k, v))?,
        ),
    };
    Ok(LuminaireDesc {
        light,
        position: if kind == "directional" {
            t.optional_with("position", Vec3::ZERO, |k, v| src.vec3(k, v))?
        } else {
            t.required_with("position", |k, v| src.vec3(k, v))?
        },
        aim: t.optional_with("aim", Vec3::NEG_Y, |k, v| src.vec3(k, v))?,
        rotation: t.optional_with("rotation", 0.0, |k, v| src.f64(k, v))?,
        multiplier: t.optional_with("multiplier", 1.0, |k, v| src.f64(k, v))?,
        colour: t.optional("colour", |k, v| src.rgb(k, v))?,
    })
}

/// A shorthand light's strength: exactly one of `intensity` and `flux`.
fn strength(kind: &str, t: &mut Table<'_>) -> Result<Strength, SceneError> {
    let src = t.src;
    let intensity = t.optional("intensity", |k, v| src.f64(k, v))?;
    let flux = t.optional("flux", |k, v| src.f64(k, v))?;
    match (intensity, flux) {
        (Some(i), None) => Ok(Strength::Intensity(i)),
        (None, Some(f)) => Ok(Strength::Flux(f)),
        (Some(i), Some(_)) => Err(src.error_at(&i, "give `intensity` or `flux`, not both")),
        (None, None) => Err(src.error(
            &t.span,
            &t.child_path("intensity"),
            format!("a {kind} light needs `intensity` (cd) or `flux` (lm)"),
        )),
    }
}

/// One `csg` operand: a `shape` with its keys and an optional `transform`.
fn parse_operand(mut t: Table<'_>) -> Result<OperandDesc, SceneError> {
    let src = t.src;
    let shape = t.required_with("shape", |k, v| src.string(k, v))?;
    let Some(allowed) = allowed_keys(&shape.value, &["shape", "transform"]) else {
        return Err(src.error_at(&shape, format!("unknown shape `{}`", shape.value)));
    };
    t.check_keys(&allowed)?;
    let transform = take_transform(&mut t)?;
    Ok(OperandDesc {
        pos: src.pos(t.span.start),
        key: t.path.clone(),
        transform,
        shape: parse_shape(&shape.value, &mut t)?,
    })
}

/// The keys allowed beside `common` for shape `name`, or `None` for an unknown shape.
fn allowed_keys(name: &str, common: &[&'static str]) -> Option<Vec<&'static str>> {
    let (_, keys) = SHAPES.iter().find(|(s, _)| *s == name)?;
    Some(common.iter().chain(keys.iter()).copied().collect())
}
