//! SIGINT/SIGTERM mid-run (exit 130, whole rows, summary written) and a closed stdout (no panic)
//! (reliability.md C05, C07).

mod common;

use common::{parse_csv, rows_of, tumble};
use std::fs;
use std::io::{BufRead, BufReader, Read};
use std::process::{Command, Stdio};
use std::time::Duration;

/// Starts a run of the demo long enough never to finish by itself (10⁷ steps of 1 ms), waits until
/// it is simulating, sends `signal`, and checks how it ends.
fn interrupt_with(signal: &str) {
    let dir = tempfile::tempdir().unwrap();
    let mut child = tumble(dir.path())
        .args(["run", "--duration", "10000", "--out", "t.csv", "--summary", "s.json"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // the start line comes after the signal handlers are installed and the outputs opened
    let mut stdout = BufReader::new(child.stdout.take().unwrap());
    let mut first = String::new();
    stdout.read_line(&mut first).unwrap();
    assert!(first.starts_with("running <built-in demo>"), "{first}");
    std::thread::sleep(Duration::from_millis(300));
    let killed = Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status().unwrap();
    assert!(killed.success());
    let mut rest = String::new();
    stdout.read_to_string(&mut rest).unwrap();
    let mut stderr = String::new();
    child.stderr.take().unwrap().read_to_string(&mut stderr).unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{signal}: {stderr}");
    assert!(stderr.contains("interrupted at step"), "{stderr}");
    assert!(rest.contains("(interrupted)"), "the table is printed: {rest}");

    // the trajectory: whole rows, every body at every sample, renamed into place
    let rows = parse_csv(&fs::read_to_string(dir.path().join("t.csv")).unwrap());
    assert!(!dir.path().join("t.csv.partial").exists());
    let flipper = rows_of(&rows, "flipper");
    let stable = rows_of(&rows, "stable");
    assert_eq!(flipper.len(), stable.len());
    let t_last = flipper.last().unwrap().t;
    assert!(t_last > 0.0 && t_last < 10_000.0, "{t_last}");

    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.path().join("s.json")).unwrap()).unwrap();
    assert_eq!(summary["stopped"], "interrupted");
    assert_eq!(summary["samples"].as_u64().unwrap(), flipper.len() as u64);
    let steps = summary["steps"].as_u64().unwrap();
    assert!(steps > 0 && steps < 10_000_000);
    assert!(common::json_close(&summary["simulated_time"], steps as f64 * 1e-3), "{}", summary["simulated_time"]);
    assert!(stderr.contains(&format!("interrupted at step {steps} ")), "{stderr}");
    // the state at the interruption is the last sample
    assert_eq!(t_last, steps as f64 * 1e-3);
}

#[test]
fn sigterm_finishes_the_step_flushes_and_exits_130() {
    interrupt_with("TERM");
}

#[test]
fn sigint_finishes_the_step_flushes_and_exits_130() {
    interrupt_with("INT");
}

#[test]
fn a_closed_stdout_is_no_panic() {
    let dir = tempfile::tempdir().unwrap();
    // the reader goes away before anything is written (as `tumble run | true`)
    let mut child = tumble(dir.path())
        .args(["run", "--duration", "0.3"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let mut stderr = String::new();
    child.stderr.take().unwrap().read_to_string(&mut stderr).unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(0), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.is_empty(), "a closed pipe is a quiet exit: {stderr}");
    assert!(dir.path().join("out/demo.csv").is_file(), "the run itself completed");
}

#[test]
fn a_reader_that_stops_after_ten_bytes_is_no_panic() {
    let dir = tempfile::tempdir().unwrap();
    // `tumble run | head -c 10`
    let mut child = tumble(dir.path())
        .args(["run", "--duration", "0.3"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdout = child.stdout.take().unwrap();
    let mut head = [0u8; 10];
    stdout.read_exact(&mut head).unwrap();
    drop(stdout);
    let mut stderr = String::new();
    child.stderr.take().unwrap().read_to_string(&mut stderr).unwrap();
    let status = child.wait().unwrap();
    assert_eq!(&head, b"running <b");
    assert_eq!(status.code(), Some(0), "{stderr}");
    assert!(stderr.is_empty(), "{stderr}");
}

/// Runs `tumble ARGS` in `dir` with a stdout whose reader has gone before anything is written (as
/// `tumble ... | true`); returns the exit status and stderr.
fn with_a_closed_stdout(dir: &std::path::Path, args: &[&str]) -> (Option<i32>, String) {
    let mut child = tumble(dir).args(args).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    drop(child.stdout.take());
    let mut stderr = String::new();
    child.stderr.take().unwrap().read_to_string(&mut stderr).unwrap();
    (child.wait().unwrap().code(), stderr)
}

#[test]
fn a_closed_pipe_for_the_summary_is_a_quiet_exit_with_the_trajectory_complete() {
    // the README's `--summary /dev/stdout -q`, read by a reader that stops at once
    let dir = tempfile::tempdir().unwrap();
    let args = ["run", "--duration", "0.3", "--out", "t.csv", "--summary", "/dev/stdout", "-q"];
    let (status, stderr) = with_a_closed_stdout(dir.path(), &args);
    assert_eq!(status, Some(0), "{stderr}");
    assert!(stderr.is_empty(), "a closed pipe is a quiet exit: {stderr}");
    // the trajectory is whole: renamed into place, every body sampled up to the end of the run
    assert!(!dir.path().join("t.csv.partial").exists());
    let rows = parse_csv(&fs::read_to_string(dir.path().join("t.csv")).unwrap());
    let (flipper, stable) = (rows_of(&rows, "flipper"), rows_of(&rows, "stable"));
    assert_eq!(flipper.len(), stable.len());
    assert_eq!(flipper.first().unwrap().t, 0.0);
    assert!((flipper.last().unwrap().t - 0.3).abs() < 1e-12, "ends at t = {}", flipper.last().unwrap().t);

    // the same without -q: the start line and the table meet the closed pipe too
    let dir = tempfile::tempdir().unwrap();
    let (status, stderr) = with_a_closed_stdout(dir.path(), &args[..7]);
    assert_eq!(status, Some(0), "{stderr}");
    assert!(stderr.is_empty(), "{stderr}");
    assert!(dir.path().join("t.csv").is_file());

    // a reader that takes the summary whole still gets it
    let dir = tempfile::tempdir().unwrap();
    let output = tumble(dir.path()).args(args).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(summary["stopped"], "completed");
}

#[test]
fn the_commands_that_print_are_quiet_on_a_closed_stdout() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let path = |p: &str| root.join(p).display().to_string();
    let commands = [
        vec!["check".to_string(), path("scenes/demo.toml")],
        vec!["mass".to_string(), path("crates/tumble/tests/fixtures/meshes/cube.obj")],
        vec!["model".to_string(), path("scenes/robots/double_pendulum.urdf")],
        vec!["model".to_string(), path("scenes/robots/double_pendulum.urdf"), "--json".to_string()],
    ];
    for args in commands {
        let dir = tempfile::tempdir().unwrap();
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        // the command prints something when its stdout is read
        let output = tumble(dir.path()).args(&args).output().unwrap();
        assert_eq!(output.status.code(), Some(0), "{args:?}: {}", String::from_utf8_lossy(&output.stderr));
        assert!(!output.stdout.is_empty(), "{args:?} prints nothing");
        let (status, stderr) = with_a_closed_stdout(dir.path(), &args);
        assert_eq!(status, Some(0), "{args:?}: {stderr}");
        assert!(stderr.is_empty(), "{args:?}: {stderr}");
    }
}
