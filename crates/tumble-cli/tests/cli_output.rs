//! Trajectory and summary files: the default path, both formats, the summary JSON, and outputs that
//! cannot be written (exit 4, detected before simulating, or mid-run) (reliability.md C02, C04, C08,
//! C11).

mod common;

use assert_cmd::prelude::*;
use common::{files, parse_csv, rows_of, tumble};
use predicates::prelude::*;
use predicates::str::contains;
use std::fs;
use std::path::PathBuf;

#[test]
fn without_out_the_demo_goes_to_out_demo_csv_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let output = tumble(dir.path()).args(["run", "--duration", "0.5"]).assert().success().get_output().clone();
    let stdout = String::from_utf8(output.stdout).unwrap();
    assert!(output.stderr.is_empty(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("out/demo.csv"), "{stdout}");
    assert_eq!(files(dir.path()), [PathBuf::from("out"), PathBuf::from("out/demo.csv")], "no .partial left");
    let rows = parse_csv(&fs::read_to_string(dir.path().join("out/demo.csv")).unwrap());
    // 500 steps, every 10th written (the demo's sample_every), plus t = 0: 51 samples of 6 moving
    // bodies (the floor is fixed)
    assert_eq!(rows.len(), 306);
    let flipper = rows_of(&rows, "flipper");
    assert_eq!(flipper.len(), 51);
    assert_eq!(flipper[0].t, 0.0);
    assert_eq!(flipper[50].t, 0.5);
    assert_eq!(flipper[1].t, 0.01);
    // initial state of the demo's flipper: identity orientation, ω = (0.01, 5, 0.01) rad/s
    assert_eq!(flipper[0].values, [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.01, 5.0, 0.01]);
    // the quaternion stays a unit quaternion
    for row in &rows {
        let q = &row.values[3..7];
        assert!((q.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-12, "{row:?}");
    }
}

#[test]
fn the_table_reports_the_run_and_the_demo_flips() {
    let dir = tempfile::tempdir().unwrap();
    let output = tumble(dir.path()).args(["run", "--duration", "12"]).assert().success().get_output().clone();
    let stdout = String::from_utf8(output.stdout).unwrap();
    for label in [
        "bodies",
        "steps",
        "simulated time",
        "wall time",
        "body-steps/s",
        "energy error",
        "angular momentum error",
        "flips",
        "trajectory",
    ] {
        assert!(stdout.contains(label), "{label} missing from:\n{stdout}");
    }
    // flips every 6.45 s, the first at 3.7 s: two in 12 s, the mean interval and the exact one given;
    // the stable spin never flips
    assert!(stdout.contains("flipper 2 (every 6.4"), "{stdout}");
    assert!(stdout.contains("exact 2K/λ = 6.4506 s), stable 0"), "{stdout}");
    assert!(stdout.contains("12000"), "{stdout}");
    // the thrown box is watched until it lands; the landings are accounted for
    assert!(stdout.contains("box 0 (until its first contact at 0.86 s)"), "{stdout}");
    for label in ["collisions", "friction, resting contact", "energy balance             E₀ − E − lost = "] {
        assert!(stdout.contains(label), "{label} missing from:\n{stdout}");
    }
    assert!(stdout.contains("contacts took energy out"), "{stdout}");
    assert!(!stdout.to_lowercase().contains("nan"), "{stdout}");
}

#[test]
fn json_lines_and_summary_follow_the_contract_and_quiet_prints_nothing() {
    let dir = tempfile::tempdir().unwrap();
    tumble(dir.path())
        .args(["run", "--duration", "0.2", "--integrator", "splitting", "--dt", "0.002"])
        .args(["--sample-every", "1", "--out", "t.jsonl", "--summary", "s.json", "--quiet"])
        .assert()
        .success()
        .stdout("")
        .stderr("");
    let text = fs::read_to_string(dir.path().join("t.jsonl")).unwrap();
    let lines: Vec<serde_json::Value> = text.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    assert_eq!(lines.len(), 101);
    for (i, (line, text)) in lines.iter().zip(text.lines()).enumerate() {
        // serde_json's default parser is not correctly rounded: read `t` with Rust's
        let t: f64 = text.strip_prefix("{\"t\":").unwrap().split(',').next().unwrap().parse().unwrap();
        assert_eq!(t, i as f64 * 0.002, "the exact time of step {i}");
        let bodies = line["bodies"].as_array().unwrap();
        assert_eq!(bodies.len(), 6, "the moving bodies");
        assert_eq!(bodies[0]["name"], "flipper");
        for (key, len) in [("position", 3), ("orientation", 4), ("velocity", 3), ("angular_velocity", 3)] {
            assert_eq!(bodies[0][key].as_array().unwrap().len(), len, "{key}");
        }
    }
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.path().join("s.json")).unwrap()).unwrap();
    assert_eq!(summary["steps"], 100);
    assert!(common::json_close(&summary["simulated_time"], 0.2), "{}", summary["simulated_time"]);
    assert!(summary["wall_time_s"].as_f64().unwrap() > 0.0);
    assert_eq!(summary["bodies"], 7);
    assert_eq!(summary["free_bodies"], 6);
    assert_eq!(summary["integrator"], "splitting");
    assert!(common::json_close(&summary["dt"], 0.002), "{}", summary["dt"]);
    for key in ["initial", "final", "max_relative_error"] {
        assert!(summary["energy"][key].is_f64(), "energy.{key}");
    }
    // gravity's torque about the world origin changes the falling bodies' angular momentum
    assert!(summary["angular_momentum"]["max_relative_error"].as_f64().unwrap() > 0.0);
    // no contact yet at t = 0.2 s
    assert_eq!(summary["contact"]["collisions"], 0);
    for key in ["initial", "final"] {
        assert_eq!(summary["linear_momentum"][key].as_array().unwrap().len(), 3);
        assert_eq!(summary["angular_momentum"][key].as_array().unwrap().len(), 3);
    }
    assert_eq!(summary["stopped"], "completed");
    assert_eq!(summary["samples"], 101);
    let mut names = files(dir.path());
    names.sort();
    assert_eq!(names, [PathBuf::from("s.json"), PathBuf::from("t.jsonl")]);
}

