//! The BVH against brute force: every query on random triangle soups (with degenerate and
//! axis-aligned triangles, rays from inside, axis-parallel rays) must give what a loop over all
//! triangles gives.
//!
//! Tolerance: the hierarchy runs the very same ray–triangle arithmetic as
//! `Ray::intersect_triangle`, so hit distances agree exactly; the only freedom is which of
//! several triangles at the same distance is reported (shared edges, duplicates), so the
//! reported triangle must have the brute-force distance to within 1e-6 relative.

use glam::Vec3;
use radiosity::accel::isa::{self, Isa};
use radiosity::accel::{Bvh, Ray};
use radiosity::hash::SplitMix;

/// splitmix64 (Steele et al. 2014), with the draws the tests need.
struct Rng(SplitMix);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0.next_u64()
    }
    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * ((self.next() >> 40) as f32 / (1u64 << 24) as f32)
    }
    fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// A soup of `n` triangles in [-1, 1]³: mostly small and large random ones, plus zero-area
/// ones (points, collinear), axis-aligned ones (flat boxes) and exact duplicates.
fn soup(n: usize, rng: &mut Rng) -> Vec<[Vec3; 3]> {
    let mut tris: Vec<[Vec3; 3]> = Vec::with_capacity(n);
    while tris.len() < n {
        let c = rng.vec(-1.0, 1.0);
        let size = if rng.below(4) == 0 { 1.0 } else { 0.1 };
        let tri = match rng.below(10) {
            0 => [c, c, c],
            1 => [c, c + Vec3::X * size, c + Vec3::X * 2.0 * size],
            2 => {
                // Axis-aligned: lies in the plane z = c.z (or x, y).
                let (u, v) =
                    [(Vec3::X, Vec3::Y), (Vec3::Y, Vec3::Z), (Vec3::Z, Vec3::X)][rng.below(3)];
                [c, c + u * size, c + v * size]
            }
            3 if !tris.is_empty() => tris[rng.below(tris.len())],
            _ => [c, c + rng.vec(-size, size), c + rng.vec(-size, size)],
        };
        tris.push(tri);
    }
    tris
}

/// Rays from inside and outside the soup; a third of them axis-parallel (two zero components),
/// some with one zero component, some through a triangle's vertex plane.
fn rays(count: usize, tris: &[[Vec3; 3]], rng: &mut Rng) -> Vec<Ray> {
    (0..count)
        .map(|i| {
            let mut origin = rng.vec(-1.5, 1.5);
            let dir = match i % 6 {
                0 | 1 => {
                    let axis = [Vec3::X, Vec3::Y, Vec3::Z][rng.below(3)];
                    if rng.below(2) == 0 {
                        axis
                    } else {
                        -axis
                    }
                }
                2 => {
                    let mut d = rng.vec(-1.0, 1.0);
                    d[rng.below(3)] = 0.0;
                    d
                }
                3 if !tris.is_empty() => {
                    // Aim at a random point of a random triangle.
                    let [a, b, c] = tris[rng.below(tris.len())];
                    let (s, t) = (rng.range(0.0, 0.5), rng.range(0.0, 0.5));
                    a + s * (b - a) + t * (c - a) - origin
                }
                4 if !tris.is_empty() => {
                    // Start in the plane of a triangle's vertex, move along that plane's axes.
                    let v = tris[rng.below(tris.len())][0];
                    origin.z = v.z;
                    Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0)
                }
                _ => rng.vec(-1.0, 1.0),
            };
            Ray::new(origin, dir)
        })
        .filter(|r| r.dir != Vec3::ZERO)
        .collect()
}

/// Nearest (t, triangle) by brute force, t in (0, t_max).
fn brute_closest(tris: &[[Vec3; 3]], ray: &Ray, t_max: f32) -> Option<(f32, u32)> {
    let mut best = None;
    let mut best_t = t_max;
    for (i, tri) in tris.iter().enumerate() {
        if let Some((t, _, _)) = ray.intersect_triangle(tri, best_t) {
            best_t = t;
            best = Some((t, i as u32));
        }
    }
    best
}

fn brute_occluded(tris: &[[Vec3; 3]], ray: &Ray, t_max: f32) -> bool {
    tris.iter()
        .any(|t| ray.intersect_triangle(t, t_max).is_some())
}

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 1e-6 * a.abs().max(b.abs()).max(1.0)
}

