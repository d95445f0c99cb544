//! Parsing: TOML text → [`SceneDesc`], with the line, column and key path of every value.
//!
//! Two steps. First serde and the `toml` crate read the text into a small tree in which every
//! key and value keeps its byte span (the `toml` crate's `Spanned` protocol, see [`Value`]).
//! Then a reader walks the tree table by table: it rejects unknown keys (the TOML analogue of
//! serde's `deny_unknown_fields`), checks types, rejects the `nan`/`inf` literals TOML allows,
//! and fills the description structs. Serde's derive cannot do the second step alone: the
//! `shape` key selects which other keys an object has, and internally tagged enums lose spans.
//!
//! Meaning (ranges, material names, polygon shapes) is checked later, in [`super::validate`].

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

use glam::Vec3;
use serde::de::{self, Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};

use super::description::{
    CameraDesc, Field, MaterialDesc, ObjectDesc, OperandDesc, Pos, RenderDesc, SceneDesc,
    ShapeDesc, TransformDesc,
};
use super::SceneError;
use crate::Rgb;
use model::implicit::Sdf;

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
];

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
    top.check_keys(&["camera", "cameras", "render", "materials", "objects"])?;
    let mut desc = SceneDesc {
        file: file.to_path_buf(),
        ..SceneDesc::default()
    };
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

/// One `[[objects]]` entry: the common keys, then the shape's own.
fn parse_object(mut t: Table<'_>, index: usize) -> Result<ObjectDesc, SceneError> {
    let src = t.src;
    let shape = t.required_with("shape", |k, v| src.string(k, v))?;
    let Some((_, shape_keys)) = SHAPES.iter().find(|(s, _)| *s == shape.value) else {
        let known: Vec<&str> = SHAPES.iter().map(|(s, _)| *s).collect();
        return Err(SceneError::at(
            src.loc_of(shape.pos),
            format!(
                "unknown shape `{}` (expected one of: {})",
                shape.value,
                known.join(", ")
            ),
        )
        .with_key(shape.key));
    };
    let allowed: Vec<&str> = OBJECT_KEYS
        .iter()
        .chain(shape_keys.iter())
        .copied()
        .collect();
    t.check_keys(&allowed)?;
    let name = t.optional("name", |k, v| src.string(k, v))?;
    let material = t.optional("material", |k, v| src.string(k, v))?;
    let transform = match t.take("transform") {
        Some((_, v)) => Some(parse_transform(Table::new(
            src,
            t.child_path("transform"),
            v,
        )?)?),
        None => None,
    };
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
            base: t.optional("base", |k, v| src.string(k, v))?,
            vertices: t.optional("vertices", |k, v| src.vec3_list(k, v))?,
            faces: t.optional("faces", |k, v| {
                src.list(k, v, |k, v| src.list(k, v, |k, v| src.u32(k, v)))
            })?,
            scheme: t.optional_with("scheme", "catmull_clark".to_string(), |k, v| {
                src.string(k, v)
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
            op: t.required_with("op", |k, v| src.string(k, v))?,
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
        _ => ShapeDesc::Mesh {
            path: t.required_with("path", |k, v| Ok(src.string(k, v)?.map(PathBuf::from)))?,
        },
    })
}

/// One `csg` operand: a `shape` with its keys and an optional `transform`.
fn parse_operand(mut t: Table<'_>) -> Result<OperandDesc, SceneError> {
    let src = t.src;
    let shape = t.required_with("shape", |k, v| src.string(k, v))?;
    let Some((_, keys)) = SHAPES.iter().find(|(s, _)| *s == shape.value) else {
        return Err(SceneError::at(
            src.loc_of(shape.pos),
            format!("unknown shape `{}`", shape.value),
        )
        .with_key(shape.key));
    };
    let allowed: Vec<&str> = ["shape", "transform"]
        .iter()
        .chain(keys.iter())
        .copied()
        .collect();
    t.check_keys(&allowed)?;
    let transform = match t.take("transform") {
        Some((_, v)) => Some(parse_transform(Table::new(
            src,
            t.child_path("transform"),
            v,
        )?)?),
        None => None,
    };
    Ok(OperandDesc {
        pos: src.pos(t.span.start),
        key: t.path.clone(),
        transform,
        shape: parse_shape(&shape.value, &mut t)?,
    })
}

