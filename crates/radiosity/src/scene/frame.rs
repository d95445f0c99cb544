//! Automatic framing: a camera for a scene that has none (a bare OBJ file, or a TOML scene
//! without `[camera]`).
//!
//! The rule, like the Cornell box camera: look along +z at the centre c of the bounding box,
//! from the −z side, with +y up and a vertical field of view of 40°. The eye stands back far
//! enough that the box's bounding sphere (radius r, half the box diagonal) fits the view:
//! distance r / sin(fov_y / 2) from c, so the sphere touches the edges of the view cone.

use glam::Vec3;

use super::{Camera, Polygon};

/// Vertical field of view of a framed camera, degrees.
pub const FRAME_FOV_Y: f32 = 40.0;

/// A camera named `default` that sees every polygon (see the module doc).
#[must_use]
pub fn frame(polygons: &[Polygon]) -> Camera {
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
    Camera {
        name: "default".into(),
        eye: centre - Vec3::Z * distance,
        target: centre,
        up: Vec3::Y,
        fov_y: FRAME_FOV_Y,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let c = frame(&polygons);
        let axis = (c.target - c.eye).normalize();
        let half = (c.fov_y.to_radians() * 0.5).cos();
        for v in &polygons[0].vertices {
            // The cone of half-angle fov/2 about the axis contains the bounding sphere.
            assert!(axis.dot((*v - c.eye).normalize()) >= half - 1e-6, "{v}");
        }
        assert_eq!(frame(&[]).target, Vec3::ZERO);
    }
}
