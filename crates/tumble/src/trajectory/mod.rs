//! Trajectory output.