/// A signed distance expression: a table with one key naming the node (`sphere`, `box`,
/// `torus`, `cylinder`, `plane`, `metaballs`, `union`, `intersection`, `difference`,
/// `smooth_union`) whose value holds its parameters, operands in `of`, and an optional
/// `transform`. Parameters are range-checked here, where their positions are known.
fn parse_sdf(src: &Source<'_>, key: &str, v: Value) -> Result<Sdf, SceneError> {
    const NODES: &[(&str, &[&str])] = &[
        ("sphere", &["center", "radius"]),
        ("box", &["min", "max"]),
        ("torus", &["center", "major", "minor"]),
        ("cylinder", &["center", "radius", "half_height"]),
        ("plane", &["normal", "offset"]),
        ("metaballs", &["balls", "threshold"]),
        ("union", &["of"]),
        ("intersection", &["of"]),
        ("difference", &["of"]),
        ("smooth_union", &["of", "k"]),
    ];
    let outer = Table::new(src, key.to_string(), v)?;
    let span = outer.span.clone();
    let mut entries = outer.entries;
    if entries.len() != 1 {
        let names: Vec<&str> = NODES.iter().map(|(n, _)| *n).collect();
        return Err(src.error(&span, key, format!("expected one of: {}", names.join(", "))));
    }
    let (node, body) = entries.remove(0);
    let path = format!("{key}.{}", node.name);
    let Some((name, keys)) = NODES.iter().find(|(n, _)| *n == node.name) else {
        let names: Vec<&str> = NODES.iter().map(|(n, _)| *n).collect();
        return Err(src.error(
            &node.span,
            &path,
            format!("unknown expression (expected one of: {})", names.join(", ")),
        ));
    };
    let mut t = Table::new(src, path.clone(), body)?;
    let allowed: Vec<&str> = keys.iter().chain(["transform"].iter()).copied().collect();
    t.check_keys(&allowed)?;
    let positive = |f: Field<f32>| -> Result<f64, SceneError> {
        if f.value > 0.0 {
            Ok(f64::from(f.value))
        } else {
            Err(SceneError::at(src.loc_of(f.pos), "must be positive").with_key(f.key))
        }
    };
    let p3 = |f: Field<Vec3>| f.value.as_dvec3();
    let operands = |t: &mut Table<'_>, n: Option<usize>| -> Result<Vec<Sdf>, SceneError> {
        let list = t.required_with("of", |k, v| {
            let at = src.field(k, &v, ());
            let whole = v.span.clone();
            let items = src.array(v, k)?;
            if items.len() < 2 || n.is_some_and(|n| items.len() != n) {
                return Err(src.error(
                    &whole,
                    k,
                    match n {
                        Some(n) => format!("expected exactly {n} operands"),
                        None => "expected at least 2 operands".to_string(),
                    },
                ));
            }
            let sdfs = items
                .into_iter()
                .enumerate()
                .map(|(i, x)| parse_sdf(src, &format!("{k}[{i}]"), x))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(at.map(|()| sdfs))
        })?;
        Ok(list.value)
    };
    let sdf = match *name {
        "sphere" => Sdf::Sphere {
            center: p3(t.required_with("center", |k, v| src.vec3(k, v))?),
            radius: positive(t.required_with("radius", |k, v| src.f32(k, v))?)?,
        },
        "box" => {
            let min = t.required_with("min", |k, v| src.vec3(k, v))?;
            let max = t.required_with("max", |k, v| src.vec3(k, v))?;
            if !min.value.cmplt(max.value).all() {
                return Err(SceneError::at(
                    src.loc_of(max.pos),
                    "max must exceed min on every axis",
                )
                .with_key(max.key));
            }
            Sdf::Box {
                min: p3(min),
                max: p3(max),
            }
        }
        "torus" => Sdf::Torus {
            center: p3(t.optional_with("center", Vec3::ZERO, |k, v| src.vec3(k, v))?),
            major: positive(t.required_with("major", |k, v| src.f32(k, v))?)?,
            minor: positive(t.required_with("minor", |k, v| src.f32(k, v))?)?,
        },
        "cylinder" => Sdf::Cylinder {
            center: p3(t.optional_with("center", Vec3::ZERO, |k, v| src.vec3(k, v))?),
            radius: positive(t.required_with("radius", |k, v| src.f32(k, v))?)?,
            half_height: positive(t.required_with("half_height", |k, v| src.f32(k, v))?)?,
        },
        "plane" => {
            let n = t.required_with("normal", |k, v| src.vec3(k, v))?;
            let Some(normal) = n.value.as_dvec3().try_normalize() else {
                return Err(
                    SceneError::at(src.loc_of(n.pos), "normal must not be zero").with_key(n.key)
                );
            };
            Sdf::Plane {
                normal,
                offset: t.optional_with("offset", 0.0, |k, v| src.f64(k, v))?.value,
            }
        }
        "metaballs" => {
            let balls = t.required_with("balls", |k, v| {
                let at = src.field(k, &v, ());
                let balls = src
                    .array(v, k)?
                    .into_iter()
                    .enumerate()
                    .map(|(i, b)| {
                        let key = format!("{k}[{i}]");
                        let [x, y, z, r] = src.numbers::<4>(&key, &b)?;
                        if r > 0.0 {
                            Ok((glam::DVec3::new(x, y, z), r))
                        } else {
                            Err(src.error(&b.span, &key, "radius (4th number) must be positive"))
                        }
                    })
                    .collect::<Result<Vec<_>, SceneError>>()?;
                Ok(at.map(|()| balls))
            })?;
            if balls.value.is_empty() {
                return Err(
                    SceneError::at(src.loc_of(balls.pos), "expected at least one ball")
                        .with_key(balls.key),
                );
            }
            let threshold = t.optional_with("threshold", 0.3, |k, v| src.f64(k, v))?;
            if !(threshold.value > 0.0 && threshold.value < 1.0) {
                return Err(SceneError::at(
                    src.loc_of(threshold.pos),
                    "threshold must be in (0, 1)",
                )
                .with_key(threshold.key));
            }
            Sdf::Metaballs {
                balls: balls.value,
                threshold: threshold.value,
            }
        }
        "union" => Sdf::Union(operands(&mut t, None)?),
        "intersection" => Sdf::Intersection(operands(&mut t, None)?),
        "difference" => {
            let mut ops = operands(&mut t, Some(2))?;
            let b = ops.pop().map(Box::new);
            let a = ops.pop().map(Box::new);
            match (a, b) {
                (Some(a), Some(b)) => Sdf::Difference(a, b),
                _ => return Err(src.error(&span, &path, "expected exactly 2 operands")),
            }
        }
        _ => {
            let k = positive(t.required_with("k", |k, v| src.f32(k, v))?)?;
            let mut ops = operands(&mut t, Some(2))?;
            let b = ops.pop().map(Box::new);
            let a = ops.pop().map(Box::new);
            match (a, b) {
                (Some(a), Some(b)) => Sdf::SmoothUnion { a, b, k },
                _ => return Err(src.error(&span, &path, "expected exactly 2 operands")),
            }
        }
    };
    match t.take("transform") {
        Some((_, v)) => {
            let tr = parse_transform(Table::new(src, format!("{path}.transform"), v)?)?;
            let pos = tr.scale.pos;
            let key = tr.scale.key.clone();
            sdf.transformed(
                tr.scale.value.as_dvec3(),
                tr.rotate.value.as_dvec3(),
                tr.translate.value.as_dvec3(),
            )
            .ok_or_else(|| SceneError::at(src.loc_of(pos), "scale must not be zero").with_key(key))
        }
        None => Ok(sdf),
    }
}

