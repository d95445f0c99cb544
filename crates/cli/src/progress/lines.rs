//! Progress as lines of text, for a stderr that is not a terminal (a log file, CI, a batch
//! farm), where bars would be hidden and a long run would otherwise say nothing.
//!
//! Two kinds of line, each written whole:
//!
//! ```text
//! STAGE: DONE/TOTAL UNIT after S s                  while the stage runs, every `every`
//! STAGE (PHASE): DONE/TOTAL UNIT after S s          the same within a phase of the stage
//! STAGE done: COUNT WHAT, COUNT WHAT... in S s      when it ends
//! STAGE stopped: DONE/TOTAL UNIT in S s             when it ends short of its work
//! ```
//!
//! for instance
//!
//! ```text
//! meshing (near field): 81920/543233 elements after 10.0 s
//! meshing done: 6 patches, 2500 elements in 0.05 s
//! form factors: 1536/2500 rows after 10.0 s
//! form factors done: 2500 rows in 16.30 s
//! solve done: 37 iterations, 1993744 links in 0.41 s
//! render done: 65536 pixels in 3.21 s
//! ```
//!
//! A stage whose amount of work is not known in advance has no total in its progress lines
//! (`solve: 37 iterations after 10.0 s`). A phase ([`Progress::phase`]: the meshing's
//! `subdivision`, `contacts`, `shadows`, `near field`, `bvh`; the hierarchical solver's
//! `pass 2/7, refining`) counts its own work from zero.
//! The summary is the stage's tallies ([`Progress::tally`]) or, without them, the work done
//! (`640/2500 rows` short of the total); a stage a Ctrl-C cut short ([`Progress::cut_short`])
//! says `stopped`, never `done`. Seconds are wall-clock from the stage's start; counts are plain
//! integers.
//!
//! A progress line is due once `every` has passed since the stage began or since its last
//! line. [`Progress::advance`] writes it when due, and a ticker thread wakes when the next one
//! falls due, so a stage that advances rarely (a long refinement pass) still reports. With
//! `every` zero every event is due: a progress line at the stage's start and at each advance,
//! and no thread. That makes the lines testable without waiting on a clock.

use std::io::Write;
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use radiosity::progress::{Progress, Work};

/// Writes progress lines to a stream (stderr, or a buffer in tests); see the module docs.
pub struct Lines {
    /// The state the reporting calls and the ticker share.
    shared: Arc<Shared>,
    /// The thread that writes the progress lines of stages that do not advance; `None` when
    /// `every` is zero.
    ticker: Option<JoinHandle<()>>,
}

/// What the reporter and its ticker share.
struct Shared {
    /// Time between two progress lines of a stage.
    every: Duration,
    /// The stream and the current stage.
    state: Mutex<State>,
    /// Wakes the ticker: a stage started, or the reporter is dropped.
    wake: Condvar,
}

/// The stream and the current stage.
struct State {
    /// Where the lines go.
    out: Box<dyn Write + Send>,
    /// The stage under way, if any.
    stage: Option<Stage>,
    /// Set when the reporter is dropped: the ticker ends.
    closed: bool,
}

/// A stage under way.
struct Stage {
    /// Its name (`"form factors"`).
    name: String,
    /// The phase under way, if the stage announced one (`"near field"`).
    phase: Option<String>,
    /// The work it announced.
    work: Work,
    /// Units of work done so far.
    done: u64,
    /// The figures of its summary, in the order reported.
    tallies: Vec<(u64, &'static str)>,
    /// When it began.
    began: Instant,
    /// When its last progress line was written (its start before the first).
    last_line: Instant,
}

impl Stage {
    /// `STAGE: DONE/TOTAL UNIT after S s`, or `STAGE: DONE UNIT after S s` when the total is
    /// not known; `STAGE (PHASE): ...` within a phase.
    fn progress_line(&self, now: Instant) -> String {
        let seconds = now.duration_since(self.began).as_secs_f64();
        let name = match &self.phase {
            Some(phase) => format!("{} ({phase})", self.name),
            None => self.name.clone(),
        };
        let Work { total, unit } = self.work;
        let done = self.done;
        if total == 0 {
            format!("{name}: {done} {unit} after {seconds:.1} s")
        } else {
            format!("{name}: {done}/{total} {unit} after {seconds:.1} s")
        }
    }

