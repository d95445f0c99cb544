//! Progress of `render`, `solve` and `compare` on stderr: bars on a terminal ([`Bars`], from the
//! `report` crate that the developer tools share), lines of text anywhere else ([`Lines`]: a
//! log file, CI, a batch farm), nothing with `--quiet`.

mod lines;

use std::io::IsTerminal;
use std::time::Duration;

pub use lines::Lines;
use radiosity::progress::{Progress, Work};
use report::Bars;

/// How a run reports its stages: `--quiet` and `--progress-every`.
#[derive(Clone, Copy, Debug)]
pub struct Reporting {
    /// Nothing at all (`--quiet`).
    pub quiet: bool,
    /// Without a terminal: the time between two progress lines of a stage.
    pub every: Duration,
}

impl Reporting {
    /// The reporter for stderr as it is: nothing when quiet, bars on a terminal, else lines.
    pub fn on_stderr(self) -> Stderr {
        if self.quiet {
            Stderr::Quiet
        } else if std::io::stderr().is_terminal() {
            Stderr::Bars(Bars::new(true))
        } else {
            Stderr::Lines(Lines::stderr(self.every))
        }
    }
}

/// The reporter [`Reporting::on_stderr`] chose.
pub enum Stderr {
    /// `--quiet`: nothing.
    Quiet,
    /// A terminal: a bar per stage.
    Bars(Bars),
    /// Not a terminal: a line per stage, and progress lines within.
    Lines(Lines),
}

impl Progress for Stderr {
    fn start(&self, stage: &str, work: Work) {
        match self {
            Self::Quiet => {}
            Self::Bars(bars) => bars.start(stage, work),
            Self::Lines(lines) => lines.start(stage, work),
        }
    }

    fn phase(&self, name: &str, work: Work) {
        match self {
            Self::Quiet => {}
            Self::Bars(bars) => bars.phase(name, work),
            Self::Lines(lines) => lines.phase(name, work),
        }
    }

    fn advance(&self, n: u64) {
        match self {
            Self::Quiet => {}
            Self::Bars(bars) => bars.advance(n),
            Self::Lines(lines) => lines.advance(n),
        }
    }

    fn tally(&self, count: u64, what: &'static str) {
        match self {
            Self::Quiet => {}
            Self::Bars(bars) => bars.tally(count, what),
            Self::Lines(lines) => lines.tally(count, what),
        }
    }

    fn finish(&self) {
        match self {
            Self::Quiet => {}
            Self::Bars(bars) => bars.finish(),
            Self::Lines(lines) => lines.finish(),
        }
    }

    fn cut_short(&self) {
        match self {
            Self::Quiet => {}
            Self::Bars(bars) => bars.cut_short(),
            Self::Lines(lines) => lines.cut_short(),
        }
    }
}
