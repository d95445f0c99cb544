//! Checking: a parsed [`SceneDesc`] is checked for meaning before anything is built.
//!
//! Ranges follow the physics (docs/scene-format.md): a diffuse reflectance ρ must satisfy 0 ≤ ρ < 1
//! per channel (ρ = 1 would make the radiosity system B = E + ρFB singular in a closed scene),
//! emitted radiance is non-negative, and every polygon must be a proper polygon; one that is
//! strongly non-planar (beyond the tolerance below) is not an error but is split into triangles
//! with a warning when the scene is built.
//!
//! A polygon's plane is the one through its centroid c with normal n = A/|A|, where A is the
//! Newell vector area ½ Σ vᵢ × vᵢ₊₁. It is accepted when
//!
//! * it has at least three distinct vertices,
//! * |A| > 10⁻⁶ · d², d the diagonal of its bounding box (otherwise it is collinear, zero area),
//! * maxᵢ |n · (vᵢ − c)| ≤ [`NON_PLANAR_TOLERANCE`] · d (1 %: the measured Cornell walls are
//!   out of plane by about 0.1 % of their size and pass; a quad with a corner lifted by a
//!   tenth of its side fails).

use std::collections::HashSet;
use std::fmt;

use glam::Vec3;

use super::description::{
    Field, GridPlace, LightDesc, LuminaireDesc, ObjectDesc, SceneDesc, ShapeDesc, SkyDesc, Strength,
};
use super::environment::{solar, CieSkyKind};
use super::{grid, Loc, SceneError};
use crate::Rgb;

/// Largest distance of a vertex from a polygon's plane, as a fraction of the diagonal of the
/// polygon's bounding box.
pub const NON_PLANAR_TOLERANCE: f32 = 0.01;

/// Relative area below which a polygon counts as collinear: |A| ≤ this · d².
const ZERO_AREA: f32 = 1e-6;

/// Most sphere subdivisions (20·4⁷ = 327 680 triangles).
pub const MAX_SPHERE_SUBDIVISIONS: u32 = 7;

/// Largest image side accepted in `[render]`.
pub const MAX_IMAGE_SIDE: u32 = 16384;

/// Why a polygon cannot be a patch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PolygonProblem {
    /// Fewer than three distinct vertices.
    TooFewVertices(usize),
    /// All vertices on one line (or a zero-area outline).
    ZeroArea,
    /// A vertex lies `deviation` (as a fraction of the size) away from the plane.
    NonPlanar(f32),
}

impl fmt::Display for PolygonProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooFewVertices(n) => write!(
                f,
                "degenerate polygon: {n} distinct vertices, at least 3 are needed"
            ),
            Self::ZeroArea => f.write_str("degenerate polygon: zero area (collinear vertices)"),
            Self::NonPlanar(d) => write!(
                f,
                "polygon is not planar: a vertex is {:.2} % of its size off its plane (at most \
                 {} % is accepted)",
                d * 100.0,
                NON_PLANAR_TOLERANCE * 100.0
            ),
        }
    }
}

/// What, if anything, keeps `vertices` from being a planar polygon (see the module doc).
#[must_use]
pub fn polygon_problem(vertices: &[Vec3]) -> Option<PolygonProblem> {
    let mut distinct: Vec<Vec3> = Vec::with_capacity(vertices.len());
    for &v in vertices {
        if !distinct.contains(&v) {
            distinct.push(v);
        }
    }
    if distinct.len() < 3 {
        return Some(PolygonProblem::TooFewVertices(distinct.len()));
    }
    let (lo, hi) = vertices
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    let size = (hi - lo).length();
    let area = model::polymesh::vector_area(vertices);
    let magnitude = area.length();
    if magnitude.is_nan() || magnitude <= ZERO_AREA * size * size {
        return Some(PolygonProblem::ZeroArea);
    }
    let normal = area.normalize();
    let centre = vertices.iter().copied().sum::<Vec3>() / vertices.len() as f32;
    let deviation = vertices
        .iter()
        .map(|&v| normal.dot(v - centre).abs())
        .fold(0.0, f32::max)
        / size;
    (deviation > NON_PLANAR_TOLERANCE).then_some(PolygonProblem::NonPlanar(deviation))
}

