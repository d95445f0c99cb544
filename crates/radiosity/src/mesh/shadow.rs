//! Shadow refinement: elements that a shadow boundary crosses are split finer.
//!
//! A constant radiosity per element averages the lit and the shadowed part of an element that
//! the edge of a shadow crosses: the element shines the mean into its neighbours, and the
//! objects casting the shadow see the floor under them too bright (a ball on a table, lit from
//! above, saw the table's lit top where its own shadow lies: `scenes/suite/furnished-room`).
//! The exact cure is to mesh along the boundaries of the umbrae and penumbrae (discontinuity
//! meshing: Heckbert 1992; Lischinski, Tampieri & Greenberg 1992). Within a quadtree the next
//! best, as for contact lines ([`super::contact`]), is to find the crossed elements a priori
//! from the direct light alone and split them [`SHADOW_LEVELS`] levels deeper (light-driven
//! subdivision, Campbell & Fussell 1990).
//!
//! The test: the direct radiosity ρ·E_d at a [`GRID`] × [`GRID`] set of points of an element,
//!
//! ```text
//! E_d(x) = Σ_samples y on the emitters  E(y)/π · cos θ_x cos θ_y / max(r², a_y) · a_y · V(x, y)
//! ```
//!
//! with a_y the area a sample stands for (the point kernel's singularity next to an emitter is
//! no shadow, so r² never goes below it) and V a shadow ray. What a shadow takes away is the
//! same sum over the occluded samples; an element is split when that *blocked* radiosity
//! differs between its points by more than [`JUMP`] of the brightest element's mean direct
//! radiosity. The light's smooth fall-off across an open floor blocks nothing and splits
//! nothing: this is a test for shadows, not a gradient criterion.
//!
//! The cost is elements × [`GRID`]² × samples shadow rays per pass, each possibly crossing the
//! whole scene (a light outside a window is seen, through the window or not, by every surface
//! facing it). So the samples are a stratified estimate of the emitters, never more than
//! [`EMITTER_SAMPLES`], and each pass takes no more than [`RAY_BUDGET`] allows: a square grid
//! on each root face, or, on an emitter cut into more root faces than its share of samples (an
//! imprinted window light), one point per group of root faces of equal area, the groups
//! formed k-d fashion (bands along the emitter, then groups across each band).

use std::sync::atomic::{AtomicU64, Ordering};

use glam::Vec3;
use rayon::prelude::*;

use super::ELEMENT_BATCH;
use super::{Face, Mesh, MAX_LEVEL};
use crate::accel::{Bvh, Ray};
use crate::progress::{Batched, Progress};
use crate::Rgb;

/// Extra quadtree levels for elements that a shadow boundary crosses (each level halves the
/// straddling strip's width, as for contact lines). Measured on `scenes/suite` against Mitsuba
/// 3 (worst object, solve time): the furnished room +1.53 % (18 s) without, +0.40 % (29 s) at
/// 2 levels, +0.42 % (37 s) at 3; the Cornell box with every block face an object +0.87 % (9 s),
/// +0.62 % (15 s), +0.51 % (18 s).
pub const SHADOW_LEVELS: u8 = 2;

/// Side of the grid of points tested on each element.
const GRID: u32 = 3;

/// Most sample points on all emitters together: a square grid on each root face of each
/// emitting polygon, up to 36 per polygon (one per equal-area group of root faces when there
/// are more root faces than that); with more emitting polygons than samples, every k-th
/// polygon stands for k of them.
const EMITTER_SAMPLES: usize = 64;

/// Most shadow rays of each pass (elements × test points × emitter samples): on meshes of
/// hundreds of thousands of root faces, which the hierarchical solver starts from, the emitter
/// samples fall to keep within it (never below [`MIN_EMITTER_SAMPLES`]). The second pass
/// measures up to four times the elements of the first, so it may take fewer. Measured with
/// `cargo xtask bench --suite hierarchical`: the 256 002-triangle sphere field took 28.0 s before
/// shadow refinement and 33.5 s with 64 samples. Bitterli's staircase (1.8 million elements, a
/// window light imprinted into 4362 root faces, each a sample while the samples ignored this
/// bound) meshes in 29 s, where it ran over 1100 s.
const RAY_BUDGET: usize = 40_000_000;

