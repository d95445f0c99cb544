//! Progress reporting from long stages, without the engine knowing about terminals.

/// Receives progress of a long stage. The command line shows bars; tests pass [`Silent`].
pub trait Progress: Sync {
    /// A stage named `stage` begins with `total` units of work (0 when the amount is not known
    /// in advance, as for iterations to convergence).
    fn start(&self, stage: &str, total: u64);
    /// `n` more units are done.
    fn advance(&self, n: u64);
    /// The current stage is over.
    fn finish(&self);
}

/// Reports nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;

impl Progress for Silent {
    fn start(&self, _: &str, _: u64) {}
    fn advance(&self, _: u64) {}
    fn finish(&self) {}
}
