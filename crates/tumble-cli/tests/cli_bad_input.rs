//! Bad input: exit 2, a message on stderr starting with `error: `, and no file created
//! (reliability.md C01, C03, C09, R03).

mod common;

use assert_cmd::prelude::*;
use common::{files, tumble};
use predicates::prelude::*;
use predicates::str::contains;
use std::fs;

/// Runs `tumble ARGS` in an empty directory and checks exit 2, `error: ` first on stderr, nothing
/// on stdout and no file created. Returns stderr.
fn bad_input(args: &[&str]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let output = tumble(dir.path()).args(args).output().unwrap();
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
    assert!(stderr.starts_with("error: "), "{args:?}: {stderr}");
    assert!(output.stdout.is_empty(), "{args:?}: {}", String::from_utf8_lossy(&output.stdout));
    assert!(files(dir.path()).is_empty(), "{args:?} created {:?}", files(dir.path()));
    stderr
}

#[test]
fn a_zero_or_negative_or_nan_step_is_rejected_naming_the_flag() {
    for dt in ["0", "-1", "nan", "inf", "1e-12"] {
        let stderr = bad_input(&["run", "--dt", dt, "--duration", "0.01"]);
        assert!(stderr.contains("--dt"), "{dt}: {stderr}");
        assert!(stderr.contains(&format!("(got {})", dt.parse::<f64>().unwrap())), "{dt}: {stderr}");
    }
    assert!(bad_input(&["run", "--dt=-1"]).contains("must be finite and > 0"));
}

#[test]
fn a_negative_or_infinite_duration_is_rejected() {
    for duration in ["-1", "inf", "-inf", "NaN"] {
        let stderr = bad_input(&["run", "--duration", duration]);
        assert!(stderr.contains("--duration: must be finite and ≥ 0"), "{duration}: {stderr}");
    }
}

#[test]
fn too_many_steps_are_rejected() {
    let stderr = bad_input(&["run", "--duration", "1e6", "--dt", "1e-6"]);
    assert!(stderr.contains("exceeds the cap of 1e9 steps"), "{stderr}");
}

#[test]
fn sample_every_zero_is_rejected() {
    assert!(bad_input(&["run", "--sample-every", "0"]).contains("--sample-every: must be ≥ 1"));
    assert!(bad_input(&["run", "--sample-every", "-3"]).contains("--sample-every"));
}

#[test]
fn an_unknown_integrator_lists_the_valid_ones() {
    let stderr = bad_input(&["run", "--integrator", "leapfrog"]);
    assert!(stderr.contains("leapfrog"), "{stderr}");
    for name in ["euler", "semi_implicit_euler", "rk4", "dopri5", "splitting", "splitting4"] {
        assert!(stderr.contains(name), "{name} missing from: {stderr}");
    }
}

#[test]
fn an_unknown_flag_or_command_is_a_usage_error() {
    assert!(bad_input(&["run", "--bogus"]).contains("--bogus"));
    assert!(bad_input(&["run", "--dt"]).contains("--dt"));
    assert!(bad_input(&["simulate"]).contains("simulate"));
    bad_input(&["check"]);
    bad_input(&["run", "a.toml", "b.toml"]);
}

#[test]
fn no_command_shows_the_usage_on_stderr() {
    let dir = tempfile::tempdir().unwrap();
    tumble(dir.path()).assert().code(2).stdout("").stderr(contains("Usage: tumble <COMMAND>"));
    assert!(files(dir.path()).is_empty());
}

#[test]
fn a_missing_scene_file_is_named() {
    let stderr = bad_input(&["run", "no-such-scene.toml"]);
    assert!(stderr.contains("no-such-scene.toml"), "{stderr}");
    let stderr = bad_input(&["check", "no-such-scene.toml"]);
    assert!(stderr.contains("no-such-scene.toml"), "{stderr}");
}

#[test]
fn an_unsupported_output_extension_is_rejected() {
    for out in ["traj.txt", "traj.json", "traj", "out/traj.CSV.gz"] {
        let stderr = bad_input(&["run", "--out", out]);
        assert!(stderr.contains(out), "{out}: {stderr}");
        assert!(stderr.contains("FILE.csv or FILE.jsonl"), "{out}: {stderr}");
    }
}

#[test]
fn a_trajectory_that_would_exceed_10_gb_needs_force() {
    // 1e9 steps of 6 bodies, every step written: ~1.8 TB
    let stderr = bad_input(&["run", "--duration", "1e5", "--dt", "1e-4", "--sample-every", "1"]);
    assert!(stderr.contains("10 GB") && stderr.contains("--force"), "{stderr}");
}

#[test]
fn the_scene_file_is_never_overwritten() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("scene.toml");
    fs::write(&scene, "version = 1\n").unwrap();
    std::os::unix::fs::symlink(&scene, dir.path().join("link.csv")).unwrap();
    for args in [
        vec!["run", "scene.toml", "--summary", "scene.toml"],
        vec!["run", "scene.toml", "--summary", "./scene.toml"],
        vec!["run", "scene.toml", "--out", "link.csv"],
    ] {
        tumble(dir.path())
            .args(&args)
            .assert()
            .code(2)
            .stderr(contains("refusing to overwrite").and(predicate::str::starts_with("error: ")));
        assert_eq!(fs::read_to_string(&scene).unwrap(), "version = 1\n", "{args:?}");
        assert_eq!(files(dir.path()).len(), 2, "{args:?}: {:?}", files(dir.path()));
    }
}

