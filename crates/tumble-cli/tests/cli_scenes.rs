//! `tumble run` and `tumble check` on scene files: divergence (exit 3, valid output up to the last
//! finite state), scene errors (exit 2, file:line:col, nothing written), warnings, flag overrides,
//! default output paths, and every scene shipped in `scenes/`.

mod common;

use assert_cmd::prelude::*;
use common::{files, parse_csv, rows_of, tumble};
use predicates::prelude::*;
use predicates::str::contains;
use std::fs;
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&fs::read_to_string(path).unwrap()).unwrap()
}

/// A body driven by a torque of 1.05e12 N·m about a unit moment: its spin passes the sanity bound
/// of 1e10 rad/s between t = 9 ms and t = 10 ms (step 10 of 1 ms).
const RUNAWAY: &str = r#"
version = 1

[world]
gravity = [0.0, 0.0, 0.0]
dt = 0.001
duration = 1.0
sample_every = 4

[[body]]
name = "calm"
mass = 1.0
inertia = [1.0, 2.0, 3.0]
angular_velocity = [0.0, 1.0, 0.0]

[[body]]
name = "runaway"
mass = 1.0
inertia = [1.0, 1.0, 1.0]
position = [2.0, 0.0, 0.0]
torque_body = [0.0, 0.0, 1.05e12]
"#;

#[test]
fn a_diverging_run_is_exit_3_naming_body_quantity_step_and_time_and_its_output_stays_valid() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("runaway.toml"), RUNAWAY).unwrap();
    let output = tumble(dir.path())
        .args(["run", "runaway.toml", "--out", "t.csv", "--summary", "s.json"])
        .assert()
        .code(3)
        .get_output()
        .clone();
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(stderr.starts_with("error: simulation diverged: body `runaway`"), "{stderr}");
    assert!(stderr.contains("angular velocity"), "{stderr}");
    assert!(stderr.contains("at step 10, t = 0.01 s"), "{stderr}");
    assert!(stderr.contains("t.csv"), "{stderr}");

    // samples at steps 0, 4, 8, then the last finite state, step 9
    let rows = parse_csv(&fs::read_to_string(dir.path().join("t.csv")).unwrap());
    let runaway: Vec<f64> = rows_of(&rows, "runaway").iter().map(|r| r.t).collect();
    assert_eq!(runaway, [0.0, 4.0, 8.0, 9.0].map(|n| n * 0.001), "t = steps · dt exactly");
    assert_eq!(rows_of(&rows, "calm").len(), 4);
    let spin = rows_of(&rows, "runaway").last().unwrap().values[12];
    assert!((spin - 1.05e12 * 0.009).abs() < 1.0, "ω_z = τ t at the last finite state: {spin}");

    let summary = read_json(&dir.path().join("s.json"));
    assert_eq!(summary["stopped"], "diverged");
    assert_eq!(summary["steps"], 9);
    assert_eq!(summary["samples"], 4);
    assert!(common::json_close(&summary["simulated_time"], 9.0 * 0.001), "{}", summary["simulated_time"]);
    let mut names = files(dir.path());
    names.sort();
    assert_eq!(names, ["runaway.toml", "s.json", "t.csv"].map(PathBuf::from), "no .partial left");
}

/// Four balls moving towards one point with a pair budget of 3 (`[world] max_pairs`): the step at
/// which their four pairs appear goes over it.
const CONVERGING: &str = "version = 1\n[world]\ngravity = [0.0, 0.0, 0.0]\ndt = 0.01\nduration = 4.0\n\
                          sample_every = 10\nmax_pairs = 3\n\
                          [[body]]\nname = \"east\"\nmass = 1.0\nshape = { type = \"sphere\", radius = 0.5 }\n\
                          position = [3.0, 0.0, 0.0]\nvelocity = [-1.0, 0.0, 0.0]\n\
                          [[body]]\nname = \"west\"\nmass = 1.0\nshape = { type = \"sphere\", radius = 0.5 }\n\
                          position = [-3.0, 0.0, 0.0]\nvelocity = [1.0, 0.0, 0.0]\n\
                          [[body]]\nname = \"north\"\nmass = 1.0\nshape = { type = \"sphere\", radius = 0.5 }\n\
                          position = [0.0, 3.0, 0.0]\nvelocity = [0.0, -1.0, 0.0]\n\
                          [[body]]\nname = \"south\"\nmass = 1.0\nshape = { type = \"sphere\", radius = 0.5 }\n\
                          position = [0.0, -3.0, 0.0]\nvelocity = [0.0, 1.0, 0.0]\n";

