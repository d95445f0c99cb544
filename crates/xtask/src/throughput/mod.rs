//! The ray-throughput benchmark: scenes ([`scenes`]), rays ([`rays`]), timing, and the
//! workload file that `benches/embree_rays.py` traces with Intel Embree for comparison.
//!
//! For each scene, [`run`] builds the hierarchy and traces each ray set with both queries
//! (occlusion and closest hit), one ray at a time, interleaved and in packets, in a rayon pool of each asked size, best of [`REPETITIONS`]
//! timings after a warm-up; it also records the build time (best of [`REPETITIONS`]) and the
//! hierarchy's memory per triangle ([`Bvh::memory_bytes`]).
//!
//! Workload file (little-endian): `u32` triangle count N, `u32` ray-set count S, N × 9 `f32`
//! (a, b, c of each triangle, x y z each), then S ray sets, each a 16-byte ASCII name padded
//! with NUL bytes, a `u32` ray count M and M × 7 `f32` (origin x y z, direction x y z, far
//! end t_max). Both tracers trace ray k with t in (0, t_max).

pub mod rays;
pub mod scenes;

use std::io::{self, Write};
use std::time::Instant;

use glam::Vec3;
use rayon::prelude::*;
use serde::Serialize;

pub use rays::{AreaLight, Camera, RaySet};
pub use scenes::BenchScene;

use radiosity::accel::isa::{self, Isa};
use radiosity::accel::{Bvh, Hit, Ray};

/// Far end of the rays that run to infinity (Embree's wrapper is given the same).
pub const T_MAX: f32 = 1e30;
/// Repetitions of each measurement; the best is reported.
const REPETITIONS: usize = 3;
/// Rays per rayon task.
const CHUNK: usize = 4096;

/// Throughput of one query on one ray set in one pool.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Rate {
    /// Worker threads of the rayon pool.
    pub threads: usize,
    /// Best occlusion (any-hit) throughput, rays per second.
    pub occlusion_rays_per_second: f64,
    /// Best closest-hit throughput, rays per second.
    pub closest_hit_rays_per_second: f64,
    /// Best occlusion throughput of the interleaved query ([`Bvh::occluded_many`]).
    pub occlusion_batched_rays_per_second: f64,
    /// Best closest-hit throughput of the interleaved query ([`Bvh::closest_hits`]).
    pub closest_hit_batched_rays_per_second: f64,
    /// Best occlusion throughput of the packet query ([`Bvh::occluded_coherent`]).
    pub occlusion_packet_rays_per_second: f64,
    /// Best closest-hit throughput of the packet query ([`Bvh::closest_hits_coherent`]).
    pub closest_hit_packet_rays_per_second: f64,
}

/// Results on one ray set.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SetReport {
    /// Name of the set ([`RaySet::name`]).
    pub name: &'static str,
    /// Rays in the set.
    pub rays: usize,
    /// Rays found occluded (a check against another tracer).
    pub occluded: usize,
    /// Rays that hit something in the closest-hit pass.
    pub hits: usize,
    /// One entry per pool size.
    pub rates: Vec<Rate>,
}

/// Build time in one pool.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BuildTime {
    /// Worker threads of the rayon pool.
    pub threads: usize,
    /// Best build time, seconds.
    pub seconds: f64,
}

/// Everything measured on one scene.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SceneReport {
    /// Name of the scene.
    pub scene: &'static str,
    /// Triangles in the scene.
    pub triangles: usize,
    /// Instruction set the queries ran on ([`isa::current`]).
    pub isa: Isa,
    /// Bytes the hierarchy holds (nodes, triangles, indices) per input triangle.
    pub bytes_per_triangle: f64,
    /// One entry per pool size.
    pub builds: Vec<BuildTime>,
    /// One entry per ray set.
    pub sets: Vec<SetReport>,
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

/// How many rays of `set` `hit` says yes to, over the current rayon pool.
fn count(set: &RaySet, hit: impl Fn(usize) -> bool + Sync) -> usize {
    let indices: Vec<usize> = (0..set.rays.len()).collect();
    indices
        .par_chunks(CHUNK)
        .map(|chunk| chunk.iter().filter(|&&k| hit(k)).count())
        .sum()
}