/// The fewest emitter samples the budget leaves.
const MIN_EMITTER_SAMPLES: usize = 4;

/// The smallest jump of blocked direct radiosity across an element that splits it, as a
/// fraction of the brightest element's mean direct radiosity (the hierarchical solver's
/// [`crate::solve::hierarchical::GRADIENT`] is the same kind of bound). At 0.1 the shadow of
/// the furnished room's ball on the table goes unrefined (the ball +1.38 %), and at 0.2 every
/// shadow but the strongest (+1.66 %).
const JUMP: f64 = 0.05;

/// One point on an emitter: where, its front normal, and the exitance times the area it stands
/// for, over π.
struct Sample {
    at: Vec3,
    normal: Vec3,
    area: f32,
    power: Rgb,
}

impl Mesh {
    /// Splits every element whose direct light jumps across it (see the module docs), and its
    /// crossed children, down to [`SHADOW_LEVELS`] below its patch's uniform level (never below
    /// [`MAX_LEVEL`]). Gives up, leaving the mesh valid but unfinished, once `stop` returns
    /// true. Reports the elements measured to `progress`, and tallies the shadow rays cast.
    pub(super) fn refine_shadows(
        &mut self,
        bvh: &Bvh,
        stop: &(dyn Fn() -> bool + Sync),
        progress: &dyn Progress,
    ) {
        let rays = AtomicU64::new(0);
        self.split_shadows(bvh, stop, progress, &rays);
        progress.tally(rays.into_inner(), "shadow rays");
    }

    /// [`Mesh::refine_shadows`], counting the shadow rays into `rays`.
    fn split_shadows(
        &mut self,
        bvh: &Bvh,
        stop: &(dyn Fn() -> bool + Sync),
        progress: &dyn Progress,
        rays: &AtomicU64,
    ) {
        let most = budget_samples(self.elements.len());
        let samples = self.emitter_samples(most);
        if samples.is_empty() {
            return;
        }
        let lift = bvh.lift();
        let measured = Batched::new(progress, ELEMENT_BATCH);
        // A stopped run measures nothing more: no jump, no split.
        let direct = |mesh: &Mesh, samples: &[Sample], n: u32| {
            if stop() {
                Direct::default()
            } else {
                measured.one();
                let direct = mesh.direct_spread(bvh, samples, lift, n);
                rays.fetch_add(direct.rays, Ordering::Relaxed);
                direct
            }
        };
        let first: Vec<Direct> = self
            .elements
            .par_iter()
            .map(|&n| direct(self, &samples, n))
            .collect();
        let brightest = first.iter().map(|d| d.mean).fold(0.0, f64::max);
        if brightest <= 0.0 {
            return;
        }
        let limit = JUMP * brightest;
        // No deeper than SHADOW_LEVELS below the patch's uniform level (its shallowest
        // element): a strip already split along a contact line or a cover's outline stays as
        // it is.
        let uniform = self.uniform_levels();
        let deepest = |mesh: &Mesh, n: u32| {
            (uniform[mesh.nodes[n as usize].patch as usize] + SHADOW_LEVELS).min(MAX_LEVEL)
        };
        let mut split: Vec<u32> = self
            .elements
            .iter()
            .zip(&first)
            .filter(|&(&n, d)| d.jump > limit && self.nodes[n as usize].level < deepest(self, n))
            .map(|(&n, _)| n)
            .collect();
        for done in 1..=SHADOW_LEVELS {
            if split.is_empty() {
                break;
            }
            self.refine(&split);
            if done == SHADOW_LEVELS {
                break;
            }
            let children: Vec<u32> = split
                .iter()
                .flat_map(|&n| {
                    let c = self.nodes[n as usize].children.expect("just split");
                    c..c + 4
                })
                .collect();
            // The same samples as the first pass, unless that would break the ray budget: up
            // to four times its elements may be measured again.
            let samples = self.emitter_samples(most.min(budget_samples(children.len())));
            let jumps: Vec<f64> = children
                .par_iter()
                .map(|&n| direct(self, &samples, n).jump)
                .collect();
            split = children
                .into_iter()
                .zip(jumps)
                .filter(|&(n, jump)| {
                    jump > limit && self.nodes[n as usize].level < deepest(self, n)
                })
                .map(|(n, _)| n)
                .collect();
        }
    }

