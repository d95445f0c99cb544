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

use glam::Vec3;
use rayon::prelude::*;

use super::near_field::NearField;
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
    let n = mesh.element_count();
    let proj = Projection::new(camera, image.width, image.height);
    let union = |mut a: Vec<bool>, b: Vec<bool>| {
        a.iter_mut().zip(b).for_each(|(a, b)| *a |= b);
        a
    };
    let seen = (0..image.height)
        .into_par_iter()
        .fold(
            || vec![false; n],
            |mut out, y| {
                for x in 0..image.width {
                    for k in 0..PROBES * PROBES {
                        let (i, j) = ((k % PROBES) as f32, (k / PROBES) as f32);
                        let step = 1.0 / PROBES as f32;
                        let px = x as f32 + (i + 0.5) * step;
                        let py = y as f32 + (j + 0.5) * step;
                        let (origin, dir) = proj.primary_ray(px, py);
                        let Some(hit) = world.intersect(origin, dir, f32::INFINITY) else {
                            continue;
                        };
                        let patch = world.patch(hit.diffuse.map_or(hit.triangle, |d| d.0));
                        near.mark_within(mesh, hit.point, 2.0 * near.reach(patch), &mut out);
                    }
                }
                out
            },
        )
        .reduce(|| vec![false; n], union);
    let wanted = (0..n)
        .into_par_iter()
        .filter(|&e| seen[e])
        .fold(
            || vec![false; n],
            |mut out, e| {
                let node = mesh.element(e);
                let (centre, radius): (Vec3, f32) = node.sphere();
                near.mark_within(mesh, centre, near.reach(node.patch) + radius, &mut out);
                out
            },
        )
        .reduce(|| vec![false; n], union);
    Some(wanted)
}
