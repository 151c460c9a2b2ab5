//! `tumble run --contacts FILE.jsonl`: one line per sample with every active contact of the step
//! that ended there (the contract's "Robots in contact" section), its force the step's impulse over
//! `dt`; bad names and unwritable files refused like the other outputs (exit 2 / exit 4, nothing
//! written).

mod common;

use assert_cmd::prelude::*;
use common::{files, parse_csv, tumble};
use predicates::prelude::*;
use std::fs;
use std::path::Path;

fn scene(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name).to_string_lossy().into_owned()
}

fn lines(path: &Path) -> Vec<serde_json::Value> {
    fs::read_to_string(path).unwrap().lines().map(|l| serde_json::from_str(l).unwrap()).collect()
}

fn vec3(v: &serde_json::Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    assert_eq!(a.len(), 3);
    [0, 1, 2].map(|i| a[i].as_f64().unwrap())
}

#[test]
fn the_bouncing_ball_strikes_then_rests_on_its_weight() {
    let dir = tempfile::tempdir().unwrap();
    tumble(dir.path())
        .args(["run", &scene("bounce.toml"), "--out", "b.csv", "--contacts", "c.jsonl"])
        .assert()
        .success()
        .stdout(predicate::str::contains("c.jsonl (JSON Lines, 1921 samples)"));
    let samples = lines(&dir.path().join("c.jsonl"));
    let rows = parse_csv(&fs::read_to_string(dir.path().join("b.csv")).unwrap());
    // one line per trajectory sample, at the same times
    assert_eq!(samples.len(), rows.len());
    for (s, r) in samples.iter().zip(&rows) {
        assert_eq!(s["t"].as_f64().unwrap(), r.t);
    }
    assert_eq!(samples[0]["contacts"].as_array().unwrap().len(), 0, "no step ends at t = 0");
    // the ball (density 800 kg/m³, radius 0.1 m) and the first impact, at √(2·2/9.81) = 0.639 s, with
    // e = 0.7: an impulse of m (1 + e) v over one step of 1/480 s
    let m = 800.0 * 4.0 / 3.0 * std::f64::consts::PI * 1e-3;
    let dt = 1.0 / 480.0;
    let first = samples.iter().find(|s| !s["contacts"].as_array().unwrap().is_empty()).unwrap();
    let t_first = first["t"].as_f64().unwrap();
    assert!((t_first - (4.0f64 / 9.81).sqrt()).abs() < dt, "first contact at {t_first} s");
    let c = &first["contacts"][0];
    assert_eq!((c["a"].as_str(), c["b"].as_str()), (Some("floor"), Some("ball")));
    assert_eq!(vec3(&c["normal"]), [0.0, 0.0, 1.0]);
    let v = (2.0f64 * 9.81 * 2.0).sqrt();
    let fz = vec3(&c["force"])[2];
    assert!((fz * dt / (m * 1.7 * v) - 1.0).abs() < 0.02, "impact force {fz} N");
    // at the end the ball rests: the floor holds its weight, nothing else
    let last = samples.last().unwrap()["contacts"].as_array().unwrap();
    assert_eq!(last.len(), 1);
    let f = vec3(&last[0]["force"]);
    assert!((f[2] / (m * 9.81) - 1.0).abs() < 1e-6, "resting force {f:?} N, weight {} N", m * 9.81);
    assert!(f[0].abs() + f[1].abs() < 1e-12);
    let depth = last[0]["depth"].as_f64().unwrap();
    assert!(depth.abs() < 1e-3, "depth {depth} m");
}

