//! Enclosures: light from everywhere as an inward-facing box around the scene.
//!
//! A radiosity solver exchanges light between surfaces, so light that comes from every
//! direction — the default sky ([`super::sky`]), a distant environment
//! ([`super::environment`]) — enters as one more object: a closed box whose faces point inward
//! (counter-clockwise seen from inside) and reflect nothing. What a point inside receives from
//! a box face of radiance L is L times the solid angle the face covers, so a box of uniform
//! radiance L gives every surface open to it the irradiance πL whatever its size and shape;
//! a direction-dependent radiance needs the box far away and split into tiles
//! ([`super::environment`]).
//!
//! [`bounds`] is what the box must enclose: the polygons and the cameras' eyes (seen from
//! outside, the one-sided faces would be black). [`box_faces_inward`] makes the six faces,
//! [`Scene::add_enclosure`] the object, its materials and polygons.

use glam::Vec3;

use super::{Material, Object, Polygon, Scene};
use crate::Rgb;

/// The box around the scene's polygons and its cameras' eyes (finite points only), or `None`
/// when there is nothing to enclose.
#[must_use]
pub fn bounds(scene: &Scene) -> Option<(Vec3, Vec3)> {
    box_around(
        scene
            .polygons
            .iter()
            .flat_map(|p| p.vertices.iter().copied())
            .chain(scene.cameras.iter().map(|c| c.eye))
            .filter(|v| v.is_finite()),
    )
}

/// The smallest axis-aligned box (lower and upper corner) around `points`, or `None` for no
/// points.
#[must_use]
pub fn box_around(points: impl IntoIterator<Item = Vec3>) -> Option<(Vec3, Vec3)> {
    let (lo, hi) = points.into_iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), v| (lo.min(v), hi.max(v)),
    );
    lo.cmple(hi).all().then_some((lo, hi))
}

/// The bounds grown by `margin` times their diagonal on every side (by a tiny amount when
/// they are a single point, so the box is never flat).
#[must_use]
pub fn grown((lo, hi): (Vec3, Vec3), margin: f32) -> (Vec3, Vec3) {
    let gap = margin * (hi - lo).length().max(f32::MIN_POSITIVE.sqrt());
    (lo - Vec3::splat(gap), hi + Vec3::splat(gap))
}

/// The six faces of the box [lo, hi], each counter-clockwise seen from inside. A face
/// [a, b, c, d] is the parallelogram a + s (b − a) + t (d − a), s, t ∈ [0, 1].
#[must_use]
pub fn box_faces_inward(lo: Vec3, hi: Vec3) -> [[Vec3; 4]; 6] {
    let c = |x: bool, y: bool, z: bool| {
        Vec3::new(
            if x { hi.x } else { lo.x },
            if y { hi.y } else { lo.y },
            if z { hi.z } else { lo.z },
        )
    };
    let (f, t) = (false, true);
    [
        // x = lo (normal +x), x = hi (normal −x)
        [c(f, f, f), c(f, t, f), c(f, t, t), c(f, f, t)],
        [c(t, f, f), c(t, f, t), c(t, t, t), c(t, t, f)],
        // y = lo (normal +y), y = hi (normal −y)
        [c(f, f, f), c(f, f, t), c(t, f, t), c(t, f, f)],
        [c(f, t, f), c(t, t, f), c(t, t, t), c(f, t, t)],
        // z = lo (normal +z), z = hi (normal −z)
        [c(f, f, f), c(t, f, f), c(t, t, f), c(f, t, f)],
        [c(f, f, t), c(f, t, t), c(t, t, t), c(t, f, t)],
    ]
}

impl Scene {
    /// Adds an object named `name` made of `polygons`, each with its own emitted radiance and a
    /// material (also named `name`) that reflects nothing: the faces or tiles of an enclosure.
    /// Polygons of equal radiance share a material. Returns the object's index.
    pub fn add_enclosure(&mut self, name: &str, polygons: Vec<(Vec<Vec3>, Rgb)>) -> usize {
        self.objects.push(Object { name: name.into() });
        let object = self.objects.len() - 1;
        let first = self.materials.len();
        for (vertices, emission) in polygons {
            let material = (first..self.materials.len())
                .find(|&m| self.materials[m].emission == emission)
                .unwrap_or_else(|| {
                    self.materials.push(Material {
                        name: name.into(),
                        reflectance: Rgb::ZERO,
                        emission,
                        ..Material::default()
                    });
                    self.materials.len() - 1
                });
            self.polygons.push(Polygon {
                vertices,
                material,
                object,
                uv: None,
            });
        }
        object
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn newell(v: &[Vec3]) -> Vec3 {
        (0..v.len())
            .map(|i| v[i].cross(v[(i + 1) % v.len()]))
            .sum::<Vec3>()
            * 0.5
    }

    #[test]
    fn the_box_faces_inward_and_is_closed() {
        let (lo, hi) = (Vec3::new(-1.0, 0.0, 2.0), Vec3::new(3.0, 1.0, 5.0));
        let centre = 0.5 * (lo + hi);
        let faces = box_faces_inward(lo, hi);
        let mut total = Vec3::ZERO;
        for f in &faces {
            let n = newell(f);
            total += n;
            // The front faces the centre, and the face is the parallelogram of its docs.
            assert!(n.dot(centre - f[0]) > 0.0, "{f:?}");
            assert!((f[0] + (f[1] - f[0]) + (f[3] - f[0]) - f[2]).length() < 1e-6);
        }
        assert!(total.length() < 1e-5, "closed: {total}");
    }

    #[test]
    fn bounds_take_the_cameras_and_skip_what_is_not_finite() {
        let mut scene = Scene::default();
        assert_eq!(bounds(&scene), None);
        scene.polygons.push(Polygon {
            vertices: vec![Vec3::ZERO, Vec3::X, Vec3::new(f32::NAN, 0.0, 0.0)],
            material: 0,
            object: 0,
            uv: None,
        });
        scene.cameras.push(super::super::Camera {
            name: "c".into(),
            eye: Vec3::new(0.0, 2.0, 0.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y: 40.0,
        });
        assert_eq!(bounds(&scene), Some((Vec3::ZERO, Vec3::new(1.0, 2.0, 0.0))));
    }

    #[test]
    fn equal_radiances_share_a_material() {
        let mut scene = Scene::default();
        let square = vec![Vec3::ZERO, Vec3::X, Vec3::ONE, Vec3::Y];
        let object = scene.add_enclosure(
            "env",
            vec![
                (square.clone(), Rgb::ONE),
                (square.clone(), Rgb::splat(2.0)),
                (square, Rgb::ONE),
            ],
        );
        assert_eq!(object, 0);
        assert_eq!(scene.materials.len(), 2);
        assert_eq!(scene.polygons[2].material, scene.polygons[0].material);
        assert!(scene
            .materials
            .iter()
            .all(|m| m.name == "env" && m.is_emitter()));
        assert!(scene.materials.iter().all(|m| m.reflectance == Rgb::ZERO));
    }
}
