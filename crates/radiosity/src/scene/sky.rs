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
//! units. The box is an [`enclosure`], an object of its own (`default_sky`), so it shows in
//! stats and exports and takes its share of the element budget, like any surface.
//! `--no-default-light` turns it off.

use super::{enclosure, Material, Scene};
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
    /// Whether any polygon's material emits light, or the scene has a luminaire.
    #[must_use]
    pub fn has_emitter(&self) -> bool {
        !self.luminaires.is_empty()
            || self.polygons.iter().any(|p| {
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
        let Some((lo, hi)) = enclosure::bounds(self).map(|b| enclosure::grown(b, MARGIN)) else {
            return false;
        };
        let faces = enclosure::box_faces_inward(lo, hi);
        self.add_enclosure(
            NAME,
            faces
                .iter()
                .map(|f| (f.to_vec(), Rgb::splat(RADIANCE)))
                .collect(),
        );
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Object, Polygon};
    use glam::Vec3;

    #[test]
    fn only_a_scene_without_emitters_gets_a_sky() {
        let square = Polygon {
            vertices: vec![Vec3::ZERO, Vec3::X, Vec3::X + Vec3::Z, Vec3::Z],
            material: 0,
            object: 0,
            uv: None,
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