#[test]
fn a_run_over_the_contact_budget_is_exit_3_and_its_output_stays_valid() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("c.toml"), CONVERGING).unwrap();
    let output = tumble(dir.path())
        .args(["run", "c.toml", "--out", "t.csv", "--summary", "s.json", "-q"])
        .assert()
        .code(3)
        .get_output()
        .clone();
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(stderr.starts_with("error: contact budget exceeded at step "), "{stderr}");
    assert!(stderr.contains("4 candidate pairs, more than the budget of 3"), "{stderr}");
    assert!(stderr.contains("t.csv"), "{stderr}");
    let summary = read_json(&dir.path().join("s.json"));
    assert_eq!(summary["stopped"], "contact_budget");
    let steps = summary["steps"].as_u64().unwrap();
    assert!(stderr.contains(&format!("at step {} (t = ", steps + 1)), "{stderr}");
    // every sample up to the last step taken, the last one included, all four balls in each
    let rows = parse_csv(&fs::read_to_string(dir.path().join("t.csv")).unwrap());
    let times: Vec<f64> = rows_of(&rows, "east").iter().map(|r| r.t).collect();
    assert_eq!(times.len() as u64, steps / 10 + 1 + u64::from(!steps.is_multiple_of(10)));
    assert_eq!(*times.last().unwrap(), steps as f64 * 0.01);
    assert_eq!(rows.len(), 4 * times.len());
    let mut names = files(dir.path());
    names.sort();
    assert_eq!(names, ["c.toml", "s.json", "t.csv"].map(PathBuf::from), "no .partial left");
}

/// 20,000 balls at one spot (`spacing = [0, 0, 0]`): refused at load, nothing written.
#[test]
fn a_grid_at_one_spot_is_exit_2_naming_its_spacing() {
    let dir = tempfile::tempdir().unwrap();
    let heap = "version = 1\n[[grid]]\ncount = [20, 20, 50]\nspacing = [0.0, 0.0, 0.0]\n\
                [grid.body]\nname = \"ball\"\nmass = 1.0\nshape = { type = \"sphere\", radius = 0.5 }\n";
    fs::write(dir.path().join("heap.toml"), heap).unwrap();
    tumble(dir.path()).args(["run", "heap.toml", "--out", "t.csv"]).assert().code(2).stderr(
        contains("heap.toml:4:11: grid[0].spacing").and(contains("all at one spot")).and(contains("max_pairs")),
    );
    assert_eq!(files(dir.path()), [PathBuf::from("heap.toml")]);
}

#[test]
fn a_diverging_run_in_json_lines_stays_valid() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("runaway.toml"), RUNAWAY).unwrap();
    tumble(dir.path()).args(["run", "runaway.toml", "--out", "t.jsonl", "-q"]).assert().code(3);
    let text = fs::read_to_string(dir.path().join("t.jsonl")).unwrap();
    let lines: Vec<serde_json::Value> = text.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    assert_eq!(lines.len(), 4);
    assert!(!text.contains("null") && !text.contains("NaN"));
}

