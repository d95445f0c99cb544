//! Interrupting and resuming the iterative solvers.
//!
//! Every iterate of the solvers is a usable answer: after k sweeps of Jacobi from B⁰ = E the
//! solution holds exactly the first k bounces of light (Gauss-Seidel at least those), and
//! progressive refinement's B is every shot so far, with the rest waiting as unshot radiosity
//! (Cohen et al. 1988). So a solve can stop between two iterations and return what it has. A
//! [`Control`] carries the caller's wishes into the solver without the engine knowing where
//! they come from (the command line sets the stop flag from SIGINT):
//!
//! - **stop**: checked before every sweep or shot, and between the row chunks of the
//!   form-factor matrix. Stopped before the matrix is complete, a gathering solver has nothing
//!   but the emission and returns B = E after zero iterations; otherwise it returns the last
//!   iterate. Either way [`super::Solution::interrupted`] is set.
//! - **checkpoint**: after an iteration, once `every` has passed since the last save (and once
//!   more when stopped), the solver hands a [`Checkpoint`] to `save`.
//! - **resume**: the solver starts from a checkpoint instead of from E. The state at an
//!   iteration boundary is complete — B and the iteration count for the gathering solvers
//!   (whose sweeps recompute the source means from B), plus the unshot radiosity and link
//!   count for progressive refinement — so a resumed solve performs exactly the operations the
//!   uninterrupted one would have, and its answer is bit-identical.
//!
//! A checkpoint records a fingerprint: FNV-1a over the method, every element's area,
//! reflectance and emission bits, the sources' element ranges and the caller's
//! [`Control::context`] (the pipeline folds in the form-factor settings). A checkpoint whose
//! fingerprint differs is refused ([`super::SolveError::CheckpointMismatch`]). The file is JSON
//! with every f64 stored as its IEEE-754 bits (a `u64`), so it round-trips exactly.
//! The hierarchical solver refines the elements as it runs: it neither stops early nor takes
//! checkpoints.

use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use super::{Method, SolveError, System};
use crate::Rgb;

/// Version of the checkpoint format.
const FORMAT: u32 = 1;

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
    /// Whether checkpoints are asked for or given.
    #[must_use]
    pub fn uses_checkpoints(&self) -> bool {
        self.checkpoint.is_some() || self.resume.is_some()
    }

    /// Whether the stop flag is set.
    #[must_use]
    pub fn stopped(&self) -> bool {
        self.stop
            .as_ref()
            .is_some_and(|s| s.load(Ordering::Relaxed))
    }
}

/// The state of an iterative solve at an iteration boundary.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// Format version.
    format: u32,
    /// Fingerprint of the system and settings (see the module documentation).
    fingerprint: u64,
    /// The solver's name.
    method: String,
    /// Sweeps or shots done.
    iterations: usize,
    /// The residual after them, as bits.
    residual: u64,
    /// Non-zero form factors used so far (progressive).
    links: u64,
    /// B per element, as bits.
    radiosity: Vec<[u64; 3]>,
    /// Unshot radiosity per source, as bits (progressive; empty otherwise).
    unshot: Vec<[u64; 3]>,
}

/// An iterate handed to or taken from a checkpoint.
pub(super) struct Iterate {
    pub iterations: usize,
    pub residual: f64,
    pub links: u64,
    pub radiosity: Vec<Rgb>,
    pub unshot: Vec<Rgb>,
}

impl Checkpoint {
    /// Sweeps or shots done when the checkpoint was taken.
    #[must_use]
    pub fn iterations(&self) -> usize {
        self.iterations
    }

    /// The JSON text of the checkpoint.
    ///
    /// # Errors
    /// Never in practice (every field is serialisable); serde's error otherwise.
    pub fn to_json(&self) -> serde_json::Result<Vec<u8>> {
        serde_json::to_vec(self)
    }

    /// Reads a checkpoint from its JSON text.
    ///
    /// # Errors
    /// When the text is not a checkpoint of this format version.
    pub fn from_json(text: &[u8]) -> Result<Self, String> {
        let cp: Self =
            serde_json::from_slice(text).map_err(|e| format!("not a checkpoint: {e}"))?;
        if cp.format != FORMAT {
            return Err(format!(
                "checkpoint format {} is not supported (expected {FORMAT})",
                cp.format
            ));
        }
        Ok(cp)
    }

    fn new(fingerprint: u64, method: Method, it: &Iterate) -> Self {
        let bits = |v: &[Rgb]| v.iter().map(|x| x.to_array().map(f64::to_bits)).collect();
        Self {
            format: FORMAT,
            fingerprint,
            method: method.name().to_owned(),
            iterations: it.iterations,
            residual: it.residual.to_bits(),
            links: it.links,
            radiosity: bits(&it.radiosity),
            unshot: bits(&it.unshot),
        }
    }

