//! Helpers shared by the command-line tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The CSV header of the contract.
pub const HEADER: &str = "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz";

/// `tumble` with its working directory in `dir`.
pub fn tumble(dir: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_tumble"));
    command.current_dir(dir);
    command
}

/// Every entry under `dir`, recursively, relative to it, sorted.
pub fn files(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            found.push(path.strip_prefix(dir).unwrap().to_path_buf());
            if path.is_dir() && !path.is_symlink() {
                stack.push(path);
            }
        }
    }
    found.sort();
    found
}

/// One parsed CSV row: time, body, and the 13 numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub t: f64,
    pub body: String,
    pub values: Vec<f64>,
}

/// Parses a whole trajectory CSV, checking the header, that every row is complete, that every
/// number is finite and written as the shortest text that reads back to it.
pub fn parse_csv(text: &str) -> Vec<Row> {
    assert!(text.ends_with('\n'), "the file ends with a whole row");
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(HEADER));
    lines
        .map(|line| {
            let fields: Vec<&str> = line.split(',').collect();
            assert_eq!(fields.len(), 15, "row `{line}`");
            let numbers: Vec<f64> = fields
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != 1)
                .map(|(_, f)| {
                    let x: f64 = f.parse().unwrap_or_else(|e| panic!("`{f}` in `{line}`: {e}"));
                    assert!(x.is_finite(), "`{f}` in `{line}`");
                    assert_eq!(ryu::Buffer::new().format_finite(x), *f, "shortest round-trip text");
                    x
                })
                .collect();
            Row { t: numbers[0], body: fields[1].to_string(), values: numbers[1..].to_vec() }
        })
        .collect()
}

/// The rows of one body.
pub fn rows_of<'a>(rows: &'a [Row], body: &str) -> Vec<&'a Row> {
    rows.iter().filter(|r| r.body == body).collect()
}

/// A number read from JSON with serde_json, whose default parser is not correctly rounded (it may
/// be one or two ulps off): equal to `expected` within 4 ulps.
pub fn json_close(value: &serde_json::Value, expected: f64) -> bool {
    let got = value.as_f64().unwrap_or(f64::NAN);
    (got - expected).abs() <= 4.0 * f64::EPSILON * expected.abs()
}