#[test]
fn the_summary_and_the_trajectory_must_differ() {
    let stderr = bad_input(&["run", "--out", "a.jsonl", "--summary", "a.jsonl"]);
    assert!(stderr.contains("the same file as the trajectory"), "{stderr}");
}

#[test]
fn a_wall_time_limit_must_be_positive() {
    for limit in ["0", "-1", "nan"] {
        let stderr = bad_input(&["run", "--max-wall-time", limit]);
        assert!(stderr.contains("--max-wall-time: must be finite and > 0"), "{limit}: {stderr}");
    }
}

#[test]
fn a_step_that_makes_too_many_steps_is_named_with_its_value() {
    // the demo lasts 30 s: 30 / 1e-8 = 3e9 steps, over the cap
    let stderr = bad_input(&["run", "--dt", "1e-8"]);
    assert!(stderr.starts_with("error: --dt: duration/dt = 3e9 steps exceeds the cap"), "{stderr}");
    assert!(stderr.contains("(got 0.00000001)"), "{stderr}");
}

#[test]
fn bad_convex_points_and_compounds_are_exit_2_naming_the_line_and_field() {
    let cases = [
        ("shape = { type = \"convex\", points = [[0, 0, 0], [1, 0, 0], [0, 1, 0]] }", "body[0].shape.points"),
        ("shape = { type = \"convex\", points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]] }", "coplanar"),
        (
            "shape = { type = \"convex\", points = [[0, 0, 0], [1, 0, 0], [0, nan, 0], [0, 0, 1]] }",
            "body[0].shape.points[2]",
        ),
        ("shapes = [{ type = \"plane\" }]", "body[0].shapes[0].type"),
        (
            "shape = { type = \"sphere\", radius = 1.0 }\nshapes = [{ type = \"sphere\", radius = 1.0 }]",
            "body[0].shapes",
        ),
    ];
    for (shape, expected) in cases {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("bad.toml");
        fs::write(&scene, format!("version = 1\n[[body]]\nname = \"b\"\ndensity = 1.0\n{shape}\n")).unwrap();
        for command in ["check", "run"] {
            let output = common::tumble(dir.path()).args([command, "bad.toml"]).output().unwrap();
            let stderr = String::from_utf8(output.stderr).unwrap();
            assert_eq!(output.status.code(), Some(2), "{command} `{shape}`: {stderr}");
            assert!(stderr.contains("bad.toml:5:") || stderr.contains("bad.toml:6:"), "{stderr}");
            assert!(stderr.contains(expected), "{command} `{shape}`: no `{expected}` in {stderr}");
            assert_eq!(files(dir.path()), vec![std::path::PathBuf::from("bad.toml")], "{command} wrote a file");
        }
    }
}

/// Runs `tumble ARGS` in `dir`, which holds the inputs already: exit 2, `error: ` first on stderr,
/// nothing on stdout, and no entry added to `dir`. Returns stderr.
fn bad_input_in(dir: &std::path::Path, args: &[&str]) -> String {
    let before = files(dir);
    let output = tumble(dir).args(args).output().unwrap();
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
    assert!(stderr.starts_with("error: "), "{args:?}: {stderr}");
    assert!(output.stdout.is_empty(), "{args:?}: {}", String::from_utf8_lossy(&output.stdout));
    assert_eq!(files(dir), before, "{args:?} wrote a file");
    stderr
}

#[test]
fn an_input_that_is_a_directory_is_named() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["scene.toml", "scene.json", "mesh.obj", "robot.urdf"] {
        fs::create_dir(dir.path().join(name)).unwrap();
    }
    for args in [
        ["run", "scene.toml"],
        ["check", "scene.toml"],
        ["run", "scene.json"],
        ["mass", "mesh.obj"],
        ["model", "robot.urdf"],
    ] {
        let stderr = bad_input_in(dir.path(), &args);
        assert!(stderr.contains(args[1]), "{args:?}: {stderr}");
        assert!(stderr.to_lowercase().contains("is a directory"), "{args:?}: {stderr}");
    }
}

#[test]
fn an_unreadable_input_is_named() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let cube = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    let robot = "<robot name=\"r\"><link name=\"a\"/></robot>\n";
    for (name, text) in [("scene.toml", "version = 1\n"), ("mesh.obj", cube), ("robot.urdf", robot)] {
        let path = dir.path().join(name);
        fs::write(&path, text).unwrap();
        fs::set_permissions(&path, fs::Permissions::from_mode(0o000)).unwrap();
    }
    // permissions do not stop a privileged user (root) from reading: nothing to test then
    if fs::read(dir.path().join("scene.toml")).is_ok() {
        eprintln!("skipped: a file of mode 000 is readable here (running as root?)");
        return;
    }
    for args in [["run", "scene.toml"], ["check", "scene.toml"], ["mass", "mesh.obj"], ["model", "robot.urdf"]] {
        let stderr = bad_input_in(dir.path(), &args);
        assert!(stderr.contains(args[1]), "{args:?}: {stderr}");
        assert!(stderr.contains("Permission denied"), "{args:?}: {stderr}");
    }
}