    /// `STAGE done: COUNT WHAT, ... in S s` (`STAGE stopped: ...` if `stopped`): the
    /// tallies, or else the work done, `DONE/TOTAL UNIT` short of the total.
    fn summary_line(&self, now: Instant, stopped: bool) -> String {
        let seconds = now.duration_since(self.began).as_secs_f64();
        let Work { total, unit } = self.work;
        let summary = if !self.tallies.is_empty() {
            let figures: Vec<String> = self
                .tallies
                .iter()
                .map(|(count, what)| format!("{count} {what}"))
                .collect();
            figures.join(", ")
        } else if total == 0 || self.done >= total {
            format!("{} {unit}", self.done)
        } else {
            format!("{}/{total} {unit}", self.done)
        };
        let ended = if stopped { "stopped" } else { "done" };
        format!("{} {ended}: {summary} in {seconds:.2} s", self.name)
    }
}

impl State {
    /// Writes `line` and a newline in one write, so that lines from several threads and the
    /// program's other messages do not interleave; a failed write is ignored, like a hidden
    /// progress bar.
    fn write_line(&mut self, line: &str) {
        let _ = self.out.write_all(format!("{line}\n").as_bytes());
        let _ = self.out.flush();
    }

    /// Writes the current stage's progress line if `every` has passed since its last line.
    fn report_if_due(&mut self, every: Duration, now: Instant) {
        let Some(stage) = &mut self.stage else {
            return;
        };
        if now.saturating_duration_since(stage.last_line) < every {
            return;
        }
        stage.last_line = now;
        let line = stage.progress_line(now);
        self.write_line(&line);
    }

    /// Ends the current stage, if any, with its summary line (`stopped`: cut short).
    fn end_stage(&mut self, stopped: bool) {
        if let Some(stage) = self.stage.take() {
            let line = stage.summary_line(Instant::now(), stopped);
            self.write_line(&line);
        }
    }
}

impl Shared {
    /// The state, whatever a panicking thread left it as (it holds nothing a panic can break).
    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The ticker: writes the current stage's progress line whenever it falls due, sleeping
    /// until then, until the reporter is dropped.
    fn tick(&self) {
        let mut state = self.lock();
        while !state.closed {
            let now = Instant::now();
            state.report_if_due(self.every, now);
            let wait = state.stage.as_ref().map_or(self.every, |stage| {
                self.every
                    .saturating_sub(now.saturating_duration_since(stage.last_line))
            });
            state = self
                .wake
                .wait_timeout(state, wait)
                .unwrap_or_else(PoisonError::into_inner)
                .0;
        }
    }
}

impl Lines {
    /// Lines on stderr, a progress line every `every` within a stage.
    pub fn stderr(every: Duration) -> Self {
        Self::new(Box::new(std::io::stderr()), every)
    }

    /// Lines written to `out`, a progress line every `every` within a stage (zero: at the
    /// stage's start and at every advance).
    pub fn new(out: Box<dyn Write + Send>, every: Duration) -> Self {
        let shared = Arc::new(Shared {
            every,
            state: Mutex::new(State {
                out,
                stage: None,
                closed: false,
            }),
            wake: Condvar::new(),
        });
        // Without a ticker a stage that does not advance is silent until it ends: the lines
        // are a convenience, so a thread that cannot start is no error.
        let ticker = (!every.is_zero())
            .then(|| {
                let shared = Arc::clone(&shared);
                std::thread::Builder::new()
                    .name("progress lines".into())
                    .spawn(move || shared.tick())
                    .ok()
            })
            .flatten();
        Self { shared, ticker }
    }
}

impl Progress for Lines {
    /// Begins `stage`; a stage still under way is ended first, with its summary (as done).
    fn start(&self, stage: &str, work: Work) {
        let mut state = self.shared.lock();
        state.end_stage(false);
        let now = Instant::now();
        state.stage = Some(Stage {
            name: stage.to_owned(),
            phase: None,
            work,
            done: 0,
            tallies: Vec::new(),
            began: now,
            last_line: now,
        });
        state.report_if_due(self.shared.every, now);
        self.shared.wake.notify_all();
    }

