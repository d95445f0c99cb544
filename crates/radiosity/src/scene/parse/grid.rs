//! `[[grids]]`: a calculation grid ([`crate::scene::grid`]).

use super::table::Table;
use crate::scene::description::{GridDesc, GridPlace};
use crate::scene::SceneError;

/// One `[[grids]]` entry: `name`, `corners` (three points) or `on` (an object's name), not
/// both, `spacing`, optional `normal`.
pub(super) fn parse_grid(mut t: Table<'_>) -> Result<GridDesc, SceneError> {
    let src = t.src;
    t.check_keys(&["name", "corners", "on", "spacing", "normal"])?;
    let name = t.required_with("name", |k, v| src.string(k, v))?;
    let corners = t.optional("corners", |k, v| src.vec3_list(k, v))?;
    let on = t.optional("on", |k, v| src.string(k, v))?;
    let place = match (corners, on) {
        (Some(corners), None) => GridPlace::Corners(corners),
        (None, Some(on)) => GridPlace::On(on),
        (Some(_), Some(on)) => {
            return Err(src.error_at(
                &on,
                "`corners` and `on` exclude each other: a grid lies on a parallelogram or on \
                 an object, give one",
            ))
        }
        (None, None) => {
            return Err(src.error(
                &t.span,
                &t.path,
                "missing `corners` (a parallelogram) or `on` (an object's name): where the \
                 grid lies",
            ))
        }
    };
    Ok(GridDesc {
        name,
        place,
        spacing: t.required_with("spacing", |k, v| src.f32(k, v))?,
        normal: t.optional("normal", |k, v| src.vec3(k, v))?,
    })
}
