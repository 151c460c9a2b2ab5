//! `tumble model` and `tumble dynamics` (the contract in design.md, "Multibody commands").

mod common;

use common::{files, tumble};
use serde_json::Value;
use std::fs;
use std::path::PathBuf;

fn robots() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tumble/tests/fixtures/robots")
}

fn run_ok(args: &[&str]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let output = tumble(dir.path()).args(args).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{args:?}: {}", String::from_utf8_lossy(&output.stderr));
    String::from_utf8(output.stdout).unwrap()
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

fn assert_close(what: &str, a: &[f64], b: &[f64], tol: f64) {
    assert_eq!(a.len(), b.len(), "{what}");
    let scale = b.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        assert!((x - y).abs() <= tol * scale, "{what}[{k}]: {x} vs {y}");
    }
}

#[test]
fn model_json_lists_the_joints_in_depth_first_order() {
    let urdf = robots().join("panda.urdf");
    let out = run_ok(&["model", urdf.to_str().unwrap(), "--json"]);
    let layout: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(layout["name"], "panda");
    assert_eq!((layout["nq"].as_u64(), layout["nv"].as_u64()), (Some(9), Some(9)));
    let joints = layout["joints"].as_array().unwrap();
    let movable: Vec<&str> =
        joints.iter().filter(|j| j["type"] != "fixed").map(|j| j["name"].as_str().unwrap()).collect();
    assert_eq!(movable[0], "panda_joint1");
    assert_eq!(movable[8], "panda_finger_joint2");
    let hand = joints.iter().find(|j| j["name"] == "panda_hand_joint").unwrap();
    assert_eq!(hand["type"], "fixed");
    assert_eq!(hand["nv"], 0);
    assert!(hand["q_index"].is_null());
    let finger = joints.iter().find(|j| j["name"] == "panda_finger_joint1").unwrap();
    assert_eq!((finger["type"].as_str(), finger["parent"].as_str()), (Some("prismatic"), Some("panda_hand")));
    assert_eq!((finger["q_index"].as_u64(), finger["v_index"].as_u64()), (Some(7), Some(7)));
    let mass = layout["total_mass"].as_f64().unwrap();
    assert!((mass - 17.451901).abs() < 1e-9, "{mass}");
}

#[test]
fn model_with_a_floating_base_starts_with_the_floating_joint() {
    let urdf = robots().join("solo12.urdf");
    let out = run_ok(&["model", urdf.to_str().unwrap(), "--floating", "--json"]);
    let layout: Value = serde_json::from_str(&out).unwrap();
    assert_eq!((layout["nq"].as_u64(), layout["nv"].as_u64()), (Some(19), Some(18)));
    let first = &layout["joints"][0];
    assert_eq!(
        (first["type"].as_str(), first["nq"].as_u64(), first["nv"].as_u64()),
        (Some("floating"), Some(7), Some(6))
    );
    // the table names the same joints
    let table = run_ok(&["model", urdf.to_str().unwrap(), "--floating"]);
    assert!(table.contains("nq = 19, nv = 18") && table.contains("root_joint") && table.contains("FL_HAA"), "{table}");
}

#[test]
fn bad_urdf_is_exit_2_with_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.urdf");
    fs::write(&path, "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"a\"/>\n</robot>\n").unwrap();
    let output = tumble(dir.path()).args(["model", "bad.urdf"]).output().unwrap();
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.starts_with("error: bad.urdf:3:1: <link name=\"a\">: duplicate link name 'a'"), "{stderr}");
    let output = tumble(dir.path()).args(["model", "missing.urdf"]).output().unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&output.stderr).contains("missing.urdf"));
}

