//! The one road every solver takes: a [`Solver`] receives a prepared [`Job`] — the geometry
//! (mesh, BVH, sources), its form factors, the settings, the caller's [`Control`] and the
//! linear system in solver-friendly arrays — and fills the one [`Solution`], which
//! [`super::solve_controlled`] starts at B = E.
//!
//! Adding a solver is one file with a unit struct implementing [`Solver`] (its checkpoint
//! state's [`Shape`] included), and its line in the [`Method`] registry with its arm in
//! [`Method::solver`]. Checkpoints, the stop flag and progress reach it through the job
//! ([`Job::session`]), so every solver is interruptible and resumable the same way.

use super::checkpoint::{self, Control, Session, Shape};
use super::{Method, Settings, Solution, SolveError, System};
use crate::formfactor::{FormFactors, Geometry};
use crate::progress::Progress;

/// A radiosity solver: see the module documentation.
pub(super) trait Solver: Sync {
    /// Solves `job` into `solution` (B = E on entry, the method and nothing else set).
    ///
    /// # Errors
    /// What the method refuses: a matrix beyond the budget, a checkpoint of another run.
    fn solve(&self, job: Job, solution: &mut Solution) -> Result<(), SolveError>;

    /// What this solver's checkpoint state holds for a problem of `elements` elements: a
    /// checkpoint to resume from must hold exactly that.
    fn checkpoint_shape(&self, elements: usize) -> Shape;
}

/// Everything a solver works from.
pub(super) struct Job<'a> {
    /// Mesh, BVH and sources.
    pub g: &'a Geometry<'a>,
    /// The form factors.
    pub ff: &'a dyn FormFactors,
    /// The method solving it.
    pub method: Method,
    /// Tolerance, iteration limit, budget and the method's own options.
    pub settings: &'a Settings,
    /// Stop flag, checkpoints, resuming.
    pub control: &'a Control,
    /// Where progress goes.
    pub progress: &'a dyn Progress,
    /// The elements and sources as arrays.
    pub system: System,
}

impl<'a> Job<'a> {
    /// The checkpoint session of this job: the resumed checkpoint, if any, checked against
    /// the problem.
    pub fn session(&self) -> Result<Session<'a>, SolveError> {
        let method = self.method;
        let problem =
            checkpoint::Problem::new(self.g.mesh, self.g.sources, method, self.control.context);
        Session::new(self.control, problem, method)
    }
}
