//! Interrupting and resuming the solvers.
//!
//! Every iterate of the solvers is a usable answer: after k sweeps of Jacobi from B⁰ = E the
//! solution holds exactly the first k bounces of light (Gauss-Seidel at least those), and
//! progressive refinement's B is every shot so far, with the rest waiting as unshot radiosity
//! (Cohen et al. 1988); hierarchical radiosity's B after each refine-and-solve pass is the
//! solution on the links refined so far. So a solve can stop between two iterations and return
//! what it has. A [`Control`] carries the caller's wishes into the solver without the engine
//! knowing where they come from (the command line sets the stop flag from SIGINT):
//!
//! - **stop**: checked before every sweep, shot or refinement round, and between the row
//!   chunks of the form-factor matrix. Stopped before the matrix is complete, a gathering
//!   solver has nothing but the emission and returns B = E after zero iterations (or the
//!   iterate it resumed from); otherwise it returns the last iterate. Either way
//!   [`super::Solution::interrupted`] is set.
//! - **checkpoint**: after an iteration (a pass for the hierarchical solver), once `every` has
//!   passed since the last save, and once more when stopped — in the form-factor stage too —
//!   the solver hands a [`Checkpoint`] to `save`.
//! - **resume**: the solver starts from a checkpoint instead of from E. The state at an
//!   iteration boundary is complete, so a resumed solve performs exactly the operations the
//!   uninterrupted one would have, and its answer is bit-identical:
//!   - the gathering solvers: B, the iteration count and **the form-factor rows computed so
//!     far** (all of them once the matrix is complete), so a resumed run computes only the
//!     missing rows; each row depends on its element only;
//!   - progressive refinement: B, the irradiance received, the unshot radiosity per element
//!     and the link count;
//!   - hierarchical radiosity: the refinement replayed (the leaves split, in order), the links,
//!     and the push-pull state of every node and cluster, at the last whole pass.
//!
//! A checkpoint records a fingerprint: FNV-1a over the method, every element's corners,
//! reflectance and emission bits, the sources and the caller's [`Control::context`] (the
//! pipeline folds in the form-factor settings). A checkpoint whose fingerprint differs is
//! refused ([`super::SolveError::CheckpointMismatch`]). The file is binary, every number stored
//! with its exact bits ([`file`]): the matrix of a large scene is gigabytes, which text would
//! triple.

pub mod file;
mod hierarchy;

use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::matrix::Matrix;
use super::{Method, SolveError};
use crate::mesh::Mesh;
use crate::Rgb;

pub(super) use hierarchy::Hierarchy;

/// Receives checkpoints: called from the solving thread.
pub type SaveCheckpoint = Arc<dyn Fn(&Checkpoint) + Send + Sync>;

/// Periodic saving of the solver state.
#[derive(Clone)]
pub struct Checkpointing {
    /// Least time between two saves (zero: after every iteration).
    pub every: Duration,
    /// Where the checkpoints go.
    pub save: SaveCheckpoint,
}

impl fmt::Debug for Checkpointing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Checkpointing")
            .field("every", &self.every)
            .finish_non_exhaustive()
    }
}

/// What the caller asks of a running solve besides its [`super::Settings`]: see the module
/// documentation. The default stops never, saves nothing and starts afresh.
#[derive(Clone, Debug, Default)]
pub struct Control {
    /// Stop as soon as this becomes true.
    pub stop: Option<Arc<AtomicBool>>,
    /// Save the state periodically.
    pub checkpoint: Option<Checkpointing>,
    /// Start from this state.
    pub resume: Option<Checkpoint>,
    /// Folded into the fingerprint: whatever else decides the answer (e.g. form-factor
    /// settings).
    pub context: u64,
}

impl Control {
    /// Whether the stop flag is set.
    #[must_use]
    pub fn stopped(&self) -> bool {
        self.stop
            .as_ref()
            .is_some_and(|s| s.load(Ordering::Relaxed))
    }
}

/// The state of a solve at an iteration boundary.
#[derive(Clone, Debug, PartialEq)]
pub struct Checkpoint {
    /// Fingerprint of the problem and settings (see the module documentation).
    fingerprint: u64,
    /// The solver's name.
    method: String,
    /// The form-factor rows computed so far (gathering solvers).
    matrix: Option<Matrix>,
    /// The solver's state.
    state: Iterate,
}

