//! Automatic framing: a camera for a scene that has none (a bare OBJ file, or a TOML scene
//! without `[camera]`).
//!
//! The rule: look at the centre c of the bounding box, with +y up and a vertical field of view
//! of 40°, from the side that *sees* the most front-facing area. The candidates are the four
//! horizontal sides −z, +z, −x, +x and the same four raised by [`TILT`] (looking down on the
//! scene). Each is scored by sampling [`SAMPLES`] points on the polygons (area-weighted,
//! deterministic) and summing, over the samples the eye can see (a shadow ray to the eye, so a
//! ceiling's back hides the room below it), the area each stands for times how squarely its
//! front faces the eye (both sides for two-sided materials). The best score wins; a raised view
//! must beat the best level one by [`TILT_MARGIN`], and ties go to the −z side, the Cornell box
//! camera's. A model exported from a modelling tool faces its viewers' default camera (glTF
//! viewers look from +z), so it is seen from the front rather than from behind (a glTF rendered
//! from −z came out black: every face turned away); an object on a floor is seen from above
//! rather than edge-on. The eye stands back far enough that the box's bounding sphere (radius
//! r, half the box diagonal) fits the view: distance r / sin(fov_y / 2) from c, so the sphere
//! touches the edges of the view cone.

use glam::Vec3;

use super::{Camera, Material, Polygon};
use crate::accel::{Bvh, Ray};
use crate::hash::mix;

/// Vertical field of view of a framed camera, degrees.
pub const FRAME_FOV_Y: f32 = 40.0;

/// Elevation of the raised candidate views, degrees.
pub const TILT: f32 = 30.0;

/// How much more a raised view must see than the best level one to be chosen.
pub const TILT_MARGIN: f32 = 1.1;

/// Sample points on the polygons per scoring.
pub const SAMPLES: u32 = 512;

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
    let samples = Samples::new(polygons, materials);
    let seen = |view: Vec3| samples.seen_from(centre - view * distance);
    // View directions, the Cornell box's first so that it wins ties.
    let level = [Vec3::Z, -Vec3::Z, Vec3::X, -Vec3::X];
    let (mut view, mut best) = (level[0], seen(level[0]));
    for &d in &level[1..] {
        let s = seen(d);
        if s > best {
            (view, best) = (d, s);
        }
    }
    let (sin, cos) = TILT.to_radians().sin_cos();
    let mut raised = (view, best * TILT_MARGIN);
    for d in level {
        let d = d * cos - Vec3::Y * sin;
        let s = seen(d);
        if s > raised.1 {
            raised = (d, s);
        }
    }
    Camera {
        name: "default".into(),
        eye: centre - raised.0 * distance,
        target: centre,
        up: Vec3::Y,
        fov_y: FRAME_FOV_Y,
    }
}

/// Points spread over the polygons by area, with the area each stands for.
struct Samples {
    /// (point, unit normal, area it stands for, two-sided).
    points: Vec<(Vec3, Vec3, f32, bool)>,
    /// What hides them.
    bvh: Bvh,
}

impl Samples {
    fn new(polygons: &[Polygon], materials: &[Material]) -> Self {
        let mut triangles = Vec::new();
        let mut two_sided = Vec::new();
        for p in polygons {
            let both = materials.get(p.material).is_some_and(|m| m.two_sided);
            for w in p.vertices[1..].windows(2) {
                triangles.push([p.vertices[0], w[0], w[1]]);
                two_sided.push(both);
            }
        }
        let areas: Vec<f32> = triangles
            .iter()
            .map(|t| 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length())
            .map(|a| if a.is_finite() { a } else { 0.0 })
            .collect();
        let total: f32 = areas.iter().sum();
        let mut points = Vec::new();
        if total > 0.0 {
            // Systematic sampling along the cumulative area: deterministic, and every
            // triangle larger than total / SAMPLES gets a point.
            let step = total / SAMPLES as f32;
            let mut next = step * 0.5;
            let mut below = 0.0;
            for (k, (t, &a)) in triangles.iter().zip(&areas).enumerate() {
                let normal = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
                while next < below + a {
                    let bits = mix(u64::from(k as u32) << 32 | points.len() as u64);
                    let (u, v) = (unit(bits), unit(bits >> 32));
                    let (u, v) = if u + v > 1.0 {
                        (1.0 - u, 1.0 - v)
                    } else {
                        (u, v)
                    };
                    let p = t[0] + u * (t[1] - t[0]) + v * (t[2] - t[0]);
                    points.push((p, normal, step, two_sided[k]));
                    next += step;
                }
                below += a;
            }
        }
        Self {
            points,
            bvh: Bvh::build(&triangles),
        }
    }

