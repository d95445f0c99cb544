//! The `transform` table an object, a `csg` operand or a signed distance expression may hold:
//! `transform = { scale, rotate, translate }` ([`TransformDesc`]: scale, then rotate about x,
//! y, z in degrees, then translate). It sits below both shape and signed-distance parsing,
//! which each read one.

use glam::Vec3;

use super::table::Table;
use super::value::Kind;
use crate::scene::description::TransformDesc;
use crate::scene::SceneError;

/// The optional `transform` table of an object, operand or signed distance expression.
pub(super) fn take_transform(t: &mut Table<'_>) -> Result<Option<TransformDesc>, SceneError> {
    let path = t.child_path("transform");
    t.take("transform")
        .map(|(_, v)| parse_transform(Table::new(t.src, path, v)?))
        .transpose()
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
