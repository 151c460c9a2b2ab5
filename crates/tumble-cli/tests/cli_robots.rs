//! `tumble run` and `tumble check` with `[[robot]]` scenes: trajectory rows `robot/link`, JSON Lines
//! `q` and `v`, robots' energy in the summary, and bad robot entries (exit 2, file, line and field,
//! nothing written).

mod common;

use common::{files, parse_csv, tumble};
use std::fs;
use std::path::{Path, PathBuf};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

#[test]
fn the_double_pendulum_scene_writes_link_rows_and_conserves_energy() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes().join("double_pendulum.toml");
    let output = tumble(dir.path())
        .args(["run", scene.to_str().unwrap(), "--out", "dp.csv", "--summary", "s.json", "--quiet"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let rows = parse_csv(&fs::read_to_string(dir.path().join("dp.csv")).unwrap());
    // 10 s, every 10th step: 1001 samples of three links
    assert_eq!(rows.len(), 3 * 1001);
    let names: Vec<&str> = rows[..3].iter().map(|r| r.body.as_str()).collect();
    assert_eq!(names, ["pendulum/upper", "pendulum/lower", "pendulum/tip"]);
    // the upper link's origin is the pivot, fixed at [0, 0, 2.5]
    for row in rows.iter().filter(|r| r.body == "pendulum/upper") {
        assert_eq!(&row.values[..3], &[0.0, 0.0, 2.5]);
    }
    // the lower link's origin stays 1 m from the pivot
    for row in rows.iter().filter(|r| r.body == "pendulum/lower") {
        let d = ((row.values[1]).powi(2) + (row.values[2] - 2.5).powi(2) + row.values[0].powi(2)).sqrt();
        assert!((d - 1.0).abs() < 1e-12, "{d}");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.path().join("s.json")).unwrap()).unwrap();
    let error = summary["energy"]["max_relative_error"].as_f64().unwrap();
    let initial = summary["energy"]["initial"].as_f64().unwrap();
    // E0 = kinetic 0 + potential: the centres of mass at 2.5 − 0.5 cos 1 and 2.5 − cos 1 − 0.5 cos 0.5
    let expected = 9.81 * ((2.5 - 0.5 * 1f64.cos()) + (2.5 - 1f64.cos() - 0.5 * 0.5f64.cos()));
    assert!((initial - expected).abs() < 1e-12, "{initial} vs {expected}");
    eprintln!("double pendulum via tumble run: energy max relative error {error:e} of {initial} J");
    assert!(error < 1e-9, "{error}");
}

#[test]
fn json_lines_carry_link_entries_and_q_v() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes().join("panda.toml");
    let output = tumble(dir.path())
        .args(["run", scene.to_str().unwrap(), "--out", "p.jsonl", "--duration", "0.5", "--quiet"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let text = fs::read_to_string(dir.path().join("p.jsonl")).unwrap();
    let lines: Vec<serde_json::Value> = text.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    assert_eq!(lines.len(), 51);
    for line in &lines {
        assert_eq!(line["bodies"].as_array().unwrap().len(), 12);
        let robot = &line["robots"][0];
        assert_eq!(robot["name"], "panda");
        assert_eq!(robot["q"].as_array().unwrap().len(), 9);
        assert_eq!(robot["v"].as_array().unwrap().len(), 9);
    }
    assert_eq!(lines[0]["bodies"][0]["name"], "panda/panda_link1");
    assert_eq!(lines[0]["robots"][0]["q"][1], -0.3);
    // the trajectory reads back with the library's reader, links as bodies
    let read = tumble::trajectory::read(&dir.path().join("p.jsonl"), Default::default()).unwrap();
    assert_eq!(read.bodies.len(), 12);
    assert!(read.bodies.iter().all(|b| b.starts_with("panda/")));
}

#[test]
fn check_describes_the_robots() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes().join("panda.toml");
    let output = tumble(dir.path()).args(["check", scene.to_str().unwrap()]).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let stdout = String::from_utf8(output.stdout).unwrap();
    assert!(stdout.contains("robot `panda`"), "{stdout}");
    assert!(stdout.contains("panda_joint1"), "{stdout}");
}

/// Writes `scene` (TOML) beside a copy of the double pendulum URDF and runs it: exit 2, stderr,
/// nothing written.
fn bad_scene(scene: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    fs::create_dir(dir.path().join("robots")).unwrap();
    fs::copy(scenes().join("robots/double_pendulum.urdf"), dir.path().join("robots/dp.urdf")).unwrap();
    fs::write(dir.path().join("s.toml"), scene).unwrap();
    let before = files(dir.path());
    let output = tumble(dir.path()).args(["run", "s.toml", "--out", "o.csv"]).output().unwrap();
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert_eq!(files(dir.path()), before, "nothing is written");
    stderr
}