    /// Counts the phase's work from here on; with `every` zero, reports its start.
    fn phase(&self, name: &str, work: Work) {
        let mut state = self.shared.lock();
        if let Some(stage) = &mut state.stage {
            stage.phase = Some(name.to_owned());
            stage.work = work;
            stage.done = 0;
            if self.shared.every.is_zero() {
                state.report_if_due(Duration::ZERO, Instant::now());
            }
        }
    }

    fn advance(&self, n: u64) {
        let mut state = self.shared.lock();
        if let Some(stage) = &mut state.stage {
            stage.done += n;
            state.report_if_due(self.shared.every, Instant::now());
        }
    }

    fn tally(&self, count: u64, what: &'static str) {
        if let Some(stage) = &mut self.shared.lock().stage {
            stage.tallies.push((count, what));
        }
    }

    fn finish(&self) {
        self.shared.lock().end_stage(false);
    }

    fn cut_short(&self) {
        self.shared.lock().end_stage(true);
    }
}

impl Drop for Lines {
    fn drop(&mut self) {
        self.shared.lock().closed = true;
        self.shared.wake.notify_all();
        if let Some(ticker) = self.ticker.take() {
            let _ = ticker.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stream the test reads back after the reporter wrote to it.
    #[derive(Clone, Default)]
    struct Buffer(Arc<Mutex<Vec<u8>>>);

    impl Write for Buffer {
        fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
            self.0.lock().expect("lock").extend_from_slice(bytes);
            Ok(bytes.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    impl Buffer {
        fn lines(&self) -> Vec<String> {
            let bytes = self.0.lock().expect("lock").clone();
            String::from_utf8(bytes)
                .expect("utf-8")
                .lines()
                .map(str::to_owned)
                .collect()
        }
    }

    /// The line with its seconds replaced by `S`, after checking they are a number ≥ 0 with
    /// `decimals` digits after the point.
    fn without_seconds(line: &str, decimals: usize) -> String {
        let body = line.strip_suffix(" s").unwrap_or_else(|| panic!("{line}"));
        let (head, seconds) = body.rsplit_once(' ').unwrap_or_else(|| panic!("{line}"));
        let value: f64 = seconds.parse().unwrap_or_else(|_| panic!("{line}"));
        assert!(value >= 0.0, "{line}");
        assert_eq!(
            seconds.split_once('.').map(|(_, d)| d.len()),
            Some(decimals)
        );
        format!("{head} S s")
    }

    /// Runs a form-factor stage of 4 rows done 2 at a time and a solve of 3 iterations
    /// through a reporter with interval `every`; returns its lines.
    fn two_stages(every: Duration) -> Vec<String> {
        let buffer = Buffer::default();
        let lines = Lines::new(Box::new(buffer.clone()), every);
        lines.start("form factors", Work::of(4, "rows"));
        lines.advance(2);
        lines.advance(2);
        lines.finish();
        lines.start("solve", Work::open_ended("iterations"));
        for _ in 0..3 {
            lines.advance(1);
        }
        lines.tally(3, "iterations");
        lines.tally(120, "links");
        lines.finish();
        drop(lines);
        buffer.lines()
    }

    #[test]
    fn a_zero_interval_reports_the_start_and_every_advance_then_the_summary() {
        let lines = two_stages(Duration::ZERO);
        let progress: Vec<String> = lines
            .iter()
            .filter(|l| !l.contains(" done: "))
            .map(|l| without_seconds(l, 1))
            .collect();
        assert_eq!(
            progress,
            [
                "form factors: 0/4 rows after S s",
                "form factors: 2/4 rows after S s",
                "form factors: 4/4 rows after S s",
                "solve: 0 iterations after S s",
                "solve: 1 iterations after S s",
                "solve: 2 iterations after S s",
                "solve: 3 iterations after S s",
            ]
        );
        let done: Vec<String> = lines
            .iter()
            .filter(|l| l.contains(" done: "))
            .map(|l| without_seconds(l, 2))
            .collect();
        // Without tallies the summary is the work done; with them, the tallies in order.
        assert_eq!(
            done,
            [
                "form factors done: 4 rows in S s",
                "solve done: 3 iterations, 120 links in S s",
            ]
        );
        // Each stage's summary is its last line.
        assert!(lines[3].starts_with("form factors done: "), "{lines:?}");
        assert!(lines[8].starts_with("solve done: "), "{lines:?}");
    }

    #[test]
    fn an_interval_never_reached_leaves_only_the_summaries() {
        // Duration::MAX cannot pass: no progress line can fall due, whatever the machine's
        // speed; the ticker sleeps until the reporter is dropped.
        let lines = two_stages(Duration::MAX);
        let lines: Vec<String> = lines.iter().map(|l| without_seconds(l, 2)).collect();
        assert_eq!(
            lines,
            [
                "form factors done: 4 rows in S s",
                "solve done: 3 iterations, 120 links in S s",
            ]
        );
    }

    #[test]
    fn a_stage_cut_short_or_replaced_says_how_far_it_got() {
        let buffer = Buffer::default();
        let lines = Lines::new(Box::new(buffer.clone()), Duration::MAX);
        lines.start("render", Work::of(256, "tiles"));
        lines.advance(12);
        lines.cut_short();
        lines.start("solve", Work::open_ended("iterations"));
        lines.advance(3);
        lines.tally(3, "iterations");
        lines.cut_short();
        lines.start("form factors", Work::of(64, "rows"));
        lines.advance(16);
        // A new stage ends the one under way with its summary.
        lines.start("display", Work::of(8, "levels"));
        lines.advance(8);
        lines.finish();
        // Reports outside a stage are ignored.
        lines.advance(1);
        lines.tally(5, "pixels");
        lines.finish();
        drop(lines);
        let lines: Vec<String> = buffer
            .lines()
            .iter()
            .map(|l| without_seconds(l, 2))
            .collect();
        assert_eq!(
            lines,
            [
                "render stopped: 12/256 tiles in S s",
                "solve stopped: 3 iterations in S s",
                "form factors done: 16/64 rows in S s",
                "display done: 8 levels in S s",
            ]
        );
    }

    #[test]
    fn a_phase_names_itself_and_counts_its_own_work() {
        let buffer = Buffer::default();
        let lines = Lines::new(Box::new(buffer.clone()), Duration::ZERO);
        lines.start("meshing", Work::open_ended("elements"));
        lines.phase("contacts", Work::open_ended("elements"));
        lines.advance(5);
        lines.phase("near field", Work::of(9, "elements"));
        lines.advance(9);
        lines.tally(2, "patches");
        lines.tally(9, "elements");
        lines.finish();
        drop(lines);
        let lines: Vec<String> = buffer
            .lines()
            .iter()
            .map(|l| without_seconds(l, if l.contains(" done: ") { 2 } else { 1 }))
            .collect();
        assert_eq!(
            lines,
            [
                "meshing: 0 elements after S s",
                "meshing (contacts): 0 elements after S s",
                "meshing (contacts): 5 elements after S s",
                "meshing (near field): 0/9 elements after S s",
                "meshing (near field): 9/9 elements after S s",
                "meshing done: 2 patches, 9 elements in S s",
            ]
        );
    }
}
