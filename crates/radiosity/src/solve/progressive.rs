//! Progressive refinement (Cohen, Chen, Wallace & Greenberg 1988, "A progressive refinement
//! approach to fast radiosity image generation"): instead of gathering, *shoot*.
//!
//! Every source s keeps an unshot radiosity ΔB_s, initially its (mean) emission. Each step
//! picks the source with the largest unshot power A_s ‖ΔB_s‖₁, computes one column of form
//! factors F_{e→s} on the fly, and gives every element
//!
//! ```text
//! ΔB_e = ρ_e F_es ΔB_s ,   B_e += ΔB_e ,   ΔB_{s(e)} += A_e ΔB_e / A_{s(e)} ,
//! ```
//!
//! (the paper's F_se A_s / A_e is F_es by reciprocity), then sets ΔB_s = 0. Memory is O(n): no
//! matrix is stored. It stops when the unshot power falls below the tolerance times the emitted
//! power, or after the iteration limit (one iteration = one shot).
//!
//! For display before convergence, the paper's *ambient term* spreads the unshot power evenly
//! and lets it interreflect with the mean reflectance ρ̄ = Σ A ρ / Σ A:
//!
//! ```text
//! ambient = Σ_s A_s ΔB_s / Σ_s A_s · 1 / (1 − ρ̄)     (per channel),
//! ```
//!
//! and an element is shown as B_e + ρ_e · ambient. [`super::Solution::radiosity`] holds B
//! without it; the ambient goes to [`super::Solution::ambient`].
//!
//! **Near sources are opened** as the gathering solvers open them ([`super::opened_sources`]):
//! a receiver next to a coarse source sees its parts with very different kernels, and the
//! source's mean unshot radiosity misstates what reaches it (a source straddling the footprint
//! of a block standing on a floor shone its lit part's light into the block: a bare OBJ block,
//! every face two-sided, came out 1.4 % too bright, its inside three times brighter than with
//! Gauss-Seidel). So every element keeps its own unshot radiosity ΔB_e (the source's is their
//! area-weighted mean), each receiver's opened pieces of each source are found once, with their
//! factors, before the first shot, and a shot gives a receiver that opens the source
//! Σ_p F_ep ΔB̄_p over its pieces instead of F_es ΔB_s.
//!
//! The column and the opened pieces are computed in parallel (each value depends on its pair
//! only); the updates are applied in element order, then in the order of the receivers that open
//! the source, and the largest source is the first of equals, so the result is the same at any
//! thread count.

use std::ops::Range;
use std::time::Instant;

use rayon::prelude::*;

use super::checkpoint::{Iterate, Session, Shape};
use super::opened_sources::{self, Piece, Scratch};
use super::solver::{Job, Solver};
use super::{l1, Settings, Solution, SolveError, System};
use crate::formfactor::{FormFactors, Geometry};
use crate::progress::{Progress, Work};
use crate::Rgb;

/// What a progressive solve returns.
pub(super) struct Shots {
    pub radiosity: Vec<Rgb>,
    /// Σ over the shots of F_es ΔB_s: the light each element received.
    pub irradiance: Vec<Rgb>,
    pub iterations: usize,
    pub residual: f64,
    pub links: u64,
    pub ambient: Rgb,
    pub form_factor_seconds: f64,
    /// A sample after each shot (the residual: the unshot fraction).
    pub history: Vec<super::Sample>,
    /// Whether the session was stopped before convergence.
    pub interrupted: bool,
}

/// Progressive refinement as a [`Solver`].
pub(super) struct Progressive;

