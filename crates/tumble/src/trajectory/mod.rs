//! Trajectory output and the run summary.
//!
//! - [`TrajectoryWriter`]: CSV or JSON Lines, one sample per call, buffered, no allocation per sample.
//! - [`Monitor`]: the invariants of a run (energy, linear and angular momentum) and the flips of
//!   bodies turning about their intermediate principal axis, observed at every sample.
//! - [`Summary`]: what a run did, serialised as the summary JSON of the contract.
//! - [`read`](mod@read): trajectories read back into frames, with precise errors; [`derived`]: the invariants
//!   and body-frame angular velocity of the frames read back (for plots and the replay).
//!
//! Everything written is in the world frame and SI units: position of the centre of mass (m),
//! orientation `[w, x, y, z]` of the body axes the user gave (`world_from_user`), velocity of the
//! centre of mass (m/s), angular velocity (rad/s). Numbers are written as the shortest text that reads
//! back to the same `f64` (`ryu`), so re-reading a file gives the exact values (Python's `float` and
//! `json` read them exactly; serde_json needs its `float_roundtrip` feature). A non-finite value is
//! never written: it is an error ([`TrajectoryError::NonFinite`]).
//!
//! CSV (header exactly as below, one row per sample per non-fixed body):
//!
//! ```text
//! t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz
//! ```
//!
//! JSON Lines (one object per sample):
//!
//! ```text
//! {"t":0.0,"bodies":[{"name":"a","position":[..],"orientation":[..],"velocity":[..],"angular_velocity":[..]}]}
//! ```

mod contacts;
pub mod derived;
mod monitor;
pub mod read;
mod summary;
mod writer;
pub(crate) use writer::body_row;

pub use contacts::ContactWriter;
pub use monitor::{relative_error, EnergyRise, FlipCounter, Invariants, Monitor, ENERGY_RISE};
pub use read::{read, BodySample, Frame, ReadError, ReadOptions, Trajectory, Truncation};
pub use summary::{AngularMomentumSummary, EnergySummary, FlipSummary, LinearMomentumSummary, StopReason, Summary};
pub use summary::{JointStepsSummary, ProfileSummary, RobotSummary, TendonStepsSummary};
pub use writer::{TrajectoryWriter, CSV_HEADER};

use std::path::Path;

/// A trajectory file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Comma-separated values with a header line (`.csv`).
    Csv,
    /// One JSON object per line and per sample (`.jsonl`).
    JsonLines,
}

impl Format {
    /// The format named by a file's extension: `.csv` or `.jsonl` (case-insensitive); `None` otherwise.
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "csv" => Some(Format::Csv),
            "jsonl" => Some(Format::JsonLines),
            _ => None,
        }
    }

    /// The usual extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Csv => "csv",
            Format::JsonLines => "jsonl",
        }
    }
}

/// Why a trajectory or summary could not be written.
#[derive(Debug, thiserror::Error)]
pub enum TrajectoryError {
    /// The sink failed (disk full, closed pipe, ...).
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// A value to be written is NaN or infinite; nothing of that sample was written.
    #[error("body `{body}`: {quantity} is not finite at t = {time} s; it was not written")]
    NonFinite {
        /// The body's name.
        body: String,
        /// Which quantity, e.g. `velocity`.
        quantity: &'static str,
        /// The sample's time (s).
        time: f64,
    },
    /// A summary field is not finite.
    #[error("summary field `{field}` is not finite; the summary was not written")]
    NonFiniteSummary {
        /// The field path, e.g. `energy.final`.
        field: String,
    },
    /// The world handed to the writer does not have the bodies it was created for.
    #[error("the world has {got} bodies, the trajectory was started with {expected}")]
    BodiesChanged {
        /// Bodies when the writer was created.
        expected: usize,
        /// Bodies now.
        got: usize,
    },
}

#[cfg(test)]
mod tests;