/// The fixture states through the command line give Pinocchio's results (1e-9 relative).
#[test]
fn dynamics_reproduces_the_pinocchio_fixtures() {
    for (name, floating) in [("solo12", true), ("ur5", false)] {
        let fixture: Value =
            serde_json::from_str(&fs::read_to_string(robots().join(format!("{name}.json"))).unwrap()).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let states = fixture["states"].as_array().unwrap();
        let input: String = states
            .iter()
            .map(|s| format!("{}\n", serde_json::json!({"q": s["q"], "v": s["v"], "tau": s["tau_in"], "a": s["a"]})))
            .collect();
        fs::write(dir.path().join("in.jsonl"), input).unwrap();
        let urdf = robots().join(format!("{name}.urdf"));
        let mut args = vec!["dynamics", urdf.to_str().unwrap(), "--input", "in.jsonl", "--out", "out.jsonl"];
        if floating {
            args.push("--floating");
        }
        // Pinocchio's numbering
        args.extend(["--joint-order", "name"]);
        let output = tumble(dir.path()).args(&args).output().unwrap();
        assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
        let out = fs::read_to_string(dir.path().join("out.jsonl")).unwrap();
        let lines: Vec<Value> = out.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
        assert_eq!(lines.len(), states.len());
        for (s, (got, want)) in lines.iter().zip(states).enumerate() {
            for key in ["bias", "qdd", "tau"] {
                let expected = if key == "qdd" { "qdd" } else { key };
                assert_close(&format!("{name} {s} {key}"), &numbers(&got[key]), &numbers(&want[expected]), 1e-9);
            }
            let m: Vec<f64> = got["mass_matrix"].as_array().unwrap().iter().flat_map(numbers).collect();
            let m_want: Vec<f64> = want["mass_matrix"].as_array().unwrap().iter().flat_map(numbers).collect();
            assert_close(&format!("{name} {s} mass matrix"), &m, &m_want, 1e-9);
        }
    }
}

#[test]
fn dynamics_without_tau_or_a_gives_only_the_mass_matrix_and_bias_and_gravity_can_be_set() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("in.jsonl"), "{\"q\": [0.3, -0.2], \"v\": [0, 0]}\n\n").unwrap();
    let urdf = robots().join("double_pendulum.urdf");
    let u = urdf.to_str().unwrap();
    let output = tumble(dir.path())
        .args(["dynamics", u, "--input", "in.jsonl", "--out", "out.jsonl", "--gravity", "0", "0", "0"])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let line: Value = serde_json::from_str(fs::read_to_string(dir.path().join("out.jsonl")).unwrap().trim()).unwrap();
    let keys: Vec<&String> = line.as_object().unwrap().keys().collect();
    assert_eq!(keys, ["bias", "mass_matrix"]);
    // no gravity, no velocity: no bias
    assert_eq!(numbers(&line["bias"]), [0.0, 0.0]);
    // with gravity the bias is not zero
    let output = tumble(dir.path()).args(["dynamics", u, "--input", "in.jsonl", "--out", "g.jsonl"]).output().unwrap();
    assert_eq!(output.status.code(), Some(0));
    let line: Value = serde_json::from_str(fs::read_to_string(dir.path().join("g.jsonl")).unwrap().trim()).unwrap();
    assert!(numbers(&line["bias"]).iter().any(|b| b.abs() > 0.1), "{line}");
}