const HEAD: &str = "version = 1\n[[robot]]\nname = \"arm\"\n";

#[test]
fn bad_robot_inputs_exit_2_naming_the_file_line_and_field() {
    let e = bad_scene(&format!("{HEAD}urdf = \"robots/missing.urdf\"\n"));
    assert!(e.contains("s.toml:4:8: robot[0].urdf: ") && e.contains("missing.urdf"), "{e}");
    let e = bad_scene(&format!("{HEAD}urdf = \"robots/dp.urdf\"\nq = {{ sholder = 0.3 }}\n"));
    assert!(e.contains("s.toml:5:17: robot[0].q.sholder: unknown joint `sholder`"), "{e}");
    assert!(e.contains("did you mean `shoulder`? (movable joints: `shoulder`, `elbow`)"), "{e}");
    let e = bad_scene(&format!("{HEAD}urdf = \"robots/dp.urdf\"\nq = {{ tip_joint = 0.3 }}\n"));
    assert!(e.contains("robot[0].q.tip_joint: joint `tip_joint` is fixed"), "{e}");
    let e = bad_scene(&format!(
        "{HEAD}urdf = \"robots/dp.urdf\"\nbase = \"floating\"\nq = {{ root_joint = [0.0, 0.0, 1.0, 1.0] }}\n"
    ));
    assert!(e.contains("s.toml:6:") && e.contains("robot[0].q.root_joint: a floating joint takes 7 numbers"), "{e}");
    let e = bad_scene(&format!(
        "{HEAD}urdf = \"robots/dp.urdf\"\nbase = \"floating\"\nposition = [0.0, 0.0, 1.0]\nq = {{ root_joint = [0, 0, 1, 1, 0, 0, 0] }}\n"
    ));
    assert!(e.contains("robot[0].q.root_joint: the base pose is already given"), "{e}");
    let e = bad_scene(&format!("{HEAD}urdf = \"robots/dp.urdf\"\npd = {{ elbow = {{ kp = 1.0 }} }}\n"));
    assert!(e.contains("robot[0].pd.elbow: missing `target`"), "{e}");
    let e = bad_scene(&format!("{HEAD}urdf = \"robots/dp.urdf\"\nbsae = \"fixed\"\n"));
    assert!(e.contains("unknown key `bsae`") && e.contains("did you mean `base`?"), "{e}");
    let e = bad_scene(&format!("{HEAD}urdf = \"robots/dp.urdf\"\nq = {{ shoulder = 0.1, shoulder = 0.2 }}\n"));
    assert!(e.contains("s.toml:5:"), "{e}");
    // a URDF error keeps the URDF's own position
    let dir_urdf =
        "<robot name=\"x\">\n  <link name=\"a\">\n    <inertial><mass value=\"-1\"/></inertial>\n  </link>\n</robot>\n";
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("x.urdf"), dir_urdf).unwrap();
    fs::write(dir.path().join("s.toml"), format!("{HEAD}urdf = \"x.urdf\"\n")).unwrap();
    let output = tumble(dir.path()).args(["run", "s.toml", "--out", "o.csv"]).output().unwrap();
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("s.toml:4:8: robot[0].urdf: x.urdf:3:") && stderr.contains("mass"), "{stderr}");
}

#[test]
fn a_diverging_robot_exits_3_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    fs::copy(scenes().join("robots/double_pendulum.urdf"), dir.path().join("dp.urdf")).unwrap();
    let scene = "version = 1\n[world]\ndt = 0.01\nduration = 1.0\n[[robot]]\nname = \"arm\"\nurdf = \"dp.urdf\"\ntorque = { elbow = 1e13 }\n";
    fs::write(dir.path().join("s.toml"), scene).unwrap();
    let output = tumble(dir.path()).args(["run", "s.toml", "--out", "o.csv", "--quiet"]).output().unwrap();
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(3), "{stderr}");
    assert!(stderr.contains("`arm`") && stderr.contains("joint `") && stderr.contains("step 1"), "{stderr}");
    // the last finite state (the initial one) was written
    let rows = parse_csv(&fs::read_to_string(dir.path().join("o.csv")).unwrap());
    assert_eq!(rows.len(), 3);
}