/// `transform = { scale, rotate, translate }`.
fn parse_transform(mut t: Table<'_>) -> Result<TransformDesc, SceneError> {
    let src = t.src;
    t.check_keys(&["scale", "rotate", "translate"])?;
    Ok(TransformDesc {
        scale: t.optional_with("scale", Vec3::ONE, |k, v| match &v.kind {
            Kind::Array(_) => src.vec3(k, v),
            _ => Ok(src.f32(k, v)?.map(Vec3::splat)),
        })?,
        rotate: t.optional_with("rotate", Vec3::ZERO, |k, v| src.vec3(k, v))?,
        translate: t.optional_with("translate", Vec3::ZERO, |k, v| src.vec3(k, v))?,
    })
}

/// The text being parsed: file name and line starts, to turn byte offsets into positions.
struct Source<'a> {
    file: &'a Path,
    text: &'a str,
    line_starts: Vec<usize>,
}

impl<'a> Source<'a> {
    fn new(text: &'a str, file: &'a Path) -> Self {
        let line_starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Self {
            file,
            text,
            line_starts,
        }
    }

    /// 1-based line and column (in characters) of a byte offset.
    fn pos(&self, offset: usize) -> Pos {
        let offset = offset.min(self.text.len());
        let line = self.line_starts.partition_point(|&s| s <= offset).max(1);
        let start = self.line_starts[line - 1];
        let col = self
            .text
            .get(start..offset)
            .map_or(offset - start, |s| s.chars().count())
            + 1;
        Pos { line, col }
    }