    /// At most `most` sample points on the fronts of the emitting patches (see
    /// [`EMITTER_SAMPLES`]).
    fn emitter_samples(&self, most: usize) -> Vec<Sample> {
        let emitters: Vec<usize> = (0..self.patches.len())
            .filter(|&p| !self.patches[p].back && self.patches[p].emission.max_element() > 0.0)
            .collect();
        let stride = emitters.len().div_ceil(most).max(1);
        let per_polygon = (most / emitters.len().max(1)).clamp(1, 36);
        let mut out = Vec::new();
        for &p in emitters.iter().step_by(stride) {
            let patch = &self.patches[p];
            let sample = |at: Vec3, area: f64| Sample {
                at,
                normal: patch.normal,
                area: area as f32,
                power: patch.emission * (area * stride as f64 / std::f64::consts::PI),
            };
            let faces: Vec<&Face> = self.roots[p]
                .clone()
                .map(|r| &self.nodes[r as usize].face)
                .collect();
            if faces.len() > per_polygon {
                // More root faces than samples (an emitter cut by imprinted outlines): one
                // sample per group of them.
                for (at, area) in strata(patch.normal, &faces, per_polygon) {
                    out.push(sample(at, area));
                }
                continue;
            }
            let n = ((per_polygon / faces.len()) as f64).sqrt().floor() as u32;
            for face in faces {
                let area = face.area() / f64::from(n * n);
                for j in 0..n {
                    for i in 0..n {
                        let cell = |k: u32| (k as f32 + 0.5) / n as f32;
                        out.push(sample(face.point(cell(i), cell(j)), area));
                    }
                }
            }
        }
        debug_assert!(out.len() <= most);
        out
    }

    /// The direct light over node `n`'s test points (see [`Direct`]).
    fn direct_spread(&self, bvh: &Bvh, samples: &[Sample], lift: f32, n: u32) -> Direct {
        let node = &self.nodes[n as usize];
        let patch = &self.patches[node.patch as usize];
        let normal = patch.normal;
        let rho = patch.reflectance.element_sum() / 3.0;
        let (mut sum, mut lo, mut hi, mut rays) = (0.0, f64::INFINITY, 0.0f64, 0);
        let g = GRID as f32;
        for j in 0..GRID {
            for i in 0..GRID {
                let x = node.face.point((i as f32 + 0.5) / g, (j as f32 + 0.5) / g);
                let (mut open, mut blocked) = (0.0, 0.0);
                for s in samples {
                    let (e, visible) = match irradiance(x, normal, s, lift) {
                        Seen::Unshadowed(e) => (e, true),
                        Seen::Through(e, ray, length) => {
                            rays += 1;
                            (e, !bvh.occluded(&ray, length))
                        }
                    };
                    if visible {
                        open += e;
                    } else {
                        blocked += e;
                    }
                }
                sum += rho * open;
                lo = lo.min(rho * blocked);
                hi = hi.max(rho * blocked);
            }
        }
        Direct {
            mean: sum / f64::from(GRID * GRID),
            jump: hi - lo,
            rays,
        }
    }
}

/// The most emitter samples a pass that measures `elements` elements may take: as many as
/// [`RAY_BUDGET`] allows, between [`MIN_EMITTER_SAMPLES`] and [`EMITTER_SAMPLES`].
#[must_use]
fn budget_samples(elements: usize) -> usize {
    let per_element = elements.max(1) * (GRID * GRID) as usize;
    (RAY_BUDGET / per_element).clamp(MIN_EMITTER_SAMPLES, EMITTER_SAMPLES)
}