/// Why a camera cannot look: the scene file and the command line (`--eye` …) share the test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CameraProblem {
    /// The eye and the target are one point: no view direction.
    TargetIsEye,
    /// The up direction is zero or along the view direction.
    UpAlongView,
    /// The vertical field of view (degrees) is outside (0, 180).
    FieldOfView(f32),
}

/// The first problem of a camera at `eye` looking at `target` with `up` and a vertical field of
/// view of `fov_y` degrees, if any.
#[must_use]
pub fn camera_problem(eye: Vec3, target: Vec3, up: Vec3, fov_y: f32) -> Option<CameraProblem> {
    let dir = target - eye;
    if dir.length_squared() == 0.0 {
        return Some(CameraProblem::TargetIsEye);
    }
    if dir.cross(up).length_squared() <= 1e-12 * dir.length_squared() {
        return Some(CameraProblem::UpAlongView);
    }
    if !(fov_y > 0.0 && fov_y < 180.0) {
        return Some(CameraProblem::FieldOfView(fov_y));
    }
    None
}

/// Checks a parsed scene: value ranges, material references, shapes and cameras.
///
/// # Errors
/// The first problem found, with `file:line:col` and key.
pub fn check(desc: &SceneDesc) -> Result<(), SceneError> {
    let mut names = HashSet::new();
    for c in &desc.cameras {
        if !names.insert(c.name.value.as_str()) {
            return Err(fail(desc, &c.name, "duplicate camera name".into()));
        }
        match camera_problem(c.eye.value, c.target.value, c.up.value, c.fov_y.value) {
            Some(CameraProblem::TargetIsEye) => {
                return Err(fail(desc, &c.target, "target equals eye".into()));
            }
            Some(CameraProblem::UpAlongView) => {
                return Err(fail(
                    desc,
                    &c.up,
                    "up is zero or parallel to the view direction".into(),
                ));
            }
            Some(CameraProblem::FieldOfView(fov)) => {
                return Err(fail(
                    desc,
                    &c.fov_y,
                    format!("{fov} is outside (0, 180) degrees"),
                ));
            }
            None => {}
        }
    }
    for side in [&desc.render.width, &desc.render.height]
        .into_iter()
        .flatten()
    {
        if side.value == 0 || side.value > MAX_IMAGE_SIDE {
            return Err(fail(
                desc,
                side,
                format!("{} is outside 1..={MAX_IMAGE_SIDE} pixels", side.value),
            ));
        }
    }
    for m in &desc.materials {
        check_channels(
            &m.reflectance,
            "reflectance",
            |x| (0.0..1.0).contains(&x),
            "[0, 1)",
        )
        .map_err(|msg| fail(desc, &m.reflectance, msg))?;
        check_channels(&m.emission, "emitted radiance", |x| x >= 0.0, "[0, ∞)")
            .map_err(|msg| fail(desc, &m.emission, msg))?;
        for f in [&m.specular, &m.transmission] {
            check_channels(f, "value", |x| (0.0..=1.0).contains(&x), "[0, 1]")
                .map_err(|msg| fail(desc, f, msg))?;
        }
        if m.ior.value <= 0.0 {
            return Err(fail(
                desc,
                &m.ior,
                format!("index of refraction {} must be positive", m.ior.value),
            ));
        }
    }
    for o in &desc.objects {
        check_object(desc, o)?;
    }
    if let Some(sky) = &desc.sky {
        let Some(kind) = CieSkyKind::named(&sky.kind.value) else {
            let names = CieSkyKind::NAMES.join(", ");
            return Err(fail(
                desc,
                &sky.kind,
                format!("unknown sky type (known: {names})"),
            ));
        };
        let l = sky.zenith_luminance.value;
        if l < 0.0 {
            return Err(fail(
                desc,
                &sky.zenith_luminance,
                format!("{l} must not be negative"),
            ));
        }
        let sun = sun_direction(desc, sky)?;
        if let Some(e) = &sky.sun_illuminance {
            if !(e.value.is_finite() && e.value >= 0.0) {
                return Err(fail(desc, e, "must be a finite number ≥ 0".into()));
            }
            if sun.is_none() {
                return Err(fail(
                    desc,
                    e,
                    "the sun's beam needs `sun`, the direction towards the sun, or `latitude`, \
                     `longitude`, `date` and `time`"
                        .into(),
                ));
            }
        }
        if sun.is_none() && kind == CieSkyKind::Type12 {
            return Err(fail(
                desc,
                &sky.kind,
                "cie-12 needs `sun`, the direction towards the sun, or `latitude`, \
                 `longitude`, `date` and `time`"
                    .into(),
            ));
        }
    }
    let mut grids = HashSet::new();
    for g in &desc.grids {
        if !grids.insert(g.name.value.as_str()) {
            return Err(fail(desc, &g.name, "duplicate grid name".into()));
        }
        let name = &g.name.value;
        if name.is_empty() || name.starts_with('.') || name.contains(['/', '\\', ':']) {
            return Err(fail(
                desc,
                &g.name,
                format!("grid name {name:?} cannot name its file (<name>.csv)"),
            ));
        }
        match &g.place {
            GridPlace::Corners(c) => {
                let Ok(corners) = <[Vec3; 3]>::try_from(c.value.as_slice()) else {
                    let n = c.value.len();
                    return Err(fail(
                        desc,
                        c,
                        format!(
                            "{n} corners, 3 are needed (origin, end of the first axis, end of \
                             the second)"
                        ),
                    ));
                };
                if let Some((fault, message)) = grid::problem(corners, g.spacing.value) {
                    return Err(match fault {
                        grid::Fault::Corners => fail(desc, c, message),
                        grid::Fault::Spacing => fail(desc, &g.spacing, message),
                    });
                }
            }
            GridPlace::On(on) => {
                if let Some(message) = grid::spacing_problem(g.spacing.value) {
                    return Err(fail(desc, &g.spacing, message));
                }
                if !desc.objects.iter().any(|o| o.name() == on.value) {
                    let mut known: Vec<String> =
                        desc.objects.iter().map(ObjectDesc::name).collect();
                    known.sort_unstable();
                    known.dedup();
                    return Err(fail(
                        desc,
                        on,
                        format!(
                            "unknown object `{}` (defined: {})",
                            on.value,
                            if known.is_empty() {
                                "none".to_string()
                            } else {
                                known.join(", ")
                            }
                        ),
                    ));
                }
            }
        }
        if let Some(n) = &g.normal {
            if n.value.length() <= 0.0 {
                return Err(fail(desc, n, "normal is zero".into()));
            }
        }
    }
    Ok(())
}

