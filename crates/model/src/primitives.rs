//! Primitive instancing's building blocks: boxes and spheres as polygon meshes.

use glam::Vec3;

use crate::PolyMesh;

/// An axis-aligned box from `min` to `max` as six outward-facing quads.
#[must_use]
pub fn cuboid(min: Vec3, max: Vec3) -> PolyMesh {
    let corner = |i: u32| {
        Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    };
    let positions = (0..8).map(corner).collect();
    // Corner index bits: x = 1, y = 2, z = 4. Each face counter-clockwise seen from outside.
    let faces = vec![
        vec![0, 4, 6, 2], // -x
        vec![1, 3, 7, 5], // +x
        vec![0, 1, 5, 4], // -y
        vec![2, 6, 7, 3], // +y
        vec![0, 2, 3, 1], // -z
        vec![4, 5, 7, 6], // +z
    ];
    PolyMesh { positions, faces }
}

/// A sphere as a subdivided icosahedron: 20·4^`subdivisions` outward-facing triangles whose
/// vertices lie on the sphere.
#[must_use]
pub fn icosphere(center: Vec3, radius: f32, subdivisions: u32) -> PolyMesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut unit: Vec<Vec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|p| Vec3::from_array(*p).normalize())
    .collect();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        // Split every triangle in four at its edge midpoints, shared between neighbours.
        let mut midpoints = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, unit: &mut Vec<Vec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                unit.push(((unit[a as usize] + unit[b as usize]) * 0.5).normalize());
                unit.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(tris.len() * 4);
        for [a, b, c] in tris {
            let ab = midpoint(a, b, &mut unit);
            let bc = midpoint(b, c, &mut unit);
            let ca = midpoint(c, a, &mut unit);
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        tris = next;
    }
    PolyMesh {
        positions: unit.iter().map(|&u| center + u * radius).collect(),
        faces: tris.iter().map(|t| t.to_vec()).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polymesh::vector_area;

    /// Sum of a closed mesh's vector areas is zero and every face points away from the centre.
    fn assert_closed_outward(mesh: &PolyMesh, centre: Vec3) {
        let mut total = Vec3::ZERO;
        for f in 0..mesh.faces.len() {
            let vs = mesh.face_positions(f);
            let va = vector_area(&vs);
            let c = vs.iter().copied().sum::<Vec3>() / vs.len() as f32;
            assert!(va.dot(c - centre) > 0.0, "face {f} points inward");
            total += va;
        }
        assert!(total.length() < 1e-4, "not closed: {total}");
    }

    #[test]
    fn box_is_closed_outward_with_right_area() {
        let b = cuboid(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
        assert_closed_outward(&b, Vec3::new(0.5, 1.0, 1.5));
        assert!((b.area() - 22.0).abs() < 1e-5);
    }

    #[test]
    fn icosphere_converges_to_sphere_area() {
        let c = Vec3::new(1.0, 2.0, 3.0);
        let s = icosphere(c, 2.0, 4);
        assert_eq!(s.faces.len(), 20 * 256);
        assert_closed_outward(&s, c);
        for p in &s.positions {
            assert!(((*p - c).length() - 2.0).abs() < 1e-5);
        }
        // Inscribed polyhedron: area slightly below 4πr², within 0.5 % at this level.
        let exact = 4.0 * std::f64::consts::PI * 4.0;
        assert!((s.area() - exact).abs() / exact < 5e-3, "{}", s.area());
    }
}