/// What [`Mesh::direct_spread`] measures on one element.
#[derive(Clone, Copy, Default)]
struct Direct {
    /// The mean direct radiosity over the test points (one scalar: the channels' mean).
    mean: f64,
    /// The spread of the blocked direct radiosity between the test points.
    jump: f64,
    /// The shadow rays cast.
    rays: u64,
}

/// At most `k` points standing for equal-area groups of `faces`, the root faces of one planar
/// patch of normal `normal`, with each group's area: a k-d stratification. The faces, sorted
/// by centroid along the patch's longer extent, go into ⌊√k⌋ bands of equal area; each band,
/// sorted across, into ⌊k / ⌊√k⌋⌋ groups of equal area. A group's point is the centroid of its
/// median face by area, which lies on the emitter even where the group's own centroid would
/// fall in a hole.
fn strata(normal: Vec3, faces: &[&Face], k: usize) -> Vec<(Vec3, f64)> {
    let centres: Vec<Vec3> = faces.iter().map(|f| f.centroid()).collect();
    let areas: Vec<f64> = faces.iter().map(|f| f.area()).collect();
    let (u, v) = normal.any_orthonormal_pair();
    let extent = |axis: Vec3| {
        let (lo, hi) = centres
            .iter()
            .map(|c| c.dot(axis))
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x), hi.max(x))
            });
        hi - lo
    };
    let (along, across) = if extent(u) >= extent(v) {
        (u, v)
    } else {
        (v, u)
    };
    let sorted = |mut run: Vec<usize>, axis: Vec3| {
        run.sort_by(|&a, &b| centres[a].dot(axis).total_cmp(&centres[b].dot(axis)));
        run
    };
    let bands = ((k as f64).sqrt().floor() as usize).max(1);
    let mut out = Vec::new();
    for band in equal_area(sorted((0..faces.len()).collect(), along), &areas, bands) {
        for group in equal_area(sorted(band, across), &areas, (k / bands).max(1)) {
            let area: f64 = group.iter().map(|&f| areas[f]).sum();
            let mut before = 0.0;
            let median = group
                .iter()
                .find(|&&f| {
                    before += areas[f];
                    before >= 0.5 * area
                })
                .or(group.last())
                .expect("groups are not empty");
            out.push((centres[*median], area));
        }
    }
    out
}

/// `run` cut into at most `m` consecutive groups of about equal area: item i goes to group
/// ⌊m · (A_before + a_i / 2) / A⌋, with A_before the area of the items before it and A the
/// total. Empty groups are dropped.
fn equal_area(run: Vec<usize>, areas: &[f64], m: usize) -> Vec<Vec<usize>> {
    let total: f64 = run.iter().map(|&i| areas[i]).sum();
    let mut groups: Vec<Vec<usize>> = vec![Vec::new(); m];
    let mut before = 0.0;
    for i in run {
        let at = (m as f64 * (before + 0.5 * areas[i]) / total.max(f64::MIN_POSITIVE)) as usize;
        groups[at.min(m - 1)].push(i);
        before += areas[i];
    }
    groups.retain(|g| !g.is_empty());
    groups
}

/// What one shadow ray from a test point to an emitter sample would be.
enum Seen {
    /// No shadow to find: the sample lies behind either surface (irradiance 0), or the point
    /// lies within the sample's own cell.
    Unshadowed(f64),
    /// The unoccluded irradiance, if the ray (and its length) gets through.
    Through(f64, Ray, f32),
}