#[test]
fn a_scene_flag_overrides_and_an_existing_output_is_replaced() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("t.csv"), "old\n").unwrap();
    tumble(dir.path()).args(["run", "--duration", "0.01", "--out", "t.csv", "-q"]).assert().success();
    let rows = parse_csv(&fs::read_to_string(dir.path().join("t.csv")).unwrap());
    assert_eq!(rows.len(), 12, "t = 0 and t = 0.01 for six moving bodies");
}

/// Runs `tumble ARGS` in a directory with a regular file `file.txt` and a directory `adir.csv`;
/// checks exit 4 with a message naming `named`, before any simulation (stdout empty, though the
/// run asked for would take minutes), and that no file was added.
fn unwritable(args: &[&str], named: &str) {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("file.txt"), "x").unwrap();
    fs::create_dir(dir.path().join("adir.csv")).unwrap();
    let before = files(dir.path());
    let output = tumble(dir.path()).args(["run", "--duration", "1e4"]).args(args).output().unwrap();
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(4), "{args:?}: {stderr}");
    assert!(stderr.starts_with(&format!("error: cannot write '{named}'")), "{args:?}: {stderr}");
    assert!(output.stdout.is_empty(), "{args:?}: the simulation did not start");
    assert_eq!(files(dir.path()), before, "{args:?}");
}

#[test]
fn an_unwritable_output_is_reported_before_simulating() {
    unwritable(&["--out", "/proc/x.csv"], "/proc/x.csv");
    unwritable(&["--out", "missing-dir/x.csv"], "missing-dir/x.csv");
    unwritable(&["--out", "file.txt/x.csv"], "file.txt/x.csv");
    unwritable(&["--out", "adir.csv"], "adir.csv");
    unwritable(&["--out", "t.csv", "--summary", "/proc/s.json"], "/proc/s.json");
    unwritable(&["--out", "t.csv", "--summary", "file.txt/s.json"], "file.txt/s.json");
}