impl Solver for Progressive {
    fn solve(&self, job: Job, solution: &mut Solution) -> Result<(), SolveError> {
        let mut session = job.session()?;
        let Job {
            g,
            ff,
            settings,
            progress,
            system,
            ..
        } = job;
        let start = Instant::now();
        progress.start("solve", Work::open_ended("iterations"));
        let run = run(&system, g, ff, settings, &mut session, progress);
        progress.tally(run.iterations as u64, "iterations");
        progress.tally(run.links, "links");
        progress.end(run.interrupted);
        solution.radiosity = run.radiosity;
        solution.irradiance = run.irradiance;
        solution.iterations = run.iterations;
        solution.residual = run.residual;
        solution.history = run.history;
        solution.links = run.links;
        solution.ambient = run.ambient;
        solution.interrupted = run.interrupted;
        solution.form_factor_seconds = run.form_factor_seconds;
        solution.solve_seconds = start.elapsed().as_secs_f64() - run.form_factor_seconds;
        Ok(())
    }

    /// B, the irradiance received and the unshot radiosity of every element.
    fn checkpoint_shape(&self, elements: usize) -> Shape {
        Shape {
            radiosity: elements,
            irradiance: elements,
            unshot: elements,
            hierarchy: false,
        }
    }
}

/// Shoots until the unshot power is below the tolerance, the iteration limit is reached or the
/// session is stopped (from B = E, or from the session's checkpoint).
pub(super) fn run(
    system: &System,
    g: &Geometry,
    ff: &dyn FormFactors,
    settings: &Settings,
    session: &mut Session,
    progress: &dyn Progress,
) -> Shots {
    let n = system.area.len();
    // Unshot radiosity per element; the sources' are their open-area means.
    let (mut b, mut h, mut unshot, mut iterations, mut links) = match session.resume() {
        Some(it) => (
            it.radiosity,
            it.irradiance,
            it.unshot,
            it.iterations,
            it.links,
        ),
        None => {
            let h = system.first_shot.clone();
            let e = system.emission.clone();
            (e.clone(), h, e, 0, 0u64)
        }
    };
    let mut source_unshot: Vec<Rgb> = system
        .source_elements
        .iter()
        .zip(&system.source_area)
        .map(|(r, &a)| {
            let power: Rgb = r.clone().map(|e| unshot[e] * system.area[e]).sum();
            if a > 0.0 {
                power / a
            } else {
                Rgb::ZERO
            }
        })
        .collect();
    let start = Instant::now();
    let near = Near::find(g, ff, n);
    let mut ff_seconds = start.elapsed().as_secs_f64();
    let mut column = vec![0.0f32; n];
    let mut opens = vec![false; n];
    let unshot_power = |unshot: &[Rgb]| -> f64 {
        unshot
            .iter()
            .zip(&system.source_area)
            .map(|(u, a)| a * l1(*u))
            .sum()
    };
    let mut residual = unshot_power(&source_unshot) / system.emitted;
    let (started, mut history, mut interrupted) = (Instant::now(), Vec::new(), false);
    let state = |b: &[Rgb], h: &[Rgb], unshot: &[Rgb], iterations, residual, links| Iterate {
        iterations,
        residual,
        links,
        radiosity: b.to_vec(),
        irradiance: h.to_vec(),
        unshot: unshot.to_vec(),
        hierarchy: None,
    };
    while iterations < settings.max_iterations && residual >= settings.tolerance {
        if session.stopped() {
            interrupted = true;
            break;
        }
        // The source with the most unshot power (the first of equals).
        let mut s = 0;
        let mut best = -1.0;
        for (k, (u, a)) in source_unshot.iter().zip(&system.source_area).enumerate() {
            let p = a * l1(*u);
            if p > best {
                (s, best) = (k, p);
            }
        }
        let shoot = std::mem::replace(&mut source_unshot[s], Rgb::ZERO);
        let start = Instant::now();
        ff.column(g, s, &mut column);
        ff_seconds += start.elapsed().as_secs_f64();
        // What the receivers that open the source gather from its pieces, before the
        // source's own unshot radiosity is cleared.
        let opened: Vec<(usize, Rgb)> = near.receivers[s]
            .iter()
            .map(|(e, range)| {
                let received = near.pieces[range.clone()]
                    .iter()
                    .map(|p| mean(system, &unshot, &p.elements) * f64::from(p.factor))
                    .sum();
                (*e as usize, received)
            })
            .collect();
        for e in system.source_elements[s].clone() {
            unshot[e] = Rgb::ZERO;
        }
        for &(e, _) in &opened {
            opens[e] = true;
        }
        let mut give = |e: usize, received: Rgb| {
            links += 1;
            h[e] += received;
            let delta = system.reflectance[e] * received;
            b[e] += delta;
            unshot[e] += delta;
            let r = system.source_of[e] as usize;
            if system.source_area[r] > 0.0 {
                source_unshot[r] += delta * (system.area[e] / system.source_area[r]);
            }
        };
        for (e, &f) in column.iter().enumerate() {
            if f != 0.0 && !opens[e] {
                give(e, shoot * f64::from(f));
            }
        }
        for &(e, received) in &opened {
            opens[e] = false;
            if received != Rgb::ZERO {
                give(e, received);
            }
        }
        residual = unshot_power(&source_unshot) / system.emitted;
        iterations += 1;
        history.push(super::Sample {
            iteration: iterations,
            seconds: started.elapsed().as_secs_f64(),
            residual,
        });
        progress.advance(1);
        session.after_iteration(false, || {
            state(&b, &h, &unshot, iterations, residual, links)
        });
    }
    if interrupted {
        session.after_iteration(true, || state(&b, &h, &unshot, iterations, residual, links));
    }
    Shots {
        radiosity: b,
        irradiance: h,
        iterations,
        residual,
        links,
        ambient: ambient(system, &source_unshot),
        form_factor_seconds: ff_seconds,
        history,
        interrupted,
    }
}

