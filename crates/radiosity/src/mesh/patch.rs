//! Patches: the sides of the scene's planar polygons that take part in light transport.
//!
//! Each polygon gives one patch for its front. A `two_sided` material gives a second patch for
//! the back (the same corners in reverse order, so its "front" is the polygon's back), which
//! reflects with the same ρ but never emits: emission is from the front only (DESIGN.md §2).

use glam::Vec3;

use super::triangulate::{is_convex, triangulate};
use super::Face;
use crate::{Rgb, Scene};

/// One reflecting (and possibly emitting) side of a scene polygon.
#[derive(Clone, Debug)]
pub struct Patch {
    /// Index into [`Scene::polygons`].
    pub polygon: u32,
    /// Index into [`Scene::objects`].
    pub object: u32,
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Whether this is the back side of a two-sided polygon.
    pub back: bool,
    /// Whether the polygon's material is two-sided (so this patch has a reversed twin).
    pub two_sided: bool,
    /// Unit normal (Newell's method).
    pub normal: Vec3,
    /// Area.
    pub area: f64,
    /// Diffuse reflectance ρ.
    pub reflectance: Rgb,
    /// Emitted exitance E = π·L_e (W·m⁻²); zero on back sides.
    pub emission: Rgb,
}

/// The patches of `scene` with the root faces of each patch's element quadtree.
pub(super) fn patches(scene: &Scene) -> Vec<(Patch, Vec<Face>)> {
    let mut out = Vec::with_capacity(scene.polygons.len());
    for (i, polygon) in scene.polygons.iter().enumerate() {
        let material = &scene.materials[polygon.material];
        let normal = model::polymesh::vector_area(&polygon.vertices).normalize_or_zero();
        let roots = root_faces(&polygon.vertices, normal);
        let area = roots.iter().map(Face::area).sum();
        let front = Patch {
            polygon: i as u32,
            object: polygon.object as u32,
            material: polygon.material as u32,
            back: false,
            two_sided: material.two_sided,
            normal,
            area,
            reflectance: material.reflectance,
            emission: material.emission * std::f64::consts::PI,
        };
        if material.two_sided {
            let back = Patch {
                back: true,
                normal: -normal,
                emission: Rgb::ZERO,
                ..front.clone()
            };
            let reversed = roots.iter().map(reverse).collect();
            out.push((front, roots));
            out.push((back, reversed));
        } else {
            out.push((front, roots));
        }
    }
    out
}

/// The same face seen from the other side.
fn reverse(face: &Face) -> Face {
    match *face.corners() {
        [a, b, c] => Face::triangle(a, c, b),
        [a, b, c, d] => Face::quad(a, d, c, b),
        _ => unreachable!("faces have three or four corners"),
    }
}

/// Splits a polygon into the root faces of its quadtree: a triangle stays a triangle; a convex
/// quadrilateral stays a quadrilateral, cut into near-square strips when it is elongated (so
/// that subdivision does not make slivers); anything else is triangulated by ear clipping.
pub(super) fn root_faces(vertices: &[Vec3], normal: Vec3) -> Vec<Face> {
    match *vertices {
        [a, b, c] => vec![Face::triangle(a, b, c)],
        [a, b, c, d] if is_convex(vertices, normal) => strips(a, b, c, d),
        _ => triangulate(vertices, normal)
            .into_iter()
            .map(|[a, b, c]| {
                Face::triangle(
                    vertices[a as usize],
                    vertices[b as usize],
                    vertices[c as usize],
                )
            })
            .collect(),
    }
}

/// Cuts the quad `a b c d` into k ≈ aspect-ratio strips across its longer direction.
fn strips(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Vec<Face> {
    let along_ab = 0.5 * (a.distance(b) + d.distance(c));
    let along_bc = 0.5 * (b.distance(c) + a.distance(d));
    let ratio = along_ab.max(along_bc) / along_ab.min(along_bc).max(f32::MIN_POSITIVE);
    let k = (ratio.round() as usize).clamp(1, 64);
    // Rotate the corner order (keeping the orientation) so the long direction runs p → q.
    let (p, q, r, s) = if along_ab >= along_bc {
        (a, b, c, d)
    } else {
        (b, c, d, a)
    };
    (0..k)
        .map(|i| {
            let (t0, t1) = (i as f32 / k as f32, (i + 1) as f32 / k as f32);
            Face::quad(p.lerp(q, t0), p.lerp(q, t1), s.lerp(r, t1), s.lerp(r, t0))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elongated_quad_becomes_square_strips_of_same_orientation() {
        let (a, b, c, d) = (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 4.0, 0.0),
            Vec3::new(0.0, 4.0, 0.0),
        );
        let faces = root_faces(&[a, b, c, d], Vec3::Z);
        assert_eq!(faces.len(), 4);
        let total: f64 = faces.iter().map(Face::area).sum();
        assert!((total - 4.0).abs() < 1e-6);
        for f in &faces {
            assert!(f.normal().dot(Vec3::Z) > 0.999);
            assert!((f.area() - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn reversed_face_has_opposite_normal() {
        let f = Face::quad(Vec3::ZERO, Vec3::X, Vec3::X + Vec3::Y, Vec3::Y);
        assert_eq!(reverse(&f).normal(), -f.normal());
    }
}
