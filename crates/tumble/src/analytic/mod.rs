//! Exact reference solutions.
