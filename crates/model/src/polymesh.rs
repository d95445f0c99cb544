//! A polygon mesh: shared positions and faces that index them.
//!
//! The common currency between the modeling toolkit and the renderer. Faces are planar polygons
//! with three or more vertices, counter-clockwise seen from the front.

use glam::Vec3;

use crate::Transform;

/// Positions plus faces, each face a list of indices into `positions`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PolyMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Faces as counter-clockwise (seen from the front) index lists.
    pub faces: Vec<Vec<u32>>,
}

impl PolyMesh {
    /// The corners of face `f`, in order.
    ///
    /// # Panics
    /// If `f` or one of its indices is out of range.
    #[must_use]
    pub fn face_positions(&self, f: usize) -> Vec<Vec3> {
        self.faces[f]
            .iter()
            .map(|&i| self.positions[i as usize])
            .collect()
    }

    /// Applies `transform` to every position (orientation is kept when the transform mirrors,
    /// by reversing every face).
    pub fn transform(&mut self, transform: &Transform) {
        for p in &mut self.positions {
            *p = transform.point(*p);
        }
        if transform.mirrors() {
            for f in &mut self.faces {
                f.reverse();
            }
        }
    }

    /// Sum of face areas (each face measured by its vector area, exact for planar polygons).
    #[must_use]
    pub fn area(&self) -> f64 {
        (0..self.faces.len())
            .map(|f| f64::from(vector_area(&self.face_positions(f)).length()))
            .sum()
    }
}

/// Vector area of a polygon: half the sum of the cross products of consecutive vertices (Newell's
/// method). Its direction is the polygon's normal (right-hand rule), its length the area of a
/// planar polygon.
#[must_use]
pub fn vector_area(vertices: &[Vec3]) -> Vec3 {
    // Accumulate relative to the first vertex, which keeps precision far from the origin.
    let Some(&origin) = vertices.first() else {
        return Vec3::ZERO;
    };
    let mut sum = glam::DVec3::ZERO;
    for w in vertices.windows(2).skip(1) {
        sum += (w[0] - origin).as_dvec3().cross((w[1] - origin).as_dvec3());
    }
    (sum * 0.5).as_vec3()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_square_has_unit_area_and_up_normal() {
        let sq = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        assert_eq!(vector_area(&sq), Vec3::new(0.0, 0.0, 1.0));
    }

    #[test]
    fn non_convex_l_shape_area() {
        // An L made of three unit squares.
        let l = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ];
        assert!((vector_area(&l).z - 3.0).abs() < 1e-6);
    }
}
