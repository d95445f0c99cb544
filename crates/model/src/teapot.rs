//! The Utah teapot (Martin Newell, 1975): 32 bicubic Bézier patches over 306 control points,
//! the public-domain data set of the course's surface-modeling lecture, in
//! `crates/model/data/teapot.txt`.
//!
//! The file is in Newell's text format, which [`parse_newell`] reads for any patch set: a
//! patch count, one line per patch of 16 comma-separated 1-based control-point indices (row by
//! row, u major), a point count, and one `x,y,z` line per point. The original data is z-up;
//! [`teapot_patches`] turns it to y-up ((x, y, z) ↦ (x, z, −y), a rotation) so that it stands
//! on the floor of a scene, 3.15 units tall and about 6 long (spout to handle).
//!
//! In the data, S_u × S_v points into the pot (renderers of the time negated it);
//! [`teapot_patches`] reverses u so that the fronts face out. The rim, body, lid and
//! bottom patches meet along shared boundary curves, which [`crate::surface::tessellate`]
//! cuts identically on both sides; the handle and spout pass through the body, as in the
//! original model.

use glam::DVec3;

use crate::surface::NurbsSurface;

/// Newell's data, compiled in.
pub const TEAPOT_DATA: &str = include_str!("../data/teapot.txt");

/// Reads bicubic Bézier patches in Newell's format (see the module docs).
///
/// # Errors
/// A one-line message with the 1-based line number: a missing or malformed count, index or
/// coordinate, an index out of range, or a patch without 16 indices.
pub fn parse_newell(text: &str) -> Result<Vec<NurbsSurface>, String> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let mut next = |what: &str| {
        lines
            .next()
            .ok_or_else(|| format!("unexpected end of file: expected {what}"))
    };
    let count = |(n, l): (usize, &str), what: &str| {
        l.parse::<usize>()
            .map_err(|_| format!("line {n}: expected the number of {what}, found `{l}`"))
    };
    let patch_count = count(next("the number of patches")?, "patches")?;
    let mut patches = Vec::with_capacity(patch_count.min(1 << 16));
    for _ in 0..patch_count {
        let (n, l) = next("a patch's 16 indices")?;
        let ids = l
            .split(',')
            .map(|s| s.trim().parse::<usize>())
            .collect::<Result<Vec<_>, _>>()
            .map_err(|_| format!("line {n}: expected 16 comma-separated indices"))?;
        if ids.len() != 16 || ids.contains(&0) {
            return Err(format!("line {n}: expected 16 indices from 1"));
        }
        patches.push((n, ids));
    }
    let point_count = count(next("the number of points")?, "points")?;
    let mut points = Vec::with_capacity(point_count.min(1 << 20));
    for _ in 0..point_count {
        let (n, l) = next("a point `x,y,z`")?;
        let c = l
            .split(',')
            .map(|s| s.trim().parse::<f64>())
            .collect::<Result<Vec<_>, _>>()
            .map_err(|_| format!("line {n}: expected `x,y,z`"))?;
        match c[..] {
            [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => {
                points.push(DVec3::new(x, y, z));
            }
            _ => return Err(format!("line {n}: expected three finite numbers `x,y,z`")),
        }
    }
    patches
        .into_iter()
        .map(|(n, ids)| {
            let control = ids
                .iter()
                .map(|&i| points.get(i - 1).copied())
                .collect::<Option<Vec<_>>>()
                .ok_or_else(|| format!("line {n}: index out of range (1 to {point_count})"))?;
            NurbsSurface::bezier(4, 4, &control).ok_or_else(|| format!("line {n}: invalid patch"))
        })
        .collect()
}

/// The teapot's 32 patches, y-up, outward.
#[must_use]
pub fn teapot_patches() -> Vec<NurbsSurface> {
    parse_newell(TEAPOT_DATA)
        .unwrap_or_default()
        .into_iter()
        .map(|p| p.map_points(|q| DVec3::new(q.x, q.z, -q.y)).flipped())
        .collect()
}
