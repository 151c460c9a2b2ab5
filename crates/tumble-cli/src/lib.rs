//! The `tumble` command-line tool.
//!
//! - [`cli`]: the command line (clap).
//! - [`run`]: `tumble run`: load, validate, open the outputs, simulate, report.
//! - [`check`]: `tumble check`: load, validate, describe.
//! - [`plot`]: `tumble plot` (and `run --plot`): stacked panels over time, SVG or PNG.
//! - [`view`]: `tumble view` (and `run --view`): a 3D replay in one self-contained HTML file.
//! - [`mass`]: `tumble mass`: the mass properties of a mesh, as JSON.
//! - [`model`]: `tumble model`: the joint layout of a URDF robot.
//! - [`dynamics`]: `tumble dynamics`: mass matrix, bias, forward and inverse dynamics; `--bench`.
//! - [`output`]: output files, written beside the target and renamed into place.
//! - [`report`]: the printed summary table and the progress bar.
//! - [`signal`]: SIGINT/SIGTERM end a run cleanly after the current step.
//! - [`error`]: exit statuses.
//!
//! Exit statuses (the contract): 0 success; 2 bad input (scene, flags, files), nothing written;
//! 3 the simulation diverged, what was written stays valid; 4 the output could not be written;
//! 130 interrupted.
#![forbid(unsafe_code)]

pub mod check;
pub mod cli;
pub mod dynamics;
pub mod error;
pub mod mass;
pub mod model;
pub mod output;
pub mod plot;
pub mod report;
pub mod run;
pub mod signal;
pub mod view;

use clap::Parser;
use error::Status;
use std::io::Write;
use std::process::ExitCode;

/// Parses the command line, runs the command, prints any error on stderr, and gives the exit status.
pub fn main() -> ExitCode {
    let cli = match cli::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // usage errors go to stderr with status 2; --help and --version to stdout with 0
            let status = if e.use_stderr() { Status::BadInput } else { Status::Success };
            let _ = e.print();
            return status.into();
        }
    };
    let result = match cli.command {
        cli::Command::Run(args) => run::run(&args),
        cli::Command::Check(args) => check::check(&args),
        cli::Command::Plot(args) => plot::plot(&args),
        cli::Command::View(args) => view::view(&args),
        cli::Command::Mass(args) => mass::mass(&args),
        cli::Command::Model(args) => model::model(&args),
        cli::Command::Dynamics(args) => dynamics::dynamics(&args),
    };
    match result {
        Ok(status) => status.into(),
        Err(failure) => {
            // never panic on a closed stderr: the status still tells
            let _ = writeln!(std::io::stderr().lock(), "error: {:#}", failure.error);
            failure.status.into()
        }
    }
}
