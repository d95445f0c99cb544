//! The default sky: what lights a scene that has no light of its own.
//!
//! A model downloaded without emissive materials (an OBJ without `Ke`, a glTF without
//! `emissiveFactor`) would solve to black. Instead the command line encloses it in a uniform
//! sky — the "white furnace" of rendering tests: an axis-aligned box around the scene's bounds
//! and its cameras' eyes (seen from outside, its one-sided faces would be black), [`MARGIN`] of
//! the bounds' diagonal away on every side, whose six inward-facing faces emit
//! radiance [`RADIANCE`] and reflect nothing. Every surface open to the sky then receives
//! irradiance π·[`RADIANCE`]·(the fraction of its hemisphere that sees the sky, counting
//! interreflections): an ambient-occlusion look that shows the model's shape, in physical
//! units. The sky is an object of its own (`default_sky`), so it shows in stats and exports and
//! takes its share of the element budget, like any surface. `--no-default-light` turns it off.

use glam::Vec3;

use super::{Material, Object, Polygon, Scene};
use crate::Rgb;

/// Emitted radiance of the sky, W·m⁻²·sr⁻¹ per channel (so its exitance is π).
pub const RADIANCE: f64 = 1.0;

/// Gap between the scene's bounds and the sky, as a fraction of the bounds' diagonal.
pub const MARGIN: f32 = 0.1;

/// The loading warning of a scene without light (it follows the file's name).
pub const NO_LIGHT: &str = "no material emits light; the scene will be black";

/// The name of the sky's object and material.
pub const NAME: &str = "default_sky";

impl Scene {
    /// Whether any polygon's material emits light.
    #[must_use]
    pub fn has_emitter(&self) -> bool {
        self.polygons.iter().any(|p| {
            self.materials
                .get(p.material)
                .is_some_and(Material::is_emitter)
        })
    }

    /// Encloses the scene in the default sky (module docs) if nothing in it emits light.
    /// Returns whether it did.
    pub fn add_default_sky(&mut self) -> bool {
        if self.has_emitter() {
            return false;
        }
        let (lo, hi) = self
            .polygons
            .iter()
            .flat_map(|p| p.vertices.iter().copied())
            .chain(self.cameras.iter().map(|c| c.eye))
            .filter(|v| v.is_finite())
            .fold(
                (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
                |(lo, hi), v| (lo.min(v), hi.max(v)),
            );
        if !(lo.cmple(hi).all()) {
            return false;
        }
        let gap = MARGIN * (hi - lo).length().max(f32::MIN_POSITIVE.sqrt());
        let (lo, hi) = (lo - Vec3::splat(gap), hi + Vec3::splat(gap));
        self.materials.push(Material {
            name: NAME.into(),
            reflectance: Rgb::ZERO,
            emission: Rgb::splat(RADIANCE),
            ..Material::default()
        });
        self.objects.push(Object { name: NAME.into() });
        let (material, object) = (self.materials.len() - 1, self.objects.len() - 1);
        for vertices in box_faces_inward(lo, hi) {
            self.polygons.push(Polygon {
                vertices: vertices.to_vec(),
                material,
                object,
            });
        }
        true
    }
}

/// The six faces of the box [lo, hi], each counter-clockwise seen from inside.
fn box_faces_inward(lo: Vec3, hi: Vec3) -> [[Vec3; 4]; 6] {
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
    fn the_sky_faces_inward_and_encloses_the_bounds() {
        let (lo, hi) = (Vec3::new(-1.0, 0.0, 2.0), Vec3::new(3.0, 1.0, 5.0));
        let centre = 0.5 * (lo + hi);
        let faces = box_faces_inward(lo, hi);
        let mut total = Vec3::ZERO;
        for f in &faces {
            let n = newell(f);
            total += n;
            // The front faces the centre.
            assert!(n.dot(centre - f[0]) > 0.0, "{f:?}");
        }
        assert!(total.length() < 1e-5, "closed: {total}");
    }

    #[test]
    fn only_a_scene_without_emitters_gets_a_sky() {
        let square = Polygon {
            vertices: vec![Vec3::ZERO, Vec3::X, Vec3::X + Vec3::Z, Vec3::Z],
            material: 0,
            object: 0,
        };
        let mut dark = Scene {
            materials: vec![Material::default()],
            objects: vec![Object {
                name: "floor".into(),
            }],
            polygons: vec![square.clone()],
            ..Scene::default()
        };
        assert!(dark.add_default_sky());
        assert!(dark.has_emitter());
        assert_eq!(dark.polygons.len(), 7);
        assert_eq!(dark.objects.last().map(|o| o.name.as_str()), Some(NAME));
        let mut lit = Scene {
            materials: vec![Material {
                emission: Rgb::ONE,
                ..Material::default()
            }],
            objects: vec![Object {
                name: "lamp".into(),
            }],
            polygons: vec![square],
            ..Scene::default()
        };
        assert!(!lit.add_default_sky());
        assert_eq!(lit.polygons.len(), 1);
    }
}
