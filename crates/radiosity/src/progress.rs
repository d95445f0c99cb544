//! Progress reporting from long stages, without the engine knowing about terminals.
//!
//! A stage (meshing, form factors, solve, hierarchical, display, render) is reported as
//! [`Progress::start`] with the work it expects, [`Progress::advance`] as units of that work
//! are done, any number of [`Progress::tally`] figures that sum up what it produced, and
//! [`Progress::finish`]. The stages and what they count:
//!
//! | stage          | work unit                        | tallies                            |
//! |----------------|----------------------------------|------------------------------------|
//! | `meshing`      | steps (3)                        | patches, elements                  |
//! | `form factors` | rows (one per element)           | none: the rows done sum it up      |
//! | `solve`        | iterations (total not known)     | iterations, links                  |
//! | `hierarchical` | passes                           | elements, links, iterations        |
//! | `display`      | levels (the vertices, then each  | vertices, triangles (when          |
//! |                | round of edge midpoints)         | complete)                          |
//! | `render`       | tiles or bands                   | pixels (when complete)             |
//!
//! The command line draws bars on a terminal and prints lines in a log; tests pass [`Silent`].

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
    /// `n` more units are done.
    fn advance(&self, n: u64);
    /// The current stage produced `count` `what` (`"elements"`, `"links"`): a figure of its
    /// summary, reported before [`Progress::finish`]. A stage whose product is only whole
    /// when it completes (pixels, vertices) tallies it only then, leaving a stopped stage's
    /// summary to the work done.
    fn tally(&self, count: u64, what: &'static str) {
        let _ = (count, what);
    }
    /// The current stage is over (done or stopped).
    fn finish(&self);
}

/// Reports nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {
    fn start(&self, _: &str, _: Work) {}
    fn advance(&self, _: u64) {}
    fn finish(&self) {}
}