/// The direction towards the sun that `[sky]` declares: its `sun`, or the sun's position at
/// its `latitude`, `longitude`, `date` and `time` (with `utc_offset` and `north`;
/// [`solar`]); `None` when it declares neither.
///
/// # Errors
/// A place and time that is incomplete, out of range or given beside `sun`, a `north` with no
/// horizontal part, or a sun below the horizon, each located at its key.
pub fn sun_direction(desc: &SceneDesc, sky: &SkyDesc) -> Result<Option<Vec3>, SceneError> {
    let placed = sky.latitude.is_some()
        || sky.longitude.is_some()
        || sky.date.is_some()
        || sky.time.is_some()
        || sky.utc_offset.is_some()
        || sky.north.is_some();
    if !placed {
        return match &sky.sun {
            Some(sun) if sun.value.y <= 0.0 => Err(fail(
                desc,
                sun,
                "the sun must be above the horizon (y > 0)".into(),
            )),
            Some(sun) => Ok(Some(sun.value.normalize())),
            None => Ok(None),
        };
    }
    if let Some(sun) = &sky.sun {
        return Err(fail(
            desc,
            sun,
            "give either `sun` or the place and time (`latitude`, `longitude`, `date`, `time`), \
             not both"
                .into(),
        ));
    }
    let missing = |key: &str| {
        fail(
            desc,
            &sky.kind,
            format!("the sun's position needs `{key}` beside the other keys of the place and time"),
        )
    };
    let number = |f: &Option<Field<f64>>, key: &str, limit: f64| match f {
        None => Err(missing(key)),
        Some(f) if f.value.is_nan() || f.value.abs() > limit => {
            Err(fail(desc, f, format!("{} is not within ±{limit}", f.value)))
        }
        Some(f) => Ok(f.value),
    };
    let latitude = number(&sky.latitude, "latitude", 90.0)?;
    let longitude = number(&sky.longitude, "longitude", 180.0)?;
    let utc_offset = match &sky.utc_offset {
        None => 0.0,
        Some(_) => number(&sky.utc_offset, "utc_offset", 14.0)?,
    };
    let date = sky.date.as_ref().ok_or_else(|| missing("date"))?;
    let time = sky.time.as_ref().ok_or_else(|| missing("time"))?;
    let moment = solar::Moment {
        latitude,
        longitude,
        date: solar::parse_date(&date.value).ok_or_else(|| {
            fail(
                desc,
                date,
                format!("{:?} is not a date YYYY-MM-DD", date.value),
            )
        })?,
        minutes: solar::parse_time(&time.value)
            .ok_or_else(|| fail(desc, time, format!("{:?} is not a time HH:MM", time.value)))?,
        utc_offset,
    };
    let north = match &sky.north {
        Some(n)
            if n.value.x.hypot(n.value.z) <= f32::EPSILON * n.value.length()
                || !n.value.is_finite() =>
        {
            return Err(fail(
                desc,
                n,
                "north must have a horizontal part (x or z)".into(),
            ));
        }
        Some(n) => n.value,
        None => Vec3::NEG_Z,
    };
    let elevation = moment.elevation();
    if elevation <= 0.0 {
        return Err(fail(
            desc,
            time,
            format!("the sun is below the horizon there and then (elevation {elevation:.1}°)"),
        ));
    }
    Ok(Some(moment.direction(north)))
}