    fn loc_of(&self, pos: Pos) -> super::Loc {
        super::Loc {
            file: self.file.to_path_buf(),
            line: pos.line,
            col: pos.col,
        }
    }

    fn loc(&self, offset: usize) -> super::Loc {
        self.loc_of(self.pos(offset))
    }

    fn error(&self, span: &Range<usize>, key: &str, message: impl Into<String>) -> SceneError {
        let e = SceneError::at(self.loc(span.start), message);
        if key.is_empty() {
            e
        } else {
            e.with_key(key)
        }
    }

    fn wrong_type(&self, key: &str, v: &Value, expected: &str) -> SceneError {
        self.error(
            &v.span,
            key,
            format!("expected {expected}, found {}", v.kind),
        )
    }

    fn field<T>(&self, key: &str, v: &Value, value: T) -> Field<T> {
        Field {
            value,
            pos: self.pos(v.span.start),
            key: key.to_string(),
        }
    }

    fn array(&self, v: Value, key: &str) -> Result<Vec<Value>, SceneError> {
        match v.kind {
            Kind::Array(items) => Ok(items),
            _ => Err(self.wrong_type(key, &v, "an array")),
        }
    }

    /// An array whose items are read by `item` (each with its indexed key, `key[i]`).
    fn list<T>(
        &self,
        key: &str,
        v: Value,
        item: impl Fn(&str, Value) -> Result<Field<T>, SceneError>,
    ) -> Result<Field<Vec<T>>, SceneError> {
        let at = self.field(key, &v, ());
        let items = self
            .array(v, key)?
            .into_iter()
            .enumerate()
            .map(|(i, x)| Ok(item(&format!("{key}[{i}]"), x)?.value))
            .collect::<Result<Vec<T>, SceneError>>()?;
        Ok(at.map(|()| items))
    }

    /// An array of points.
    fn vec3_list(&self, key: &str, v: Value) -> Result<Field<Vec<Vec3>>, SceneError> {
        self.list(key, v, |k, x| self.vec3(k, x))
    }

    /// An array of finite numbers.
    fn f64_list(&self, key: &str, v: Value) -> Result<Field<Vec<f64>>, SceneError> {
        self.list(key, v, |k, x| self.f64(k, x))
    }

    fn string(&self, key: &str, v: Value) -> Result<Field<String>, SceneError> {
        match &v.kind {
            Kind::Str(s) => Ok(self.field(key, &v, s.clone())),
            _ => Err(self.wrong_type(key, &v, "a string")),
        }
    }

    fn boolean(&self, key: &str, v: Value) -> Result<Field<bool>, SceneError> {
        match v.kind {
            Kind::Bool(b) => Ok(self.field(key, &v, b)),
            _ => Err(self.wrong_type(key, &v, "true or false")),
        }
    }

    fn u32(&self, key: &str, v: Value) -> Result<Field<u32>, SceneError> {
        match v.kind {
            Kind::Int(i) => match u32::try_from(i) {
                Ok(n) => Ok(self.field(key, &v, n)),
                Err(_) => Err(self.error(
                    &v.span,
                    key,
                    format!("{i} is out of range (0 to {})", u32::MAX),
                )),
            },
            _ => Err(self.wrong_type(key, &v, "a whole number")),
        }
    }

