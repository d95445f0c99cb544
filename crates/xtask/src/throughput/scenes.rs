//! The generated benchmark scenes, each with the camera of its primary rays and the light of
//! its shadow rays.
//!
//! - `spheres`: a closed 20 × 10 × 20 room (walls facing in) filled with overlapping
//!   icospheres of radius 0.15–1.2 and 320–5120 triangles each. Depth complexity is high: most
//!   rays cross several spheres' boxes before they hit, and every ray hits (the room is
//!   closed), so an occlusion query ends at the first blocker found — often a wall. The
//!   twelve wall triangles span the scene: their boxes overlap everything.
//! - `spheres-open`: the same spheres without the room. Rays escape between the spheres, and
//!   a ray that escapes must have every box on its way ruled out: the worst case of an
//!   occlusion query.
//! - `teapot`: the Utah teapot's 32 Bézier patches tessellated on a uniform grid of the
//!   patches' parameters (a real smooth surface with long thin triangles near the lid's knob
//!   and the spout's tip, and degenerate ones at the patches' poles), seen from above and in
//!   front, lit from above.
//!
//! The Cornell box (the built-in scene's polygons) is added by the command line, which owns
//! scene loading.

use glam::Vec3;

use super::rays::{AreaLight, Camera};

/// A scene of the benchmark: its triangles and what its coherent rays need.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchScene {
    /// Short name (the workload file is `<name>.bin`).
    pub name: &'static str,
    /// The triangle soup.
    pub triangles: Vec<[Vec3; 3]>,
    /// Camera of the primary rays.
    pub camera: Camera,
    /// Target of the shadow rays.
    pub light: AreaLight,
}

/// Triangles of a polygon mesh, fanned from each face's first vertex; `flip` reverses them.
fn fan(mesh: &model::PolyMesh, flip: bool, out: &mut Vec<[Vec3; 3]>) {
    for f in 0..mesh.faces.len() {
        let p = mesh.face_positions(f);
        for k in 1..p.len().saturating_sub(1) {
            out.push(if flip {
                [p[0], p[k + 1], p[k]]
            } else {
                [p[0], p[k], p[k + 1]]
            });
        }
    }
}

/// The sphere field of about `target` triangles (within one sphere's worth), with its room
/// (first, twelve triangles) if `closed`. The spheres do not depend on `closed`.
#[must_use]
pub fn sphere_field_triangles(target: usize, closed: bool) -> Vec<[Vec3; 3]> {
    let lo = Vec3::new(-10.0, 0.0, -10.0);
    let hi = Vec3::new(10.0, 10.0, 10.0);
    let mut tris = Vec::with_capacity(target + 5120);
    fan(&model::primitives::cuboid(lo, hi), true, &mut tris);
    let room = tris.len();
    let mut rng = radiosity::hash::SplitMix(0x5EED);
    while tris.len() + 160 < target {
        let s = rng.next_f32();
        let radius = 0.15 + 1.05 * s * s;
        // Finer spheres where they are larger, and never much past the target.
        let mut subdivisions = 2 + (radius > 0.4) as u32 + (radius > 0.8) as u32;
        while subdivisions > 1 && tris.len() + (20 << (2 * subdivisions)) / 2 > target {
            subdivisions -= 1;
        }
        let span = hi - lo - Vec3::splat(2.0 * radius);
        let centre = lo
            + Vec3::splat(radius)
            + span * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        fan(
            &model::primitives::icosphere(centre, radius, subdivisions),
            false,
            &mut tris,
        );
    }
    if !closed {
        tris.drain(..room);
    }
    tris
}

/// The sphere field, closed or open (see the module docs). The camera stands inside the room
/// half a unit from its −z wall, looking along +z with a 60° view; the light is a 4 × 4
/// square centred over the field, just under the ceiling when closed and a unit above the
/// room's top when open (so that the shadow rays of the open field cross all of it).
#[must_use]
pub fn sphere_field(target: usize, closed: bool) -> BenchScene {
    let light_y = if closed { 9.9 } else { 11.0 };
    BenchScene {
        name: if closed { "spheres" } else { "spheres-open" },
        triangles: sphere_field_triangles(target, closed),
        camera: Camera {
            eye: Vec3::new(0.0, 5.0, -9.5),
            target: Vec3::new(0.0, 5.0, 0.0),
            fov_y_degrees: 60.0,
        },
        light: AreaLight {
            corner: Vec3::new(-2.0, light_y, -2.0),
            edge_a: Vec3::new(4.0, 0.0, 0.0),
            edge_b: Vec3::new(0.0, 0.0, 4.0),
        },
    }
}

/// The teapot on an n × n grid per patch with n = ⌊√(target / 64)⌋ (two triangles per grid
/// cell, one at a pole, 32 patches: about `target` triangles). It stands on y = 0, 3.15 units tall; the
/// camera looks at its middle from 11 units away, above and in front, with a 40° view; the
/// light is a 2 × 2 square two units over its top.
#[must_use]
pub fn teapot(target: usize) -> BenchScene {
    let n = ((target as f64 / 64.0).sqrt() as usize).max(1);
    let settings = model::surface::tessellate::TessellationSettings {
        // Finer than any grid can reach, so every patch gets the most segments.
        tolerance: 1e-9,
        max_segments: n,
    };
    let mesh = model::surface::tessellate(&model::teapot::teapot_patches(), &settings);
    let mut triangles = Vec::with_capacity(64 * n * n);
    fan(&mesh, false, &mut triangles);
    let (lo, hi) = triangles
        .iter()
        .flatten()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    let middle = (lo + hi) * 0.5;
    BenchScene {
        name: "teapot",
        triangles,
        camera: Camera {
            eye: middle + Vec3::new(0.4, 0.5, -1.0).normalize() * 11.0,
            target: middle,
            fov_y_degrees: 40.0,
        },
        light: AreaLight {
            corner: Vec3::new(middle.x - 1.0, hi.y + 2.0, middle.z - 1.0),
            edge_a: Vec3::new(2.0, 0.0, 0.0),
            edge_b: Vec3::new(0.0, 0.0, 2.0),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_field_is_near_target_and_deterministic() {
        let a = sphere_field_triangles(20_000, true);
        assert!(
            a.len() >= 20_000 - 160 && a.len() <= 20_000 + 2560,
            "{}",
            a.len()
        );
        assert_eq!(a, sphere_field_triangles(20_000, true));
        // The open field is the closed one without its twelve wall triangles.
        assert_eq!(a[12..], sphere_field_triangles(20_000, false)[..]);
    }

    #[test]
    fn teapot_has_the_asked_size_and_faces_out() {
        let scene = teapot(20_000);
        // n = ⌊√(20000/64)⌋ = 17: 32 patches × 17² cells × 2 triangles, less one for each
        // cell at a pole (welded to a triangle): 8 patches (lid top, bottom) × 17.
        assert_eq!(scene.triangles.len(), 32 * 17 * 17 * 2 - 8 * 17);
        // Fronts face out of the closed pot: the signed volume Σ a·(b × c)/6 is positive.
        let volume: f64 = scene
            .triangles
            .iter()
            .map(|[a, b, c]| f64::from(a.dot(b.cross(*c))) / 6.0)
            .sum();
        assert!(volume > 0.0, "{volume}");
    }
}
