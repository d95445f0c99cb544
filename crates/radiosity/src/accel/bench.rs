//! The ray-throughput benchmark: scene and ray generation, timing, and the workload file that
//! `benches/embree_rays.py` traces with Intel Embree for comparison.
//!
//! Rays are *incoherent*, as in radiosity gathering and path tracing: each starts at a uniform
//! random point of a random triangle, lifted off it by 10⁻⁴ of the scene diagonal along the
//! normal n = (b − a) × (c − a), and goes in a cosine-distributed direction of the hemisphere
//! around n (Malley's method: a uniform point of the unit disk lifted to the hemisphere,
//! pdf = cos θ / π).
//!
//! Workload file (little-endian): `u32` triangle count N, `u32` ray count M, then N × 9 `f32`
//! (a, b, c of each triangle, x y z each), then M × 6 `f32` (origin x y z, direction x y z).
//! Both tracers use t in (0, [`T_MAX`]).

use std::io::{self, Write};
use std::time::Instant;

use glam::Vec3;
use rayon::prelude::*;
use serde::Serialize;

use super::{Bvh, Ray};
use crate::hash::SplitMix;

/// Far end of every benchmark ray (Embree's wrapper is given the same).
pub const T_MAX: f32 = 1e30;
/// Repetitions of each measurement; the best is reported.
const REPETITIONS: usize = 3;
/// Rays per rayon task.
const CHUNK: usize = 4096;