    /// A finite number (integers are accepted).
    fn number(&self, key: &str, v: &Value) -> Result<f64, SceneError> {
        let x = match v.kind {
            Kind::Int(i) => i as f64,
            Kind::Float(x) => x,
            _ => return Err(self.wrong_type(key, v, "a number")),
        };
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.error(
                &v.span,
                key,
                format!("`{x}` is not allowed: numbers must be finite"),
            ))
        }
    }

    fn f64(&self, key: &str, v: Value) -> Result<Field<f64>, SceneError> {
        let x = self.number(key, &v)?;
        Ok(self.field(key, &v, x))
    }

    fn f32(&self, key: &str, v: Value) -> Result<Field<f32>, SceneError> {
        let x = self.number(key, &v)?;
        if (x as f32).is_finite() {
            Ok(self.field(key, &v, x as f32))
        } else {
            Err(self.error(
                &v.span,
                key,
                format!("{x:e} is too large for single precision"),
            ))
        }
    }

    /// Exactly `N` finite numbers.
    fn numbers<const N: usize>(&self, key: &str, v: &Value) -> Result<[f64; N], SceneError> {
        let Kind::Array(items) = &v.kind else {
            return Err(self.wrong_type(key, v, &format!("an array of {N} numbers")));
        };
        if items.len() != N {
            return Err(self.error(
                &v.span,
                key,
                format!("expected {N} numbers, found {}", items.len()),
            ));
        }
        let mut out = [0.0; N];
        for (i, (o, item)) in out.iter_mut().zip(items).enumerate() {
            *o = self.number(&format!("{key}[{i}]"), item)?;
        }
        Ok(out)
    }

    fn vec3(&self, key: &str, v: Value) -> Result<Field<Vec3>, SceneError> {
        let [x, y, z] = self.numbers::<3>(key, &v)?;
        let p = Vec3::new(x as f32, y as f32, z as f32);
        if p.is_finite() {
            Ok(self.field(key, &v, p))
        } else {
            Err(self.error(&v.span, key, "a coordinate is too large"))
        }
    }

    /// An RGB triple, or one number for grey.
    fn rgb(&self, key: &str, v: Value) -> Result<Field<Rgb>, SceneError> {
        let c = match v.kind {
            Kind::Int(_) | Kind::Float(_) => Rgb::splat(self.number(key, &v)?),
            _ => Rgb::from_array(self.numbers::<3>(key, &v)?),
        };
        Ok(self.field(key, &v, c))
    }
}

/// A table being read: keys are taken one by one; leftovers are unknown keys.
struct Table<'s> {
    src: &'s Source<'s>,
    path: String,
    span: Range<usize>,
    entries: Vec<(Key, Value)>,
}

impl<'s> Table<'s> {
    fn new(src: &'s Source<'s>, path: String, v: Value) -> Result<Self, SceneError> {
        match v.kind {
            Kind::Table(entries) => Ok(Self {
                src,
                path,
                span: v.span,
                entries,
            }),
            _ => Err(src.wrong_type(&path, &v, "a table")),
        }
    }

    fn child_path(&self, name: &str) -> String {
        if self.path.is_empty() {
            name.to_string()
        } else {
            format!("{}.{name}", self.path)
        }
    }

    /// Fails on the first key (in file order) not in `allowed`.
    fn check_keys(&self, allowed: &[&str]) -> Result<(), SceneError> {
        match self
            .entries
            .iter()
            .find(|(k, _)| !allowed.contains(&k.name.as_str()))
        {
            Some((k, _)) => Err(self.src.error(
                &k.span,
                &self.child_path(&k.name),
                format!("unknown key (expected one of: {})", allowed.join(", ")),
            )),
            None => Ok(()),
        }
    }

    fn take(&mut self, name: &str) -> Option<(Key, Value)> {
        let i = self.entries.iter().position(|(k, _)| k.name == name)?;
        Some(self.entries.remove(i))
    }

    /// An optional key without a default.
    fn optional<T>(
        &mut self,
        name: &str,
        read: impl FnOnce(&str, Value) -> Result<Field<T>, SceneError>,
    ) -> Result<Option<Field<T>>, SceneError> {
        let key = self.child_path(name);
        self.take(name).map(|(_, v)| read(&key, v)).transpose()
    }

    fn optional_with<T>(
        &mut self,
        name: &str,
        default: T,
        read: impl FnOnce(&str, Value) -> Result<Field<T>, SceneError>,
    ) -> Result<Field<T>, SceneError> {
        let key = self.child_path(name);
        match self.take(name) {
            Some((_, v)) => read(&key, v),
            None => Ok(Field {
                value: default,
                pos: self.src.pos(self.span.start),
                key,
            }),
        }
    }

    fn required_with<T>(
        &mut self,
        name: &str,
        read: impl FnOnce(&str, Value) -> Result<Field<T>, SceneError>,
    ) -> Result<Field<T>, SceneError> {
        let key = self.child_path(name);
        match self.take(name) {
            Some((_, v)) => read(&key, v),
            None => Err(self.src.error(&self.span, &key, "missing required key")),
        }
    }

    fn default_field<T>(&self, value: T) -> Field<T> {
        Field {
            value,
            pos: self.src.pos(self.span.start),
            key: self.path.clone(),
        }
    }
}

/// The byte span and kind of a TOML value (the reader's tree).
struct Value {
    span: Range<usize>,
    kind: Kind,
}

