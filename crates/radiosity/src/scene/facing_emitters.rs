//! A warning for emitters that face another surface right in front of them.
//!
//! An emitter whose vertex order turns it toward the wall it was meant to hang on (a window
//! drawn a millimetre in front of its wall, facing the wall) pours its light into the gap. The
//! physics is then what it is — the light is trapped and absorbed there — but a mesh of elements
//! cannot represent it: the wall's elements that straddle the emitter's outline average the
//! brightly lit gap with the room side and shine that into the room (measured on
//! `scenes/suite/emitter-near-wall-facing`: the ceiling 120 % too bright against a path tracer).
//! Either way it is almost certainly not what the user meant, so loading says so.
//!
//! The test: rays along the emitter's normal from its centroid and from points halfway to each
//! corner; if every one hits another polygon closer than [`NEAR`] times the emitter's size
//! (√area), the emitter faces a surface.

use glam::Vec3;

use super::Scene;
use crate::accel::Ray;

/// Distance, relative to the emitter's size (√area), below which a surface counts as "right in
/// front of" it.
pub const NEAR: f32 = 0.02;

/// One warning per emitting polygon that faces another surface closer than [`NEAR`] of its
/// size, naming its object and the distance.
#[must_use]
pub fn warnings(scene: &Scene, file: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (i, emitter) in scene.polygons.iter().enumerate() {
        if !scene.materials[emitter.material].is_emitter() {
            continue;
        }
        let vector_area = model::polymesh::vector_area(&emitter.vertices);
        let (area, normal) = (vector_area.length(), vector_area.normalize_or_zero());
        if area <= 0.0 || !area.is_finite() {
            continue;
        }
        let reach = NEAR * area.sqrt();
        let centroid = emitter.vertices.iter().sum::<Vec3>() / emitter.vertices.len() as f32;
        let origins = std::iter::once(centroid)
            .chain(emitter.vertices.iter().map(|&v| centroid.lerp(v, 0.5)));
        // The nearest hit of each ray, if any; the emitter is trapped when every ray hits.
        let mut farthest = 0.0f32;
        let trapped = origins.into_iter().all(|o| {
            let ray = Ray::new(o, normal);
            let nearest = scene
                .polygons
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .flat_map(|(_, p)| {
                    let first = p.vertices[0];
                    p.vertices[1..]
                        .windows(2)
                        .filter_map(move |w| ray.intersect_triangle(&[first, w[0], w[1]], reach))
                })
                .map(|(t, _, _)| t)
                .fold(f32::INFINITY, f32::min);
            farthest = farthest.max(nearest);
            nearest < reach
        });
        if trapped {
            out.push(format!(
                "{file}: emitter `{}` faces another surface {farthest:.4} units in front of it \
                 ({:.2} % of its size): \
                 its light is trapped in the gap (check its vertex order: emission is from the \
                 front, counter-clockwise side)",
                scene.objects[emitter.object].name,
                100.0 * farthest / area.sqrt()
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Material, Object, Polygon};
    use crate::Rgb;

    fn scene(gap: f32) -> Scene {
        let square = |z: f32, flip: bool| {
            let mut v = vec![
                Vec3::new(0.0, 0.0, z),
                Vec3::new(1.0, 0.0, z),
                Vec3::new(1.0, 1.0, z),
                Vec3::new(0.0, 1.0, z),
            ];
            if flip {
                v.reverse();
            }
            v
        };
        Scene {
            materials: vec![
                Material::default(),
                Material {
                    emission: Rgb::ONE,
                    ..Material::default()
                },
            ],
            objects: vec![
                Object {
                    name: "wall".into(),
                },
                Object {
                    name: "window".into(),
                },
            ],
            polygons: vec![
                Polygon {
                    vertices: square(0.0, false),
                    material: 0,
                    object: 0,
                },
                // Facing −z, toward the wall at z = 0.
                Polygon {
                    vertices: square(gap, true),
                    material: 1,
                    object: 1,
                },
            ],
            ..Scene::default()
        }
    }

    #[test]
    fn an_emitter_facing_a_wall_a_millimetre_away_is_named() {
        let w = warnings(&scene(0.001), "s.toml");
        assert_eq!(w.len(), 1);
        assert!(
            w[0].contains("`window`") && w[0].contains("0.0010 units"),
            "{}",
            w[0]
        );
        assert!(
            warnings(&scene(0.1), "s.toml").is_empty(),
            "10 % of its size is a room"
        );
        // Facing away from the wall: nothing in front.
        let mut away = scene(0.001);
        away.polygons[1].vertices.reverse();
        assert!(warnings(&away, "s.toml").is_empty());
    }
}
