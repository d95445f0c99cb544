//! The modeling and solid shapes of the scene format as polygon meshes, built by the `model`
//! crate: patches, revolutions, sweeps, subdivision surfaces, the teapot, implicit surfaces,
//! CSG and instances' prototypes.

use std::path::Path;

use glam::Vec3;
use model::{PolyMesh, Transform};

use crate::scene::description::{BaseMesh, Field, ObjectDesc, Pos, SceneDesc, ShapeDesc};
use crate::scene::{Loc, SceneError};

/// Default chordal tolerance of curved shapes, as a fraction of the control net's diagonal.
const RELATIVE_TOLERANCE: f64 = 0.002;

/// Segments per patch direction at most, for curved shapes.
const MAX_SEGMENTS: usize = 64;

/// The modeling shapes (patches, revolutions, subdivision surfaces, the teapot) as polygons,
/// built by the `model` crate; problems the validator cannot see (knot vectors, net sizes,
/// unreadable patch files) are reported at their key.
pub(super) fn modeled_mesh(
    desc: &SceneDesc,
    o: &ObjectDesc,
    shape: &ShapeDesc,
) -> Result<PolyMesh, SceneError> {
    use glam::DVec3;
    use model::curve::Nurbs;
    use model::surface::{self, NurbsSurface, TessellationSettings};

    let fail = |pos: Pos, key: &str, message: String| {
        let at = Loc {
            file: desc.file.clone(),
            line: pos.line,
            col: pos.col,
        };
        SceneError::at(at, message).with_key(key.to_string())
    };
    let at_object =
        |key: &str, message: String| fail(o.pos, &format!("objects[{}].{key}", o.index), message);
    // Tessellates patches with the given or the default (relative) tolerance.
    let tessellate = |patches: &[NurbsSurface], tolerance: &Option<Field<f64>>| {
        let tolerance = tolerance.as_ref().map_or_else(
            || {
                let (lo, hi) = patches
                    .iter()
                    .flat_map(|p| p.homogeneous().iter().map(|h| h.truncate() / h.w))
                    .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
                        (lo.min(p), hi.max(p))
                    });
                RELATIVE_TOLERANCE * (hi - lo).length()
            },
            |t| t.value,
        );
        let settings = TessellationSettings {
            tolerance,
            max_segments: MAX_SEGMENTS,
        };
        surface::tessellate(patches, &settings)
    };
    let net = |points: &Field<Vec<Vec<Vec3>>>| -> Result<(usize, usize, Vec<DVec3>), SceneError> {
        let rows = points.value.len();
        let cols = points.value.first().map_or(0, Vec::len);
        if rows < 2 || cols < 2 || points.value.iter().any(|r| r.len() != cols) {
            return Err(fail(
                points.pos,
                &points.key,
                "expected a grid of at least 2 × 2 points (rows of equal length)".into(),
            ));
        }
        let flat = points
            .value
            .iter()
            .flatten()
            .map(|p| p.as_dvec3())
            .collect();
        Ok((rows, cols, flat))
    };
    let bad = |f: &dyn Fn() -> (Pos, String)| {
        let (pos, key) = f();
        fail(
            pos,
            &key,
            "inconsistent degree, knots, weights and points (see docs/scene-format.md)".into(),
        )
    };
    Ok(match shape {
        ShapeDesc::Teapot { tolerance } => tessellate(&model::teapot::teapot_patches(), tolerance),
        ShapeDesc::BezierPatch {
            points,
            path,
            tolerance,
        } => {
            let patches = if let Some(points) = points {
                let (rows, cols, flat) = net(points)?;
                NurbsSurface::bezier(rows, cols, &flat)
                    .into_iter()
                    .collect()
            } else if let Some(path) = path {
                let full = desc
                    .file
                    .parent()
                    .unwrap_or(Path::new(""))
                    .join(&path.value);
                let text = std::fs::read_to_string(&full).map_err(|e| {
                    fail(
                        path.pos,
                        &path.key,
                        format!("cannot read `{}`: {e}", full.display()),
                    )
                })?;
                model::teapot::parse_newell(&text)
                    .map_err(|e| fail(path.pos, &path.key, format!("`{}`: {e}", full.display())))?
            } else {
                Vec::new()
            };
            tessellate(&patches, tolerance)
        }
        ShapeDesc::NurbsSurface {
            points,
            weights,
            degree,
            knots_u,
            knots_v,
            tolerance,
        } => {
            let (rows, cols, flat) = net(points)?;
            let (p, q) = match degree.as_ref().map(|d| d.value.as_slice()) {
                None => (3.min(rows - 1), 3.min(cols - 1)),
                Some(&[p, q]) => (p as usize, q as usize),
                Some(_) => {
                    let d = degree
                        .as_ref()
                        .map_or((o.pos, String::new()), |d| (d.pos, d.key.clone()));
                    return Err(fail(d.0, &d.1, "expected [p, q]".into()));
                }
            };
            let w: Vec<f64> = match weights {
                Some(w) => w.value.iter().flatten().copied().collect(),
                None => vec![1.0; flat.len()],
            };
            let clamped =
                |d: usize, n: usize| model::curve::bspline::clamped_knots(d, n).unwrap_or_default();
            let ku = knots_u
                .as_ref()
                .map_or_else(|| clamped(p, rows), |k| k.value.clone());
            let kv = knots_v
                .as_ref()
                .map_or_else(|| clamped(q, cols), |k| k.value.clone());
            // Name the key at fault where one can be told: knot counts and weight counts.
            for (knots, count, degree) in [(knots_u, rows, p), (knots_v, cols, q)] {
                if let Some(k) = knots {
                    if k.value.len() != count + degree + 1 {
                        return Err(fail(
                            k.pos,
                            &k.key,
                            format!(
                                "expected {} knots ({count} points + degree {degree} + 1), found {}",
                                count + degree + 1,
                                k.value.len()
                            ),
                        ));
                    }
                }
            }
            if let Some(weights) = weights {
                if w.len() != flat.len() {
                    return Err(fail(
                        weights.pos,
                        &weights.key,
                        format!(
                            "expected {} weights, one per point, found {}",
                            flat.len(),
                            w.len()
                        ),
                    ));
                }
            }
            let patch = NurbsSurface::new((p, q), (ku, kv), (rows, cols), &flat, &w)
                .ok_or_else(|| bad(&|| (points.pos, points.key.clone())))?;
            tessellate(&[patch], tolerance)
        }
        ShapeDesc::Revolve {
            profile,
            weights,
            degree,
            knots,
            origin,
            axis,
            angle,
            tolerance,
        } => {
            let pts: Vec<DVec3> = profile.value.iter().map(|p| p.as_dvec3()).collect();
            if pts.len() < 2 {
                return Err(fail(
                    profile.pos,
                    &profile.key,
                    "at least 2 profile points".into(),
                ));
            }
            let p = degree
                .as_ref()
                .map_or(3.min(pts.len() - 1), |d| d.value as usize);
            let w = weights
                .as_ref()
                .map_or_else(|| vec![1.0; pts.len()], |w| w.value.clone());
            let k = knots.as_ref().map_or_else(
                || model::curve::bspline::clamped_knots(p, pts.len()).unwrap_or_default(),
                |k| k.value.clone(),
            );
            let curve = Nurbs::new(p, k, &pts, &w)
                .ok_or_else(|| bad(&|| (profile.pos, profile.key.clone())))?;
            let s = surface::revolve::revolve(
                &curve,
                origin.value.as_dvec3(),
                axis.value.as_dvec3(),
                angle.value,
            )
            .ok_or_else(|| fail(axis.pos, &axis.key, "axis must be non-zero".into()))?;
            tessellate(&[s], tolerance)
        }
        ShapeDesc::Subdivision {
            base,
            vertices,
            faces,
            scheme,
            levels,
        } => {
            let mesh = match (base, vertices, faces) {
                (Some(b), _, _) => match b.value {
                    BaseMesh::Cube => {
                        model::primitives::cuboid(Vec3::splat(-0.5), Vec3::splat(0.5))
                    }
                    BaseMesh::Tetrahedron => PolyMesh {
                        positions: vec![
                            Vec3::new(1.0, 1.0, 1.0),
                            Vec3::new(1.0, -1.0, -1.0),
                            Vec3::new(-1.0, 1.0, -1.0),
                            Vec3::new(-1.0, -1.0, 1.0),
                        ]
                        .into_iter()
                        .map(|p| p * 0.5)
                        .collect(),
                        faces: vec![vec![0, 1, 2], vec![0, 3, 1], vec![0, 2, 3], vec![1, 3, 2]],
                    },
                },
                (None, Some(v), Some(f)) => PolyMesh {
                    positions: v.value.clone(),
                    faces: f.value.clone(),
                },
                _ => return Err(at_object("base", "missing base mesh".into())),
            };
            surface::subdivision::subdivide(&mesh, scheme.value, levels.value)
        }
        // Not modeling shapes: [`solid_mesh`] and the builder mesh these.
        ShapeDesc::Polygon { .. }
        | ShapeDesc::Box { .. }
        | ShapeDesc::Sphere { .. }
        | ShapeDesc::Mesh { .. }
        | ShapeDesc::Implicit { .. }
        | ShapeDesc::Csg { .. }
        | ShapeDesc::Instance { .. }
        | ShapeDesc::Luminaire(_) => PolyMesh::default(),
    })
}

