//! The three kinds of benchmark rays.
//!
//! - *Incoherent* rays, as in radiosity gathering and path tracing: each starts at a uniform
//!   random point of a random triangle, lifted off it by 10⁻⁴ of the scene diagonal along the
//!   normal n = (b − a) × (c − a), and goes in a cosine-distributed direction of the hemisphere
//!   around n ([`cosine_direction`], pdf = cos θ / π). Neighbouring rays share nothing, so
//!   every ray walks its own path through the tree. t runs to [`T_MAX`].
//! - *Primary* rays of a pinhole camera, one through the centre of each pixel of a
//!   [`PRIMARY_SIDE`]² image, row by row: neighbouring rays start at one point and differ by
//!   a fraction of a degree, so they visit nearly the same nodes in the same order (the rays
//!   of the final render). t runs to [`T_MAX`].
//! - *Shadow* rays from the closest hit of each primary ray that hits to a uniform random point
//!   of one rectangular area light: the next-event rays of a renderer, coherent at their
//!   origins and converging on the light. The origin is lifted off the surface by 10⁻⁴ of
//!   the scene diagonal towards the camera's side; the direction is the light point minus the
//!   origin, unnormalised, and t runs to 1 (the light is not geometry: no triangle lies
//!   between it and the ray's end).
//!
//! All are deterministic for their seed.

use glam::Vec3;

use radiosity::accel::{Bvh, Ray};
use radiosity::hash::SplitMix;
use radiosity::sampling::cosine_direction;

use super::T_MAX;

/// Side of the square image the primary rays are cast through.
pub const PRIMARY_SIDE: usize = 512;

/// Rays with their far ends: ray k is traced with t in (0, `t_max[k]`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RaySet {
    /// Short name (at most 16 bytes of ASCII: it is written to the workload file).
    pub name: &'static str,
    /// The rays.
    pub rays: Vec<Ray>,
    /// Far end of each ray.
    pub t_max: Vec<f32>,
}

/// A pinhole camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Centre of projection.
    pub eye: Vec3,
    /// A point the view centre goes through.
    pub target: Vec3,
    /// Vertical field of view, degrees.
    pub fov_y_degrees: f32,
}

/// A parallelogram light: `corner` + s·`edge_a` + t·`edge_b`, s, t in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaLight {
    /// One corner.
    pub corner: Vec3,
    /// First edge from the corner.
    pub edge_a: Vec3,
    /// Second edge from the corner.
    pub edge_b: Vec3,
}

/// Uniform in 0..n (n > 0).
fn below(rng: &mut SplitMix, n: usize) -> usize {
    (((rng.next_u64() >> 32) * n as u64) >> 32) as usize
}

/// 10⁻⁴ of the diagonal of `bvh`'s scene: how far ray origins are lifted off surfaces.
fn lift(bvh: &Bvh) -> f32 {
    let bounds = bvh.bounds();
    1e-4 * (bounds.max - bounds.min).length()
}

/// `count` incoherent rays (see the module docs) from `triangles`, which `bvh` was built from
/// (it gives the scene's scale). Zero-area triangles are skipped; with none of positive area
/// the set is empty.
#[must_use]
pub fn incoherent(triangles: &[[Vec3; 3]], bvh: &Bvh, count: usize, seed: u64) -> RaySet {
    let lift = lift(bvh);
    let mut rng = SplitMix(seed);
    let mut rays = Vec::with_capacity(count);
    let mut misses = 0usize;
    while rays.len() < count && !triangles.is_empty() {
        let [a, b, c] = triangles[below(&mut rng, triangles.len())];
        let Some(n) = (b - a).cross(c - a).try_normalize() else {
            // Give up after many zero-area draws in a row.
            misses += 1;
            if misses > 1000 {
                break;
            }
            continue;
        };
        misses = 0;
        // Uniform point of the triangle (fold the unit square onto it).
        let (mut s, mut t) = (rng.next_f32(), rng.next_f32());
        if s + t > 1.0 {
            (s, t) = (1.0 - s, 1.0 - t);
        }
        let origin = a + s * (b - a) + t * (c - a) + lift * n;
        let (u1, u2) = (rng.next_f32(), rng.next_f32());
        rays.push(Ray::new(origin, cosine_direction(n, u1, u2)));
    }
    RaySet {
        name: "incoherent",
        t_max: vec![T_MAX; rays.len()],
        rays,
    }
}

