//! Progress bars on a terminal for the engine's long stages (meshing, form factors, solving)
//! and the developer tools' runs (benchmark cases, suite scenes):
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

/// A bar's look for `total` units of work (a spinner when the total is not known), with the
/// phase, if any, after the stage's name.
fn style(total: u64) -> ProgressStyle {
    let template = if total == 0 {
        "{prefix:>14} {msg}{spinner} {pos} ({elapsed})"
    } else {
        "{prefix:>14} {msg}[{bar:30}] {pos}/{len} ({elapsed}, eta {eta})"
    };
    ProgressStyle::with_template(template)
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> ")
}

impl Bars {
    /// Clears the current bar, if any, and prints `STAGE ENDED in S s`.
    fn end_bar(&self, ended: &str) {
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
                "{:>14} {ended} in {seconds:.2} s",
                bar.prefix()
            );
        }
    }
}

impl Progress for Bars {
    fn start(&self, stage: &str, work: Work) {
        let total = work.total;
        if !self.enabled {
            return;
        }
        let length = (total > 0).then_some(total);
        let bar = ProgressBar::with_draw_target(length, ProgressDrawTarget::stderr())
            .with_style(style(total))
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

    /// Restarts the bar on the phase's work, naming the phase after the stage.
    fn phase(&self, name: &str, work: Work) {
        if let Some(bar) = self
            .bar
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .as_ref()
        {
            // The position first: a redraw between two of these calls never shows the new
            // length under the old phase's count.
            bar.set_position(0);
            if work.total == 0 {
                bar.unset_length();
            } else {
                bar.set_length(work.total);
            }
            bar.reset_eta();
            bar.set_message(format!("{name} "));
            bar.set_style(style(work.total));
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
        self.end_bar("done");
    }

    fn cut_short(&self) {
        self.end_bar("stopped");
    }
}
