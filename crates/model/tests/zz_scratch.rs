use glam::{DVec3, Vec3};
use model::brep::closed_topology;
use model::csg::difference;
use model::implicit::marching_cubes::MarchingCubes;
use model::implicit::Sdf;
use model::primitives::{cuboid, icosphere};
#[test]
fn scratch() {
    let c = cuboid(Vec3::splat(-0.45), Vec3::splat(0.45));
    let cyl = Sdf::Cylinder {
        center: DVec3::ZERO,
        radius: 0.16,
        half_height: 0.8,
    };
    let cm = MarchingCubes::around(&cyl, 16).unwrap().polygonize(&cyl);
    for r in [0.55f32, 0.56, 0.57, 0.59, 0.6, 0.61, 0.62] {
        for sub in [2, 3] {
            let d = difference(&c, &icosphere(Vec3::new(0.013, 0.007, 0.011), r, sub));
            let f = difference(&d, &cm);
            println!(
                "R {r} {sub} {} {}",
                closed_topology(&d).is_ok(),
                closed_topology(&f).is_ok()
            );
        }
    }
}
