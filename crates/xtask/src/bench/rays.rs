//! `cargo xtask bench`: ray throughput of the BVH (see [`crate::throughput`]) on the
//! built-in Cornell box, the sphere field closed and open, and the teapot, each with
//! incoherent, primary and shadow rays.

use std::io::{IsTerminal, Write};

use anyhow::Context;
use glam::Vec3;
use radiosity::accel::isa::{self, Isa};
use radiosity::accel::Bvh;
use radiosity::io::atomic::write_atomic;
use radiosity::mesh::{Mesh, Subdivision};
use radiosity::progress::{Progress, Work};
use radiosity::scene::builtin;
use report::Bars;

use super::{BenchArgs, BenchIsa};
use crate::throughput::{self, AreaLight, BenchScene, Camera, RaySet};

/// The built-in Cornell box's polygons as triangles, with the camera of its scene file
/// (`scenes/cornell/scene.toml`, millimetres) and a light just under its ceiling light.
fn cornell() -> anyhow::Result<BenchScene> {
    let scene = builtin::load("cornell").context("the built-in Cornell box is missing")??;
    Ok(BenchScene {
        name: "cornell",
        triangles: Mesh::build(&scene, Subdivision::Elements(1)).triangles,
        camera: Camera {
            eye: Vec3::new(278.0, 273.0, -800.0),
            target: Vec3::new(278.0, 273.0, 0.0),
            fov_y_degrees: 39.3077,
        },
        light: AreaLight {
            corner: Vec3::new(213.0, 548.0, 227.0),
            edge_a: Vec3::new(130.0, 0.0, 0.0),
            edge_b: Vec3::new(0.0, 0.0, 105.0),
        },
    })
}

/// A scene of about the given number of triangles (the Cornell box ignores it).
type Maker = fn(usize) -> anyhow::Result<BenchScene>;

/// The scenes by name, in the order they are measured.
const SCENES: [(&str, Maker); 4] = [
    ("cornell", |_| cornell()),
    ("spheres", |n| Ok(throughput::scenes::sphere_field(n, true))),
    ("spheres-open", |n| {
        Ok(throughput::scenes::sphere_field(n, false))
    }),
    ("teapot", |n| Ok(throughput::scenes::teapot(n))),
];

/// Measures every scene for each thread count, prints one line per measurement, and writes the
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
    let isa = isa::set(match args.isa {
        Some(BenchIsa::Baseline) => Isa::Baseline,
        Some(BenchIsa::Avx2) | None => Isa::Avx2,
    });
    writeln!(std::io::stderr(), "ray queries compiled for {isa:?}")?;
    let target = args.triangles as usize;
    let mut all = Vec::new();
    let mut out = std::io::stdout().lock();
    let bars = Bars::new(std::io::stderr().is_terminal());
    for (name, make) in SCENES {
        if !args.scenes.is_empty() && !args.scenes.iter().any(|s| s == name) {
            continue;
        }
        let scene = make(target)?;
        // A spinner while the scene is built and measured (stderr, on a terminal only).
        bars.start(&format!("bench {}", scene.name), Work::open_ended("steps"));
        let sets = ray_sets(&scene, args);
        if let Some(dir) = &args.workload {
            let path = dir.join(format!("{}.bin", scene.name));
            write_atomic(&path, |w| {
                throughput::write_workload(w, &scene.triangles, &sets)
            })
            .with_context(|| format!("{}: cannot write", path.display()))?;
        }
        let report = throughput::run(scene.name, &scene.triangles, &sets, &threads)
            .context("cannot start threads")?;
        bars.finish();
        for b in &report.builds {
            writeln!(
                out,
                "{:<12} triangles {:>8}  threads {:>2}  build {:.3} s  {:.1} bytes/triangle",
                report.scene, report.triangles, b.threads, b.seconds, report.bytes_per_triangle,
            )?;
        }
        for s in &report.sets {
            for r in &s.rates {
                writeln!(
                    out,
                    "{:<12} {:<10} rays {:>7}  threads {:>2}  Mrays/s: occlusion {:6.2}, \
                     interleaved {:6.2}, packets {:6.2}; closest hit {:6.2}, \
                     interleaved {:6.2}, packets {:6.2}  occluded {}  hits {}",
                    report.scene,
                    s.name,
                    s.rays,
                    r.threads,
                    r.occlusion_rays_per_second / 1e6,
                    r.occlusion_batched_rays_per_second / 1e6,
                    r.occlusion_packet_rays_per_second / 1e6,
                    r.closest_hit_rays_per_second / 1e6,
                    r.closest_hit_batched_rays_per_second / 1e6,
                    r.closest_hit_packet_rays_per_second / 1e6,
                    s.occluded,
                    s.hits,
                )?;
            }
        }
        all.push(report);
    }
    if let Some(path) = &args.json {
        let json = serde_json::to_vec_pretty(&all)?;
        write_atomic(path, |w| w.write_all(&json))
            .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    Ok(())
}

/// The incoherent, primary and shadow rays of `scene`.
fn ray_sets(scene: &BenchScene, args: &BenchArgs) -> [RaySet; 3] {
    let bvh = Bvh::build(&scene.triangles);
    let incoherent =
        throughput::rays::incoherent(&scene.triangles, &bvh, args.rays as usize, args.seed);
    let primary = throughput::rays::primary(&scene.camera);
    let shadow =
        throughput::rays::shadow(&scene.triangles, &bvh, &primary, &scene.light, args.seed);
    [incoherent, primary, shadow]
}
