//! Signed distance expressions for `implicit` shapes: a tree of primitives (sphere, box,
//! torus, cylinder, plane, metaballs) and operators (union, intersection, difference, smooth
//! union), read into [`Sdf`] with every parameter range-checked where its position is known.

use glam::Vec3;
use model::implicit::Sdf;

use super::source::Source;
use super::table::Table;
use super::transform::take_transform;
use super::value::Value;
use crate::scene::description::Field;
use crate::scene::SceneError;

/// A signed distance expression: a table with one key naming the node (`sphere`, `box`,
/// `torus`, `cylinder`, `plane`, `metaballs`, `union`, `intersection`, `difference`,
/// `smooth_union`) whose value holds its parameters, operands in `of`, and an optional
/// `transform`. Parameters are range-checked here, where their positions are known.
pub(super) fn parse_sdf(src: &Source<'_>, key: &str, v: Value) -> Result<Sdf, SceneError> {
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
    match take_transform(&mut t)? {
        Some(tr) => {
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
