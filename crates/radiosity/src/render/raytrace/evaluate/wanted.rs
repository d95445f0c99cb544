//! The elements a picture needs evaluated.
//!
//! Before the picture, every element's far part R and the values at its pieces are settled
//! ([`super::far_radiosity`]): the exact direct light at four points of the element and the
//! near field gathered there, twice. That is work per element, and a scanned or tessellated
//! model has hundreds of thousands of elements the camera never sees (Bitterli's veach-ajar:
//! 585 000 elements, most on four teapots, for a 256 × 144 picture). A point of the picture
//! reads only
//!
//! - R at the vertices of the lit-mesh triangle it lies on, from the elements around them on
//!   its own surface, all within one element diameter of it, which is at most 1/`NEAR_REACH`
//!   of its patch's near-field reach r (the reach is taken from the largest element of the
//!   surface);
//! - the pieces of the elements within r of it (its near field).
//!
//! So the elements within 2r of a visible point need their second settling, and those within
//! their own reach (plus their diameter) of those need their first: two dilations of the set
//! of visible points over the near field's box tree. The visible points are found by 2 × 2
//! primary rays per pixel. Every other element gets the cheap split, R = B_i with no near
//! part, which no point of the picture reads. A scene with mirrors or glass is evaluated
//! everywhere: its rays go anywhere.

use std::ops::Range;

use glam::Vec3;
use rayon::prelude::*;

use super::near_field::{NearField, NEAR_REACH};
use crate::mesh::Mesh;
use crate::render::camera::Projection;
use crate::render::raytrace::world::World;
use crate::render::RasterSettings;
use crate::scene::Camera;
use crate::Scene;

/// Primary rays per pixel side that find the visible points.
const PROBES: u32 = 2;

/// The elements the picture through `camera` can read (by element index), or `None` when it
/// may read any (a scene with specular materials).
pub(super) fn wanted(
    scene: &Scene,
    world: &World,
    mesh: &Mesh,
    near: &NearField,
    (camera, image): (&Camera, &RasterSettings),
) -> Option<Vec<bool>> {
    if scene.materials.iter().any(|m| m.is_specular()) {
        return None;
    }
    let proj = Projection::new(camera, image.width, image.height);
    let visible: Vec<(Vec3, f32)> = (0..image.height)
        .into_par_iter()
        .flat_map_iter(|y| {
            let proj = &proj;
            (0..image.width * PROBES * PROBES).filter_map(move |k| {
                let (x, sub) = (k / (PROBES * PROBES), k % (PROBES * PROBES));
                let step = 1.0 / PROBES as f32;
                let px = x as f32 + ((sub % PROBES) as f32 + 0.5) * step;
                let py = y as f32 + ((sub / PROBES) as f32 + 0.5) * step;
                let (origin, dir) = proj.primary_ray(px, py);
                let hit = world.intersect(origin, dir, f32::INFINITY)?;
                let patch = world.patch(hit.diffuse.map_or(hit.triangle, |d| d.0));
                Some((hit.point, 2.0 * near.reach(patch)))
            })
        })
        .collect();
    // A visible point reads R at the vertices of its lit-mesh triangle, from elements of its
    // own surface at most one of their diameters from a vertex, which is within the largest
    // element diameter of the surface (reach / NEAR_REACH) of the point; and the pieces of
    // the elements it opens.
    let seen = mark(mesh, near, visible, |e, point, d, slack| {
        let (centre, diameter) = near.element_shape(mesh, e);
        near.opens(mesh, e, point, slack)
            || centre.distance(point) < 0.5 * d / NEAR_REACH + diameter + slack
    });
    // Each seen element's pieces, within its radius of its centre, read the pieces of the
    // elements they open.
    let (mut around, mut radius) = (Vec::new(), 0.0f32);
    for e in (0..mesh.element_count()).filter(|&e| seen[e]) {
        let node = mesh.element(e);
        let (centre, r) = node.sphere();
        around.push((centre, near.reach(node.patch) + r));
        radius = radius.max(r);
    }
    Some(mark(mesh, near, around, |e, point, _, slack| {
        near.opens(mesh, e, point, slack + radius)
    }))
}

/// The elements that `keep(e, point, d, slack)` accepts among those within distance d of some
/// ball (point, d) of `balls`, `slack` what the merging below adds to the distance. Balls are
/// merged into cells of a grid of side d/2 (d rounded up to a power of 2^¼), each queried once
/// with its cell's half-diagonal as the slack: a superset, at a cost bounded by the space
/// they cover, not by their number.
fn mark(
    mesh: &Mesh,
    near: &NearField,
    balls: Vec<(Vec3, f32)>,
    keep: impl Fn(usize, Vec3, f32, f32) -> bool + Sync,
) -> Vec<bool> {
    let mut cells: Vec<(i32, [i32; 3])> = balls
        .into_iter()
        .filter(|(p, d)| p.is_finite() && *d > 0.0)
        .map(|(p, d)| {
            let level = (d.log2() * 4.0).ceil() as i32;
            let side = 0.5 * rounded(level);
            let cell = (p / side).floor();
            (level, [cell.x as i32, cell.y as i32, cell.z as i32])
        })
        .collect();
    cells.sort_unstable();
    cells.dedup();
    let kept: Vec<u32> = cells
        .par_iter()
        .flat_map_iter(|&(level, [x, y, z])| {
            let d = rounded(level);
            let side = 0.5 * d;
            let centre = (Vec3::new(x as f32, y as f32, z as f32) + 0.5) * side;
            let slack = 0.87 * side;
            let mut ranges: Vec<Range<u32>> = Vec::new();
            near.within(mesh, centre, d + slack, &mut ranges);
            ranges
                .into_iter()
                .flatten()
                .filter(|&e| keep(e as usize, centre, d, slack))
                .collect::<Vec<u32>>()
        })
        .collect();
    let mut marked = vec![false; mesh.element_count()];
    for e in kept {
        marked[e as usize] = true;
    }
    marked
}

/// 2^(level/4).
fn rounded(level: i32) -> f32 {
    (level as f32 / 4.0).exp2()
}
