//! `radiosity bench`: ray throughput of the BVH on incoherent rays
//! (see [`radiosity::accel::bench`]).

use std::io::Write;

use anyhow::Context;
use radiosity::accel::{bench, Bvh};
use radiosity::io::atomic::write_atomic;

use crate::args::BenchArgs;

/// Builds the sphere field, generates the rays, times occlusion and closest-hit queries for
/// each thread count, and prints one line per count (plus JSON and the workload if asked).
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    let threads: Vec<usize> = if args.threads.is_empty() {
        let cores = std::thread::available_parallelism().map_or(1, usize::from);
        if cores > 1 {
            vec![1, cores]
        } else {
            vec![1]
        }
    } else {
        args.threads.iter().map(|&n| n as usize).collect()
    };
    let triangles = bench::sphere_field_triangles(args.triangles as usize);
    let bvh = Bvh::build(&triangles);
    let rays = bench::incoherent_rays(&triangles, &bvh, args.rays as usize, args.seed);
    drop(bvh);
    if let Some(path) = &args.workload {
        bench::write_workload(path, &triangles, &rays)
            .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    let reports = bench::run(&triangles, &rays, &threads).context("cannot start threads")?;
    let mut out = std::io::stdout().lock();
    for r in &reports {
        writeln!(
            out,
            "threads {:>3}  triangles {}  rays {}  build {:.3} s  occlusion {:.2} Mrays/s  \
             closest hit {:.2} Mrays/s",
            r.threads,
            r.triangles,
            r.rays,
            r.build_seconds,
            r.occlusion_rays_per_second / 1e6,
            r.closest_hit_rays_per_second / 1e6,
        )?;
    }
    if let Some(path) = &args.json {
        let json = serde_json::to_vec_pretty(&reports)?;
        write_atomic(path, |w| w.write_all(&json))
            .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    Ok(())
}