#[test]
fn a_scene_error_is_exit_2_with_file_line_column_and_nothing_written() {
    let dir = tempfile::tempdir().unwrap();
    let bad = "version = 1\n\n[[body]]\nname = \"a\"\nmass = -1.0\ninertia = [1.0, 2.0, 3.0]\n";
    fs::write(dir.path().join("bad.toml"), bad).unwrap();
    for command in ["run", "check"] {
        tumble(dir.path())
            .args([command, "bad.toml"])
            .assert()
            .code(2)
            .stdout("")
            .stderr(predicate::str::starts_with("error: bad.toml:5:8: body[0].mass:").and(contains("(got -1)")));
        assert_eq!(files(dir.path()), [PathBuf::from("bad.toml")], "{command}");
    }
    fs::write(dir.path().join("syntax.toml"), "version = 1\n[[body]\n").unwrap();
    tumble(dir.path()).args(["run", "syntax.toml"]).assert().code(2).stderr(contains("syntax.toml:2:"));
    tumble(dir.path()).args(["run", "."]).assert().code(2).stderr(predicate::str::starts_with("error: "));
    fs::write(dir.path().join("binary.toml"), b"version = 1\n\xff\xfe\n").unwrap();
    tumble(dir.path())
        .args(["run", "binary.toml"])
        .assert()
        .code(2)
        .stderr(predicate::str::starts_with("error: binary.toml:").and(contains("UTF-8")));
    assert_eq!(files(dir.path()).len(), 3, "{:?}", files(dir.path()));
}

#[test]
fn a_gravity_scale_that_is_not_finite_is_exit_2_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let bad = "version = 1\n\n[[body]]\nname = \"a\"\nmass = 1.0\ninertia = [1.0, 2.0, 3.0]\ngravity_scale = nan\n";
    fs::write(dir.path().join("g.toml"), bad).unwrap();
    for command in ["run", "check"] {
        tumble(dir.path())
            .args([command, "g.toml"])
            .assert()
            .code(2)
            .stdout("")
            .stderr(predicate::str::starts_with("error: g.toml:7:17: body[0].gravity_scale: must be finite"));
        assert_eq!(files(dir.path()), [PathBuf::from("g.toml")], "{command}");
    }
}

/// `[world] threads`: an integer ≥ 0; anything else is exit 2 naming the file, line, column and
/// key; `--threads` overrides it and is checked the same way; the trajectory does not depend on it.
#[test]
fn the_threads_setting_is_checked_and_changes_no_number() {
    let dir = tempfile::tempdir().unwrap();
    for (value, expected) in [("-2", "t.toml:3:11: world.threads: must be an integer ≥ 0"), ("1.5", "t.toml:3:")] {
        fs::write(dir.path().join("t.toml"), format!("version = 1\n[world]\nthreads = {value}\n")).unwrap();
        tumble(dir.path())
            .args(["run", "t.toml"])
            .assert()
            .code(2)
            .stdout("")
            .stderr(predicate::str::starts_with(format!("error: {expected}")));
    }
    fs::write(dir.path().join("t.toml"), "version = 1\n[world]\nthreads = 5000\n").unwrap();
    tumble(dir.path()).args(["run", "t.toml"]).assert().code(2).stderr(contains("world.threads: must be at most 1024"));
    tumble(dir.path())
        .args(["run", "--threads", "5000"])
        .assert()
        .code(2)
        .stderr(predicate::str::starts_with("error: --threads: must be at most 1024"));
    tumble(dir.path()).args(["run", "--threads", "-1"]).assert().code(2);
    // the balls on one and on two threads: the same trajectory, byte for byte
    let balls = scenes_dir().join("balls.toml");
    for threads in ["1", "2"] {
        tumble(dir.path())
            .arg("run")
            .arg(&balls)
            .args(["--duration", "1", "-q", "--threads", threads, "--out", &format!("b{threads}.csv")])
            .assert()
            .success();
    }
    let one = fs::read(dir.path().join("b1.csv")).unwrap();
    assert!(one.len() > 1000);
    assert_eq!(one, fs::read(dir.path().join("b2.csv")).unwrap());
}