/// A TOML key with its byte span.
struct Key {
    span: Range<usize>,
    name: String,
}

/// What a TOML value is.
enum Kind {
    Bool(bool),
    Int(i64),
    Float(f64),
    Str(String),
    Datetime,
    Array(Vec<Value>),
    Table(Vec<(Key, Value)>),
}

impl fmt::Display for Kind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Bool(_) => "a boolean",
            Self::Int(_) => "an integer",
            Self::Float(_) => "a float",
            Self::Str(_) => "a string",
            Self::Datetime => "a date-time",
            Self::Array(_) => "an array",
            Self::Table(_) => "a table",
        })
    }
}

// The `toml` crate reports spans through serde_spanned's protocol: a value asked for as a struct
// of this name and these fields is handed over as a map {start, end, value}. `toml::Spanned`
// cannot be used directly because implicit tables (`materials` in `[materials.white]`) have no
// span and make it fail; here a value without a span is read as is and takes its key's span.
const SPANNED: &str = "$__serde_spanned_private_Spanned";
const SPANNED_START: &str = "$__serde_spanned_private_start";
const SPANNED_FIELDS: &[&str] = &[
    SPANNED_START,
    "$__serde_spanned_private_end",
    "$__serde_spanned_private_value",
];
const DATETIME_FIELD: &str = "$__toml_private_datetime";

impl<'de> Deserialize<'de> for Value {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_struct(SPANNED, SPANNED_FIELDS, ValueVisitor)
    }
}

/// The value inside a spanned map, read without asking for a span again.
struct Unspanned(Value);

impl<'de> Deserialize<'de> for Unspanned {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(ValueVisitor).map(Unspanned)
    }
}

impl<'de> Deserialize<'de> for Key {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_struct(SPANNED, SPANNED_FIELDS, KeyVisitor)
    }
}

struct KeyVisitor;

impl<'de> Visitor<'de> for KeyVisitor {
    type Value = Key;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a key")
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Key, E> {
        Ok(Key {
            span: 0..0,
            name: v.to_string(),
        })
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Key, A::Error> {
        let (Some(_), start) = (map.next_key::<String>()?, map.next_value::<usize>()?) else {
            return Err(de::Error::custom("malformed key span"));
        };
        let (Some(_), end) = (map.next_key::<String>()?, map.next_value::<usize>()?) else {
            return Err(de::Error::custom("malformed key span"));
        };
        let (Some(_), name) = (map.next_key::<String>()?, map.next_value::<String>()?) else {
            return Err(de::Error::custom("malformed key span"));
        };
        Ok(Key {
            span: start..end,
            name,
        })
    }
}

struct ValueVisitor;

impl ValueVisitor {
    fn value(kind: Kind) -> Value {
        Value { span: 0..0, kind }
    }
}

impl<'de> Visitor<'de> for ValueVisitor {
    type Value = Value;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a TOML value")
    }

    fn visit_bool<E: de::Error>(self, v: bool) -> Result<Value, E> {
        Ok(Self::value(Kind::Bool(v)))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Value, E> {
        Ok(Self::value(Kind::Int(v)))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Value, E> {
        Ok(Self::value(match i64::try_from(v) {
            Ok(i) => Kind::Int(i),
            Err(_) => Kind::Float(v as f64),
        }))
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Value, E> {
        Ok(Self::value(Kind::Float(v)))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Value, E> {
        Ok(Self::value(Kind::Str(v.to_string())))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut items = Vec::new();
        while let Some(item) = seq.next_element()? {
            items.push(item);
        }
        Ok(Self::value(Kind::Array(items)))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let mut entries = Vec::new();
        while let Some(key) = map.next_key::<Key>()? {
            if key.span.is_empty() && key.name == SPANNED_START {
                // The spanned protocol: start, end, then the value itself.
                let start: usize = map.next_value()?;
                let _ = map.next_key::<Key>()?;
                let end: usize = map.next_value()?;
                let _ = map.next_key::<Key>()?;
                let Unspanned(mut value) = map.next_value()?;
                value.span = start..end;
                return Ok(value);
            }
            if key.name == DATETIME_FIELD {
                map.next_value::<de::IgnoredAny>()?;
                return Ok(Self::value(Kind::Datetime));
            }
            let mut value: Value = map.next_value()?;
            if value.span.is_empty() {
                value.span = key.span.clone();
            }
            entries.push((key, value));
        }
        Ok(Self::value(Kind::Table(entries)))
    }
}