/// A luminaire's values: a direction to aim, a positive multiplier, a visible tint, a
/// strength and a spot's angles in order.
fn check_luminaire(desc: &SceneDesc, l: &LuminaireDesc) -> Result<(), SceneError> {
    if !l.position.value.is_finite() {
        return Err(fail(desc, &l.position, "position must be finite".into()));
    }
    if !(l.aim.value.is_finite() && l.aim.value.length() > 0.0) {
        return Err(fail(
            desc,
            &l.aim,
            "aim must be a non-zero direction".into(),
        ));
    }
    if !l.rotation.value.is_finite() {
        return Err(fail(desc, &l.rotation, "rotation must be finite".into()));
    }
    if !(l.multiplier.value.is_finite() && l.multiplier.value > 0.0) {
        return Err(fail(
            desc,
            &l.multiplier,
            "multiplier must be positive".into(),
        ));
    }
    if let Some(c) = &l.colour {
        check_channels(c, "colour", |x| x.is_finite() && x >= 0.0, "[0, ∞)")
            .map_err(|m| fail(desc, c, m))?;
        if crate::color::luminance(c.value) <= 0.0 {
            return Err(fail(desc, c, "colour must have a luminance above 0".into()));
        }
    }
    let strength = match &l.light {
        LightDesc::File(..) => None,
        LightDesc::Directional(e) => {
            if !(e.value.is_finite() && e.value >= 0.0) {
                return Err(fail(desc, e, "must be a finite number ≥ 0".into()));
            }
            None
        }
        LightDesc::Point(s) => Some(s),
        LightDesc::Spot {
            strength,
            cone,
            beam,
        } => {
            if !(cone.value > 0.0 && cone.value <= 180.0) {
                return Err(fail(desc, cone, "cone must be in (0°, 180°]".into()));
            }
            if let Some(b) = beam {
                if !(b.value >= 0.0 && b.value < cone.value) {
                    return Err(fail(
                        desc,
                        b,
                        format!("beam must be in [0°, cone = {}°)", cone.value),
                    ));
                }
            }
            Some(strength)
        }
    };
    if let Some(Strength::Intensity(f) | Strength::Flux(f)) = strength {
        if !(f.value.is_finite() && f.value >= 0.0) {
            return Err(fail(desc, f, "must be a finite number ≥ 0".into()));
        }
    }
    Ok(())
}

