//! What a long render reports to and listens to.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::progress::{Progress, Silent};

/// What a long render reports to and listens to: progress, in tiles or bands, under the stage
/// "render", and a stop flag read before every tile or band (a tile of a 64-ray gather takes
/// well under a second).
#[derive(Clone, Copy)]
pub struct Watch<'a> {
    /// Told of every finished tile.
    pub progress: &'a dyn Progress,
    /// Set (by Ctrl-C, say) to stop the render: it then returns no image.
    pub stop: Option<&'a AtomicBool>,
}

impl Watch<'_> {
    /// Reports nothing and never stops.
    pub const SILENT: Watch<'static> = Watch {
        progress: &Silent,
        stop: None,
    };

    /// Whether the stop flag is set.
    #[must_use]
    pub fn stopped(&self) -> bool {
        self.stop.is_some_and(|s| s.load(Ordering::Relaxed))
    }
}