/// The mesh of a shape in its own frame (before the object's transform): primitives, implicit
/// surfaces by marching cubes, CSG trees by BSP Booleans of their transformed operands, and the
/// modeled surfaces of [`modeled_mesh`]. Validation has refused the shapes that cannot be
/// meshes here (files and instances).
pub(super) fn solid_mesh(
    desc: &SceneDesc,
    o: &ObjectDesc,
    shape: &ShapeDesc,
) -> Result<PolyMesh, SceneError> {
    Ok(match shape {
        ShapeDesc::Polygon { vertices } => PolyMesh {
            positions: vertices.value.clone(),
            faces: vec![(0..vertices.value.len() as u32).collect()],
        },
        ShapeDesc::Box { min, max } => model::primitives::cuboid(min.value, max.value),
        ShapeDesc::Sphere {
            center,
            radius,
            subdivisions,
        } => model::primitives::icosphere(center.value, radius.value, subdivisions.value),
        ShapeDesc::Implicit { sdf, resolution } => {
            model::implicit::marching_cubes::MarchingCubes::around(&sdf.value, resolution.value)
                .map(|mc| mc.polygonize(&sdf.value))
                .unwrap_or_default()
        }
        ShapeDesc::Csg { op, operands } => {
            let mut result: Option<PolyMesh> = None;
            for operand in &operands.value {
                let mut mesh = solid_mesh(desc, o, &operand.shape)?;
                if let Some(t) = &operand.transform {
                    mesh.transform(&Transform::from_srt(
                        t.scale.value,
                        t.rotate.value,
                        t.translate.value,
                    ));
                }
                result = Some(match result {
                    None => mesh,
                    Some(acc) => model::csg::apply(op.value, &acc, &mesh),
                });
            }
            result.unwrap_or_default()
        }
        ShapeDesc::Mesh { .. } | ShapeDesc::Instance { .. } | ShapeDesc::Luminaire(_) => {
            PolyMesh::default()
        }
        shape @ (ShapeDesc::BezierPatch { .. }
        | ShapeDesc::NurbsSurface { .. }
        | ShapeDesc::Revolve { .. }
        | ShapeDesc::Subdivision { .. }
        | ShapeDesc::Teapot { .. }) => modeled_mesh(desc, o, shape)?,
    })
}