/// An error at `f`'s place and key.
pub(super) fn fail<T>(desc: &SceneDesc, f: &Field<T>, message: String) -> SceneError {
    SceneError::at(
        Loc {
            file: desc.file.clone(),
            line: f.pos.line,
            col: f.pos.col,
        },
        message,
    )
    .with_key(f.key.clone())
}

/// Every channel of `f` passes `ok`, or a message naming the channel.
fn check_channels(
    f: &Field<Rgb>,
    what: &str,
    ok: impl Fn(f64) -> bool,
    range: &str,
) -> Result<(), String> {
    for (name, x) in ["red", "green", "blue"].iter().zip(f.value.to_array()) {
        if !ok(x) {
            return Err(format!("{what} {x} ({name}) is outside {range}"));
        }
    }
    Ok(())
}

/// One object: its material reference, transform and shape.
fn check_object(desc: &SceneDesc, o: &ObjectDesc) -> Result<(), SceneError> {
    match &o.material {
        Some(m) if !desc.materials.iter().any(|d| d.name.value == m.value) => {
            let mut known: Vec<&str> = desc
                .materials
                .iter()
                .map(|d| d.name.value.as_str())
                .collect();
            known.sort_unstable();
            return Err(fail(
                desc,
                m,
                format!(
                    "unknown material `{}` (defined: {})",
                    m.value,
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                ),
            ));
        }
        Some(m) if matches!(o.shape, ShapeDesc::Luminaire(_)) => {
            return Err(fail(
                desc,
                m,
                "a luminaire takes no material (its light is its `file`, `intensity` or `flux`)"
                    .into(),
            ));
        }
        None if !matches!(o.shape, ShapeDesc::Mesh { .. } | ShapeDesc::Luminaire(_)) => {
            let key = format!("objects[{}].material", o.index);
            return Err(fail(
                desc,
                &Field {
                    value: (),
                    pos: o.pos,
                    key,
                },
                "missing required key".into(),
            ));
        }
        _ => {}
    }
    if let Some(t) = &o.transform {
        if t.scale.value.abs().min_element() == 0.0 {
            return Err(fail(desc, &t.scale, "scale must not be zero".into()));
        }
    }
    match &o.shape {
        ShapeDesc::Polygon { vertices } => {
            // Strongly non-planar polygons are split into triangles by the builder, with a
            // warning; degenerate ones are errors.
            match polygon_problem(&vertices.value) {
                None | Some(PolygonProblem::NonPlanar(_)) => {}
                Some(problem) => return Err(fail(desc, vertices, problem.to_string())),
            }
        }
        ShapeDesc::Box { min, max } => {
            if !min.value.cmplt(max.value).all() {
                return Err(fail(
                    desc,
                    max,
                    format!(
                        "max {} must exceed min {} on every axis",
                        max.value, min.value
                    ),
                ));
            }
        }
        ShapeDesc::Sphere {
            radius,
            subdivisions,
            ..
        } => {
            if radius.value <= 0.0 {
                return Err(fail(desc, radius, "radius must be positive".into()));
            }
            if subdivisions.value > MAX_SPHERE_SUBDIVISIONS {
                return Err(fail(
                    desc,
                    subdivisions,
                    format!("at most {MAX_SPHERE_SUBDIVISIONS} subdivisions"),
                ));
            }
        }
        ShapeDesc::Mesh { .. } => {}
        ShapeDesc::Implicit { .. } | ShapeDesc::Csg { .. } => check_solid(desc, &o.shape)?,
        ShapeDesc::Instance { of } => {
            let target = desc
                .objects
                .iter()
                .find(|t| t.name.as_ref().is_some_and(|n| n.value == of.value));
            match target.map(|t| &t.shape) {
                None => {
                    return Err(fail(desc, of, format!("no object named `{}`", of.value)));
                }
                Some(
                    ShapeDesc::Instance { .. } | ShapeDesc::Mesh { .. } | ShapeDesc::Luminaire(_),
                ) => {
                    return Err(fail(
                        desc,
                        of,
                        "an instance cannot reuse another instance, a mesh file or a luminaire"
                            .into(),
                    ));
                }
                Some(_) => {}
            }
        }
        ShapeDesc::Luminaire(l) => check_luminaire(desc, l)?,
        ShapeDesc::BezierPatch {
            points,
            path,
            tolerance,
        } => {
            check_tolerance(desc, tolerance.as_ref())?;
            match (points, path) {
                (Some(_), Some(p)) => {
                    return Err(fail(desc, p, "give either `points` or `path`".into()))
                }
                (None, None) => {
                    let at = Field {
                        value: (),
                        pos: o.pos,
                        key: format!("objects[{}].points", o.index),
                    };
                    return Err(fail(desc, &at, "missing `points` (or `path`)".into()));
                }
                _ => {}
            }
        }
        ShapeDesc::NurbsSurface { tolerance, .. } | ShapeDesc::Teapot { tolerance } => {
            check_tolerance(desc, tolerance.as_ref())?;
        }
        ShapeDesc::Revolve {
            angle, tolerance, ..
        } => {
            check_tolerance(desc, tolerance.as_ref())?;
            if !(angle.value > 0.0 && angle.value <= 360.0) {
                return Err(fail(
                    desc,
                    angle,
                    "angle must be in (0, 360] degrees".into(),
                ));
            }
        }
        ShapeDesc::Subdivision {
            base,
            vertices,
            faces,
            levels,
            ..
        } => {
            if levels.value > MAX_SUBDIVISION_LEVELS {
                return Err(fail(
                    desc,
                    levels,
                    format!("at most {MAX_SUBDIVISION_LEVELS} levels"),
                ));
            }
            match (base, vertices, faces) {
                (Some(_), None, None) => {}
                (None, Some(v), Some(f)) => {
                    let n = v.value.len();
                    if let Some(bad) = f
                        .value
                        .iter()
                        .find(|face| face.len() < 3 || face.iter().any(|&i| i as usize >= n))
                    {
                        return Err(fail(
                            desc,
                            f,
                            format!("face {bad:?} needs 3 or more indices below {n}"),
                        ));
                    }
                }
                _ => {
                    let at = Field {
                        value: (),
                        pos: o.pos,
                        key: format!("objects[{}].base", o.index),
                    };
                    return Err(fail(
                        desc,
                        &at,
                        "give either `base` or both `vertices` and `faces`".into(),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Most subdivision levels (each multiplies the face count by 4).
pub const MAX_SUBDIVISION_LEVELS: u32 = 6;

/// A chordal tolerance, when given, is positive.
fn check_tolerance(desc: &SceneDesc, tolerance: Option<&Field<f64>>) -> Result<(), SceneError> {
    match tolerance {
        Some(t) if t.value <= 0.0 => Err(fail(desc, t, "tolerance must be positive".into())),
        _ => Ok(()),
    }
}

/// Most marching-cubes cells along a side of an implicit shape.
pub const MAX_IMPLICIT_RESOLUTION: u32 = 192;

/// An `implicit` or `csg` shape (and, recursively, a `csg` operand): a bounded expression with
/// a sane resolution; operands closed solids (box, sphere, implicit, csg) with a usable
/// transform.
fn check_solid(desc: &SceneDesc, shape: &ShapeDesc) -> Result<(), SceneError> {
    match shape {
        ShapeDesc::Implicit { sdf, resolution } => {
            if sdf.value.bounds().is_none() {
                return Err(fail(
                    desc,
                    sdf,
                    "the solid is unbounded (intersect it with a box)".into(),
                ));
            }
            if !(4..=MAX_IMPLICIT_RESOLUTION).contains(&resolution.value) {
                return Err(fail(
                    desc,
                    resolution,
                    format!("resolution must be in 4..={MAX_IMPLICIT_RESOLUTION}"),
                ));
            }
        }
        ShapeDesc::Csg { operands, .. } => {
            if operands.value.len() < 2 {
                return Err(fail(desc, operands, "expected at least 2 operands".into()));
            }
            for operand in &operands.value {
                let at = Field {
                    value: (),
                    pos: operand.pos,
                    key: operand.key.clone(),
                };
                if let Some(t) = &operand.transform {
                    if t.scale.value.abs().min_element() == 0.0 {
                        return Err(fail(desc, &t.scale, "scale must not be zero".into()));
                    }
                }
                match &operand.shape {
                    ShapeDesc::Box { min, max } if !min.value.cmplt(max.value).all() => {
                        return Err(fail(desc, max, "max must exceed min on every axis".into()));
                    }
                    ShapeDesc::Sphere {
                        radius,
                        subdivisions,
                        ..
                    } if radius.value <= 0.0 || subdivisions.value > MAX_SPHERE_SUBDIVISIONS => {
                        return Err(fail(
                            desc,
                            radius,
                            format!(
                                "radius must be positive, subdivisions at most \
                                 {MAX_SPHERE_SUBDIVISIONS}"
                            ),
                        ));
                    }
                    ShapeDesc::Box { .. } | ShapeDesc::Sphere { .. } => {}
                    s @ (ShapeDesc::Implicit { .. } | ShapeDesc::Csg { .. }) => {
                        check_solid(desc, s)?;
                    }
                    _ => {
                        return Err(fail(
                            desc,
                            &at,
                            "a csg operand must be a closed solid: box, sphere, implicit or csg"
                                .into(),
                        ));
                    }
                }
            }
        }
        _ => {}
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(lift: f32) -> Vec<Vec3> {
        vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, lift),
            Vec3::new(0.0, 1.0, 0.0),
        ]
    }

    #[test]
    fn polygon_checks() {
        assert_eq!(polygon_problem(&square(0.0)), None);
        // 0.004 lift: the plane fit spreads it to ±0.001 per corner, 0.07 % of √2 → accepted.
        assert_eq!(polygon_problem(&square(0.004)), None);
        assert!(matches!(
            polygon_problem(&square(0.2)),
            Some(PolygonProblem::NonPlanar(_))
        ));
        let line = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        assert_eq!(polygon_problem(&line), Some(PolygonProblem::ZeroArea));
        let dup = [Vec3::ZERO, Vec3::X, Vec3::X, Vec3::ZERO];
        assert_eq!(
            polygon_problem(&dup),
            Some(PolygonProblem::TooFewVertices(2))
        );
        let nan = [Vec3::ZERO, Vec3::X, Vec3::splat(f32::NAN)];
        assert!(polygon_problem(&nan).is_some());
    }
}