#[test]
fn a_default_output_directory_that_cannot_be_made_is_exit_4() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("out"), "a file where the directory would go").unwrap();
    tumble(dir.path())
        .args(["run", "--duration", "1e4"])
        .assert()
        .code(4)
        .stdout("")
        .stderr(predicate::str::starts_with("error: cannot write 'out/demo.csv'"));
}

#[test]
fn a_full_disk_mid_run_is_exit_4_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    std::os::unix::fs::symlink("/dev/full", dir.path().join("full.csv")).unwrap();
    // the trajectory (~2 MB) outgrows the 64 KiB buffer: the failure comes mid-run
    tumble(dir.path())
        .args(["run", "--out", "full.csv", "--quiet"])
        .assert()
        .code(4)
        .stdout("")
        .stderr(predicate::str::starts_with("error: cannot write 'full.csv'").and(contains("No space left on device")));
    use std::os::unix::fs::FileTypeExt;
    assert!(fs::metadata("/dev/full").unwrap().file_type().is_char_device(), "the device is still a device");
}

#[test]
fn a_full_disk_for_the_summary_is_exit_4() {
    let dir = tempfile::tempdir().unwrap();
    std::os::unix::fs::symlink("/dev/full", dir.path().join("full.json")).unwrap();
    tumble(dir.path())
        .args(["run", "--duration", "0.01", "--out", "t.csv", "--summary", "full.json", "--quiet"])
        .assert()
        .code(4)
        .stderr(predicate::str::starts_with("error: cannot write 'full.json'"));
}

#[test]
fn a_special_file_is_written_in_place() {
    let dir = tempfile::tempdir().unwrap();
    std::os::unix::fs::symlink("/dev/null", dir.path().join("null.csv")).unwrap();
    tumble(dir.path()).args(["run", "--duration", "0.1", "--out", "null.csv", "-q"]).assert().success();
    assert!(fs::symlink_metadata(dir.path().join("null.csv")).unwrap().file_type().is_symlink());
}

#[test]
fn a_file_size_limit_mid_run_is_exit_4_and_the_previous_file_survives() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("t.csv"), "previous\n").unwrap();
    // a file-size limit of 32 KiB, with SIGXFSZ ignored so that the write fails with EFBIG
    let command = format!("trap '' XFSZ; ulimit -f 64; exec {} run --out t.csv -q", env!("CARGO_BIN_EXE_tumble"));
    let output = std::process::Command::new("sh").args(["-c", &command]).current_dir(dir.path()).output().unwrap();
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(4), "{stderr}");
    assert!(stderr.starts_with("error: cannot write 't.csv': File too large"), "{stderr}");
    assert!(stderr.contains("t.csv.partial"), "{stderr}");
    assert_eq!(fs::read_to_string(dir.path().join("t.csv")).unwrap(), "previous\n", "the previous file survives");
    // what was written before the failure is valid, up to its last whole line
    let partial = fs::read_to_string(dir.path().join("t.csv.partial")).unwrap();
    let rows = parse_csv(&partial[..partial.rfind('\n').unwrap() + 1]);
    assert!(rows.len() > 100, "{}", rows.len());
}

#[test]
fn a_stdout_that_cannot_be_written_is_exit_4_before_simulating() {
    let dir = tempfile::tempdir().unwrap();
    let full = fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
    let output = tumble(dir.path())
        .args(["run", "--duration", "1e4", "--out", "t.csv", "--summary", "s.json"])
        .stdout(full)
        .output()
        .unwrap();
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(4), "{stderr}");
    assert!(stderr.starts_with("error: cannot write to standard output"), "{stderr}");
    assert!(files(dir.path()).is_empty(), "{:?}", files(dir.path()));
}

#[test]
fn the_summary_can_go_to_stdout() {
    let dir = tempfile::tempdir().unwrap();
    let output = tumble(dir.path())
        .args(["run", "--duration", "0.5", "--out", "t.csv", "--summary", "/dev/stdout", "-q"])
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(summary["steps"], 500);
    assert_eq!(files(dir.path()), [PathBuf::from("t.csv")]);
}