#[test]
fn a_contacts_file_must_be_json_lines_and_not_another_output() {
    let dir = tempfile::tempdir().unwrap();
    for (args, message) in [
        (&["--contacts", "c.csv"][..], "--contacts c.csv: the contacts file is JSON Lines; name it FILE.jsonl"),
        (&["--out", "t.jsonl", "--contacts", "t.jsonl"][..], "--contacts t.jsonl: the same file as --out t.jsonl"),
        (&["--summary", "s.jsonl", "--contacts", "s.jsonl"][..], "the same file as --summary s.jsonl"),
    ] {
        tumble(dir.path())
            .args(["run", "--duration", "0.1"])
            .args(args)
            .assert()
            .code(2)
            .stdout("")
            .stderr(predicate::str::starts_with("error: ").and(predicate::str::contains(message)));
        assert!(files(dir.path()).is_empty(), "{args:?}: nothing written");
    }
}

#[test]
fn an_unwritable_contacts_file_is_exit_4_before_simulating() {
    for path in ["/proc/c.jsonl", "missing-dir/c.jsonl"] {
        let dir = tempfile::tempdir().unwrap();
        let output = tumble(dir.path())
            .args(["run", "--duration", "1e4", "--out", "t.csv", "--contacts", path])
            .output()
            .unwrap();
        let stderr = String::from_utf8(output.stderr).unwrap();
        assert_eq!(output.status.code(), Some(4), "{stderr}");
        assert!(stderr.starts_with(&format!("error: cannot write '{path}'")), "{stderr}");
        assert!(output.stdout.is_empty());
        assert!(files(dir.path()).is_empty(), "{path}: the trajectory's file was removed too");
    }
}

#[test]
fn a_full_disk_for_the_contacts_is_exit_4_and_the_trajectory_is_kept() {
    let dir = tempfile::tempdir().unwrap();
    std::os::unix::fs::symlink("/dev/full", dir.path().join("full.jsonl")).unwrap();
    // the pyramid's contacts (about 400 per sample) outgrow the 64 KiB buffer at once
    let output = tumble(dir.path())
        .args(["run", &scene("pyramid.toml"), "--duration", "0.5", "--out", "t.csv", "--contacts", "full.jsonl", "-q"])
        .output()
        .unwrap();
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(4), "{stderr}");
    assert!(
        stderr.starts_with("error: cannot write 'full.jsonl'") && stderr.contains("No space left on device"),
        "{stderr}"
    );
    // the trajectory written so far stays, whole rows, in its .partial file, and the message says where
    assert!(stderr.contains("t.csv.partial"), "{stderr}");
    let partial = fs::read_to_string(dir.path().join("t.csv.partial")).unwrap();
    assert!(!parse_csv(&partial).is_empty());
}

/// A robot's links in the contacts file, named `robot/link`: the quadruped of `scenes/quadruped.toml`
/// stands on its four feet (`a` the ground, `b` the foot, normal up), whose normal forces carry its
/// 4.6 kg at the end of the run.
#[test]
fn a_standing_robot_lists_its_feet_and_their_forces_carry_its_weight() {
    let dir = tempfile::tempdir().unwrap();
    tumble(dir.path())
        .args(["run", &scene("quadruped.toml"), "--out", "q.csv", "--contacts", "c.jsonl", "--quiet"])
        .assert()
        .success();
    let samples = lines(&dir.path().join("c.jsonl"));
    let last = samples.last().unwrap()["contacts"].as_array().unwrap();
    let mut feet: Vec<&str> = last.iter().map(|c| c["b"].as_str().unwrap()).collect();
    feet.sort_unstable();
    assert_eq!(feet, ["quad/FL_foot", "quad/FR_foot", "quad/HL_foot", "quad/HR_foot"]);
    for c in last {
        assert_eq!(c["a"].as_str(), Some("ground"));
        assert_eq!(vec3(&c["normal"]), [0.0, 0.0, 1.0]);
        assert!(c["depth"].as_f64().unwrap() < 1e-3);
    }
    let weight = 4.6 * 9.81;
    let fz: f64 = last.iter().map(|c| vec3(&c["force"])[2]).sum();
    assert!((fz / weight - 1.0).abs() < 5e-3, "the feet carry {fz} N, the weight is {weight} N");
}