/// How many rays of `set` the batched query `query` finds something for, [`CHUNK`] rays per
/// call, over the current rayon pool.
fn count_batched<T: Default + Clone + IsSome + Send>(
    set: &RaySet,
    query: impl Fn(&[Ray], &[f32], &mut [T]) + Sync,
) -> usize {
    set.rays
        .par_chunks(CHUNK)
        .zip(set.t_max.par_chunks(CHUNK))
        .map(|(rays, t_max)| {
            let mut out = vec![T::default(); rays.len()];
            query(rays, t_max, &mut out);
            out.iter().filter(|o| o.is_some()).count()
        })
        .sum()
}

/// What a batched query wrote for one ray: found something or not.
trait IsSome {
    fn is_some(&self) -> bool;
}

impl IsSome for bool {
    fn is_some(&self) -> bool {
        *self
    }
}

impl IsSome for Option<Hit> {
    fn is_some(&self) -> bool {
        Option::is_some(self)
    }
}

/// Builds the hierarchy over `triangles` and traces every set of `sets` with both queries, in a
/// rayon pool of each of `threads` sizes (see the module docs).
///
/// # Errors
/// When rayon cannot start a pool.
pub fn run(
    scene: &'static str,
    triangles: &[[Vec3; 3]],
    sets: &[RaySet],
    threads: &[usize],
) -> Result<SceneReport, rayon::ThreadPoolBuildError> {
    let mut builds = Vec::with_capacity(threads.len());
    let mut reports: Vec<SetReport> = sets
        .iter()
        .map(|s| SetReport {
            name: s.name,
            rays: s.rays.len(),
            occluded: 0,
            hits: 0,
            rates: Vec::with_capacity(threads.len()),
        })
        .collect();
    let mut bytes_per_triangle = 0.0;
    for &n in threads {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(n).build()?;
        pool.install(|| {
            let (seconds, bvh) = best_of(|| Bvh::build(triangles));
            let threads = pool.current_num_threads();
            builds.push(BuildTime { threads, seconds });
            bytes_per_triangle = bvh.memory_bytes() as f64 / triangles.len().max(1) as f64;
            for (set, report) in sets.iter().zip(&mut reports) {
                let rate = |seconds: f64| set.rays.len() as f64 / seconds;
                let (occlusion, occluded) =
                    best_of(|| count(set, |k| bvh.occluded(&set.rays[k], set.t_max[k])));
                let (closest, hits) = best_of(|| {
                    count(set, |k| {
                        bvh.closest_hit(&set.rays[k], set.t_max[k]).is_some()
                    })
                });
                let (occlusion_batched, occluded_batched) = best_of(|| {
                    count_batched(set, |rays, t_max, out| bvh.occluded_many(rays, t_max, out))
                });
                let (closest_batched, hits_batched) = best_of(|| {
                    count_batched(set, |rays, t_max, out: &mut [Option<Hit>]| {
                        bvh.closest_hits(rays, t_max, out);
                    })
                });
                let (occlusion_packet, occluded_packet) = best_of(|| {
                    count_batched(set, |rays, t_max, out| {
                        bvh.occluded_coherent(rays, t_max, out);
                    })
                });
                let (closest_packet, hits_packet) = best_of(|| {
                    count_batched(set, |rays, t_max, out: &mut [Option<Hit>]| {
                        bvh.closest_hits_coherent(rays, t_max, out);
                    })
                });
                debug_assert_eq!((occluded, hits), (occluded_batched, hits_batched));
                debug_assert_eq!((occluded, hits), (occluded_packet, hits_packet));
                report.occluded = occluded;
                report.hits = hits;
                report.rates.push(Rate {
                    threads,
                    occlusion_rays_per_second: rate(occlusion),
                    closest_hit_rays_per_second: rate(closest),
                    occlusion_batched_rays_per_second: rate(occlusion_batched),
                    closest_hit_batched_rays_per_second: rate(closest_batched),
                    occlusion_packet_rays_per_second: rate(occlusion_packet),
                    closest_hit_packet_rays_per_second: rate(closest_packet),
                });
            }
        });
    }
    Ok(SceneReport {
        scene,
        triangles: triangles.len(),
        isa: isa::current(),
        bytes_per_triangle,
        builds,
        sets: reports,
    })
}

