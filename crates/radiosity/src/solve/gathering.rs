//! The gathering solvers' road: compute the form-factor matrix (resuming the rows of a
//! checkpoint, stopping between chunks of rows), then sweep until converged. Jacobi and
//! Gauss-Seidel differ only in their sweep ([`super::jacobi`], [`super::gauss_seidel`]).

use std::time::Instant;

use super::checkpoint::{Iterate, Session, Shape};
use super::matrix::Matrix;
use super::solver::Job;
use super::{Run, Settings, Solution, SolveError, System};
use crate::progress::{Progress, Work};

/// A gathering solver's iterations: from the system, the complete matrix and the session to
/// the last iterate.
pub(super) type Sweeps = fn(&System, &Matrix, &Settings, &mut Session, &dyn Progress) -> Run;

/// A gathering solver's checkpoint state: B of every element (the matrix rows travel beside it).
pub(super) fn checkpoint_shape(elements: usize) -> Shape {
    Shape {
        radiosity: elements,
        ..Shape::default()
    }
}

/// Solves `job` into `solution` with the matrix, then `sweeps`.
pub(super) fn solve(job: Job, solution: &mut Solution, sweeps: Sweeps) -> Result<(), SolveError> {
    let mut session = job.session()?;
    let Job {
        g,
        ff,
        settings,
        progress,
        mut system,
        ..
    } = job;
    let start = Instant::now();
    let stop = session.stop_flag();
    let prior = session.resumed_matrix();
    let matrix = Matrix::resume(g, ff, settings.max_matrix_bytes, stop, prior, progress)?;
    solution.form_factor_seconds = start.elapsed().as_secs_f64();
    session.keep_matrix(&matrix);
    if !matrix.complete() {
        // Stopped before any sweep: what there is, E or the resumed iterate, saved with the
        // rows computed so far.
        if let Some(it) = session.resume() {
            solution.radiosity = it.radiosity;
            solution.iterations = it.iterations;
            solution.residual = it.residual;
        }
        let (radiosity, iterations) = (&solution.radiosity, solution.iterations);
        session.after_iteration(true, || Iterate {
            iterations,
            residual: solution.residual,
            radiosity: radiosity.clone(),
            ..Iterate::default()
        });
        solution.interrupted = true;
        return Ok(());
    }
    solution.links = matrix.links();
    let start = Instant::now();
    progress.start("solve", Work::open_ended("iterations"));
    system.bury(g, &matrix);
    if ff.rows_tile_the_hemisphere() {
        system.balance(&matrix);
    }
    let run = sweeps(&system, &matrix, settings, &mut session, progress);
    progress.tally(run.iterations as u64, "iterations");
    progress.tally(solution.links, "links");
    progress.end(run.interrupted);
    solution.irradiance = system.irradiance(&matrix, &run.radiosity);
    // The gather is linear in B but for the buried emission it takes off every source's mean,
    // which is the same for B and for E alone: it cancels in the difference, as does the
    // luminaires' first shot.
    let direct = system.irradiance(&matrix, &system.emitted_only());
    solution.reflected_irradiance = Some(
        solution
            .irradiance
            .iter()
            .zip(&direct)
            .map(|(&h, &d)| h - d)
            .collect(),
    );
    solution.radiosity = run.radiosity;
    solution.iterations = run.iterations;
    solution.residual = run.residual;
    solution.history = run.history;
    solution.interrupted = run.interrupted;
    solution.solve_seconds = start.elapsed().as_secs_f64();
    Ok(())
}