#[test]
fn flags_override_the_world_table() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("r.toml"), RUNAWAY.replace("torque_body = [0.0, 0.0, 1.05e12]", "")).unwrap();
    tumble(dir.path())
        .args(["run", "r.toml", "--dt", "0.005", "--duration", "0.1", "--integrator", "dopri5"])
        .args(["--sample-every", "1", "--summary", "s.json", "-q"])
        .assert()
        .success();
    let summary = read_json(&dir.path().join("s.json"));
    assert!(common::json_close(&summary["dt"], 0.005), "{}", summary["dt"]);
    assert_eq!(summary["steps"], 20);
    assert_eq!(summary["integrator"], "dopri5");
    assert_eq!(summary["samples"], 21);
    // the default output of a scene: out/<scene name>.csv
    let rows = parse_csv(&fs::read_to_string(dir.path().join("out/r.csv")).unwrap());
    assert_eq!(rows.len(), 42);
}

#[test]
fn a_flag_that_breaks_the_scene_world_is_named() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("r.toml"), RUNAWAY).unwrap();
    tumble(dir.path())
        .args(["run", "r.toml", "--dt", "0"])
        .assert()
        .code(2)
        .stderr(predicate::str::starts_with("error: --dt: must be finite and > 0 (got 0)"));
    assert_eq!(files(dir.path()), [PathBuf::from("r.toml")]);
}

#[test]
fn warnings_are_shown_by_check_and_run_but_not_with_quiet() {
    let dir = tempfile::tempdir().unwrap();
    let scene = RUNAWAY
        .replace("torque_body = [0.0, 0.0, 1.05e12]", "")
        .replace("position = [2.0, 0.0, 0.0]", "position = [2.0, 0.0, 0.0]\norientation = [1.0001, 0.0, 0.0, 0.0]");
    fs::write(dir.path().join("w.toml"), scene).unwrap();
    tumble(dir.path())
        .args(["check", "w.toml"])
        .assert()
        .success()
        .stdout(contains("warning: w.toml:").and(contains("not a unit quaternion")).and(contains("runaway")));
    tumble(dir.path())
        .args(["run", "w.toml", "--duration", "0.01"])
        .assert()
        .success()
        .stderr(predicate::str::starts_with("warning: w.toml:"));
    tumble(dir.path()).args(["run", "w.toml", "--duration", "0.01", "-q"]).assert().success().stdout("").stderr("");
}

/// Two unit cubes at rest, the second 0.7 m from the first: they overlap by 0.3 m.
const OVERLAPPING: &str = r#"
version = 1

[world]
gravity = [0.0, 0.0, 0.0]
dt = 0.001
duration = 2.0
sample_every = 10

[[body]]
name = "left"
mass = 1.0
shape = { type = "box", half_extents = [0.5, 0.5, 0.5] }

[[body]]
name = "right"
mass = 1.0
shape = { type = "box", half_extents = [0.5, 0.5, 0.5] }
position = [0.7, 0.0, 0.0]
"#;

#[test]
fn bodies_overlapping_deeply_at_the_start_are_reported_and_separated_gently() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("o.toml"), OVERLAPPING).unwrap();
    let warning = "warning: o.toml:19:12: body[1].position: body `right` overlaps body `left` by 0.3 m at the start";
    tumble(dir.path()).args(["check", "o.toml"]).assert().success().stdout(contains(warning)).stderr("");
    let output = tumble(dir.path()).args(["run", "o.toml"]).assert().success().get_output().clone();
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(stderr.starts_with(warning), "{stderr}");
    assert!(stderr.contains("max_correction_speed = 3 m/s"), "{stderr}");
    // pushed apart by the contact spring, no faster than max_correction_speed; the relaxation takes
    // back all but the last substep's push, so they part gently
    let rows = parse_csv(&fs::read_to_string(dir.path().join("out/o.csv")).unwrap());
    let (left, right) = (rows_of(&rows, "left"), rows_of(&rows, "right"));
    for row in left.iter().chain(&right) {
        let speed = (row.values[7..10].iter().map(|v| v * v).sum::<f64>()).sqrt();
        assert!(speed < 0.5, "t = {}: {} moves at {speed} m/s", row.t, row.body);
    }
    for (l, r) in left.iter().zip(&right).skip(1) {
        // no faster than max_correction_speed: each body takes half of the relative correction
        let separation = r.values[0] - l.values[0];
        assert!(separation - 0.7 <= 3.0 * r.t + 1e-9, "t = {}: separation {separation} m", r.t);
    }
    let (l, r) = (left.last().unwrap(), right.last().unwrap());
    let separation = r.values[0] - l.values[0];
    // apart (touching at 1 m), drifting at what the last push left them
    assert!(separation > 1.0 - 2e-3 && separation < 2.0, "the cubes end {separation} m apart");
}