    fn iterate(&self) -> Iterate {
        let rgb = |v: &[[u64; 3]]| {
            v.iter()
                .map(|x| Rgb::from_array(x.map(f64::from_bits)))
                .collect()
        };
        Iterate {
            iterations: self.iterations,
            residual: f64::from_bits(self.residual),
            links: self.links,
            radiosity: rgb(&self.radiosity),
            unshot: rgb(&self.unshot),
        }
    }
}

/// A solver's view of its [`Control`]: stopping, saving and the starting iterate.
pub(super) struct Session<'a> {
    control: &'a Control,
    fingerprint: u64,
    method: Method,
    last_save: Instant,
}

impl<'a> Session<'a> {
    /// Checks the resumed checkpoint, if any, against the system.
    pub fn new(control: &'a Control, system: &System, method: Method) -> Result<Self, SolveError> {
        let fingerprint = fingerprint(system, method, control.context);
        if let Some(cp) = &control.resume {
            let mismatch = |why: String| Err(SolveError::CheckpointMismatch(why));
            if cp.method != method.name() {
                return mismatch(format!(
                    "it was made by the {} solver, not {method}",
                    cp.method
                ));
            }
            let unshot = if method == Method::Progressive {
                system.source_area.len()
            } else {
                0
            };
            if cp.fingerprint != fingerprint
                || cp.radiosity.len() != system.area.len()
                || cp.unshot.len() != unshot
            {
                return mismatch(
                    "it was made for a different scene, subdivision or form-factor settings"
                        .to_owned(),
                );
            }
        }
        Ok(Self {
            control,
            fingerprint,
            method,
            last_save: Instant::now(),
        })
    }

    /// The iterate to start from, if resuming.
    pub fn resume(&self) -> Option<Iterate> {
        self.control.resume.as_ref().map(Checkpoint::iterate)
    }

    /// Whether the caller asked to stop.
    pub fn stopped(&self) -> bool {
        self.control.stopped()
    }

    /// After an iteration: saves `state()` if checkpoints are due (always when `force`).
    pub fn after_iteration(&mut self, force: bool, state: impl FnOnce() -> Iterate) {
        let Some(checkpointing) = &self.control.checkpoint else {
            return;
        };
        if force || self.last_save.elapsed() >= checkpointing.every {
            (checkpointing.save)(&Checkpoint::new(self.fingerprint, self.method, &state()));
            self.last_save = Instant::now();
        }
    }
}

/// FNV-1a (64 bit) of the system, the method and `context`.
fn fingerprint(system: &System, method: Method, context: u64) -> u64 {
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    h.bytes(method.name().as_bytes());
    h.u64(context);
    h.u64(system.area.len() as u64);
    for ((a, r), e) in system
        .area
        .iter()
        .zip(&system.reflectance)
        .zip(&system.emission)
    {
        h.u64(a.to_bits());
        for x in r.to_array().into_iter().chain(e.to_array()) {
            h.u64(x.to_bits());
        }
    }
    h.u64(system.source_elements.len() as u64);
    for range in &system.source_elements {
        h.u64(range.start as u64);
        h.u64(range.end as u64);
    }
    h.0
}

/// FNV-1a, 64 bit: a stable hash (std's hashers may change between releases).
pub(crate) struct Fnv(pub u64);

impl Fnv {
    /// Hashes `bytes` in.
    pub fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// Hashes `x` in (little-endian bytes).
    pub fn u64(&mut self, x: u64) {
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
        s.form_factors = formfactor::Settings {
            method: formfactor::Method::RayCast,
            quadrature: 1,
            rays: 4,
            seed,
            ..formfactor::Settings::default()
        };
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

    #[test]
    fn resuming_midway_gives_the_bit_identical_answer() {
        for method in [Method::Progressive, Method::GaussSeidel, Method::Jacobi] {
            let s = settings(method, 1);
            let reference = run(&s, &Control::default()).expect("solves");
            let (full, saves) = run_saving(&s);
            assert_eq!(full.solution.radiosity, reference.solution.radiosity);
            assert_eq!(saves.len(), reference.solution.iterations, "{method}");
            let middle = &saves[saves.len() / 2];
            assert!(middle.iterations() > 0 && middle.iterations() < saves.len());
            let text = middle.to_json().expect("serialises");
            let back = Checkpoint::from_json(&text).expect("parses");
            assert_eq!(&back, middle);
            let control = Control {
                resume: Some(back),
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

    #[test]
    fn stopped_before_the_matrix_gathering_returns_the_emission() {
        let control = Control {
            stop: Some(Arc::new(AtomicBool::new(true))),
            ..Control::default()
        };
        let solved = run(&settings(Method::GaussSeidel, 1), &control).expect("solves");
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
        assert!(matches!(
            err,
            PipelineError::Solve(SolveError::CheckpointUnsupported)
        ));
        assert!(Checkpoint::from_json(b"{\"format\": 1}").is_err());
        let mut future = cp.clone();
        future.format = FORMAT + 1;
        let text = future.to_json().expect("serialises");
        assert!(Checkpoint::from_json(&text).is_err());
    }
}