#[test]
fn dynamics_bad_lines_are_exit_2_naming_the_line_and_write_nothing() {
    let urdf = robots().join("solo12.urdf");
    let u = urdf.to_str().unwrap();
    let q_ok = "[0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]";
    let v_ok = "[0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]";
    let cases = [
        ("not json".to_string(), "not JSON"),
        (format!("{{\"q\": [1, 2], \"v\": {v_ok}}}"), "\"q\" has 2 numbers, the model needs 19"),
        (format!("{{\"q\": {q_ok}}}"), "\"v\" is required"),
        (format!("{{\"q\": {q_ok}, \"v\": {v_ok}, \"qd\": 1}}"), "unknown key \"qd\""),
        (format!("{{\"q\": {}, \"v\": {v_ok}}}", q_ok.replace("1,0,0,0", "2,0,0,0")), "norm 2, not 1"),
    ];
    for (line, message) in cases {
        let dir = tempfile::tempdir().unwrap();
        fs::write(dir.path().join("in.jsonl"), format!("{{\"q\": {q_ok}, \"v\": {v_ok}}}\n{line}\n")).unwrap();
        let output = tumble(dir.path())
            .args(["dynamics", u, "--floating", "--input", "in.jsonl", "--out", "out.jsonl"])
            .output()
            .unwrap();
        let stderr = String::from_utf8(output.stderr).unwrap();
        assert_eq!(output.status.code(), Some(2), "{line}: {stderr}");
        assert!(stderr.contains("in.jsonl:2: ") && stderr.contains(message), "{line}: {stderr}");
        assert_eq!(files(dir.path()), [PathBuf::from("in.jsonl")], "{line}");
    }
    // the input is never overwritten
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("in.jsonl"), "").unwrap();
    let output = tumble(dir.path()).args(["dynamics", u, "--input", "in.jsonl", "--out", "in.jsonl"]).output().unwrap();
    assert_eq!(output.status.code(), Some(2));
}

#[test]
fn dynamics_bench_prints_the_four_fields() {
    let urdf = robots().join("panda.urdf");
    let out = run_ok(&["dynamics", urdf.to_str().unwrap(), "--bench", "--bench-states", "5"]);
    let bench: Value = serde_json::from_str(&out).unwrap();
    let keys: Vec<&String> = bench.as_object().unwrap().keys().collect();
    assert_eq!(keys, ["aba_us", "crba_us", "nv", "rnea_us"]);
    assert_eq!(bench["nv"], 9);
    for key in ["rnea_us", "crba_us", "aba_us"] {
        let t = bench[key].as_f64().unwrap();
        assert!(t > 0.0 && t.is_finite(), "{key}: {t}");
    }
}

/// A robot with a link inertia that is not physical: exit 2 naming the link, its line and the flag;
/// with `--balance-inertia`, exit 0 with a warning naming the link, and `dynamics` gives finite
/// results. A massless finger: exit 2 naming the joint and `--massless fuse`, which then loads.
#[test]
fn balance_inertia_and_massless_fuse_are_asked_for_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let pr2 = robots().join("pr2.urdf");
    let pr2 = pr2.to_str().unwrap();
    let output = tumble(dir.path()).args(["model", pr2, "--json"]).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("pr2.urdf:786:7: <inertia>: inertia of link 'sensor_mount_link'"), "{stderr}");
    assert!(stderr.contains("--balance-inertia") && output.stdout.is_empty(), "{stderr}");

    let output = tumble(dir.path()).args(["model", pr2, "--json", "--balance-inertia"]).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(stderr.contains("link 'sensor_mount_link': inertia balanced"), "{stderr}");
    let layout: Value = serde_json::from_slice(&output.stdout).unwrap();
    let nv = layout["nv"].as_u64().unwrap() as usize;

    let input = dir.path().join("in.jsonl");
    let out = dir.path().join("out.jsonl");
    let state = serde_json::json!({"q": vec![0.1; nv], "v": vec![0.2; nv], "tau": vec![1.0; nv]});
    fs::write(&input, format!("{state}\n")).unwrap();
    run_ok(&["dynamics", pr2, "--balance-inertia", "--input", input.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let line: Value = serde_json::from_str(fs::read_to_string(&out).unwrap().trim()).unwrap();
    assert_eq!(numbers(&line["qdd"]).len(), nv);
    assert!(numbers(&line["qdd"]).iter().chain(&numbers(&line["bias"])).all(|x| x.is_finite()));

    let romeo = robots().join("romeo.urdf");
    let romeo = romeo.to_str().unwrap();
    let output = tumble(dir.path()).args(["model", romeo]).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("romeo.urdf:1443:3: <joint name=\"LHand\">") && stderr.contains("--massless fuse"),
        "{stderr}"
    );
    let text = run_ok(&["model", romeo, "--massless", "fuse"]);
    assert!(text.contains("warning:") && text.contains("joint 'LHand'") && text.contains("fused"), "{text}");
}