/// Checks every query of `bvh` over `rays` against brute force; returns how many hit.
fn check(tris: &[[Vec3; 3]], bvh: &Bvh, rays: &[Ray], rng: &mut Rng) -> usize {
    let mut hits = 0;
    for ray in rays {
        let expected = brute_closest(tris, ray, f32::INFINITY);
        let got = bvh.closest_hit(ray, f32::INFINITY);
        match (expected, got) {
            (None, None) => {}
            (Some((t, i)), Some(hit)) => {
                hits += 1;
                assert!(close(hit.t, t), "t {} vs brute force {t} on {ray:?}", hit.t);
                if hit.triangle != i {
                    // A tie: the reported triangle must be hit at the same distance.
                    let other = ray.intersect_triangle(&tris[hit.triangle as usize], f32::INFINITY);
                    assert!(other.is_some_and(|(t2, _, _)| close(t2, t)), "{ray:?}");
                }
                // The barycentrics give back the hit point; their rounding error grows like
                // 1/|cos| of the incidence angle, hence a loose 2e-4 of the problem's scale
                // (a wrong vertex order would be off by the triangle's size, ~0.1).
                let [a, b, c] = tris[hit.triangle as usize];
                let p = (1.0 - hit.u - hit.v) * a + hit.u * b + hit.v * c;
                let scale = 1.0 + ray.origin.length() + hit.t * ray.dir.length();
                assert!(
                    (p - ray.at(hit.t)).length() < 2e-4 * scale,
                    "{ray:?} {hit:?}"
                );
            }
            _ => panic!("brute force {expected:?}, bvh {got:?} on {ray:?}"),
        }
        // Occlusion for a few segment lengths, including just before and after the nearest hit.
        let mut limits = vec![f32::INFINITY, rng.range(0.0, 3.0)];
        if let Some((t, _)) = expected {
            limits.extend([t * 0.999, t * 1.001]);
        }
        for t_max in limits {
            assert_eq!(
                bvh.occluded(ray, t_max),
                brute_occluded(tris, ray, t_max),
                "occluded({ray:?}, {t_max})"
            );
            // And a clipped closest-hit.
            let clipped = bvh.closest_hit(ray, t_max).map(|h| h.t);
            let brute = brute_closest(tris, ray, t_max).map(|h| h.0);
            assert_eq!(clipped.is_some(), brute.is_some(), "{ray:?} {t_max}");
        }
    }
    // The interleaved queries give exactly what the one-ray queries give, ray by ray, on
    // segments and on rays that run past the scene (whose occlusion walks largest box first).
    let t_max: Vec<f32> = (0..rays.len())
        .map(|k| {
            if k % 3 == 0 {
                f32::INFINITY
            } else {
                rng.range(0.0, 3.0)
            }
        })
        .collect();
    interleaved_matches_one_ray(bvh, rays, &t_max);
    // So do the packet queries, on these incoherent rays and on coherent ones (a camera's fan
    // from one point, and segments from many points to one).
    coherent_matches_one_ray(tris, bvh, rays, &t_max);
    let eye = rng.vec(-1.5, 1.5);
    let target = rng.vec(-0.5, 0.5);
    let fan: Vec<Ray> = (0..203)
        .map(|i| {
            let (x, y) = ((i % 16) as f32 / 8.0 - 1.0, (i / 16) as f32 / 6.0 - 1.0);
            Ray::new(eye, target - eye + Vec3::new(x, y, 0.3 * x * y))
        })
        .collect();
    let fan_t: Vec<f32> = (0..fan.len())
        .map(|i| [f32::INFINITY, 1.0, 0.5][i % 3])
        .collect();
    coherent_matches_one_ray(tris, bvh, &fan, &fan_t);
    let light = rng.vec(-1.0, 1.0);
    let to_light: Vec<Ray> = (0..203)
        .map(|i| {
            let o = eye + Vec3::new((i % 16) as f32 * 0.05, (i / 16) as f32 * 0.05, 0.0);
            Ray::new(o, light - o)
        })
        .collect();
    coherent_matches_one_ray(tris, bvh, &to_light, &vec![1.0; to_light.len()]);
    hits
}