/// An iterate handed to or taken from a checkpoint: the solver's state at an iteration
/// boundary.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Iterate {
    /// Sweeps, shots or gather iterations done.
    pub iterations: usize,
    /// The residual after them.
    pub residual: f64,
    /// Non-zero form factors used so far (progressive).
    pub links: u64,
    /// B per element (gathering and progressive solvers).
    pub radiosity: Vec<Rgb>,
    /// Irradiance gathered so far per element (progressive; empty otherwise).
    pub irradiance: Vec<Rgb>,
    /// Unshot radiosity per element (progressive; empty otherwise).
    pub unshot: Vec<Rgb>,
    /// The refined hierarchy (hierarchical solver).
    pub hierarchy: Option<Hierarchy>,
}

/// The lengths of an [`Iterate`]'s vectors and whether it holds a hierarchy: what each solver's
/// state is made of ([`super::solver::Solver::checkpoint_shape`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct Shape {
    /// Elements of `radiosity`.
    pub radiosity: usize,
    /// Elements of `irradiance`.
    pub irradiance: usize,
    /// Elements of `unshot`.
    pub unshot: usize,
    /// Whether `hierarchy` is set.
    pub hierarchy: bool,
}

impl Iterate {
    /// The lengths of its vectors and whether it holds a hierarchy.
    fn shape(&self) -> Shape {
        Shape {
            radiosity: self.radiosity.len(),
            irradiance: self.irradiance.len(),
            unshot: self.unshot.len(),
            hierarchy: self.hierarchy.is_some(),
        }
    }
}

impl Checkpoint {
    /// Sweeps, shots or gather iterations done when the checkpoint was taken.
    #[must_use]
    pub fn iterations(&self) -> usize {
        self.state.iterations
    }

    /// Whether it holds form-factor rows, and whether all of them: `None` for the solvers that
    /// store no matrix.
    #[must_use]
    pub fn form_factors_complete(&self) -> Option<bool> {
        self.matrix.as_ref().map(Matrix::complete)
    }

    fn new(session: &Session, state: Iterate) -> Self {
        Self {
            fingerprint: session.problem.fingerprint,
            method: session.method.name().to_owned(),
            matrix: session.matrix.clone(),
            state,
        }
    }
}

/// What a checkpoint must match: the fingerprint and the sizes of a problem.
pub(super) struct Problem {
    fingerprint: u64,
    elements: usize,
    sources: usize,
}

impl Problem {
    /// The problem of `mesh`'s elements gathering from (or shot by) `sources`, quadtree nodes
    /// of the mesh; the hierarchical solver passes none (it makes its own links).
    pub fn new(mesh: &Mesh, sources: &[u32], method: Method, context: u64) -> Self {
        let mut h = Fnv(0xcbf2_9ce4_8422_2325);
        h.bytes(method.name().as_bytes());
        h.u64(context);
        h.u64(mesh.element_count() as u64);
        for e in 0..mesh.element_count() {
            let patch = mesh.element_patch(e);
            for c in mesh.element(e).face.corners() {
                c.to_array()
                    .iter()
                    .for_each(|x| h.u64(u64::from(x.to_bits())));
            }
            for x in patch
                .reflectance
                .to_array()
                .into_iter()
                .chain(patch.emission.to_array())
            {
                h.u64(x.to_bits());
            }
        }
        h.u64(sources.len() as u64);
        for &s in sources {
            let range = &mesh.nodes[s as usize].elements;
            h.u64(u64::from(range.start));
            h.u64(u64::from(range.end));
        }
        Self {
            fingerprint: h.0,
            elements: mesh.element_count(),
            sources: sources.len(),
        }
    }
}

/// A solver's view of its [`Control`]: stopping, saving and the starting iterate.
pub(super) struct Session<'a> {
    control: &'a Control,
    problem: Problem,
    method: Method,
    last_save: Instant,
    /// The form factors so far, carried by every checkpoint (gathering solvers).
    matrix: Option<Matrix>,
}

impl<'a> Session<'a> {
    /// Checks the resumed checkpoint, if any, against the problem.
    pub fn new(control: &'a Control, problem: Problem, method: Method) -> Result<Self, SolveError> {
        if let Some(cp) = &control.resume {
            let mismatch = |why: String| Err(SolveError::CheckpointMismatch(why));
            if cp.method != method.name() {
                return mismatch(format!(
                    "it was made by the {} solver, not {method}",
                    cp.method
                ));
            }
            let matrix_fits = cp
                .matrix
                .as_ref()
                .is_none_or(|m| m.shape() == (problem.elements, problem.sources));
            if cp.fingerprint != problem.fingerprint
                || cp.state.shape() != method.solver().checkpoint_shape(problem.elements)
                || !matrix_fits
            {
                return mismatch(
                    "it was made for a different scene, subdivision or form-factor settings"
                        .to_owned(),
                );
            }
        }
        Ok(Self {
            control,
            problem,
            method,
            last_save: Instant::now(),
            matrix: None,
        })
    }

