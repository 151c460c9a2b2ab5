//! Runs longer than a second: the progress bar (only on a terminal, never with --quiet) and the
//! periodic flush that keeps a killed run's output usable (reliability.md C06, R06).

mod common;

use common::{parse_csv, tumble, HEADER};
use std::fs;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Runs `tumble ARGS` under `script`, which gives it a terminal; returns what the terminal showed,
/// or `None` when `script` (util-linux) is not installed.
fn on_a_terminal(dir: &std::path::Path, args: &str) -> Option<String> {
    let command = format!("{} {args}", env!("CARGO_BIN_EXE_tumble"));
    let output = Command::new("script").args(["-qfec", &command, "/dev/null"]).current_dir(dir).output().ok()?;
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stdout));
    Some(String::from_utf8_lossy(&output.stdout).into_owned())
}

#[test]
fn a_long_run_on_a_terminal_shows_a_progress_bar_unless_quiet() {
    let dir = tempfile::tempdir().unwrap();
    // a run that stops at 2.5 s of wall time, whatever the speed of the build
    let run = "run --duration 10000 --max-wall-time 2.5 --out t.csv";
    let Some(screen) = on_a_terminal(dir.path(), run) else {
        eprintln!("skipped: `script` is not installed");
        return;
    };
    assert!(screen.contains("/10000000, "), "no progress bar in:\n{screen}");
    assert!(screen.contains("energy error"), "the table follows:\n{screen}");
    let quiet = on_a_terminal(dir.path(), &format!("{run} --quiet")).unwrap();
    assert!(quiet.is_empty(), "--quiet shows nothing: {quiet}");
}

#[test]
fn a_run_without_a_terminal_shows_no_progress_bar() {
    let dir = tempfile::tempdir().unwrap();
    let output = tumble(dir.path())
        .args(["run", "--duration", "10000", "--max-wall-time", "1.5", "--out", "t.csv"])
        .output()
        .unwrap();
    assert!(output.status.success());
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(stderr.starts_with("stopped at the wall-time limit") && stderr.lines().count() == 1, "{stderr}");
}

#[test]
fn a_killed_run_leaves_a_partial_file_flushed_about_every_second() {
    let dir = tempfile::tempdir().unwrap();
    // one sample every 10⁶ steps: the 64 KiB buffer never fills, only the periodic flush writes
    let mut child = tumble(dir.path())
        .args(["run", "--duration", "100000", "--sample-every", "1000000", "--out", "t.csv", "-q"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let partial = dir.path().join("t.csv.partial");
    let start = Instant::now();
    let mut text = String::new();
    while start.elapsed() < Duration::from_secs(30) {
        text = fs::read_to_string(&partial).unwrap_or_default();
        if text.lines().count() >= 3 {
            break;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(text.starts_with(HEADER), "the initial sample was flushed while running: `{text}`");
    // SIGKILL: what was flushed stays; a partial last line (none here) would be dropped
    let text = fs::read_to_string(&partial).unwrap();
    let whole = &text[..text.rfind('\n').unwrap() + 1];
    let rows = parse_csv(whole);
    assert!(rows.len() >= 2, "{rows:?}");
    assert_eq!(rows[0].t, 0.0);
    assert!(!dir.path().join("t.csv").exists(), "a killed run is never renamed into place");
}

#[test]
fn max_wall_time_stops_after_a_whole_step_with_valid_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let output = tumble(dir.path())
        .args(["run", "--duration", "10000", "--max-wall-time", "0.3", "--out", "t.csv", "--summary", "s.json"])
        .output()
        .unwrap();
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(stderr.starts_with("stopped at the wall-time limit at step "), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.path().join("s.json")).unwrap()).unwrap();
    assert_eq!(summary["stopped"], "wall_time_limit");
    let steps = summary["steps"].as_u64().unwrap();
    assert!(steps > 0 && steps < 10_000_000, "{steps}");
    assert!(summary["wall_time_s"].as_f64().unwrap() >= 0.3);
    let rows = parse_csv(&fs::read_to_string(dir.path().join("t.csv")).unwrap());
    assert_eq!(rows.last().unwrap().t, steps as f64 * 1e-3, "the state where it stopped is written");
}