/// Uniform in [0, 1) from the next 24 bits of `rng`.
fn uniform(rng: &mut SplitMix) -> f32 {
    (rng.next_u64() >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

/// Uniform in 0..n (n > 0).
fn below(rng: &mut SplitMix, n: usize) -> usize {
    (((rng.next_u64() >> 32) * n as u64) >> 32) as usize
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

/// A closed 20 × 10 × 20 room (walls facing in) filled with overlapping icospheres of radius
/// 0.15–1.2 and 320–5120 triangles each, until there are about `target` triangles (within one
/// sphere's worth). Deterministic. Depth complexity is high: most rays cross several spheres'
/// boxes before they hit.
#[must_use]
pub fn sphere_field_triangles(target: usize) -> Vec<[Vec3; 3]> {
    let lo = Vec3::new(-10.0, 0.0, -10.0);
    let hi = Vec3::new(10.0, 10.0, 10.0);
    let mut tris = Vec::with_capacity(target + 5120);
    fan(&model::primitives::cuboid(lo, hi), true, &mut tris);
    let mut rng = SplitMix(0x5EED);
    while tris.len() + 160 < target {
        let s = uniform(&mut rng);
        let radius = 0.15 + 1.05 * s * s;
        // Finer spheres where they are larger, and never much past the target.
        let mut subdivisions = 2 + (radius > 0.4) as u32 + (radius > 0.8) as u32;
        while subdivisions > 1 && tris.len() + (20 << (2 * subdivisions)) / 2 > target {
            subdivisions -= 1;
        }
        let span = hi - lo - Vec3::splat(2.0 * radius);
        let centre = lo
            + Vec3::splat(radius)
            + span * Vec3::new(uniform(&mut rng), uniform(&mut rng), uniform(&mut rng));
        fan(
            &model::primitives::icosphere(centre, radius, subdivisions),
            false,
            &mut tris,
        );
    }
    tris
}

/// `count` incoherent rays (see the module docs) from `triangles`, which `bvh` was built from
/// (it gives the scene's scale). Deterministic for a `seed`. Zero-area triangles are skipped;
/// with none of positive area the result is empty.
#[must_use]
pub fn incoherent_rays(triangles: &[[Vec3; 3]], bvh: &Bvh, count: usize, seed: u64) -> Vec<Ray> {
    let bounds = bvh.bounds();
    let lift = 1e-4 * (bounds.max - bounds.min).length();
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
        let (mut s, mut t) = (uniform(&mut rng), uniform(&mut rng));
        if s + t > 1.0 {
            (s, t) = (1.0 - s, 1.0 - t);
        }
        let origin = a + s * (b - a) + t * (c - a) + lift * n;
        // Cosine-distributed direction around n (Malley's method).
        let r = uniform(&mut rng).sqrt();
        let phi = std::f32::consts::TAU * uniform(&mut rng);
        let (x, y) = (r * phi.cos(), r * phi.sin());
        let z = (1.0 - r * r).max(0.0).sqrt();
        let (t1, t2) = n.any_orthonormal_pair();
        rays.push(Ray::new(origin, x * t1 + y * t2 + z * n));
    }
    rays
}

/// Throughput for one thread count.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RayBenchReport {
    /// Worker threads of the rayon pool.
    pub threads: usize,
    /// Triangles in the scene.
    pub triangles: usize,
    /// Rays traced per query type and repetition.
    pub rays: usize,
    /// Best hierarchy build time, seconds.
    pub build_seconds: f64,
    /// Best occlusion (any-hit) throughput, rays per second.
    pub occlusion_rays_per_second: f64,
    /// Best closest-hit throughput, rays per second.
    pub closest_hit_rays_per_second: f64,
    /// Rays found occluded (a check against another tracer).
    pub occluded: usize,
    /// Rays that hit something in the closest-hit pass.
    pub hits: usize,
}

/// Best of [`REPETITIONS`] timings of `f`, with its last result.
fn best_of<T>(mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut result = f();
    for _ in 0..REPETITIONS {
        let start = Instant::now();
        result = f();
        best = best.min(start.elapsed().as_secs_f64());
    }
    (best, result)
}

/// Builds the hierarchy and traces `rays` (occlusion, then closest hit, t < [`T_MAX`]) in a
/// rayon pool of each of `threads` sizes; best of three of each (after one warm-up run).
///
/// # Errors
/// When rayon cannot start a pool.
pub fn run(
    triangles: &[[Vec3; 3]],
    rays: &[Ray],
    threads: &[usize],
) -> Result<Vec<RayBenchReport>, rayon::ThreadPoolBuildError> {
    let mut reports = Vec::with_capacity(threads.len());
    for &n in threads {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(n).build()?;
        let report = pool.install(|| {
            let (build_seconds, bvh) = best_of(|| Bvh::build(triangles));
            let rate = |seconds: f64| rays.len() as f64 / seconds;
            let (occlusion, occluded) = best_of(|| {
                rays.par_chunks(CHUNK)
                    .map(|c| c.iter().filter(|r| bvh.occluded(r, T_MAX)).count())
                    .sum::<usize>()
            });
            let (closest, hits) = best_of(|| {
                rays.par_chunks(CHUNK)
                    .map(|c| {
                        c.iter()
                            .filter(|r| bvh.closest_hit(r, T_MAX).is_some())
                            .count()
                    })
                    .sum::<usize>()
            });
            RayBenchReport {
                threads: pool.current_num_threads(),
                triangles: triangles.len(),
                rays: rays.len(),
                build_seconds,
                occlusion_rays_per_second: rate(occlusion),
                closest_hit_rays_per_second: rate(closest),
                occluded,
                hits,
            }
        });
        reports.push(report);
    }
    Ok(reports)
}

/// Writes the triangles and rays in the workload layout of the module docs.
///
/// # Errors
/// I/O errors, and `InvalidInput` when a count does not fit in a `u32`.
pub fn write_workload(
    out: &mut dyn Write,
    triangles: &[[Vec3; 3]],
    rays: &[Ray],
) -> io::Result<()> {
    let count = |n: usize| {
        u32::try_from(n).map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "count > u32"))
    };
    let mut out = io::BufWriter::new(out);
    out.write_all(&count(triangles.len())?.to_le_bytes())?;
    out.write_all(&count(rays.len())?.to_le_bytes())?;
    let mut put = |v: Vec3| -> io::Result<()> {
        for x in v.to_array() {
            out.write_all(&x.to_le_bytes())?;
        }
        Ok(())
    };
    for tri in triangles {
        tri.iter().try_for_each(|&v| put(v))?;
    }
    for ray in rays {
        put(ray.origin)?;
        put(ray.dir)?;
    }
    out.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_field_is_near_target_and_deterministic() {
        let a = sphere_field_triangles(20_000);
        assert!(
            a.len() >= 20_000 - 160 && a.len() <= 20_000 + 2560,
            "{}",
            a.len()
        );
        assert_eq!(a, sphere_field_triangles(20_000));
    }

    #[test]
    fn rays_leave_the_front_side_with_unit_directions() {
        let tris = sphere_field_triangles(2_000);
        let bvh = Bvh::build(&tris);
        let rays = incoherent_rays(&tris, &bvh, 500, 7);
        assert_eq!(rays.len(), 500);
        // Mean cos θ of a cosine-distributed hemisphere is 2/3; with 500 samples its standard
        // error is sqrt(1/2 − 4/9)/sqrt(500) ≈ 0.011, so 0.06 is over five sigmas.
        let mut cos_sum = 0.0;
        for r in &rays {
            assert!((r.dir.length() - 1.0).abs() < 1e-4);
            // The nearest triangle plane behind the origin is the source: some triangle whose
            // front the ray leaves. Checked via the closest hit backwards being very near.
            let back = bvh.closest_hit(&Ray::new(r.origin, -r.dir), T_MAX);
            assert!(back.is_some());
            let tri = tris[back.unwrap().triangle as usize];
            let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
            cos_sum += n.dot(r.dir);
        }
        let mean = cos_sum / rays.len() as f32;
        assert!((mean - 2.0 / 3.0).abs() < 0.06, "mean cos {mean}");
    }

    #[test]
    fn workload_file_has_the_documented_layout() {
        let tris = vec![[Vec3::X, Vec3::Y, Vec3::Z]];
        let rays = vec![Ray::new(Vec3::ZERO, Vec3::ONE)];
        let mut bytes = Vec::new();
        write_workload(&mut bytes, &tris, &rays).unwrap();
        assert_eq!(bytes.len(), 8 + 9 * 4 + 6 * 4);
        assert_eq!(&bytes[0..8], &[1, 0, 0, 0, 1, 0, 0, 0]);
        assert_eq!(&bytes[8..12], &1f32.to_le_bytes());
        assert_eq!(&bytes[56..60], &1f32.to_le_bytes());
    }

    #[test]
    fn run_reports_consistent_counts() {
        let tris = sphere_field_triangles(1_000);
        let bvh = Bvh::build(&tris);
        let rays = incoherent_rays(&tris, &bvh, 300, 1);
        let reports = run(&tris, &rays, &[1, 2]).unwrap();
        // The room is closed, so every ray hits something; counts agree across thread counts.
        for r in &reports {
            assert_eq!((r.occluded, r.hits, r.rays), (300, 300, 300));
            assert!(r.occlusion_rays_per_second > 0.0 && r.build_seconds > 0.0);
        }
    }
}
