//! The element budget: how finely each patch is subdivided uniformly.
//!
//! A request (`--elements N` or `--max-element-area A`) becomes one target element area, and
//! every root face is split into 4^k equal elements, k the fewest levels that bring it to the
//! target ([`level_for`]). For a count, the target is found by bisection over the root faces'
//! areas ([`target_for`]).

use super::face::Face;
use super::patch::Patch;
use super::{Subdivision, MAX_LEVEL};

/// Levels of uniform subdivision that bring a face of area `area` to at most `target`.
pub(super) fn level_for(area: f64, target: f64) -> u8 {
    if target.is_nan() || target <= 0.0 || area <= target {
        return 0;
    }
    let levels = ((area / target).ln() / 4f64.ln()).ceil();
    levels.min(f64::from(MAX_LEVEL)) as u8
}

/// How much coarser than the target the elements of an emitter that reflects nothing may be.
///
/// Its radiosity is its emission, exactly, however it is split: it is subdivided only for its
/// part as a source of light (16× the target area: two quadtree levels coarser), and its area
/// is left out of the element budget. Without this the default sky
/// ([`crate::scene::sky`]), fifteen times the area of the chair it lights, took 94 % of the
/// elements.
pub const DARK_EMITTER_COARSENING: f64 = 16.0;

/// Whether a patch is an emitter that reflects nothing (see [`DARK_EMITTER_COARSENING`]).
fn dark_emitter(patch: &Patch) -> bool {
    patch.reflectance.max_element() <= 0.0 && patch.emission.max_element() > 0.0
}

/// The target element area of each patch for `subdivision`: one target for all patches, found
/// over the patches that share the element budget (all but the dark emitters, or all of them
/// when there is nothing else), and [`DARK_EMITTER_COARSENING`] times it for the dark emitters.
pub(super) fn patch_targets(patches: &[(Patch, Vec<Face>)], subdivision: Subdivision) -> Vec<f64> {
    let coarsen = patches.iter().any(|(p, _)| !dark_emitter(p));
    let budgeted: Vec<f64> = patches
        .iter()
        .filter(|(p, _)| !(coarsen && dark_emitter(p)))
        .flat_map(|(_, roots)| roots.iter().map(Face::area))
        .collect();
    let target = target_for(&budgeted, subdivision);
    patches
        .iter()
        .map(|(p, _)| {
            if coarsen && dark_emitter(p) {
                target * DARK_EMITTER_COARSENING
            } else {
                target
            }
        })
        .collect()
}

/// The target element area that `subdivision` asks for.
///
/// For a count n it is the area that brings the total closest to n, but never more than four
/// times the fair share (total area) / n: a scene of many small root faces (a scanned mesh of 7 000
/// triangles in a room) would otherwise spend the whole budget on them and leave each wall one
/// element, whose 2 × 2 quadrature points then miss the light's peak (the floor under such a
/// mesh came out 30 % too bright). The count then exceeds n by about the number of small roots.
/// (Four times, not once: a face just above the share would otherwise be split one level more
/// than the bisection chose, and the Cornell box would get 7 000 elements for 4 096.)
fn target_for(root_areas: &[f64], subdivision: Subdivision) -> f64 {
    match subdivision {
        Subdivision::MaxArea(a) => a,
        Subdivision::Elements(n) => {
            let share = root_areas.iter().sum::<f64>() / n.max(1) as f64;
            target_area(root_areas, n).min(4.0 * share)
        }
    }
}

/// Elements made by subdividing every root face down to `target` area.
pub(super) fn element_count(root_areas: &[f64], target: f64) -> f64 {
    root_areas
        .iter()
        .map(|&a| 4f64.powi(i32::from(level_for(a, target))))
        .sum()
}

/// The target element area that brings the total number of elements closest to `n`.
fn target_area(root_areas: &[f64], n: usize) -> f64 {
    let count = |t: f64| element_count(root_areas, t);
    let total: f64 = root_areas.iter().sum();
    let goal = n.max(1) as f64;
    // The count falls as the target grows; bisect on a log scale.
    let (mut lo, mut hi) = (total / goal / 1e4, total.max(f64::MIN_POSITIVE));
    for _ in 0..64 {
        let mid = (lo * hi).sqrt();
        if count(mid) > goal {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    // Take whichever side of the jump is closer to the request.
    if (count(lo) - goal).abs() < (count(hi) - goal).abs() {
        lo
    } else {
        hi
    }
}