    /// The iterate to start from, if resuming.
    pub fn resume(&self) -> Option<Iterate> {
        self.control.resume.as_ref().map(|cp| cp.state.clone())
    }

    /// The form factors of the checkpoint resumed from, if any.
    pub fn resumed_matrix(&self) -> Option<&Matrix> {
        self.control.resume.as_ref()?.matrix.as_ref()
    }

    /// The stop flag, if any.
    pub fn stop_flag(&self) -> Option<&AtomicBool> {
        self.control.stop.as_deref()
    }

    /// Whether the caller asked to stop.
    pub fn stopped(&self) -> bool {
        self.control.stopped()
    }

    /// Whether checkpoints are saved at all (so a solver need not prepare states for nothing).
    pub fn saving(&self) -> bool {
        self.control.checkpoint.is_some()
    }

    /// Records the form factors (complete or not) that every later checkpoint carries.
    pub fn keep_matrix(&mut self, matrix: &Matrix) {
        if self.saving() {
            self.matrix = Some(matrix.clone());
        }
    }

    /// After an iteration: saves `state()` if checkpoints are due (always when `force`).
    pub fn after_iteration(&mut self, force: bool, state: impl FnOnce() -> Iterate) {
        let Some(checkpointing) = &self.control.checkpoint else {
            return;
        };
        if force || self.last_save.elapsed() >= checkpointing.every {
            (checkpointing.save)(&Checkpoint::new(self, state()));
            self.last_save = Instant::now();
        }
    }
}

/// FNV-1a, 64 bit: a stable hash (std's hashers may change between releases).
struct Fnv(u64);

impl Fnv {
    /// Hashes `bytes` in.
    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// Hashes `x` in (little-endian bytes).
    fn u64(&mut self, x: u64) {
        self.bytes(&x.to_le_bytes());
    }
}

/// The stable hash of `text` (e.g. a settings' `Debug` form), for [`Control::context`].
#[must_use]
pub fn hash_text(text: &str) -> u64 {
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    h.bytes(text.as_bytes());
    h.0
}

#[cfg(test)]
mod tests {
    use std::sync::Mutex;

    use super::*;
    use crate::formfactor;
    use crate::mesh::Subdivision;
    use crate::pipeline::{self, PipelineError, Solved};
    use crate::progress::Silent;
    use crate::scene::builtin;
    use crate::stats::Timings;

    fn settings(method: Method, seed: u64) -> pipeline::Settings {
        let mut s = pipeline::Settings {
            subdivision: Subdivision::Elements(200),
            method: Some(method),
            ..pipeline::Settings::default()
        };
        s.form_factors = formfactor::Settings::RayCast(formfactor::raycast::Settings {
            quadrature: 1,
            rays: 4,
            seed,
        });
        s.solve.tolerance = 1e-6;
        s
    }

    fn run(settings: &pipeline::Settings, control: &Control) -> Result<Solved, PipelineError> {
        let scene = builtin::load("cornell").expect("built in").expect("loads");
        pipeline::solve_controlled(scene, settings, control, &Silent)
    }

    /// Runs to convergence saving after every iteration; returns the answer and the saves.
    fn run_saving(settings: &pipeline::Settings) -> (Solved, Vec<Checkpoint>) {
        let saved = Arc::new(Mutex::new(Vec::new()));
        let sink = Arc::clone(&saved);
        let control = Control {
            checkpoint: Some(Checkpointing {
                every: Duration::ZERO,
                save: Arc::new(move |cp| sink.lock().expect("lock").push(cp.clone())),
            }),
            ..Control::default()
        };
        let solved = run(settings, &control).expect("solves");
        let saves = saved.lock().expect("lock").clone();
        (solved, saves)
    }

    /// The checkpoint through its file encoding and back.
    fn through_a_file(cp: &Checkpoint) -> Checkpoint {
        let mut bytes = Vec::new();
        cp.write(&mut bytes).expect("encodes");
        let back = Checkpoint::read(&mut bytes.as_slice()).expect("decodes");
        assert_eq!(&back, cp);
        back
    }

