//! `radiosity bench`: ray throughput of the BVH on incoherent rays
//! (see [`radiosity::accel::bench`]), on the built-in Cornell box and on a large sphere field.

use std::io::{IsTerminal, Write};

use anyhow::Context;
use radiosity::accel::{bench, Bvh};
use radiosity::io::atomic::write_atomic;
use radiosity::mesh::{Mesh, Subdivision};
use radiosity::scene::builtin;

use radiosity::progress::Progress;

use crate::args::BenchArgs;
use crate::bars::Bars;

/// Measures both scenes for each thread count, prints one line per measurement, and writes the
/// JSON reports and the workloads if asked.
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
    let cornell = builtin::load("cornell").context("the built-in Cornell box is missing")??;
    let scenes = [
        (
            "cornell",
            Mesh::build(&cornell, Subdivision::Elements(1)).triangles,
        ),
        (
            "spheres",
            bench::sphere_field_triangles(args.triangles as usize),
        ),
    ];
    let mut all = Vec::new();
    let mut out = std::io::stdout().lock();
    let bars = Bars::new(std::io::stderr().is_terminal());
    for (name, triangles) in &scenes {
        // A spinner while the scene is built and measured (stderr, on a terminal only).
        bars.start(&format!("bench {name}"), 0);
        let bvh = Bvh::build(triangles);
        let rays = bench::incoherent_rays(triangles, &bvh, args.rays as usize, args.seed);
        drop(bvh);
        if let Some(dir) = &args.workload {
            let path = dir.join(format!("{name}.bin"));
            write_atomic(&path, |w| bench::write_workload(w, triangles, &rays))
                .with_context(|| format!("{}: cannot write", path.display()))?;
        }
        let reports = bench::run(triangles, &rays, &threads).context("cannot start threads")?;
        bars.finish();
        for r in &reports {
            writeln!(
                out,
                "{name:<8} threads {:>3}  triangles {:>8}  rays {}  build {:.3} s  \
                 occlusion {:.2} Mrays/s  closest hit {:.2} Mrays/s",
                r.threads,
                r.triangles,
                r.rays,
                r.build_seconds,
                r.occlusion_rays_per_second / 1e6,
                r.closest_hit_rays_per_second / 1e6,
            )?;
        }
        all.push(serde_json::json!({ "scene": name, "reports": reports }));
    }
    if let Some(path) = &args.json {
        let json = serde_json::to_vec_pretty(&all)?;
        write_atomic(path, |w| w.write_all(&json))
            .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    Ok(())
}