#[test]
fn check_describes_the_demo_scene() {
    let dir = tempfile::tempdir().unwrap();
    tumble(dir.path())
        .arg("check")
        .arg(scenes_dir().join("demo.toml"))
        .assert()
        .success()
        .stdout(contains("flipper").and(contains("stable")))
        .stderr("");
    assert!(files(dir.path()).is_empty(), "check writes nothing");
}

#[test]
fn every_shipped_scene_runs() {
    let dir = tempfile::tempdir().unwrap();
    let mut scenes: Vec<PathBuf> = fs::read_dir(scenes_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml" || e == "json"))
        .collect();
    scenes.sort();
    assert!(!scenes.is_empty());
    for scene in &scenes {
        let stem = scene.file_stem().unwrap().to_str().unwrap();
        let summary = dir.path().join(format!("{stem}.json"));
        tumble(dir.path())
            .arg("run")
            .arg(scene)
            .args(["--duration", "0.02", "-q", "--summary"])
            .arg(&summary)
            .assert()
            .success();
        let rows = parse_csv(&fs::read_to_string(dir.path().join(format!("out/{stem}.csv"))).unwrap());
        let summary = read_json(&summary);
        assert_eq!(summary["stopped"], "completed", "{stem}");
        let samples = summary["samples"].as_u64().unwrap() as usize;
        // a robot adds one row per moving link
        let links: u64 =
            summary["robots"].as_array().map_or(0, |r| r.iter().map(|r| r["links"].as_u64().unwrap()).sum());
        let per_sample = summary["free_bodies"].as_u64().unwrap() + links;
        assert_eq!(rows.len(), samples * per_sample as usize, "{stem}");
    }
}

#[test]
fn the_readme_examples_run() {
    let readme = fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let commands: Vec<&str> = readme.lines().filter_map(|l| l.strip_prefix("$ tumble ")).collect();
    assert_eq!(commands.len(), 3);
    let dir = tempfile::tempdir().unwrap();
    for command in commands {
        let args: Vec<String> = command
            .split_whitespace()
            .map(|a| match a.strip_prefix("scenes/") {
                Some(name) => scenes_dir().join(name).to_string_lossy().into_owned(),
                None => a.to_string(),
            })
            .collect();
        tumble(dir.path()).args(&args).assert().success();
    }
    assert!(dir.path().join("out/demo.csv").is_file());
    assert!(dir.path().join("out/top.jsonl").is_file());
    assert_eq!(read_json(&dir.path().join("out/top.json"))["integrator"], "splitting4");
}

/// Every value of a JSON document, recursively: none may be `null` (serde_json writes NaN and inf so).
fn assert_no_null(value: &serde_json::Value, path: &str) {
    match value {
        serde_json::Value::Null => panic!("{path} is null"),
        serde_json::Value::Array(items) => {
            items.iter().enumerate().for_each(|(i, v)| assert_no_null(v, &format!("{path}[{i}]")))
        }
        serde_json::Value::Object(map) => map.iter().for_each(|(k, v)| assert_no_null(v, &format!("{path}.{k}"))),
        _ => {}
    }
}

#[test]
fn an_empty_or_bodiless_scene_runs_and_writes_a_header_only_trajectory() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("empty.toml"), "").unwrap();
    fs::write(dir.path().join("none.toml"), "version = 1\n[world]\nduration = 0.01\n").unwrap();
    for (file, warning) in [
        ("empty.toml", "warning: empty.toml: the file is empty: a default world with no bodies"),
        ("none.toml", "warning: none.toml: the scene has no bodies"),
    ] {
        let output = tumble(dir.path())
            .args(["run", file, "--out", "t.csv", "--summary", "s.json"])
            .assert()
            .code(0)
            .get_output()
            .clone();
        let stderr = String::from_utf8(output.stderr).unwrap();
        assert!(stderr.starts_with(warning), "{file}: {stderr}");
        let csv = fs::read_to_string(dir.path().join("t.csv")).unwrap();
        assert_eq!(csv, format!("{}\n", common::HEADER), "{file}");
        let summary_text = fs::read_to_string(dir.path().join("s.json")).unwrap();
        assert!(!summary_text.contains("NaN") && !summary_text.contains("inf"), "{file}: {summary_text}");
        let summary = read_json(&dir.path().join("s.json"));
        assert_no_null(&summary, "summary");
        assert_eq!(summary["stopped"], "completed", "{file}");
        assert!(summary["steps"].as_u64().unwrap() > 0, "{file}: {summary}");

        tumble(dir.path()).args(["run", file, "--out", "t.jsonl", "-q"]).assert().code(0);
        let lines = fs::read_to_string(dir.path().join("t.jsonl")).unwrap();
        assert!(lines.lines().count() > 1, "{file}: one line per sample");
        for line in lines.lines() {
            let sample: serde_json::Value = serde_json::from_str(line).unwrap();
            assert_eq!(sample["bodies"], serde_json::json!([]), "{file}: {line}");
            assert!(sample["t"].as_f64().unwrap().is_finite(), "{file}: {line}");
        }
    }
}