/// The primary rays of `camera` (see the module docs), y up, row by row from the top left.
#[must_use]
pub fn primary(camera: &Camera) -> RaySet {
    let forward = (camera.target - camera.eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let half = (camera.fov_y_degrees.to_radians() * 0.5).tan();
    let side = PRIMARY_SIDE as f32;
    let mut rays = Vec::with_capacity(PRIMARY_SIDE * PRIMARY_SIDE);
    for row in 0..PRIMARY_SIDE {
        let y = (1.0 - 2.0 * (row as f32 + 0.5) / side) * half;
        for col in 0..PRIMARY_SIDE {
            let x = (2.0 * (col as f32 + 0.5) / side - 1.0) * half;
            rays.push(Ray::new(
                camera.eye,
                (forward + x * right + y * up).normalize(),
            ));
        }
    }
    RaySet {
        name: "primary",
        t_max: vec![T_MAX; rays.len()],
        rays,
    }
}

/// One shadow ray to `light` from the closest hit of each ray of `primary` that hits something
/// in `triangles` (see the module docs); `bvh` was built from `triangles`.
#[must_use]
pub fn shadow(
    triangles: &[[Vec3; 3]],
    bvh: &Bvh,
    primary: &RaySet,
    light: &AreaLight,
    seed: u64,
) -> RaySet {
    let lift = lift(bvh);
    let mut rng = SplitMix(seed);
    let mut rays = Vec::with_capacity(primary.rays.len());
    for (ray, &t_max) in primary.rays.iter().zip(&primary.t_max) {
        let Some(hit) = bvh.closest_hit(ray, t_max) else {
            continue;
        };
        let [a, b, c] = triangles[hit.triangle as usize];
        // The normal on the camera's side of the surface.
        let n = (b - a).cross(c - a).normalize_or_zero();
        let n = if n.dot(ray.dir) > 0.0 { -n } else { n };
        let origin = ray.at(hit.t) + lift * n;
        let target = light.corner + rng.next_f32() * light.edge_a + rng.next_f32() * light.edge_b;
        rays.push(Ray::new(origin, target - origin));
    }
    RaySet {
        name: "shadow",
        t_max: vec![1.0; rays.len()],
        rays,
    }
}

#[cfg(test)]
mod tests {
    use super::super::scenes::sphere_field_triangles;
    use super::*;

    #[test]
    fn incoherent_rays_leave_the_front_side_with_cosine_directions() {
        let tris = sphere_field_triangles(2_000, true);
        let bvh = Bvh::build(&tris);
        let set = incoherent(&tris, &bvh, 500, 7);
        assert_eq!(set.rays.len(), 500);
        // Mean cos θ of a cosine-distributed hemisphere is 2/3; with 500 samples its standard
        // error is sqrt(1/2 − 4/9)/sqrt(500) ≈ 0.011, so 0.06 is over five sigmas.
        let mut cos_sum = 0.0;
        for r in &set.rays {
            assert!((r.dir.length() - 1.0).abs() < 1e-4);
            // The nearest triangle behind the origin is the source: some triangle whose
            // front the ray leaves.
            let back = bvh.closest_hit(&Ray::new(r.origin, -r.dir), T_MAX).unwrap();
            let tri = tris[back.triangle as usize];
            let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
            cos_sum += n.dot(r.dir);
        }
        let mean = cos_sum / set.rays.len() as f32;
        assert!((mean - 2.0 / 3.0).abs() < 0.06, "mean cos {mean}");
    }

    #[test]
    fn primary_rays_cover_the_field_of_view() {
        let camera = Camera {
            eye: Vec3::ZERO,
            target: Vec3::Z,
            fov_y_degrees: 90.0,
        };
        let set = primary(&camera);
        assert_eq!(set.rays.len(), PRIMARY_SIDE * PRIMARY_SIDE);
        // The first pixel is top left: up (+y) and, looking along +z with y up, right is −x.
        let first = set.rays[0].dir;
        assert!(first.y > 0.0 && first.x > 0.0, "{first}");
        // Half a pixel in from the corner of a 90° square view: tan 45° · (1 − 1/512).
        let edge = 1.0 - 1.0 / PRIMARY_SIDE as f32;
        assert!((first.y / first.z - edge).abs() < 1e-5);
        // The image is symmetric: the last pixel mirrors the first.
        let last = set.rays[set.rays.len() - 1].dir;
        assert!((last + Vec3::new(first.x, first.y, -first.z)).length() < 1e-5);
    }

    #[test]
    fn shadow_rays_end_on_the_light() {
        // A floor under a light: every primary ray from above hits the floor.
        let floor = [
            [
                Vec3::new(-10.0, 0.0, -10.0),
                Vec3::new(10.0, 0.0, -10.0),
                Vec3::new(0.0, 0.0, 10.0),
            ],
            [
                Vec3::new(-10.0, 0.0, 10.0),
                Vec3::new(-10.0, 0.0, -10.0),
                Vec3::new(10.0, 0.0, 10.0),
            ],
        ];
        let bvh = Bvh::build(&floor);
        let camera = Camera {
            eye: Vec3::new(0.0, 5.0, -1.0),
            target: Vec3::ZERO,
            fov_y_degrees: 60.0,
        };
        let light = AreaLight {
            corner: Vec3::new(-1.0, 4.0, -1.0),
            edge_a: Vec3::X * 2.0,
            edge_b: Vec3::Z * 2.0,
        };
        let primary = primary(&camera);
        let set = shadow(&floor, &bvh, &primary, &light, 3);
        assert_eq!(set.rays.len(), primary.rays.len());
        for r in &set.rays {
            let end = r.at(1.0);
            assert!((end.y - 4.0).abs() < 1e-4 && end.x.abs() <= 1.0 && end.z.abs() <= 1.0);
            // Lifted above the floor, towards the camera.
            assert!(r.origin.y > 0.0 && r.origin.y < 1e-2);
        }
    }
}
