//! Progress reporting from long stages, without the engine knowing about terminals.
//!
//! A stage (meshing, form factors, solve, hierarchical, display, render) is reported as
//! [`Progress::start`] with the work it expects, [`Progress::advance`] as units of that work
//! are done, any number of [`Progress::tally`] figures that sum up what it produced, and
//! [`Progress::finish`] (or [`Progress::cut_short`] when a Ctrl-C stopped it; [`Progress::end`]
//! picks). A stage made of passes of different work announces each with
//! [`Progress::phase`], which then counts that pass's work. The stages and what they count:
//!
//! | stage          | work unit                        | tallies                            |
//! |----------------|----------------------------------|------------------------------------|
//! | `meshing`      | elements, in phases: `patches`,  | patches, elements                  |
//! |                | `contacts`, `shadows`, `near     |                                    |
//! |                | field` (elements tested each)    |                                    |
//! | `form factors` | rows (one per element)           | none: the rows done sum it up      |
//! | `solve`        | iterations (total not known)     | iterations, links                  |
//! | `hierarchical` | passes; in phases `pass P/N,     | elements, links, iterations        |
//! |                | refining` (links examined),      |                                    |
//! |                | `pass P/N, gathering`            |                                    |
//! |                | (iterations), `leaf solve`       |                                    |
//! | `display`      | levels (the vertices, then each  | vertices, triangles (when          |
//! |                | round of edge midpoints)         | complete)                          |
//! | `evaluation`   | elements settled, twice (the     | elements                           |
//! |                | evaluated picture's two passes)  |                                    |
//! | `render`       | tiles or bands                   | pixels (when complete)             |
//!
//! Work counted one unit at a time from many threads (elements tested, links examined) goes
//! through [`Batched`], so that a reporter sees a bounded number of calls.
//!
//! The command line draws bars on a terminal and prints lines in a log; tests pass [`Silent`].

use std::sync::atomic::{AtomicU64, Ordering};

/// The work a stage expects: how many units, and what one unit is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Work {
    /// Units of work expected; 0 when the amount is not known in advance (iterations to
    /// convergence).
    pub total: u64,
    /// What one unit is, plural (`"rows"`, `"tiles"`, `"iterations"`).
    pub unit: &'static str,
}

impl Work {
    /// `total` units of `unit`.
    #[must_use]
    pub const fn of(total: u64, unit: &'static str) -> Self {
        Self { total, unit }
    }

    /// Units of `unit` whose number is not known in advance.
    #[must_use]
    pub const fn open_ended(unit: &'static str) -> Self {
        Self { total: 0, unit }
    }
}

/// Receives progress of a long stage. The command line shows bars or lines; tests pass
/// [`Silent`].
pub trait Progress: Sync {
    /// A stage named `stage` begins with `work` to do.
    fn start(&self, stage: &str, work: Work);
    /// The current stage enters the pass `name` (`"near field"`), with `work` of its own:
    /// the units [`Progress::advance`] counts from here on are that pass's, from zero.
    fn phase(&self, name: &str, work: Work) {
        let _ = (name, work);
    }
    /// `n` more units are done.
    fn advance(&self, n: u64);
    /// The current stage produced `count` `what` (`"elements"`, `"links"`): a figure of its
    /// summary, reported before [`Progress::finish`]. A stage whose product is only whole
    /// when it completes (pixels, vertices) tallies it only then, leaving a stopped stage's
    /// summary to the work done.
    fn tally(&self, count: u64, what: &'static str) {
        let _ = (count, what);
    }
    /// The current stage is over, its work done.
    fn finish(&self);
    /// The current stage is over, stopped before the end of its work (a Ctrl-C): like
    /// [`Progress::finish`], saying so.
    fn cut_short(&self) {
        self.finish();
    }
    /// [`Progress::cut_short`] if `stopped`, else [`Progress::finish`].
    fn end(&self, stopped: bool) {
        if stopped {
            self.cut_short();
        } else {
            self.finish();
        }
    }
}

/// Reports nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {
    fn start(&self, _: &str, _: Work) {}
    fn advance(&self, _: u64) {}
    fn finish(&self) {}
}

/// Advances a [`Progress`] in batches of `batch` units, for work counted one unit at a time
/// from many threads; the remainder is reported when it is dropped, so drop it before the
/// stage or phase ends.
pub struct Batched<'a> {
    /// Where the batches go.
    progress: &'a dyn Progress,
    /// Units per call to [`Progress::advance`].
    batch: u64,
    /// Units counted so far.
    count: AtomicU64,
}

impl<'a> Batched<'a> {
    /// Counts for `progress`, reporting every `batch` units (at least 1).
    #[must_use]
    pub fn new(progress: &'a dyn Progress, batch: u64) -> Self {
        Self {
            progress,
            batch: batch.max(1),
            count: AtomicU64::new(0),
        }
    }

    /// One more unit is done.
    pub fn one(&self) {
        let count = self.count.fetch_add(1, Ordering::Relaxed) + 1;
        if count.is_multiple_of(self.batch) {
            self.progress.advance(self.batch);
        }
    }
}

impl Drop for Batched<'_> {
    fn drop(&mut self) {
        let rest = *self.count.get_mut() % self.batch;
        if rest > 0 {
            self.progress.advance(rest);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Counts the calls and units a reporter receives.
    #[derive(Default)]
    struct Calls {
        calls: AtomicU64,
        units: AtomicU64,
    }

    impl Progress for Calls {
        fn start(&self, _: &str, _: Work) {}
        fn advance(&self, n: u64) {
            self.calls.fetch_add(1, Ordering::Relaxed);
            self.units.fetch_add(n, Ordering::Relaxed);
        }
        fn finish(&self) {}
    }

    #[test]
    fn batched_reports_every_unit_in_few_calls() {
        use rayon::prelude::*;
        let calls = Calls::default();
        {
            let batched = Batched::new(&calls, 100);
            (0..1234).into_par_iter().for_each(|_| batched.one());
        }
        // 12 whole batches, then the remainder of 34 on drop.
        assert_eq!(calls.units.load(Ordering::Relaxed), 1234);
        assert_eq!(calls.calls.load(Ordering::Relaxed), 13);
    }
}