    #[test]
    fn resuming_midway_gives_the_bit_identical_answer() {
        for method in Method::ALL {
            let s = settings(method, 1);
            let reference = run(&s, &Control::default()).expect("solves");
            let (full, saves) = run_saving(&s);
            assert_eq!(full.solution.radiosity, reference.solution.radiosity);
            if method == Method::Hierarchical {
                // One checkpoint per pass.
                assert!(saves.len() > 2, "{}", saves.len());
            } else {
                assert_eq!(saves.len(), reference.solution.iterations, "{method}");
            }
            let middle = &saves[saves.len() / 2];
            let iterations = reference.solution.iterations;
            assert!(
                middle.iterations() > 0 && middle.iterations() < iterations,
                "{method}"
            );
            let control = Control {
                resume: Some(through_a_file(middle)),
                ..Control::default()
            };
            let resumed = run(&s, &control).expect("resumes");
            let (a, b) = (&resumed.solution, &reference.solution);
            assert_eq!(a.radiosity, b.radiosity, "{method}");
            assert_eq!(
                (a.iterations, a.residual.to_bits(), a.links),
                (b.iterations, b.residual.to_bits(), b.links),
                "{method}"
            );
            let objects = |s: &Solved| {
                serde_json::to_string(&s.stats(&Timings::default()).objects).expect("json")
            };
            assert_eq!(objects(&resumed), objects(&reference), "{method}");
        }
    }

    #[test]
    fn stopping_returns_the_iterate_so_far_and_saves_it() {
        for method in [Method::Progressive, Method::GaussSeidel] {
            let stop = Arc::new(AtomicBool::new(false));
            let flag = Arc::clone(&stop);
            let last = Arc::new(Mutex::new(None));
            let sink = Arc::clone(&last);
            let control = Control {
                stop: Some(Arc::clone(&stop)),
                checkpoint: Some(Checkpointing {
                    every: Duration::ZERO,
                    save: Arc::new(move |cp: &Checkpoint| {
                        if cp.iterations() == 3 {
                            flag.store(true, Ordering::Relaxed);
                        }
                        *sink.lock().expect("lock") = Some(cp.clone());
                    }),
                }),
                ..Control::default()
            };
            let mut s = settings(method, 1);
            let stopped = run(&s, &control).expect("solves");
            assert!(stopped.solution.interrupted, "{method}");
            assert_eq!(stopped.solution.iterations, 3, "{method}");
            s.solve.max_iterations = 3;
            let capped = run(&s, &Control::default()).expect("solves");
            assert!(!capped.solution.interrupted);
            assert_eq!(stopped.solution.radiosity, capped.solution.radiosity);
            let saved = last.lock().expect("lock").clone().expect("saved");
            assert_eq!(saved.iterations(), 3);
        }
    }

    /// Sets a stop flag once `at` units of the form-factor stage are done (the other stages'
    /// units, the meshing's elements, do not count).
    struct StopAfter {
        at: u64,
        done: std::sync::atomic::AtomicU64,
        flag: Arc<AtomicBool>,
        /// Whether the current stage is the form factors.
        counting: AtomicBool,
    }

    impl StopAfter {
        fn new(at: u64, flag: Arc<AtomicBool>) -> Self {
            Self {
                at,
                done: 0.into(),
                flag,
                counting: AtomicBool::new(false),
            }
        }
    }

    impl crate::progress::Progress for StopAfter {
        fn start(&self, stage: &str, _: crate::progress::Work) {
            self.counting
                .store(stage == "form factors", Ordering::SeqCst);
        }
        fn advance(&self, n: u64) {
            if self.counting.load(Ordering::SeqCst)
                && self.done.fetch_add(n, Ordering::SeqCst) + n >= self.at
            {
                self.flag.store(true, Ordering::SeqCst);
            }
        }
        fn finish(&self) {}
    }

