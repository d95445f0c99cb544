//! Jacobi iteration: every element gathers from the previous sweep's radiosities,
//!
//! ```text
//! B_i^{k+1} = E_i + ρ_i Σ_s F_is B̄_s^k ,   B⁰ = E ,
//! ```
//!
//! which is the Neumann series of (I − ρF)⁻¹E summed one bounce per sweep: it converges
//! because ρF has spectral radius at most max ρ < 1 (rows of F sum to at most 1). Every element
//! is independent within a sweep, so the sweep runs in parallel; each dot product is a
//! sequential sum, so the result is the same at any thread count.

use rayon::prelude::*;

use super::checkpoint::{Iterate, Session, Shape};
use super::gathering;
use super::matrix::Matrix;
use super::solver::{Job, Solver};
use super::{Run, Settings, Shine, Solution, SolveError, System};
use crate::progress::Progress;
use crate::Rgb;

/// Sweeps until the residual falls below the tolerance, the iteration limit is reached or the
/// session is stopped (from B = E, or from the session's checkpoint).
pub(super) fn run(
    system: &System,
    matrix: &Matrix,
    settings: &Settings,
    session: &mut Session,
    progress: &dyn Progress,
) -> Run {
    let mut next = vec![Rgb::ZERO; system.emission.len()];
    sweeps(system, settings, session, progress, |b, shine| {
        next.par_iter_mut().enumerate().for_each(|(e, out)| {
            *out = system.emission[e] + system.reflectance[e] * system.gather(matrix, e, shine);
        });
        let residual = system.residual(b, &next);
        std::mem::swap(b, &mut next);
        residual
    })
}

/// Jacobi iteration as a [`Solver`].
pub(super) struct Jacobi;

impl Solver for Jacobi {
    fn solve(&self, job: Job, solution: &mut Solution) -> Result<(), SolveError> {
        gathering::solve(job, solution, run)
    }

    fn checkpoint_shape(&self, elements: usize) -> Shape {
        gathering::checkpoint_shape(elements)
    }
}

/// The loop both gathering solvers share: start from B = E or the session's checkpoint, and
/// until converged, stopped or out of iterations, recompute what the sources shine exactly and
/// run `sweep(B, shine)`, which updates B and returns the sweep's residual; record the history and
/// report to the session and `progress` after each sweep.
pub(super) fn sweeps(
    system: &System,
    settings: &Settings,
    session: &mut Session,
    progress: &dyn Progress,
    mut sweep: impl FnMut(&mut Vec<Rgb>, &mut Shine) -> f64,
) -> Run {
    // A checkpoint of the form-factor stage holds no sweep yet: start as afresh.
    let (mut b, mut iterations, mut residual) = match session.resume() {
        Some(it) if it.iterations > 0 => (it.radiosity, it.iterations, it.residual),
        _ => (system.emission.clone(), 0, 1.0),
    };
    let mut shine = Shine::default();
    let (start, mut history, mut interrupted) = (std::time::Instant::now(), Vec::new(), false);
    while iterations < settings.max_iterations && residual >= settings.tolerance {
        if session.stopped() {
            interrupted = true;
            break;
        }
        system.shine(&b, &mut shine);
        residual = sweep(&mut b, &mut shine);
        iterations += 1;
        history.push(super::Sample {
            iteration: iterations,
            seconds: start.elapsed().as_secs_f64(),
            residual,
        });
        progress.advance(1);
        session.after_iteration(false, || iterate(&b, iterations, residual));
    }
    if interrupted {
        session.after_iteration(true, || iterate(&b, iterations, residual));
    }
    Run {
        radiosity: b,
        iterations,
        residual,
        history,
        interrupted,
    }
}

/// The state of a gathering solver after `iterations` sweeps.
pub(super) fn iterate(b: &[Rgb], iterations: usize, residual: f64) -> Iterate {
    Iterate {
        iterations,
        residual,
        radiosity: b.to_vec(),
        ..Iterate::default()
    }
}
