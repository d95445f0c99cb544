//! A planar polygon as the root faces of its quadtree, and the test that it is planar enough
//! to be one patch (see [`super::patch`]).

use glam::Vec3;

use super::triangulate::{is_convex, triangulate};
use super::Face;

/// How far (relative to its diameter) a polygon's corners may stray from its mean plane for it
/// to stay one patch: well above f32 rounding, well below anything that changes light.
pub const PLANAR_TOLERANCE: f32 = 1e-4;

/// Whether every corner lies within [`PLANAR_TOLERANCE`] of the polygon's diameter from the
/// plane through the corners' mean with the polygon's (Newell) normal.
pub(super) fn is_planar(vertices: &[Vec3], normal: Vec3) -> bool {
    let mean = vertices.iter().sum::<Vec3>() / vertices.len() as f32;
    let diameter = super::face::diameter(vertices);
    vertices
        .iter()
        .all(|v| normal.dot(*v - mean).abs() <= PLANAR_TOLERANCE * diameter)
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
}
