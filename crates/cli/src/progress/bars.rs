//! Progress bars on a terminal for the engine's long stages (meshing, form factors, solving):
//! one bar per stage, redrawn in place, and a line `STAGE done in S s` when it ends.

use std::io::Write;
use std::sync::{Mutex, PoisonError};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use radiosity::progress::{Progress, Work};

/// One indicatif bar per stage, drawn on stderr; or nothing at all when disabled.
pub struct Bars {
    /// The bar of the current stage; `None` between stages or when disabled.
    bar: Mutex<Option<ProgressBar>>,
    /// Whether bars are drawn.
    enabled: bool,
}

impl Bars {
    /// Bars that draw only when `enabled` (stderr is a terminal and the user did not ask for
    /// quiet).
    pub fn new(enabled: bool) -> Self {
        Self {
            bar: Mutex::new(None),
            enabled,
        }
    }
}

impl Progress for Bars {
    fn start(&self, stage: &str, work: Work) {
        let total = work.total;
        if !self.enabled {
            return;
        }
        let template = if total == 0 {
            "{prefix:>14} {spinner} {pos} ({elapsed})"
        } else {
            "{prefix:>14} [{bar:30}] {pos}/{len} ({elapsed}, eta {eta})"
        };
        let style = ProgressStyle::with_template(template)
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> ");
        let length = (total > 0).then_some(total);
        let bar = ProgressBar::with_draw_target(length, ProgressDrawTarget::stderr())
            .with_style(style)
            .with_prefix(stage.to_string());
        bar.enable_steady_tick(Duration::from_millis(200));
        let previous = self
            .bar
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .replace(bar);
        if let Some(previous) = previous {
            previous.finish_and_clear();
        }
    }

    fn advance(&self, n: u64) {
        if let Some(bar) = self
            .bar
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .as_ref()
        {
            bar.inc(n);
        }
    }

    fn finish(&self) {
        if let Some(bar) = self
            .bar
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .take()
        {
            let seconds = bar.elapsed().as_secs_f64();
            bar.finish_and_clear();
            let _ = writeln!(
                std::io::stderr(),
                "{:>14} done in {seconds:.2} s",
                bar.prefix()
            );
        }
    }
}
