//! `[[grids]]`: a calculation grid ([`crate::scene::grid`]).

use super::table::Table;
use crate::scene::description::GridDesc;
use crate::scene::SceneError;

/// One `[[grids]]` entry: `name`, `corners` (three points), `spacing`, optional `normal`.
pub(super) fn parse_grid(mut t: Table<'_>) -> Result<GridDesc, SceneError> {
    let src = t.src;
    t.check_keys(&["name", "corners", "spacing", "normal"])?;
    Ok(GridDesc {
        name: t.required_with("name", |k, v| src.string(k, v))?,
        corners: t.required_with("corners", |k, v| src.vec3_list(k, v))?,
        spacing: t.required_with("spacing", |k, v| src.f32(k, v))?,
        normal: t.optional("normal", |k, v| src.vec3(k, v))?,
    })
}