    /// Σ area · cos over the sample points whose front (either side when two-sided) faces
    /// `eye` and that `eye` sees.
    fn seen_from(&self, eye: Vec3) -> f32 {
        let lift = self.bvh.lift();
        self.points
            .iter()
            .map(|&(p, n, area, two_sided)| {
                let to_eye = eye - p;
                let cos = n.dot(to_eye.normalize_or_zero());
                let cos = if two_sided { cos.abs() } else { cos };
                if cos <= 0.0 {
                    return 0.0;
                }
                let side = if n.dot(to_eye) >= 0.0 { n } else { -n };
                let origin = p + side * lift;
                let hidden = self.bvh.occluded(&Ray::new(origin, eye - origin), 1.0);
                if hidden {
                    0.0
                } else {
                    area * cos
                }
            })
            .sum()
    }
}

/// The low 24 bits of `bits` as a number in [0, 1).
fn unit(bits: u64) -> f32 {
    ((bits & 0xFF_FFFF) as f32) / (1u32 << 24) as f32
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
                uv: None,
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

    fn quad(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Polygon {
        Polygon {
            vertices: vec![a, b, c, d],
            material: 0,
            object: 0,
            uv: None,
        }
    }

    #[test]
    fn an_object_on_a_floor_is_seen_from_above() {
        // A 4 × 4 floor facing up and a small seat over it: edge-on from the side, so the
        // raised view wins.
        let v = Vec3::new;
        let polygons = vec![
            quad(
                v(-2., 0., -2.),
                v(-2., 0., 2.),
                v(2., 0., 2.),
                v(2., 0., -2.),
            ),
            quad(
                v(-0.5, 0.5, -0.5),
                v(-0.5, 0.5, 0.5),
                v(0.5, 0.5, 0.5),
                v(0.5, 0.5, -0.5),
            ),
        ];
        let c = frame(&polygons, &[Material::default()]);
        assert!(c.eye.y > c.target.y + 1.0, "{c:?}");
    }

    #[test]
    fn an_open_box_is_seen_level_through_its_open_side() {
        // Floor, ceiling, back and side walls facing inward, open toward −z: from above, the
        // ceiling's back hides the inside, so the level view through the opening wins.
        let v = Vec3::new;
        let (o, x, y, z) = (v(0., 0., 0.), v(1., 0., 0.), v(0., 1., 0.), v(0., 0., 1.));
        let polygons = vec![
            quad(o, z, x + z, x),             // floor, facing +y
            quad(y, y + x, y + x + z, y + z), // ceiling, facing −y
            quad(z, z + y, z + y + x, z + x), // back wall at z = 1, facing −z
            quad(o, y, y + z, z),             // left wall at x = 0, facing +x
            quad(x, x + z, x + y + z, x + y), // right wall at x = 1, facing −x
        ];
        for p in &polygons {
            let n = model::polymesh::vector_area(&p.vertices);
            let inward = v(0.5, 0.5, 0.5) - p.vertices[0];
            assert!(n.dot(inward) > 0.0, "faces inward: {p:?}");
        }
        let c = frame(&polygons, &[Material::default()]);
        assert!((c.eye.y - c.target.y).abs() < 1e-4, "level: {c:?}");
        assert!(c.eye.z < 0.0, "through the open side: {c:?}");
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
            uv: None,
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
