//! `radiosity` — the command-line program of the radiosity renderer.
//!
//! ```text
//! radiosity render [SCENE] [-o out.png]... [--stats stats.json] [--export lit.ply]
//! radiosity solve SCENE --export lit.ply --stats stats.json
//! radiosity render SCENE --mode local|radiosity|raytrace [--gather N]
//! radiosity render SCENE --false-colour lux|luminance [--false-colour-scale log|linear]
//!     [--false-colour-range MIN:MAX] -o lux.png -o lux.pfm
//! radiosity compare SCENE -o compare.png
//! radiosity scenes
//! radiosity hemicube SCENE --element ID -o hemicube.png [--resolution N] [--heatmap]
//! radiosity info SCENE
//! radiosity info LUMINAIRE.ies|LUMINAIRE.ldt
//! radiosity solve SCENE --export scene.html --plot convergence.svg
//! ```
//!
//! Progress goes to stderr: bars on a terminal; otherwise (a log file, CI) a line as each stage
//! ends, `STAGE done: COUNT WHAT, ... in S s`, and `STAGE (PHASE): DONE/TOTAL UNIT after S s`
//! every `--progress-every` seconds within it (see `progress/lines.rs`); `--quiet` silences
//! both.
//!
//! Every failure prints one line `error: <cause>` on stderr (naming the file, line and key when
//! the cause is in a scene) and exits with status 2; outputs are written atomically, so a failed
//! run leaves no partial file. Ctrl-C stops a solve between iterations: the solution so far is
//! written to the requested outputs, the run says so and exits with status 130 (a second Ctrl-C
//! ends it at once); `--checkpoint FILE` saves the solver state and `--resume FILE` continues.
#![forbid(unsafe_code)]

mod args;
mod bake;
mod compare;
mod corpus;
mod curve;
mod false_colour;
mod hemicube;
mod info;
mod interrupt;
mod job;
mod photometric;
mod picture;
mod progress;
mod settings;
mod solver;
mod validate;
mod warnings;

use std::io::Write;
use std::process::ExitCode;

use clap::Parser;

use args::{Cli, Command};

/// Exit status of every failure: bad input, bad flags, unwritable outputs.
const FAILURE: u8 = 2;
/// Exit status of a solve stopped by Ctrl-C after writing its outputs (128 + SIGINT).
const INTERRUPTED: u8 = 130;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if e.use_stderr() => return fail(&e.to_string()),
        Err(e) => {
            // --help and --version: clap prints them on stdout.
            return match e.print() {
                Ok(()) => ExitCode::SUCCESS,
                Err(_) => ExitCode::from(FAILURE),
            };
        }
    };
    let result = match cli.command {
        Command::Render(args) => job::render(&args),
        Command::Solve(args) => job::solve(&args),
        Command::Bake(args) => bake::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::Scenes => list_scenes(),
        Command::Info(args) => info::run(&args),
        Command::Hemicube(args) => hemicube::run(&args),
        Command::Curve(args) => curve::run(&args),
        Command::Validate(args) => validate::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if e.is::<interrupt::Interrupted>() => {
            let _ = writeln!(std::io::stderr(), "{e}");
            ExitCode::from(INTERRUPTED)
        }
        Err(e) => fail(&format!("{e:#}")),
    }
}

/// Prints `error: <cause>` as one line on stderr and returns the failure status.
///
/// Multi-line causes are folded; clap's usage and help hints (from `Usage:` on) are left out.
fn fail(message: &str) -> ExitCode {
    let line = message
        .lines()
        .map(str::trim)
        .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ");
    let cause = line.strip_prefix("error: ").unwrap_or(&line);
    let _ = writeln!(std::io::stderr(), "error: {cause}");
    ExitCode::from(FAILURE)
}

/// `radiosity scenes`: one built-in scene per line, name and description.
fn list_scenes() -> anyhow::Result<()> {
    let names = radiosity::scene::builtin::names();
    let width = names.iter().map(|(n, _)| n.len()).max().unwrap_or(0);
    let mut out = std::io::stdout().lock();
    for (name, description) in names {
        writeln!(out, "{name:width$}  {description}")?;
    }
    Ok(())
}