/// The interleaved queries ([`Bvh::closest_hits`], [`Bvh::occluded_many`]) against the
/// one-ray ones, ray by ray: exactly the same answers. Returns the occlusion answers.
fn interleaved_matches_one_ray(bvh: &Bvh, rays: &[Ray], t_max: &[f32]) -> Vec<bool> {
    let mut closest = vec![None; rays.len()];
    bvh.closest_hits(rays, t_max, &mut closest);
    let mut occluded = vec![false; rays.len()];
    bvh.occluded_many(rays, t_max, &mut occluded);
    for (k, ray) in rays.iter().enumerate() {
        assert_eq!(closest[k], bvh.closest_hit(ray, t_max[k]), "{ray:?}");
        assert_eq!(occluded[k], bvh.occluded(ray, t_max[k]), "{ray:?}");
    }
    occluded
}

/// The packet queries ([`Bvh::closest_hits_coherent`], [`Bvh::occluded_coherent`]) against the
/// one-ray ones: the same occlusion answers and closest distances, bit for bit, and the same
/// triangle except at a tie in distance.
fn coherent_matches_one_ray(tris: &[[Vec3; 3]], bvh: &Bvh, rays: &[Ray], t_max: &[f32]) {
    let mut closest = vec![None; rays.len()];
    bvh.closest_hits_coherent(rays, t_max, &mut closest);
    let mut occluded = vec![false; rays.len()];
    bvh.occluded_coherent(rays, t_max, &mut occluded);
    for (k, ray) in rays.iter().enumerate() {
        assert_eq!(
            occluded[k],
            bvh.occluded(ray, t_max[k]),
            "{ray:?} {}",
            t_max[k]
        );
        let one = bvh.closest_hit(ray, t_max[k]);
        assert_eq!(
            closest[k].map(|h| h.t.to_bits()),
            one.map(|h| h.t.to_bits()),
            "{ray:?} {}",
            t_max[k]
        );
        if let (Some(a), Some(b)) = (closest[k], one) {
            if a.triangle == b.triangle {
                assert_eq!(a, b);
            } else {
                let t2 = ray.intersect_triangle(&tris[a.triangle as usize], f32::INFINITY);
                assert!(t2.is_some_and(|(t2, _, _)| close(t2, b.t)), "{ray:?}");
            }
        }
    }
}

/// The queries compiled for each instruction set ([`radiosity::accel::isa`]) return the same
/// bits: the same IEEE operations run in the same order.
fn same_bits_on_every_isa(bvh: &Bvh, rays: &[Ray]) {
    let trace = |isa| {
        // Other tests may switch the global choice meanwhile; they get the same bits either way.
        isa::set(isa);
        let closest: Vec<_> = rays.iter().map(|r| bvh.closest_hit(r, 2.5)).collect();
        let occluded: Vec<_> = rays.iter().map(|r| bvh.occluded(r, 2.5)).collect();
        let mut batched = vec![None; rays.len()];
        bvh.closest_hits(rays, &vec![2.5; rays.len()], &mut batched);
        let mut packets = vec![None; rays.len()];
        bvh.closest_hits_coherent(rays, &vec![2.5; rays.len()], &mut packets);
        let mut packets_occluded = vec![false; rays.len()];
        bvh.occluded_coherent(rays, &vec![2.5; rays.len()], &mut packets_occluded);
        (closest, occluded, batched, packets, packets_occluded)
    };
    let baseline = trace(Isa::Baseline);
    let best = trace(isa::detected());
    assert!(baseline == best);
}

#[test]
fn agrees_with_brute_force_on_random_soups() {
    for seed in 1..=4u64 {
        for n in [0, 1, 2, 3, 7, 8, 9, 17, 64, 500, 3000] {
            let mut rng = Rng(SplitMix(seed * 1000 + n as u64));
            let tris = soup(n, &mut rng);
            let bvh = Bvh::build(&tris);
            assert_eq!(bvh.validate(), Ok(()), "seed {seed} n {n}");
            assert_eq!(bvh.triangle_count(), n);
            let rays = rays(300, &tris, &mut rng);
            let hits = check(&tris, &bvh, &rays, &mut rng);
            same_bits_on_every_isa(&bvh, &rays);
            // The test must exercise hits, not only misses.
            if n >= 64 {
                assert!(hits > 30, "seed {seed} n {n}: only {hits} hits");
            }
        }
    }
}

