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
/// emitting polygon, up to 36 per polygon; with more emitting polygons than that, every k-th
/// polygon's centre stands for k of them.
const EMITTER_SAMPLES: usize = 64;

/// Most shadow rays of the first pass (elements × test points × emitter samples): on meshes of
/// hundreds of thousands of root faces, which the hierarchical solver starts from, the emitter
/// samples fall to keep within it (never below [`MIN_EMITTER_SAMPLES`]). Measured with
/// `radiosity bench --suite hierarchical`: the 256 002-triangle sphere field took 28.0 s before
/// shadow refinement and 33.5 s with 64 samples.
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
    /// true. Reports the elements measured to `progress`.
    pub(super) fn refine_shadows(
        &mut self,
        bvh: &Bvh,
        stop: &(dyn Fn() -> bool + Sync),
        progress: &dyn Progress,
    ) {
        let per_element = self.elements.len().max(1) * (GRID * GRID) as usize;
        let most = (RAY_BUDGET / per_element).clamp(MIN_EMITTER_SAMPLES, EMITTER_SAMPLES);
        let samples = self.emitter_samples(most);
        if samples.is_empty() {
            return;
        }
        let lift = bvh.lift();
        let measured = Batched::new(progress, ELEMENT_BATCH);
        // A stopped run measures nothing more: no jump, no split.
        let direct = |mesh: &Mesh, n: u32| {
            if stop() {
                (0.0, 0.0)
            } else {
                measured.one();
                mesh.direct_spread(bvh, &samples, lift, n)
            }
        };
        let first: Vec<(f64, f64)> = self.elements.par_iter().map(|&n| direct(self, n)).collect();
        let brightest = first.iter().map(|&(mean, _)| mean).fold(0.0, f64::max);
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
            .filter(|&(&n, &(_, jump))| {
                jump > limit && self.nodes[n as usize].level < deepest(self, n)
            })
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
            let jumps: Vec<f64> = children.par_iter().map(|&n| direct(self, n).1).collect();
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
            let roots = self.roots[p].clone();
            let n = ((per_polygon / roots.len()).max(1) as f64).sqrt().floor() as u32;
            for r in roots {
                let face: &Face = &self.nodes[r as usize].face;
                let area = face.area() / f64::from(n * n);
                for j in 0..n {
                    for i in 0..n {
                        let cell = |k: u32| (k as f32 + 0.5) / n as f32;
                        out.push(Sample {
                            at: face.point(cell(i), cell(j)),
                            normal: patch.normal,
                            area: area as f32,
                            power: patch.emission * (area * stride as f64 / std::f64::consts::PI),
                        });
                    }
                }
            }
        }
        out
    }

    /// The mean direct radiosity over node `n`'s test points (one scalar: the channels' mean),
    /// and the spread of the blocked direct radiosity between them.
    fn direct_spread(&self, bvh: &Bvh, samples: &[Sample], lift: f32, n: u32) -> (f64, f64) {
        let node = &self.nodes[n as usize];
        let patch = &self.patches[node.patch as usize];
        let normal = patch.normal;
        let rho = patch.reflectance.element_sum() / 3.0;
        let (mut sum, mut lo, mut hi) = (0.0, f64::INFINITY, 0.0f64);
        let g = GRID as f32;
        for j in 0..GRID {
            for i in 0..GRID {
                let x = node.face.point((i as f32 + 0.5) / g, (j as f32 + 0.5) / g);
                let (mut open, mut blocked) = (0.0, 0.0);
                for s in samples {
                    let (e, visible) = irradiance(bvh, x, normal, s, lift);
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
        (sum / f64::from(GRID * GRID), hi - lo)
    }
}

/// The unoccluded irradiance (channels' mean) at `x` (normal `n`) from one emitter sample, and
/// whether its shadow ray gets through.
fn irradiance(bvh: &Bvh, x: Vec3, n: Vec3, s: &Sample, lift: f32) -> (f64, bool) {
    let d = s.at - x;
    let r2 = d.length_squared();
    let cos_x = n.dot(d);
    let cos_y = -s.normal.dot(d);
    if cos_x <= 0.0 || cos_y <= 0.0 || r2 <= 0.0 {
        return (0.0, true);
    }
    let kernel = cos_x * cos_y / (r2 * r2.max(s.area));
    if r2 < s.area {
        // Within the sample's own cell: the near field of the emitter, no shadow to find (and
        // ray ends lifted off two surfaces a millimetre apart would cross).
        return (f64::from(kernel) * s.power.element_sum() / 3.0, true);
    }
    let from = x + n * lift;
    let to = s.at + s.normal * lift;
    let span = to - from;
    let length = span.length();
    let visible = span.dot(d) <= 0.0 || !bvh.occluded(&Ray::new(from, span / length), length);
    (f64::from(kernel) * s.power.element_sum() / 3.0, visible)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Subdivision;
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
            }
        };
        let mut polygons = vec![square(0.0, 1.0, 0, 0, true), square(1.0, 0.1, 1, 1, false)];
        if occluder {
            polygons.push(square(0.5, 0.1, 2, 0, false));
        }
        Scene {
            materials: vec![
                Material::default(),
                Material {
                    emission: Rgb::splat(10.0),
                    ..Material::default()
                },
            ],
            objects: ["floor", "lamp", "occluder"]
                .map(|name| Object { name: name.into() })
                .into(),
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
}