/// Writes the triangles and ray sets in the workload layout of the module docs.
///
/// # Errors
/// I/O errors, and `InvalidInput` when a count does not fit in a `u32` or a set's name is
/// longer than 16 bytes.
pub fn write_workload(
    out: &mut dyn Write,
    triangles: &[[Vec3; 3]],
    sets: &[RaySet],
) -> io::Result<()> {
    let invalid = |what: &str| io::Error::new(io::ErrorKind::InvalidInput, what.to_string());
    let count = |n: usize| u32::try_from(n).map_err(|_| invalid("count > u32"));
    let mut out = io::BufWriter::new(out);
    out.write_all(&count(triangles.len())?.to_le_bytes())?;
    out.write_all(&count(sets.len())?.to_le_bytes())?;
    let put = |out: &mut io::BufWriter<&mut dyn Write>, v: Vec3| -> io::Result<()> {
        for x in v.to_array() {
            out.write_all(&x.to_le_bytes())?;
        }
        Ok(())
    };
    for tri in triangles {
        tri.iter().try_for_each(|&v| put(&mut out, v))?;
    }
    for set in sets {
        let mut name = [0u8; 16];
        let bytes = set.name.as_bytes();
        if bytes.len() > name.len() {
            return Err(invalid("ray set name > 16 bytes"));
        }
        name[..bytes.len()].copy_from_slice(bytes);
        out.write_all(&name)?;
        out.write_all(&count(set.rays.len())?.to_le_bytes())?;
        for (ray, t_max) in set.rays.iter().zip(&set.t_max) {
            put(&mut out, ray.origin)?;
            put(&mut out, ray.dir)?;
            out.write_all(&t_max.to_le_bytes())?;
        }
    }
    out.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn workload_file_has_the_documented_layout() {
        let tris = vec![[Vec3::X, Vec3::Y, Vec3::Z]];
        let set = RaySet {
            name: "primary",
            rays: vec![Ray::new(Vec3::ZERO, Vec3::ONE)],
            t_max: vec![0.5],
        };
        let mut bytes = Vec::new();
        write_workload(&mut bytes, &tris, std::slice::from_ref(&set)).unwrap();
        assert_eq!(bytes.len(), 8 + 9 * 4 + 16 + 4 + 7 * 4);
        assert_eq!(&bytes[0..8], &[1, 0, 0, 0, 1, 0, 0, 0]);
        assert_eq!(&bytes[8..12], &1f32.to_le_bytes());
        assert_eq!(&bytes[44..51], b"primary");
        assert_eq!(&bytes[51..60], &[0; 9]);
        assert_eq!(&bytes[60..64], &[1, 0, 0, 0]);
        assert_eq!(&bytes[76..80], &1f32.to_le_bytes());
        assert_eq!(&bytes[88..92], &0.5f32.to_le_bytes());
    }

    #[test]
    fn run_reports_consistent_counts() {
        let scene = scenes::sphere_field(1_000, true);
        let bvh = Bvh::build(&scene.triangles);
        let incoherent = rays::incoherent(&scene.triangles, &bvh, 300, 1);
        let report = run(scene.name, &scene.triangles, &[incoherent], &[1, 2]).unwrap();
        // The room is closed, so every ray hits something; counts agree across thread counts.
        let set = &report.sets[0];
        assert_eq!((set.occluded, set.hits, set.rays), (300, 300, 300));
        assert_eq!(set.rates.len(), 2);
        assert!(set.rates[0].occlusion_rays_per_second > 0.0);
        // A build time per thread count; its size is the machine's, not the test's concern.
        assert!(report
            .builds
            .iter()
            .all(|b| b.seconds.is_finite() && b.seconds >= 0.0));
        // At least the triangles themselves (36 bytes each) and their indices.
        assert!(report.bytes_per_triangle >= 40.0);
    }
}
