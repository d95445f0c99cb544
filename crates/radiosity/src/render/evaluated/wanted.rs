//! The elements a picture needs evaluated.
//!
//! Before the picture, every element's far part R and the values at its pieces are settled
//! ([`super::far_radiosity`]): the exact direct light at four points of the element and the
//! near field gathered there, twice. That is work per element, and a scanned or tessellated
//! model has hundreds of thousands of elements the camera never sees (Bitterli's veach-ajar:
//! 585 000 elements, most on four teapots, for a 256 × 144 picture). A point of the picture
//! reads only
//!
//! - R at the vertices of the lit-mesh triangle it lies on, from the elements of its surface
//!   around them (within a few of their diameters d_e of the vertex: [`READ_RINGS`]);
//! - the pieces of the elements it opens, those within `OPEN_WITHIN` of their diameters.
//!
//! So the elements of a visible point's surface near the vertices of its triangle and those it
//! opens are settled, and so are those that the pieces of these open, which their second
//! settling reads. The elements' boxes, widened by the larger of the two distances, go into a
//! box tree, and each visible point, vertex and piece is one point query: the work follows
//! the pixels and the elements seen, not the mesh. The visible points are found by 2 × 2
//! primary rays per pixel. Every other element gets the cheap split, R = B_i with no near
//! part, which no point of the picture reads, except where a pixel's own samples find a
//! surface its four probes missed (along a silhouette): the furnished room at 256² settles
//! 8 826 of its 27 808 elements, and its pixels differ from those of settling all by at most
//! 3·10⁻⁴ of their value. A scene whose surfaces include mirrors or glass is evaluated
//! everywhere: its rays go anywhere.

use std::sync::atomic::{AtomicBool, Ordering};

use glam::Vec3;
use rayon::prelude::*;

use super::near_field::NearField;
use crate::accel::{Aabb, Bvh};
use crate::mesh::Mesh;
use crate::render::camera::Projection;
use crate::render::raytrace::world::World;
use crate::render::RasterSettings;
use crate::scene::Camera;
use crate::Scene;

/// A vertex's R is read from the elements around it (centroids within one of their diameters),
/// and on a surface's border extrapolated from the vertices a few rings of elements inwards
/// (`display::lit_mesh_faceted`): an element is read from vertices within this many of its
/// diameters.
const READ_RINGS: f32 = 6.0;

/// Primary rays per pixel side that find the visible points.
const PROBES: u32 = 2;

/// The elements the picture through `camera` can read (by element index), or `None` when it
/// may read any (a mesh with a specular surface: a material defined but used by no surface, or
/// only by glass left out of the mesh, does not count).
pub(super) fn wanted(
    scene: &Scene,
    world: &World,
    mesh: &Mesh,
    near: &NearField,
    (camera, image): (&Camera, &RasterSettings),
) -> Option<Vec<bool>> {
    if mesh.patches.iter().any(|p| {
        scene
            .materials
            .get(p.material as usize)
            .is_some_and(|m| m.is_specular())
    }) {
        return None;
    }
    let proj = Projection::new(camera, image.width, image.height);
    let visible: Vec<(Vec3, u32)> = (0..image.height)
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
                let triangle = hit.diffuse.map_or(hit.triangle, |d| d.0);
                hit.point.is_finite().then_some((hit.point, triangle))
            })
        })
        .collect();
    let balls = Balls::new(mesh, near);
    let mut triangles: Vec<u32> = visible.iter().map(|&(_, t)| t).collect();
    triangles.sort_unstable();
    triangles.dedup();
    let vertices = triangles.iter().flat_map(|&t| {
        let surface = near.surface(world.patch(t));
        world.lit_triangle(t).map(|v| (v, Some(surface)))
    });
    let points: Vec<(Vec3, Option<u32>)> = visible
        .iter()
        .map(|&(p, _)| (p, None))
        .chain(vertices)
        .collect();
    let wanted = balls.holding(&points, vec![false; mesh.element_count()]);
    let pieces: Vec<(Vec3, Option<u32>)> = (0..mesh.element_count())
        .filter(|&e| wanted[e])
        .flat_map(|e| near.pieces[e].centroids.map(|q| (q, None)))
        .collect();
    Some(balls.holding(&pieces, wanted))
}

/// The elements' centroids and diameters, in a box tree over their boxes widened by the
/// larger of the distance at which a point opens them and [`READ_RINGS`] diameters.
struct Balls {
    /// One degenerate triangle per element, across its widened box.
    tree: Bvh,
    /// Centroid, diameter and opening distance of each element.
    elements: Vec<(Vec3, f32, f32)>,
    /// The lit-mesh surface of each element's patch, by element.
    element_surface: Vec<u32>,
}

impl Balls {
    fn new(mesh: &Mesh, near: &NearField) -> Self {
        let elements: Vec<(Vec3, f32, f32)> = (0..mesh.element_count())
            .map(|e| {
                let (c, d) = near.element_shape(mesh, e);
                (c, d, near.open_radius(d))
            })
            .collect();
        let boxes: Vec<[Vec3; 3]> = elements
            .iter()
            .map(|&(c, d, open)| {
                let r = Vec3::splat(open.max(READ_RINGS * d));
                [c - r, c + r, c - r]
            })
            .collect();
        Self {
            tree: Bvh::build(&boxes),
            elements,
            element_surface: (0..mesh.element_count())
                .map(|e| near.surface(mesh.element(e).patch))
                .collect(),
        }
    }

    /// `marked`, with every element read from one of `points` marked too: a point p reads an
    /// element of centroid c and diameter d that it opens, and a vertex p of a lit triangle on
    /// surface s (`Some(s)`) those of s with |c − p| < [`READ_RINGS`] d.
    fn holding(&self, points: &[(Vec3, Option<u32>)], marked: Vec<bool>) -> Vec<bool> {
        let marked: Vec<AtomicBool> = marked.into_iter().map(AtomicBool::new).collect();
        points.par_iter().for_each(|&(p, surface)| {
            let query = Aabb { min: p, max: p };
            self.tree.overlapping(&query, |e| {
                let (c, d, open) = self.elements[e];
                let r = c.distance(p);
                let around = surface == Some(self.element_surface[e]) && r < READ_RINGS * d;
                if r < open || around {
                    marked[e].store(true, Ordering::Relaxed);
                }
            });
        });
        marked.into_iter().map(AtomicBool::into_inner).collect()
    }
}