/// The unoccluded irradiance (channels' mean) at `x` (normal `n`) from one emitter sample, and
/// the shadow ray that decides whether it arrives.
fn irradiance(x: Vec3, n: Vec3, s: &Sample, lift: f32) -> Seen {
    let d = s.at - x;
    let r2 = d.length_squared();
    let cos_x = n.dot(d);
    let cos_y = -s.normal.dot(d);
    if cos_x <= 0.0 || cos_y <= 0.0 || r2 <= 0.0 {
        return Seen::Unshadowed(0.0);
    }
    let kernel = cos_x * cos_y / (r2 * r2.max(s.area));
    let e = f64::from(kernel) * s.power.element_sum() / 3.0;
    if r2 < s.area {
        // Within the sample's own cell: the near field of the emitter, no shadow to find (and
        // ray ends lifted off two surfaces a millimetre apart would cross).
        return Seen::Unshadowed(e);
    }
    let from = x + n * lift;
    let to = s.at + s.normal * lift;
    let span = to - from;
    if span.dot(d) <= 0.0 {
        // The lifts crossed: the ends are too close for a shadow between them.
        return Seen::Unshadowed(e);
    }
    let length = span.length();
    Seen::Through(e, Ray::new(from, span / length), length)
}

#[cfg(test)]
mod tests {
    use std::sync::Mutex;

    use super::*;
    use crate::mesh::Subdivision;
    use crate::progress::Work;
    use crate::scene::{Material, Object, Polygon};
    use crate::Scene;

    /// A 2 × 2 floor facing up, a square lamp of side 0.2 facing down 1 above its centre, and
    /// between them a small square occluder at height 0.5 over the floor's centre (or none).
    fn floor_lamp(occluder: bool) -> Scene {
        let square = |y: f32, half: f32, object: usize, material: usize, up: bool| {
            let v = |x: f32, z: f32| Vec3::new(x * half, y, z * half);
            let ring = vec![v(-1.0, -1.0), v(-1.0, 1.0), v(1.0, 1.0), v(1.0, -1.0)];
            Polygon {
                vertices: if up {
                    ring
                } else {
                    ring.into_iter().rev().collect()
                },
                material,
                object,
                uv: None,
            }
        };
        let mut polygons = vec![square(0.0, 1.0, 0, 0, true), square(1.0, 0.1, 1, 1, false)];
        if occluder {
            polygons.push(square(0.5, 0.1, 2, 0, false));
        }
        lit(["floor", "lamp", "occluder"], polygons)
    }

    /// A scene of `polygons` on three named objects, with a grey material 0 and a lamp's
    /// material 1 (emission 10).
    fn lit(names: [&str; 3], polygons: Vec<Polygon>) -> Scene {
        Scene {
            materials: vec![
                Material::default(),
                Material {
                    emission: Rgb::splat(10.0),
                    ..Material::default()
                },
            ],
            objects: names.map(|name| Object { name: name.into() }).into(),
            polygons,
            ..Scene::default()
        }
    }

    #[test]
    fn a_shadow_edge_is_refined_open_light_is_not() {
        let floor_levels = |scene: &Scene| {
            let mesh = Mesh::build(scene, Subdivision::Elements(64));
            let floor = mesh.patches.iter().position(|p| p.object == 0).unwrap();
            let levels: Vec<u8> = mesh.roots[floor]
                .clone()
                .flat_map(|r| mesh.nodes[r as usize].elements.clone())
                .map(|e| mesh.nodes[mesh.elements[e as usize] as usize].level)
                .collect();
            (
                levels.iter().copied().min().unwrap(),
                levels.iter().copied().max().unwrap(),
            )
        };
        // Without the occluder the light falls off smoothly: nothing to split.
        let (lo, hi) = floor_levels(&floor_lamp(false));
        assert_eq!(lo, hi);
        // The occluder's shadow on the floor: elements along its edge go SHADOW_LEVELS deeper.
        let (lo, hi) = floor_levels(&floor_lamp(true));
        assert_eq!(hi, lo + SHADOW_LEVELS);
    }

    /// Records the elements the shadow pass measures and the shadow rays it tallies.
    #[derive(Default)]
    struct ShadowWork {
        phase: Mutex<String>,
        measured: AtomicU64,
        rays: AtomicU64,
    }

    impl Progress for ShadowWork {
        fn start(&self, _: &str, _: Work) {}
        fn phase(&self, name: &str, _: Work) {
            *self.phase.lock().expect("not poisoned") = name.to_owned();
        }
        fn advance(&self, n: u64) {
            if *self.phase.lock().expect("not poisoned") == "shadows" {
                self.measured.fetch_add(n, Ordering::Relaxed);
            }
        }
        fn tally(&self, count: u64, what: &'static str) {
            if what == "shadow rays" {
                self.rays.fetch_add(count, Ordering::Relaxed);
            }
        }
        fn finish(&self) {}
    }

