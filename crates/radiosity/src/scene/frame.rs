//! Automatic framing: a camera for a scene that has none (a bare OBJ file, or a TOML scene
//! without `[camera]`).
//!
//! The rule: look at the centre c of the bounding box, with +y up and a vertical field of view
//! of 40°, horizontally from the side that sees the most front-facing area. Of the four sides
//! −z, +z, −x, +x, the one whose view direction d maximises Σ A_p max(0, −n_p · d) over the
//! polygons p (both ways for two-sided ones) wins; ties go to the −z side, the Cornell box camera's. A model exported from a
//! modelling tool faces its viewers' default camera (glTF viewers look from +z), so it is seen
//! from the front rather than from behind (a glTF rendered from −z came out black: every face
//! turned away). The eye stands back far enough that the box's bounding sphere (radius r, half
//! the box diagonal) fits the view: distance r / sin(fov_y / 2) from c, so the sphere touches
//! the edges of the view cone.

use glam::Vec3;

use super::{Camera, Material, Polygon};

/// Vertical field of view of a framed camera, degrees.
pub const FRAME_FOV_Y: f32 = 40.0;

/// A camera named `default` that sees every polygon (see the module doc); a polygon whose
/// material is two-sided faces both ways.
#[must_use]
pub fn frame(polygons: &[Polygon], materials: &[Material]) -> Camera {
    let (lo, hi) = polygons
        .iter()
        .flat_map(|p| p.vertices.iter())
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    let (centre, radius) = if lo.cmple(hi).all() {
        ((lo + hi) * 0.5, ((hi - lo).length() * 0.5).max(1e-3))
    } else {
        (Vec3::ZERO, 1.0)
    };
    let distance = radius / (FRAME_FOV_Y.to_radians() * 0.5).sin();
    // View directions, the Cornell box's first so that it wins ties.
    let facing = |d: Vec3| -> f32 {
        polygons
            .iter()
            .map(|p| {
                let area = model::polymesh::vector_area(&p.vertices);
                let two_sided = materials.get(p.material).is_some_and(|m| m.two_sided);
                if two_sided {
                    area.dot(d).abs()
                } else {
                    (-area.dot(d)).max(0.0)
                }
            })
            .sum()
    };
    let mut view = Vec3::Z;
    let mut best = facing(view);
    for d in [-Vec3::Z, Vec3::X, -Vec3::X] {
        let seen = facing(d);
        if seen > best {
            (view, best) = (d, seen);
        }
    }
    Camera {
        name: "default".into(),
        eye: centre - view * distance,
        target: centre,
        up: Vec3::Y,
        fov_y: FRAME_FOV_Y,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_camera_faces_the_front_faces() {
        // A unit square facing +z (counter-clockwise seen from +z): seen from +z. Reversed, it
        // faces −z and is seen from −z; turned to face +x, from +x.
        let square = |vertices: Vec<Vec3>| {
            let polygons = vec![Polygon {
                vertices,
                material: 0,
                object: 0,
            }];
            let c = frame(&polygons, &[Material::default()]);
            (c.eye - c.target).normalize()
        };
        let plus_z = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        assert!(square(plus_z.clone()).abs_diff_eq(Vec3::Z, 1e-6));
        let minus_z: Vec<Vec3> = plus_z.iter().rev().copied().collect();
        assert!(square(minus_z).abs_diff_eq(-Vec3::Z, 1e-6));
        let plus_x = vec![Vec3::ZERO, Vec3::Z, Vec3::new(0.0, 1.0, 1.0), Vec3::Y]
            .into_iter()
            .rev()
            .collect();
        assert!(square(plus_x).abs_diff_eq(Vec3::X, 1e-6));
    }

    #[test]
    fn every_vertex_is_inside_the_view_cone() {
        let polygons = vec![Polygon {
            vertices: vec![
                Vec3::new(-3.0, 1.0, 2.0),
                Vec3::new(5.0, 1.0, 2.0),
                Vec3::new(5.0, 4.0, 9.0),
            ],
            material: 0,
            object: 0,
        }];
        let c = frame(&polygons, &[]);
        let axis = (c.target - c.eye).normalize();
        let half = (c.fov_y.to_radians() * 0.5).cos();
        for v in &polygons[0].vertices {
            // The cone of half-angle fov/2 about the axis contains the bounding sphere.
            assert!(axis.dot((*v - c.eye).normalize()) >= half - 1e-6, "{v}");
        }
        assert_eq!(frame(&[], &[]).target, Vec3::ZERO);
    }
}
