//! Per-ray work of the BVH queries on the 1M-triangle benchmark scenes: traversal steps (nodes
//! and leaves visited) and triangle packets tested per ray, which do not depend on the
//! machine's load, and rays per second one ray at a time on one thread with the queries
//! compiled for SSE2 and for AVX2 (`accel::isa`), interleaved, best of two.
//!
//! ```sh
//! cargo run --release -p xtask --features count -- traversal-counts [SCENE] [RAYS]
//! ```
//!
//! SCENE is `spheres`, `spheres-open` or `teapot` (default: all); RAYS restricts to the ray
//! sets whose name starts with it (`inc`, `pri`, `sha`). Without `--features count` the
//! counts print as zero and the timings are those of the plain build.

use std::sync::atomic::Ordering::Relaxed;
use std::time::Instant;

use clap::Args;
use radiosity::accel::isa::{self, Isa};
use radiosity::accel::Bvh;

use crate::throughput::{rays, scenes, BenchScene};

/// `cargo xtask traversal-counts`.
#[derive(Debug, Args)]
pub struct TraversalArgs {
    /// Only this scene: `spheres`, `spheres-open` or `teapot` (default: all).
    pub scene: Option<String>,
    /// Only the ray sets whose name starts with this: `inc`, `pri` or `sha` (default: all).
    pub rays: Option<String>,
}

/// Steps and packets counted since the last reset (zero without the `count` feature).
fn counts(reset: bool) -> (u64, u64) {
    #[cfg(feature = "count")]
    {
        use radiosity::accel::{COUNT_PACKETS, COUNT_STEPS};
        if reset {
            COUNT_STEPS.store(0, Relaxed);
            COUNT_PACKETS.store(0, Relaxed);
        }
        (COUNT_STEPS.load(Relaxed), COUNT_PACKETS.load(Relaxed))
    }
    #[cfg(not(feature = "count"))]
    {
        let _ = (reset, Relaxed);
        (0, 0)
    }
}

/// Makes one benchmark scene.
type Maker = fn() -> BenchScene;

/// Measures every asked scene and ray set and prints a line per query.
pub fn run(args: &TraversalArgs) {
    const TRIANGLES: usize = 1_000_000;
    let only_scene = args.scene.clone().unwrap_or_default();
    let only_set = args.rays.clone().unwrap_or_default();
    let makers: [(&str, Maker); 3] = [
        ("spheres", || scenes::sphere_field(TRIANGLES, true)),
        ("spheres-open", || scenes::sphere_field(TRIANGLES, false)),
        ("teapot", || scenes::teapot(TRIANGLES)),
    ];
    for (name, make) in makers {
        if !only_scene.is_empty() && name != only_scene {
            continue;
        }
        let scene = make();
        let start = Instant::now();
        let bvh = Bvh::build(&scene.triangles);
        println!(
            "{name}: {} triangles, build {:.2} s, {:.1} bytes/triangle, SAH cost {:.2}",
            scene.triangles.len(),
            start.elapsed().as_secs_f64(),
            bvh.memory_bytes() as f64 / scene.triangles.len() as f64,
            bvh.sah_cost()
        );
        let incoherent = rays::incoherent(&scene.triangles, &bvh, 200_000, 1);
        let primary = rays::primary(&scene.camera);
        let shadow = rays::shadow(&scene.triangles, &bvh, &primary, &scene.light, 1);
        for set in [&incoherent, &primary, &shadow] {
            if !set.name.starts_with(only_set.as_str()) {
                continue;
            }
            for any in [true, false] {
                let m = set.rays.len() as f64;
                let mut best = [f64::INFINITY; 2];
                let (mut steps, mut packets) = (0, 0);
                for _ in 0..2 {
                    for (i, choice) in [Isa::Baseline, Isa::Avx2].into_iter().enumerate() {
                        isa::set(choice);
                        counts(true);
                        let start = Instant::now();
                        let found = set
                            .rays
                            .iter()
                            .zip(&set.t_max)
                            .filter(|&(r, &t)| {
                                if any {
                                    bvh.occluded(r, t)
                                } else {
                                    bvh.closest_hit(r, t).is_some()
                                }
                            })
                            .count();
                        best[i] = best[i].min(start.elapsed().as_secs_f64());
                        std::hint::black_box(found);
                        (steps, packets) = counts(false);
                    }
                }
                // The same rays in packets of eight (`Bvh::closest_hits_coherent`), AVX2.
                let mut best_p = f64::INFINITY;
                let (mut steps_p, mut packets_p) = (0, 0);
                for _ in 0..2 {
                    counts(true);
                    let start = Instant::now();
                    let found = if any {
                        let mut out = vec![false; set.rays.len()];
                        bvh.occluded_coherent(&set.rays, &set.t_max, &mut out);
                        out.iter().filter(|&&o| o).count()
                    } else {
                        let mut out = vec![None; set.rays.len()];
                        bvh.closest_hits_coherent(&set.rays, &set.t_max, &mut out);
                        out.iter().filter(|o| o.is_some()).count()
                    };
                    best_p = best_p.min(start.elapsed().as_secs_f64());
                    std::hint::black_box(found);
                    (steps_p, packets_p) = counts(false);
                }
                println!(
                    "  {:<10} {:<11}: {:5.1} steps {:4.1} packets per ray; Mrays/s SSE2 {:6.2}, AVX2 {:6.2}; \
                     ray packets: {:5.2} steps {:4.1} packets per ray, {:6.2} Mrays/s",
                    set.name,
                    if any { "occlusion" } else { "closest hit" },
                    steps as f64 / m,
                    packets as f64 / m,
                    m / best[0] / 1e6,
                    m / best[1] / 1e6,
                    steps_p as f64 / m,
                    packets_p as f64 / m,
                    m / best_p / 1e6
                );
            }
        }
    }
}
