//! Gauss-Seidel iteration: gathering in place,
//!
//! ```text
//! B_i ← E_i + ρ_i Σ_s F_is B̄_s ,   then   B̄_{s(i)} ← B̄_{s(i)} + A_i ΔB_i / A_{s(i)} ,
//! ```
//!
//! so each element already sees the updates made earlier in the same sweep (Cohen & Greenberg
//! 1985 solve their system this way). It converges for the same reason as Jacobi, in about half
//! the sweeps. The mean radiosity of the source that contains the updated element is kept
//! current incrementally, and recomputed exactly at the start of every sweep so rounding does
//! not accumulate. The pieces of the sources a receiver opened ([`super::opened_sources`]) shine
//! the means of the sweep's start (a Jacobi step for that part: the same fixed point, a sweep or
//! two more). A sweep is sequential, hence deterministic.

use super::checkpoint::{Session, Shape};
use super::gathering;
use super::jacobi::sweeps;
use super::matrix::Matrix;
use super::solver::{Job, Solver};
use super::{l1, Run, Settings, Solution, SolveError, System};
use crate::progress::Progress;

/// Gauss-Seidel iteration as a [`Solver`].
pub(super) struct GaussSeidel;

impl Solver for GaussSeidel {
    fn solve(&self, job: Job, solution: &mut Solution) -> Result<(), SolveError> {
        gathering::solve(job, solution, run)
    }

    fn checkpoint_shape(&self, elements: usize) -> Shape {
        gathering::checkpoint_shape(elements)
    }
}

/// Sweeps until the residual falls below the tolerance, the iteration limit is reached or the
/// session is stopped (from B = E, or from the session's checkpoint).
pub(super) fn run(
    system: &System,
    matrix: &Matrix,
    settings: &Settings,
    session: &mut Session,
    progress: &dyn Progress,
) -> Run {
    sweeps(system, settings, session, progress, |b, shine| {
        let mut moved = 0.0;
        for (e, value) in b.iter_mut().enumerate() {
            let new = system.emission[e] + system.reflectance[e] * system.gather(matrix, e, shine);
            let delta = new - *value;
            *value = new;
            moved += system.area[e] * l1(delta);
            shine.sources[system.source_of[e] as usize] += delta * system.share(e);
        }
        moved / system.emitted
    })
}