/// The passive double pendulum of `scenes/` gains energy with explicit Euler at `dt = 0.01` (12 % of
/// its kinetic energy in the first 0.1 s sample interval): one warning, and `instability` in the
/// summary. `rk4` and `semi_implicit_euler` at `dt = 1e-3` keep it: no warning, no field.
#[test]
fn a_passive_scene_gaining_energy_warns_once_of_a_possible_instability() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes_dir().join("double_pendulum.toml");
    let run = |integrator: &str, dt: &str| {
        let output = tumble(dir.path())
            .args(["run", scene.to_str().unwrap(), "--integrator", integrator, "--dt", dt, "--duration", "20"])
            .args(["--out", "t.csv", "--summary", "s.json"])
            .assert()
            .code(0)
            .get_output()
            .clone();
        (String::from_utf8(output.stderr).unwrap(), read_json(&dir.path().join("s.json")))
    };
    let (stderr, summary) = run("euler", "0.01");
    assert_eq!(stderr.matches("possible instability").count(), 1, "{stderr}");
    assert!(stderr.contains("warning: possible instability at t = "), "{stderr}");
    assert!(stderr.contains("reduce dt or use a structure-preserving integrator"), "{stderr}");
    let rise = &summary["instability"];
    assert!(rise["relative"].as_f64().unwrap() > 0.01, "{rise}");
    assert!(rise["energy_rise"].as_f64().unwrap() > 0.0, "{rise}");
    assert!(stderr.contains(&format!("t = {} s", rise["time"])), "{stderr}");
    for integrator in ["rk4", "semi_implicit_euler"] {
        let (stderr, summary) = run(integrator, "0.001");
        assert!(!stderr.contains("instability"), "{integrator}: {stderr}");
        assert!(summary.get("instability").is_none(), "{integrator}");
        assert_eq!(summary["stopped"], "completed");
    }
}
