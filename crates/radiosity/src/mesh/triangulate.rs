//! Triangulation of simple planar polygons by ear clipping (Meisters 1975).
//!
//! A polygon with n corners has n − 2 triangles. An *ear* is a corner whose triangle with its two
//! neighbours is convex and contains no other corner; every simple polygon with more than three
//! corners has at least two (Meisters' two-ears theorem), so cutting ears one at a time always
//! finishes. O(n²) per polygon, which is fine for the hand-written polygons of scenes.

use glam::{Vec2, Vec3};

/// Triangles (as corner indices, same orientation as the polygon) of a simple planar polygon
/// with unit normal `normal`. Returns fewer than n − 2 triangles only for degenerate input
/// (collinear runs are cut as zero-area ears, so the result still covers the polygon).
#[must_use]
pub fn triangulate(vertices: &[Vec3], normal: Vec3) -> Vec<[u32; 3]> {
    let n = vertices.len();
    if n < 3 {
        return Vec::new();
    }
    // Project onto the plane, in a right-handed 2D frame so that the polygon is counter-clockwise.
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let p: Vec<Vec2> = vertices
        .iter()
        .map(|&x| Vec2::new(x.dot(u), x.dot(v)))
        .collect();
    let mut ring: Vec<u32> = (0..n as u32).collect();
    let mut triangles = Vec::with_capacity(n - 2);
    let cross = |a: Vec2, b: Vec2, c: Vec2| (b - a).perp_dot(c - a);
    while ring.len() > 3 {
        let m = ring.len();
        let ear = (0..m).find(|&i| {
            let (a, b, c) = (ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]);
            let (pa, pb, pc) = (p[a as usize], p[b as usize], p[c as usize]);
            if cross(pa, pb, pc) <= 0.0 {
                return false;
            }
            // No other corner inside (or on) the candidate triangle.
            ring.iter().all(|&o| {
                if o == a || o == b || o == c {
                    return true;
                }
                let q = p[o as usize];
                !(cross(pa, pb, q) >= 0.0 && cross(pb, pc, q) >= 0.0 && cross(pc, pa, q) >= 0.0)
            })
        });
        // Degenerate input (collinear or self-touching): cut the first corner and go on.
        let i = ear.unwrap_or(0);
        triangles.push([ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]]);
        ring.remove(i);
    }
    triangles.push([ring[0], ring[1], ring[2]]);
    triangles
}

/// Whether a planar polygon is convex (all turns the same way as `normal`).
#[must_use]
pub fn is_convex(vertices: &[Vec3], normal: Vec3) -> bool {
    let n = vertices.len();
    (0..n).all(|i| {
        let (a, b, c) = (vertices[i], vertices[(i + 1) % n], vertices[(i + 2) % n]);
        (b - a).cross(c - b).dot(normal) >= 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn l_shape_gives_four_triangles_of_total_area_three() {
        let l = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ];
        let tris = triangulate(&l, Vec3::Z);
        assert_eq!(tris.len(), 4);
        let mut area = 0.0;
        for [a, b, c] in tris {
            let (a, b, c) = (l[a as usize], l[b as usize], l[c as usize]);
            let signed = (b - a).cross(c - a).z * 0.5;
            assert!(signed > 0.0, "triangle flipped");
            area += signed;
        }
        assert!((area - 3.0).abs() < 1e-6);
        assert!(!is_convex(&l, Vec3::Z));
    }
}