    /// A 2 × 2 floor facing up; along its edge x = −1 a wall of height 1 facing into the room
    /// with a window (y 0.4–0.8, z −0.3–0.3); outside, a round lamp of radius 0.3 (a
    /// 200-gon, so 198 root faces) 0.6 beyond the wall and 1.2 up, facing down into the room.
    fn window_lamp() -> Scene {
        let polygon = |vertices: Vec<Vec3>, facing: Vec3, object: usize, material: usize| {
            let forward = model::polymesh::vector_area(&vertices).dot(facing) > 0.0;
            Polygon {
                vertices: if forward {
                    vertices
                } else {
                    vertices.into_iter().rev().collect()
                },
                material,
                object,
                uv: None,
            }
        };
        let floor = [(-1.0, -1.0), (-1.0, 1.0), (1.0, 1.0), (1.0, -1.0)]
            .map(|(x, z)| Vec3::new(x, 0.0, z))
            .into();
        let wall = |(y0, y1): (f32, f32), (z0, z1): (f32, f32)| {
            let v = |y, z| Vec3::new(-1.0, y, z);
            polygon(
                vec![v(y0, z0), v(y0, z1), v(y1, z1), v(y1, z0)],
                Vec3::X,
                1,
                0,
            )
        };
        let (centre, normal) = (
            Vec3::new(-1.6, 1.2, 0.0),
            Vec3::new(1.0, -1.0, 0.0).normalize(),
        );
        let (u, v) = normal.any_orthonormal_pair();
        let disc = (0..200)
            .map(|k| {
                let t = k as f32 * std::f32::consts::TAU / 200.0;
                centre + 0.3 * (t.cos() * u + t.sin() * v)
            })
            .collect();
        lit(
            ["floor", "wall", "lamp"],
            vec![
                polygon(floor, Vec3::Y, 0, 0),
                wall((0.0, 0.4), (-1.0, 1.0)),
                wall((0.8, 1.0), (-1.0, 1.0)),
                wall((0.4, 0.8), (-1.0, -0.3)),
                wall((0.4, 0.8), (0.3, 1.0)),
                polygon(disc, normal, 2, 1),
            ],
        )
    }

    #[test]
    fn a_lamp_outside_a_window_casts_a_bounded_number_of_rays_per_element() {
        let scene = window_lamp();
        let work = ShadowWork::default();
        let mesh = Mesh::build_unless(&scene, Subdivision::Elements(400), false, &|| false, &work)
            .expect("not stopped");
        let measured = work.measured.load(Ordering::Relaxed);
        let rays = work.rays.load(Ordering::Relaxed);
        // Every test point of a floor element sees the lamp, through the window or not: each
        // casts a ray to every emitter sample, of which there are at most EMITTER_SAMPLES
        // however many root faces the lamp has (here 198).
        assert!(measured > 0 && rays > 0, "{measured} elements, {rays} rays");
        let most = measured * u64::from(GRID * GRID) * EMITTER_SAMPLES as u64;
        assert!(rays <= most, "{rays} rays for {measured} elements");
        // And the refinement still does its work: the edge of the window's patch of light on
        // the floor, away from the wall's contact line, is split below the floor's level.
        let floor = mesh.patches.iter().position(|p| p.object == 0).unwrap();
        let leaves: Vec<&crate::mesh::Node> = mesh.roots[floor]
            .clone()
            .flat_map(|r| mesh.nodes[r as usize].elements.clone())
            .map(|e| &mesh.nodes[mesh.elements[e as usize] as usize])
            .collect();
        let uniform = leaves.iter().map(|n| n.level).min().unwrap();
        assert!(
            leaves
                .iter()
                .any(|n| n.level > uniform && n.face.centroid().x > -0.8),
            "no shadow edge refined on the floor"
        );
    }
}
