//! Ray throughput of the BVH on a Cornell-like box and a ~1M-triangle sphere field, for 1 and 2
//! threads; writes the workloads to /tmp for `benches/embree_rays.py`.
//!
//! `cargo run --release -p radiosity --example raybench [TRIANGLES] [RAYS]`

use glam::Vec3;
use radiosity::accel::{bench, Bvh};

/// A Cornell-like box in 36 triangles: five walls (quads), a ceiling light and two boxes.
fn cornell_like() -> Vec<[Vec3; 3]> {
    let mut tris = Vec::new();
    let mut quad = |a: Vec3, b: Vec3, c: Vec3, d: Vec3| {
        tris.push([a, b, c]);
        tris.push([a, c, d]);
    };
    let p = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    // Floor, ceiling, back, left, right walls (facing into the box).
    quad(
        p(-1., 0., 1.),
        p(1., 0., 1.),
        p(1., 0., -1.),
        p(-1., 0., -1.),
    );
    quad(
        p(-1., 2., -1.),
        p(1., 2., -1.),
        p(1., 2., 1.),
        p(-1., 2., 1.),
    );
    quad(
        p(-1., 0., -1.),
        p(1., 0., -1.),
        p(1., 2., -1.),
        p(-1., 2., -1.),
    );
    quad(
        p(-1., 0., 1.),
        p(-1., 0., -1.),
        p(-1., 2., -1.),
        p(-1., 2., 1.),
    );
    quad(p(1., 0., -1.), p(1., 0., 1.), p(1., 2., 1.), p(1., 2., -1.));
    // Light just below the ceiling, facing down.
    quad(
        p(-0.25, 1.99, -0.25),
        p(0.25, 1.99, -0.25),
        p(0.25, 1.99, 0.25),
        p(-0.25, 1.99, 0.25),
    );
    // Two boxes (five visible faces each would do; all six keep them closed).
    for (lo, hi) in [
        (p(-0.7, 0.0, -0.6), p(-0.1, 1.2, 0.0)),
        (p(0.1, 0.0, 0.1), p(0.7, 0.6, 0.7)),
    ] {
        let mesh = model::primitives::cuboid(lo, hi);
        for f in &mesh.faces {
            let v: Vec<Vec3> = f.iter().map(|&i| mesh.positions[i as usize]).collect();
            quad(v[0], v[1], v[2], v[3]);
        }
    }
    tris
}

fn main() {
    let mut args = std::env::args().skip(1);
    let target: usize = args
        .next()
        .and_then(|a| a.parse().ok())
        .unwrap_or(1_000_000);
    let ray_count: usize = args
        .next()
        .and_then(|a| a.parse().ok())
        .unwrap_or(1_000_000);
    println!(
        "{:<10} {:>9} {:>8} {:>7} {:>10} {:>14} {:>14} {:>9} {:>9}",
        "scene",
        "tris",
        "rays",
        "threads",
        "build ms",
        "occl Mray/s",
        "closest Mray/s",
        "occluded",
        "hits"
    );
    for (name, tris) in [
        ("cornell", cornell_like()),
        ("spheres", bench::sphere_field_triangles(target)),
    ] {
        let bvh = Bvh::build(&tris);
        let rays = bench::incoherent_rays(&tris, &bvh, ray_count, 1);
        let path = std::env::temp_dir().join(format!("raybench_{name}.bin"));
        if let Err(e) = bench::write_workload(&path, &tris, &rays) {
            eprintln!("cannot write {}: {e}", path.display());
        }
        match bench::run(&tris, &rays, &[1, 2]) {
            Ok(reports) => {
                for r in reports {
                    println!(
                        "{:<10} {:>9} {:>8} {:>7} {:>10.3} {:>14.2} {:>14.2} {:>9} {:>9}",
                        name,
                        r.triangles,
                        r.rays,
                        r.threads,
                        r.build_seconds * 1e3,
                        r.occlusion_rays_per_second / 1e6,
                        r.closest_hit_rays_per_second / 1e6,
                        r.occluded,
                        r.hits
                    );
                }
            }
            Err(e) => eprintln!("cannot start a thread pool: {e}"),
        }
    }
}
