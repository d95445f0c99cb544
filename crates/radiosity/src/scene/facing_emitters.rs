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

use std::collections::BTreeMap;

use glam::Vec3;

use super::Scene;
use crate::accel::{Aabb, Bvh, Ray};

/// Distance, relative to the emitter's size (√area), below which a surface counts as "right in
/// front of" it.
pub const NEAR: f32 = 0.02;

/// One warning per object whose emitting polygons face another surface closer than [`NEAR`]
/// of their size, naming the object, how many of its polygons do and the largest such distance.
///
/// The rays are short (a fiftieth of the emitter's size), so the polygons a ray may hit are
/// found through a box hierarchy over the scene's triangles: the work grows with the emitters
/// times the few triangles near each, not with emitters times polygons (a scene whose every
/// polygon emits has as many emitters as polygons).
#[must_use]
pub fn warnings(scene: &Scene, file: &str) -> Vec<String> {
    let emitters: Vec<usize> = (0..scene.polygons.len())
        .filter(|&i| scene.materials[scene.polygons[i].material].is_emitter())
        .collect();
    if emitters.is_empty() {
        return Vec::new();
    }
    // Every polygon as a fan of triangles, each remembering its polygon.
    let (triangles, owners): (Vec<[Vec3; 3]>, Vec<usize>) = scene
        .polygons
        .iter()
        .enumerate()
        .flat_map(|(j, p)| {
            let first = p.vertices[0];
            p.vertices[1..]
                .windows(2)
                .map(move |w| ([first, w[0], w[1]], j))
        })
        .unzip();
    let bvh = Bvh::build(&triangles);
    // Per object: trapped polygons, and the largest gap of one (absolute, relative to size).
    let mut trapped_in: BTreeMap<usize, (usize, f32, f32)> = BTreeMap::new();
    for i in emitters {
        let emitter = &scene.polygons[i];
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
            let mut nearest = f32::INFINITY;
            bvh.overlapping(&Aabb::from_points(&[o, ray.at(reach)]), |t| {
                if owners[t] != i {
                    if let Some((hit, _, _)) = ray.intersect_triangle(&triangles[t], reach) {
                        nearest = nearest.min(hit);
                    }
                }
            });
            farthest = farthest.max(nearest);
            nearest < reach
        });
        if trapped {
            let entry = trapped_in.entry(emitter.object).or_default();
            entry.0 += 1;
            entry.1 = entry.1.max(farthest);
            entry.2 = entry.2.max(farthest / area.sqrt());
        }
    }
    trapped_in
        .into_iter()
        .map(|(object, (count, gap, relative))| {
            let name = &scene.objects[object].name;
            let gap = format!("{gap:.4} units in front of it ({:.2} %", 100.0 * relative);
            let what = if count == 1 {
                format!("emitter `{name}` faces another surface {gap} of its size)")
            } else {
                format!(
                    "emitter `{name}` has {count} polygons facing another surface, at most \
                     {gap} of its size)"
                )
            };
            format!(
                "{file}: {what}: its light is trapped in the gap (check its vertex order: \
                 emission is from the front, counter-clockwise side)"
            )
        })
        .collect()
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
                    uv: None,
                },
                // Facing −z, toward the wall at z = 0.
                Polygon {
                    vertices: square(gap, true),
                    material: 1,
                    object: 1,
                    uv: None,
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

    #[test]
    fn one_line_per_object_however_many_of_its_polygons_are_trapped() {
        let mut s = scene(0.001);
        // Three more window panes of the same object, side by side, each a millimetre from
        // its own patch of wall.
        for k in 1..4 {
            let shift = Vec3::new(2.0 * k as f32, 0.0, 0.0);
            let mut wall = s.polygons[0].clone();
            let mut pane = s.polygons[1].clone();
            for v in wall.vertices.iter_mut().chain(pane.vertices.iter_mut()) {
                *v += shift;
            }
            pane.vertices.iter_mut().for_each(|v| v.z = 0.002);
            s.polygons.extend([wall, pane]);
        }
        let w = warnings(&s, "s.toml");
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains("`window` has 4 polygons") && w[0].contains("at most 0.0020 units"),
            "{}",
            w[0]
        );
    }
}
