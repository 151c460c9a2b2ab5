//! Exit statuses and the error that carries one.

use std::fmt::Display;
use std::process::ExitCode;

/// The exit status of `tumble` (the contract).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// 0: success.
    Success = 0,
    /// 2: bad input (scene, flags, files); nothing was written.
    BadInput = 2,
    /// 3: the simulation diverged; what was written so far is valid.
    Diverged = 3,
    /// 4: an output could not be written.
    Output = 4,
    /// 130: interrupted by SIGINT or SIGTERM after a whole step; outputs are closed and valid.
    Interrupted = 130,
}

impl From<Status> for ExitCode {
    fn from(status: Status) -> ExitCode {
        ExitCode::from(status as u8)
    }
}

/// An error to print (`error: …` on stderr) and the status to exit with.
#[derive(Debug)]
pub struct Failure {
    pub status: Status,
    pub error: anyhow::Error,
}

impl Failure {
    /// Bad input: exit 2.
    pub fn bad_input(message: impl Display) -> Self {
        Self { status: Status::BadInput, error: anyhow::anyhow!("{message}") }
    }

    /// An output that cannot be written: exit 4.
    pub fn output(message: impl Display) -> Self {
        Self { status: Status::Output, error: anyhow::anyhow!("{message}") }
    }

    /// A simulation that diverged: exit 3.
    pub fn diverged(message: impl Display) -> Self {
        Self { status: Status::Diverged, error: anyhow::anyhow!("{message}") }
    }
}
