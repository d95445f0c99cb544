//! Faces: the triangles and quadrilaterals that patches are split into.
//!
//! An element of the radiosity method is a face of an element quadtree: a quadrilateral splits
//! into four at its edge midpoints and centre, a triangle into four at its edge midpoints (three
//! corner triangles and the inverted middle one). Both splits keep every child similar to its
//! parent, so repeated subdivision never produces slivers, and every new vertex lies at a
//! dyadic position along an edge, which is what makes T-vertices easy to find in the display
//! mesh (see [`super::display`]).

use glam::Vec3;

/// A triangle or a quadrilateral, counter-clockwise seen from the front.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    corners: [Vec3; 4],
    sides: u8,
}

impl Face {
    /// A triangle `a, b, c`.
    #[must_use]
    pub fn triangle(a: Vec3, b: Vec3, c: Vec3) -> Self {
        Self {
            corners: [a, b, c, c],
            sides: 3,
        }
    }

    /// A quadrilateral `a, b, c, d` (planar or nearly so, convex).
    #[must_use]
    pub fn quad(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Self {
        Self {
            corners: [a, b, c, d],
            sides: 4,
        }
    }

    /// The three or four corners in order.
    #[must_use]
    pub fn corners(&self) -> &[Vec3] {
        &self.corners[..usize::from(self.sides)]
    }

    /// The corners in `f64` (the form-factor formulas' precision) and how many there are.
    #[must_use]
    pub fn corners_f64(&self) -> ([glam::DVec3; 4], usize) {
        let mut out = [glam::DVec3::ZERO; 4];
        for (o, c) in out.iter_mut().zip(self.corners()) {
            *o = c.as_dvec3();
        }
        (out, usize::from(self.sides))
    }

    /// Whether this is a quadrilateral.
    #[must_use]
    pub fn is_quad(&self) -> bool {
        self.sides == 4
    }

    /// Vector area (Newell): direction is the normal, length the area.
    #[must_use]
    pub fn vector_area(&self) -> glam::DVec3 {
        let c = self.corners.map(|p| p.as_dvec3());
        if self.is_quad() {
            // Half the cross product of the diagonals: exact for planar quads.
            0.5 * (c[2] - c[0]).cross(c[3] - c[1])
        } else {
            0.5 * (c[1] - c[0]).cross(c[2] - c[0])
        }
    }

    /// Area.
    #[must_use]
    pub fn area(&self) -> f64 {
        self.vector_area().length()
    }

    /// Unit normal (zero for a degenerate face).
    #[must_use]
    pub fn normal(&self) -> Vec3 {
        self.vector_area().normalize_or_zero().as_vec3()
    }

    /// Centroid of the area (for a quad: the area-weighted centroids of its two triangles).
    #[must_use]
    pub fn centroid(&self) -> Vec3 {
        let c = self.corners.map(|p| p.as_dvec3());
        if !self.is_quad() {
            return ((c[0] + c[1] + c[2]) / 3.0).as_vec3();
        }
        let a1 = 0.5 * (c[1] - c[0]).cross(c[2] - c[0]).length();
        let a2 = 0.5 * (c[2] - c[0]).cross(c[3] - c[0]).length();
        let g1 = (c[0] + c[1] + c[2]) / 3.0;
        let g2 = (c[0] + c[2] + c[3]) / 3.0;
        if a1 + a2 > 0.0 {
            ((g1 * a1 + g2 * a2) / (a1 + a2)).as_vec3()
        } else {
            ((c[0] + c[1] + c[2] + c[3]) / 4.0).as_vec3()
        }
    }

    /// Maps `(u, v)` in the unit square onto the face: bilinearly for a quad (uniform in area for
    /// a parallelogram), and for a triangle by folding the square's upper half onto the lower
    /// one, which is uniform in area. Stratified samples in the square stay stratified on the
    /// face.
    #[must_use]
    pub fn point(&self, u: f32, v: f32) -> Vec3 {
        let c = &self.corners;
        if self.is_quad() {
            let bottom = c[0].lerp(c[1], u);
            let top = c[3].lerp(c[2], u);
            bottom.lerp(top, v)
        } else {
            let (u, v) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            c[0] + (c[1] - c[0]) * u + (c[2] - c[0]) * v
        }
    }

    /// The four children of one quadtree subdivision step, each with its parent's orientation.
    #[must_use]
    pub fn split(&self) -> [Face; 4] {
        let c = &self.corners;
        let mid = |a: Vec3, b: Vec3| (a + b) * 0.5;
        if self.is_quad() {
            let (m01, m12, m23, m30) = (
                mid(c[0], c[1]),
                mid(c[1], c[2]),
                mid(c[2], c[3]),
                mid(c[3], c[0]),
            );
            let centre = (c[0] + c[1] + c[2] + c[3]) * 0.25;
            [
                Face::quad(c[0], m01, centre, m30),
                Face::quad(m01, c[1], m12, centre),
                Face::quad(centre, m12, c[2], m23),
                Face::quad(m30, centre, m23, c[3]),
            ]
        } else {
            let (m01, m12, m20) = (mid(c[0], c[1]), mid(c[1], c[2]), mid(c[2], c[0]));
            [
                Face::triangle(c[0], m01, m20),
                Face::triangle(m01, c[1], m12),
                Face::triangle(m20, m12, c[2]),
                Face::triangle(m12, m20, m01),
            ]
        }
    }

    /// Length of the longest edge (or diagonal).
    #[must_use]
    pub fn diameter(&self) -> f32 {
        diameter(self.corners())
    }
}

/// The largest distance between two of `points` (0 for fewer than two).
#[must_use]
pub fn diameter(points: &[Vec3]) -> f32 {
    let mut d: f32 = 0.0;
    for (i, a) in points.iter().enumerate() {
        for b in &points[i + 1..] {
            d = d.max(a.distance(*b));
        }
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> Face {
        Face::quad(
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
    }

    #[test]
    fn children_partition_the_parent() {
        let tri = Face::triangle(
            Vec3::ZERO,
            Vec3::new(3.0, 0.0, 1.0),
            Vec3::new(0.5, 2.0, 0.0),
        );
        for f in [quad(), tri] {
            let children = f.split();
            let sum: f64 = children.iter().map(Face::area).sum();
            assert!((sum - f.area()).abs() < 1e-6 * f.area());
            for c in &children {
                // Same orientation: the normals agree.
                assert!(c.normal().dot(f.normal()) > 0.9999);
                assert!((c.area() - f.area() / 4.0).abs() < 1e-6 * f.area());
            }
        }
    }

    #[test]
    fn point_covers_the_face() {
        let tri = Face::triangle(Vec3::ZERO, Vec3::X, Vec3::Y);
        assert_eq!(tri.point(0.0, 0.0), Vec3::ZERO);
        assert_eq!(tri.point(1.0, 1.0), Vec3::ZERO);
        assert_eq!(tri.point(1.0, 0.0), Vec3::X);
        assert_eq!(quad().point(1.0, 1.0), Vec3::new(2.0, 1.0, 0.0));
        assert_eq!(quad().centroid(), Vec3::new(1.0, 0.5, 0.0));
    }
}