/// `scenes/limit.toml`: the arm falls onto its shoulder and elbow limits and rests there; the final
/// `q` is at both limits (within 1e-4 rad), the report says which joints sat at their limits and that
/// the strikes took energy out, and the energy never rose from one sample to the next.
#[test]
fn the_limit_scene_rests_against_both_limits() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes().join("limit.toml");
    let output = tumble(dir.path())
        .args(["run", scene.to_str().unwrap(), "--out", "l.jsonl", "--summary", "s.json"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(
        stdout.contains("at a joint limit") && stdout.contains("shoulder (") && stdout.contains("elbow ("),
        "{stdout}"
    );
    assert!(stdout.contains("joint-limit strikes took energy out"), "{stdout}");
    let text = fs::read_to_string(dir.path().join("l.jsonl")).unwrap();
    let samples: Vec<serde_json::Value> = text.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    let q = |s: &serde_json::Value, k: usize| s["robots"][0]["q"][k].as_f64().unwrap();
    let last = samples.last().unwrap();
    eprintln!("limit scene: final q = [{}, {}] against limits [0.6, −0.3]", q(last, 0), q(last, 1));
    assert!((q(last, 0) - 0.6).abs() < 1e-4 && (q(last, 1) + 0.3).abs() < 1e-4);
    for s in &samples {
        assert!(q(s, 0) >= 0.6 - 1e-4 && q(s, 1) >= -0.3 - 1e-4, "past a limit at t = {}", s["t"]);
    }
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.path().join("s.json")).unwrap()).unwrap();
    let active = &summary["robots"][0]["joint_limits_active"];
    assert_eq!(active.as_array().unwrap().len(), 2, "{summary}");
}

/// A PD of gain 1e4 N·m/rad, 1 rad from its target, on the Panda's first joint (effort 87 N·m): the report names the clamped joint
/// and the summary counts its steps; with `effort_limits = false` nothing is clamped.
#[test]
fn the_report_says_when_effort_limits_clamp() {
    let dir = tempfile::tempdir().unwrap();
    fs::create_dir(dir.path().join("robots")).unwrap();
    fs::copy(scenes().join("robots/panda.urdf"), dir.path().join("robots/panda.urdf")).unwrap();
    let scene = |effort: &str| {
        format!(
            "version = 1\n[world]\ndt = 0.001\nduration = 0.2\n[[robot]]\nname = \"panda\"\nurdf = \
             \"robots/panda.urdf\"\nq = {{ panda_joint4 = -2.0 }}\n{effort}\n[robot.pd]\npanda_joint1 = {{ target = 1.0, \
             kp = 1e4, kd = 0.0 }}\n"
        )
    };
    fs::write(dir.path().join("on.toml"), scene("")).unwrap();
    fs::write(dir.path().join("off.toml"), scene("effort_limits = false")).unwrap();
    for (file, clamps) in [("on.toml", true), ("off.toml", false)] {
        let output = tumble(dir.path()).args(["run", file, "--out", "o.csv", "--summary", "s.json"]).output().unwrap();
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
        let summary: serde_json::Value =
            serde_json::from_str(&fs::read_to_string(dir.path().join("s.json")).unwrap()).unwrap();
        let clamped = &summary["robots"][0]["effort_clamped"];
        if clamps {
            assert!(stdout.contains("effort clamped") && stdout.contains("panda_joint1 ("), "{stdout}");
            assert_eq!(clamped[0]["joint"], "panda_joint1", "{summary}");
            assert!(clamped[0]["steps"].as_u64().unwrap() > 100, "{summary}");
        } else {
            assert!(!stdout.contains("effort clamped"), "{stdout}");
            assert!(clamped.is_null(), "{summary}");
        }
    }
}

#[test]
fn bad_limit_keys_exit_2_naming_the_file_line_and_field() {
    let e = bad_scene(&format!("{HEAD}urdf = \"robots/dp.urdf\"\njoint_limits = 3\n"));
    assert!(e.contains("s.toml:5:") && e.contains("joint_limits") && e.contains("bool"), "{e}");
    let e = bad_scene(&format!("{HEAD}urdf = \"robots/dp.urdf\"\neffort_limits = \"yes\"\n"));
    assert!(e.contains("s.toml:5:") && e.contains("effort_limits") && e.contains("bool"), "{e}");
}

/// A joint that starts outside its limit is a warning naming the robot, the joint, its value and
/// the limit (the run goes on).
#[test]
fn a_joint_starting_outside_its_limit_is_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    fs::create_dir(dir.path().join("robots")).unwrap();
    fs::copy(scenes().join("robots/limited_arm.urdf"), dir.path().join("robots/arm.urdf")).unwrap();
    let text = "version = 1\n[world]\nduration = 0.01\n[[robot]]\nname = \"arm\"\nurdf = \"robots/arm.urdf\"\nq = { shoulder = 1.0, elbow = 0.5 }\n";
    fs::write(dir.path().join("s.toml"), text).unwrap();
    let output = tumble(dir.path()).args(["run", "s.toml", "--out", "o.csv"]).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(
        stderr.contains("s.toml:7:")
            && stderr.contains("robot `arm`: joint `elbow` starts at q = 0.5 rad, above its upper limit [-0.3, 0.3]"),
        "{stderr}"
    );
    assert!(!stderr.contains("`shoulder` starts"), "{stderr}");
}
