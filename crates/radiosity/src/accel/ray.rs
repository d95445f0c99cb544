//! Rays, hits and the ray–triangle test.
//!
//! A ray is x(t) = o + t·d for t > 0. A triangle (a, b, c) is hit where
//! o + t·d = (1 − u − v)·a + u·b + v·c with u ≥ 0, v ≥ 0, u + v ≤ 1. With the edges
//! e₁ = b − a, e₂ = c − a and s = o − a, Cramer's rule gives (Möller & Trumbore 1997,
//! "Fast, minimum storage ray-triangle intersection"):
//!
//! ```text
//! p = d × e₂,  det = e₁·p,  q = s × e₁,
//! u = (s·p)/det,  v = (d·q)/det,  t = (e₂·q)/det.
//! ```
//!
//! Both faces are hit (visibility does not care which side a blocker shows). A triangle of zero
//! area has det = 0 and is never hit.

use glam::Vec3;

/// A ray x(t) = `origin` + t·`dir`, t > 0. `dir` need not be normalised: t is measured in units
/// of its length. Direction components may be zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Where the ray goes (any non-zero length).
    pub dir: Vec3,
}

impl Ray {
    /// A ray from `origin` along `dir`.
    #[must_use]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir }
    }

    /// The point at parameter `t`.
    #[must_use]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }

    /// The hit of this ray with one triangle with t in (0, `t_max`), as (t, u, v) where the hit
    /// point is (1 − u − v)·a + u·b + v·c; `None` on a miss or a zero-area triangle.
    ///
    /// This is the same arithmetic, bit for bit, as [`crate::accel::Bvh`] uses, so a brute-force
    /// loop over it is the reference the hierarchy is tested against.
    #[must_use]
    pub fn intersect_triangle(&self, tri: &[Vec3; 3], t_max: f32) -> Option<(f32, f32, f32)> {
        let [a, b, c] = *tri;
        intersect(self.origin, self.dir, a, b - a, c - a, t_max)
    }
}

/// The closest intersection a query found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit point: `origin + t·dir`.
    pub t: f32,
    /// Index of the triangle in the slice the hierarchy was built from.
    pub triangle: u32,
    /// Barycentric weight of the triangle's second vertex.
    pub u: f32,
    /// Barycentric weight of the triangle's third vertex.
    pub v: f32,
}

/// Möller–Trumbore on a triangle given as `v0` and its edges `e1 = v1 − v0`, `e2 = v2 − v0`:
/// (t, u, v) when 0 < t < `t_max`. NaN anywhere makes a comparison fail, so it misses.
#[inline(always)]
pub(crate) fn intersect(
    o: Vec3,
    d: Vec3,
    v0: Vec3,
    e1: Vec3,
    e2: Vec3,
    t_max: f32,
) -> Option<(f32, f32, f32)> {
    // Determinant of the system; zero for a zero-area triangle or a ray in its plane.
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return None;
    }
    let inv_det = 1.0 / det;
    // First barycentric coordinate.
    let s = o - v0;
    let u = s.dot(p) * inv_det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    // Second barycentric coordinate.
    let q = s.cross(e1);
    let v = d.dot(q) * inv_det;
    if !(v >= 0.0 && u + v <= 1.0) {
        return None;
    }
    // Distance along the ray.
    let t = e2.dot(q) * inv_det;
    if t > 0.0 && t < t_max {
        Some((t, u, v))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri() -> [Vec3; 3] {
        [Vec3::ZERO, Vec3::X, Vec3::Y]
    }

    #[test]
    fn hit_point_matches_barycentrics() {
        let ray = Ray::new(Vec3::new(0.25, 0.5, 2.0), Vec3::new(0.0, 0.0, -0.5));
        let (t, u, v) = ray.intersect_triangle(&tri(), f32::INFINITY).unwrap();
        // Exact in binary floating point: every quantity is a small dyadic rational.
        assert_eq!((t, u, v), (4.0, 0.25, 0.5));
        let [a, b, c] = tri();
        let p = (1.0 - u - v) * a + u * b + v * c;
        assert!((ray.at(t) - p).length() < 1e-6);
    }

    #[test]
    fn back_face_hits_and_t_range_is_open() {
        let up = Ray::new(Vec3::new(0.2, 0.2, -1.0), Vec3::Z);
        assert_eq!(up.intersect_triangle(&tri(), 2.0).map(|h| h.0), Some(1.0));
        // t_max is exclusive, and t = 0 (origin on the triangle) is not a hit.
        assert!(up.intersect_triangle(&tri(), 1.0).is_none());
        let on = Ray::new(Vec3::new(0.2, 0.2, 0.0), Vec3::Z);
        assert!(on.intersect_triangle(&tri(), 2.0).is_none());
    }

    #[test]
    fn misses_outside_parallel_and_degenerate() {
        let outside = Ray::new(Vec3::new(0.8, 0.8, 1.0), -Vec3::Z);
        assert!(outside.intersect_triangle(&tri(), 10.0).is_none());
        let parallel = Ray::new(Vec3::new(-1.0, 0.1, 0.0), Vec3::X);
        assert!(parallel.intersect_triangle(&tri(), 10.0).is_none());
        let flat = [Vec3::ZERO, Vec3::X, 2.0 * Vec3::X];
        let down = Ray::new(Vec3::new(0.5, 0.0, 1.0), -Vec3::Z);
        assert!(down.intersect_triangle(&flat, 10.0).is_none());
    }
}