/// The area-weighted mean of the per-element `values` over `elements`.
fn mean(system: &System, values: &[Rgb], elements: &Range<u32>) -> Rgb {
    let range = elements.start as usize..elements.end as usize;
    let area: f64 = system.area[range.clone()].iter().sum();
    let sum: Rgb = range.map(|e| values[e] * system.area[e]).sum();
    if area > 0.0 {
        sum / area
    } else {
        Rgb::ZERO
    }
}

/// The receivers that open each source, with their pieces of it.
struct Near {
    /// For every source: (receiver, its pieces: a range of `pieces`), receivers in order.
    receivers: Vec<Vec<(u32, Range<usize>)>>,
    pieces: Vec<Piece>,
}

impl Near {
    /// Every receiver's opened pieces ([`opened_sources::opened`]), grouped by source.
    fn find(g: &Geometry, ff: &dyn FormFactors, elements: usize) -> Self {
        let found: Vec<Vec<(u32, Piece)>> = (0..elements)
            .into_par_iter()
            .map_init(Scratch::default, |scratch, e| {
                let mut out = Vec::new();
                opened_sources::opened(g, ff, e, &mut out, scratch);
                out
            })
            .collect();
        let mut near = Near {
            receivers: vec![Vec::new(); g.sources.len()],
            pieces: Vec::new(),
        };
        for (e, list) in found.into_iter().enumerate() {
            let mut k = 0;
            while k < list.len() {
                let s = list[k].0;
                let first = near.pieces.len();
                while k < list.len() && list[k].0 == s {
                    near.pieces.push(list[k].1.clone());
                    k += 1;
                }
                near.receivers[s as usize].push((e as u32, first..near.pieces.len()));
            }
        }
        near
    }
}

/// The ambient term of Cohen et al. 1988 (see the module documentation).
fn ambient(system: &System, unshot: &[Rgb]) -> Rgb {
    let total: f64 = system.source_area.iter().sum();
    if total <= 0.0 {
        return Rgb::ZERO;
    }
    let mean_unshot: Rgb = unshot
        .iter()
        .zip(&system.source_area)
        .map(|(u, a)| *u * *a)
        .sum::<Rgb>()
        / total;
    let mean_rho: Rgb = system
        .reflectance
        .iter()
        .zip(&system.area)
        .map(|(r, a)| *r * *a)
        .sum::<Rgb>()
        / system.area.iter().sum::<f64>();
    mean_unshot / (Rgb::ONE - mean_rho).max(Rgb::splat(1e-6))
}