#[test]
fn interleaved_queries_agree_on_a_hierarchy_larger_than_the_cache() {
    // 40 000 triangles, about 2 MB of hierarchy: the interleaved queries prefetch and visit
    // leaves as steps of their own there (`Walk::step`'s `DEFER`), unlike on the small soups.
    let mut rng = Rng(SplitMix(77));
    let tris = soup(40_000, &mut rng);
    let bvh = Bvh::build(&tris);
    assert!(bvh.memory_bytes() > 1 << 20);
    let rays = rays(2000, &tris, &mut rng);
    let t_max: Vec<f32> = (0..rays.len())
        .map(|k| {
            if k % 2 == 0 {
                f32::INFINITY
            } else {
                rng.range(0.0, 0.5)
            }
        })
        .collect();
    let occluded = interleaved_matches_one_ray(&bvh, &rays, &t_max);
    let mut blocked = 0;
    for (k, ray) in rays.iter().enumerate() {
        if k < 200 {
            assert_eq!(occluded[k], brute_occluded(&tris, ray, t_max[k]), "{ray:?}");
        }
        blocked += usize::from(occluded[k]);
    }
    // Both answers occur.
    assert!(blocked > 100 && blocked < rays.len() - 100, "{blocked}");
}

#[test]
fn parallel_build_is_correct_and_independent_of_thread_count() {
    // Large enough for the builder's parallel top levels.
    let mut rng = Rng(SplitMix(99));
    let tris = soup(70_000, &mut rng);
    let build_in = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| Bvh::build(&tris))
    };
    let one = build_in(1);
    let two = build_in(2);
    assert_eq!(format!("{one:?}"), format!("{two:?}"));
    assert_eq!(two.validate(), Ok(()));
    let rays = rays(150, &tris, &mut rng);
    assert!(check(&tris, &two, &rays, &mut rng) > 50);
}

#[test]
fn empty_and_all_degenerate_inputs() {
    let empty = Bvh::build(&[]);
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    assert_eq!(empty.validate(), Ok(()));
    assert_eq!(empty.triangle_count(), 0);
    assert!(empty.closest_hit(&ray, f32::INFINITY).is_none());
    assert!(!empty.occluded(&ray, f32::INFINITY));

    // A thousand copies of one point and of one segment: nothing to hit, nothing breaks.
    let p = Vec3::new(0.5, 0.0, 0.0);
    let mut tris = vec![[p, p, p]; 1000];
    tris.extend(vec![[Vec3::ZERO, Vec3::X, 2.0 * Vec3::X]; 1000]);
    let bvh = Bvh::build(&tris);
    assert_eq!(bvh.validate(), Ok(()));
    assert!(bvh.closest_hit(&ray, f32::INFINITY).is_none());
    assert!(!bvh.occluded(&Ray::new(Vec3::new(0.5, 1.0, 0.0), -Vec3::Y), 5.0));
}

#[test]
fn many_identical_triangles_report_one_of_them() {
    let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let tris = vec![tri; 100];
    let bvh = Bvh::build(&tris);
    assert_eq!(bvh.validate(), Ok(()));
    let hit = bvh
        .closest_hit(&Ray::new(Vec3::new(0.1, 0.1, 1.0), -Vec3::Z), 2.0)
        .unwrap();
    assert_eq!(hit.t, 1.0);
    assert!(hit.triangle < 100);
}

#[test]
fn axis_parallel_rays_in_a_closed_box() {
    // A closed unit cube of 12 triangles; axis-parallel rays from its centre hit the wall at
    // distance 0.5 exactly, rays along a face plane (zero components, origin on the box of the
    // face) still find the opposite wall.
    let mut tris = Vec::new();
    let c = |i: u32| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32);
    for quad in [
        [0, 4, 6, 2],
        [1, 3, 7, 5],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 2, 3, 1],
        [4, 5, 7, 6],
    ] {
        tris.push([c(quad[0]), c(quad[1]), c(quad[2])]);
        tris.push([c(quad[0]), c(quad[2]), c(quad[3])]);
    }
    let bvh = Bvh::build(&tris);
    assert_eq!(bvh.validate(), Ok(()));
    let centre = Vec3::splat(0.5);
    for dir in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z] {
        let hit = bvh
            .closest_hit(&Ray::new(centre, dir), f32::INFINITY)
            .unwrap();
        assert_eq!(hit.t, 0.5);
        assert!(bvh.occluded(&Ray::new(centre, dir), 0.6));
        assert!(!bvh.occluded(&Ray::new(centre, dir), 0.5));
    }
    // On the plane z = 0.25 inside the cube, along +x: hits x = 1 at t = 0.7.
    let hit = bvh
        .closest_hit(&Ray::new(Vec3::new(0.3, 0.6, 0.25), Vec3::X), f32::INFINITY)
        .unwrap();
    assert!((hit.t - 0.7).abs() < 1e-6);
}
