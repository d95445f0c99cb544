//! Mitsuba's built-in shapes as planar polygons, in their object space (before `to_world`).
//!
//! | shape | object space | fronts |
//! |---|---|---|
//! | `rectangle` | the square [−1, 1]² in the plane z = 0 | +z |
//! | `cube` | the cube [−1, 1]³ | outward |
//! | `disk` | the unit disc in the plane z = 0 | +z |
//! | `cylinder` | radius `radius` about the segment `p0` → `p1` (default (0,0,0) → (0,0,1)), no caps | outward |
//! | `sphere` | `center`, `radius` (default 0, 1) | outward |
//!
//! Curved shapes become polygons whose area equals the curved surface's, so that an emitting
//! disc or sphere sends out the same power as Mitsuba's: a regular n-gon inscribed in a circle
//! of radius r has area (n/2)·r²·sin(2π/n), short of πr² by 0.6 % at n = 32, so its radius is
//! scaled up by √(π / ((n/2)·sin(2π/n))). The sphere is an icosphere
//! ([`model::primitives::icosphere`]) scaled the same way by its area.

use std::f32::consts::TAU;

use glam::Vec3;

/// Sides of the polygon standing for a disc, and of the cylinder's prism.
pub const CIRCLE_SIDES: usize = 32;

/// Subdivisions of the icosphere standing for a sphere (1 280 triangles).
pub const SPHERE_SUBDIVISIONS: u32 = 3;

/// The square [−1, 1]² at z = 0, front +z.
#[must_use]
pub fn rectangle() -> Vec<Vec<Vec3>> {
    vec![vec![
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.0),
    ]]
}

/// The cube [−1, 1]³, fronts outward.
#[must_use]
pub fn cube() -> Vec<Vec<Vec3>> {
    let m = model::primitives::cuboid(Vec3::splat(-1.0), Vec3::ONE);
    (0..m.faces.len()).map(|f| m.face_positions(f)).collect()
}

/// The radius of a regular `n`-gon with the area of the unit circle.
#[must_use]
pub fn equal_area_radius(n: usize) -> f32 {
    let n = n as f32;
    (std::f32::consts::PI / (0.5 * n * (TAU / n).sin())).sqrt()
}

/// The unit disc at z = 0 as one polygon of [`CIRCLE_SIDES`] sides and the disc's area, front
/// +z.
#[must_use]
pub fn disk() -> Vec<Vec<Vec3>> {
    let r = equal_area_radius(CIRCLE_SIDES);
    vec![(0..CIRCLE_SIDES)
        .map(|i| {
            let a = TAU * i as f32 / CIRCLE_SIDES as f32;
            Vec3::new(r * a.cos(), r * a.sin(), 0.0)
        })
        .collect()]
}

/// An open cylinder of `radius` about `p0` → `p1`: [`CIRCLE_SIDES`] quads with the curved
/// surface's area, fronts outward. `None` when the axis or radius is degenerate.
#[must_use]
pub fn cylinder(p0: Vec3, p1: Vec3, radius: f32) -> Option<Vec<Vec<Vec3>>> {
    let axis = (p1 - p0).try_normalize()?;
    if radius.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    // A prism's lateral area is n·2r·sin(π/n)·h against 2πr·h: scale the radius to match.
    let n = CIRCLE_SIDES as f32;
    let r = radius * std::f32::consts::PI / (n * (std::f32::consts::PI / n).sin());
    let (u, v) = axis.any_orthonormal_pair();
    let ring = |i: usize| {
        let a = TAU * i as f32 / n;
        r * (a.cos() * u + a.sin() * v)
    };
    Some(
        (0..CIRCLE_SIDES)
            .map(|i| {
                let (a, b) = (ring(i), ring((i + 1) % CIRCLE_SIDES));
                // Counter-clockwise seen from outside: around +axis, a → b is counter-clockwise
                // seen from +axis, so the outward face runs p0+a, p0+b, p1+b, p1+a.
                vec![p0 + a, p0 + b, p1 + b, p1 + a]
            })
            .collect(),
    )
}

/// A sphere as an icosphere with the sphere's area, fronts outward.
#[must_use]
pub fn sphere(center: Vec3, radius: f32) -> Vec<Vec<Vec3>> {
    let unit = model::primitives::icosphere(Vec3::ZERO, 1.0, SPHERE_SUBDIVISIONS);
    let scale = (4.0 * std::f64::consts::PI / unit.area()).sqrt() as f32 * radius;
    (0..unit.faces.len())
        .map(|f| {
            unit.face_positions(f)
                .into_iter()
                .map(|p| center + scale * p)
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(faces: &[Vec<Vec3>]) -> f64 {
        faces
            .iter()
            .map(|f| f64::from(model::polymesh::vector_area(f).length()))
            .sum()
    }

    fn outward(faces: &[Vec<Vec3>], centre: Vec3) -> bool {
        faces.iter().all(|f| {
            let c = f.iter().copied().sum::<Vec3>() / f.len() as f32;
            model::polymesh::vector_area(f).dot(c - centre) > 0.0
        })
    }

    #[test]
    fn curved_shapes_keep_their_area_and_face_outward() {
        let pi = std::f64::consts::PI;
        assert!((area(&disk()) - pi).abs() < 1e-5);
        assert!(model::polymesh::vector_area(&disk()[0]).z > 0.0);
        let c = cylinder(Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0), 0.5).unwrap();
        assert!(
            (area(&c) - 2.0 * pi * 0.5 * 2.0).abs() < 1e-4,
            "{}",
            area(&c)
        );
        assert!(c.iter().all(|f| {
            let mid = f.iter().copied().sum::<Vec3>() / 4.0;
            model::polymesh::vector_area(f).dot(Vec3::new(mid.x, mid.y, 0.0)) > 0.0
        }));
        let s = sphere(Vec3::ONE, 2.0);
        assert!((area(&s) - 4.0 * pi * 4.0).abs() < 1e-3, "{}", area(&s));
        assert!(outward(&s, Vec3::ONE));
        assert!(outward(&cube(), Vec3::ZERO));
        assert!((area(&cube()) - 24.0).abs() < 1e-6);
        assert!((area(&rectangle()) - 4.0).abs() < 1e-6);
        assert!(cylinder(Vec3::ZERO, Vec3::ZERO, 1.0).is_none());
    }
}
