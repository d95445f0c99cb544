//! Every spatial structure's `validate()` holds on random input (proptest), and queries agree
//! with brute force.

use std::f64::consts::PI;

use glam::DVec3;
use model::implicit::Sdf;
use model::spatial::bsp::{BspTree, Polygon};
use model::spatial::orthtree::{Octree, Quadtree};
use model::spatial::voxel::VoxelGrid;
use proptest::prelude::*;

fn point3() -> impl Strategy<Value = [f64; 3]> {
    [-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn octree_is_valid_and_queries_match_brute_force(
        points in prop::collection::vec(point3(), 0..300),
        capacity in 1usize..8,
        lo in point3(),
        size in 0.0..1.5f64,
    ) {
        let mut t = Octree::new([-1.0; 3], [1.0; 3], capacity, 6);
        for p in &points {
            prop_assert!(t.insert(*p).is_some());
        }
        prop_assert!(t.insert([2.0, 0.0, 0.0]).is_none());
        prop_assert!(t.insert([f64::NAN, 0.0, 0.0]).is_none());
        prop_assert_eq!(t.len(), points.len());
        t.validate().map_err(TestCaseError::fail)?;
        let hi = lo.map(|x| x + size);
        let brute: Vec<usize> = (0..points.len())
            .filter(|&i| (0..3).all(|a| points[i][a] >= lo[a] && points[i][a] <= hi[a]))
            .collect();
        prop_assert_eq!(t.query_box(lo, hi), brute);
    }

    #[test]
    fn quadtree_with_duplicates_is_valid(
        points in prop::collection::vec([-1.0..1.0f64, -1.0..1.0f64], 1..200),
        copies in 1usize..6,
    ) {
        // Repeated points cannot be separated: leaves stop splitting at the maximum depth.
        let mut t = Quadtree::new([-1.0; 2], [1.0; 2], 2, 5);
        for p in &points {
            for _ in 0..copies {
                t.insert(*p);
            }
        }
        t.validate().map_err(TestCaseError::fail)?;
        prop_assert_eq!(t.query_box([-1.0; 2], [1.0; 2]).len(), points.len() * copies);
    }

    #[test]
    fn bsp_of_random_triangles_is_valid(
        tris in prop::collection::vec((point3(), point3(), point3()), 1..40),
        probe in prop::collection::vec((point3(), point3(), point3()), 1..10),
    ) {
        let polys: Vec<Polygon> = tris
            .iter()
            .filter_map(|(a, b, c)| Polygon::new(vec![
                DVec3::from_array(*a), DVec3::from_array(*b), DVec3::from_array(*c),
            ]))
            .collect();
        let mut t = BspTree::new(polys.clone());
        t.validate().map_err(TestCaseError::fail)?;
        // Splitting keeps the total area of the input.
        let area = |ps: &[Polygon]| -> f64 {
            ps.iter().map(|p| {
                (1..p.vertices.len() - 1)
                    .map(|k| (p.vertices[k] - p.vertices[0])
                        .cross(p.vertices[k + 1] - p.vertices[0]).length() * 0.5)
                    .sum::<f64>()
            }).sum()
        };
        let (a0, a1) = (area(&polys), area(&t.all_polygons()));
        prop_assert!((a0 - a1).abs() <= 1e-6 * (1.0 + a0), "{} vs {}", a0, a1);
        // Inverting twice, adding polygons and clipping keep the invariants.
        t.invert();
        t.validate().map_err(TestCaseError::fail)?;
        t.invert();
        let extra: Vec<Polygon> = probe
            .iter()
            .filter_map(|(a, b, c)| Polygon::new(vec![
                DVec3::from_array(*a), DVec3::from_array(*b), DVec3::from_array(*c),
            ]))
            .collect();
        t.build(extra.clone());
        t.validate().map_err(TestCaseError::fail)?;
        let other = BspTree::new(extra);
        t.clip_to(&other);
        t.validate().map_err(TestCaseError::fail)?;
    }

    #[test]
    fn voxel_grid_is_valid(r in 0.1..0.9f64, res in 1u32..24) {
        let s = Sdf::Sphere { center: DVec3::ZERO, radius: r };
        let g = VoxelGrid::from_sdf(&s, DVec3::splat(-1.0), DVec3::splat(1.0), res).unwrap();
        g.validate().map_err(TestCaseError::fail)?;
        prop_assert_eq!(g.dims(), [res as usize; 3]);
        prop_assert!(g.volume() <= 8.0);
    }
}

#[test]
fn voxel_volume_converges_to_the_ball() {
    let s = Sdf::Sphere {
        center: DVec3::new(0.01, 0.02, 0.03),
        radius: 0.8,
    };
    let exact = 4.0 / 3.0 * PI * 0.512;
    // Error ~ area × h / (some constant): about 1 % at h = 2/100.
    let g = VoxelGrid::from_sdf(&s, DVec3::splat(-1.0), DVec3::splat(1.0), 100).unwrap();
    assert!((g.volume() - exact).abs() / exact < 0.01, "{}", g.volume());
    assert!(g.get(50, 50, 50) && !g.get(0, 0, 0) && !g.get(100, 0, 0));
    assert!(VoxelGrid::from_sdf(&s, DVec3::ZERO, DVec3::ZERO, 10).is_none());
}