    #[test]
    fn a_stop_in_the_form_factor_stage_saves_its_rows_and_resuming_finishes_them() {
        for method in [Method::GaussSeidel, Method::Jacobi] {
            let s = settings(method, 3);
            let reference = run(&s, &Control::default()).expect("solves");
            let flag = Arc::new(AtomicBool::new(false));
            let saved = Arc::new(Mutex::new(Vec::new()));
            let sink = Arc::clone(&saved);
            let control = Control {
                stop: Some(Arc::clone(&flag)),
                checkpoint: Some(Checkpointing {
                    // Never by the clock: the one checkpoint is the stop's.
                    every: Duration::MAX,
                    save: Arc::new(move |cp| sink.lock().expect("lock").push(cp.clone())),
                }),
                ..Control::default()
            };
            let scene = builtin::load("cornell").expect("built in").expect("loads");
            let progress = StopAfter::new(64, flag);
            let stopped = pipeline::solve_controlled(scene, &s, &control, &progress).expect("runs");
            assert!(stopped.solution.interrupted && stopped.solution.iterations == 0);
            let saves = saved.lock().expect("lock").clone();
            assert_eq!(saves.len(), 1, "one checkpoint, on the stop");
            let cp = through_a_file(&saves[0]);
            assert_eq!(cp.form_factors_complete(), Some(false), "{method}");
            let done = cp.matrix.as_ref().expect("rows").chunks_done();
            let rows = done.iter().filter(|&&d| d).count() * super::super::matrix::CHUNK_ROWS;
            assert!(rows >= 64 && rows < stopped.mesh.element_count(), "{rows}");
            let control = Control {
                resume: Some(cp),
                ..Control::default()
            };
            let resumed = run(&s, &control).expect("resumes");
            assert_eq!(resumed.solution.radiosity, reference.solution.radiosity);
            assert_eq!(resumed.solution.iterations, reference.solution.iterations);
            assert_eq!(resumed.solution.links, reference.solution.links);
        }
    }

    #[test]
    fn stopped_before_the_matrix_gathering_returns_the_emission() {
        // Stopped before anything: the meshing gives up, with nothing to show.
        let control = Control {
            stop: Some(Arc::new(AtomicBool::new(true))),
            ..Control::default()
        };
        let err = run(&settings(Method::GaussSeidel, 1), &control).expect_err("stops");
        assert!(matches!(err, PipelineError::Interrupted), "{err}");
        // Stopped after the first chunk of form factors: B = E.
        let flag = Arc::new(AtomicBool::new(false));
        let control = Control {
            stop: Some(Arc::clone(&flag)),
            ..Control::default()
        };
        let progress = StopAfter::new(1, flag);
        let scene = builtin::load("cornell").expect("built in").expect("loads");
        let s = settings(Method::GaussSeidel, 1);
        let solved = pipeline::solve_controlled(scene, &s, &control, &progress).expect("solves");
        assert!(solved.solution.interrupted);
        assert_eq!(solved.solution.iterations, 0);
        let emission: Vec<Rgb> = (0..solved.mesh.element_count())
            .map(|e| solved.mesh.element_patch(e).emission)
            .collect();
        assert_eq!(solved.solution.radiosity, emission);
    }

    #[test]
    fn a_checkpoint_of_another_run_is_refused() {
        let (_, saves) = run_saving(&settings(Method::Progressive, 1));
        let resume = |cp: &Checkpoint| Control {
            resume: Some(cp.clone()),
            ..Control::default()
        };
        let cp = &saves[1];
        let mut other_mesh = settings(Method::Progressive, 1);
        other_mesh.subdivision = Subdivision::Elements(300);
        for s in [
            settings(Method::GaussSeidel, 1),
            settings(Method::Progressive, 2),
            other_mesh,
        ] {
            let err = run(&s, &resume(cp)).expect_err("must refuse");
            assert!(
                matches!(err, PipelineError::Solve(SolveError::CheckpointMismatch(_))),
                "{err}"
            );
        }
        let err = run(&settings(Method::Hierarchical, 1), &resume(cp)).expect_err("refuses");
        assert!(
            matches!(err, PipelineError::Solve(SolveError::CheckpointMismatch(_))),
            "{err}"
        );
        // Damaged files: each refused with a reason, none accepted.
        let mut bytes = Vec::new();
        cp.write(&mut bytes).expect("encodes");
        let read = |b: &[u8]| Checkpoint::read(&mut &b[..]);
        assert_eq!(
            read(b"{\"format\": 1}"),
            Err("not a checkpoint file".to_owned())
        );
        let mut future = bytes.clone();
        future[16] += 1;
        assert!(read(&future).expect_err("refused").contains("format 4"));
        assert_eq!(
            read(&bytes[..bytes.len() - 1]),
            Err("truncated checkpoint".to_owned())
        );
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(read(&longer).is_err());
        let mut huge = bytes.clone();
        // The radiosity's count: a length beyond memory is an error, not an abort.
        let at = 16 + 4 + 8 + 8 + "progressive".len() + 8 + 8 + 8;
        huge[at..at + 8].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(read(&huge).is_err());
    }
}
