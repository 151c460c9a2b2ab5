//! `tumble model` and `tumble dynamics` on MJCF files: the layout, MuJoCo's dynamics through the
//! CLI, and refusals with exit status 2 naming file, line and column.

mod common;

use common::tumble;
use serde_json::Value;
use std::fs;
use std::path::PathBuf;

fn mjcf() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tumble/tests/fixtures/mjcf")
}

fn run(args: &[&str]) -> (Option<i32>, String, String) {
    let dir = tempfile::tempdir().unwrap();
    let output = tumble(dir.path()).args(args).output().unwrap();
    (
        output.status.code(),
        String::from_utf8(output.stdout).unwrap(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

/// `max |a − b| / max |b|`.
fn relative(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    a.iter().zip(b).fold(0.0_f64, |m, (x, y)| m.max((x - y).abs())) / scale
}

#[test]
fn model_lists_the_mjcf_joints_and_splits_a_body_with_several() {
    let hopper = mjcf().join("gymnasium/hopper.xml");
    let (code, out, err) = run(&["model", hopper.to_str().unwrap(), "--json"]);
    assert_eq!(code, Some(0), "{err}");
    let layout: Value = serde_json::from_str(&out).unwrap();
    assert_eq!((layout["nq"].as_u64(), layout["nv"].as_u64()), (Some(6), Some(6)));
    let joints = layout["joints"].as_array().unwrap();
    let movable: Vec<(&str, &str, &str)> = joints
        .iter()
        .filter(|j| j["type"] != "fixed")
        .map(|j| (j["name"].as_str().unwrap(), j["type"].as_str().unwrap(), j["child"].as_str().unwrap()))
        .collect();
    assert_eq!(
        movable,
        [
            ("rootx", "prismatic", "torso/rootx"),
            ("rootz", "prismatic", "torso/rootz"),
            ("rooty", "continuous", "torso"),
            ("thigh_joint", "revolute", "thigh"),
            ("leg_joint", "revolute", "leg"),
            ("foot_joint", "revolute", "foot"),
        ]
    );
    // MuJoCo's body masses summed (the fixture's)
    let fixture: Value = serde_json::from_str(&fs::read_to_string(mjcf().join("hopper.json")).unwrap()).unwrap();
    let mass: f64 = numbers(&fixture["body_mass"]).iter().sum();
    assert!((layout["total_mass"].as_f64().unwrap() - mass).abs() <= 1e-12 * mass);
}

/// The half cheetah (slides and hinges, no `ref`: tumble's state is MuJoCo's): the CLI's mass
/// matrix and `qdd` at `τ = 0` are MuJoCo's `mj_fullM` and contact-free `qacc` (its joint damping
/// and springs included).
#[test]
fn dynamics_of_an_mjcf_model_agree_with_mujoco() {
    let model = mjcf().join("gymnasium/half_cheetah.xml");
    let fixture: Value = serde_json::from_str(&fs::read_to_string(mjcf().join("half_cheetah.json")).unwrap()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.jsonl");
    let out = dir.path().join("out.jsonl");
    let states = fixture["states"].as_array().unwrap();
    let nv = fixture["nv"].as_u64().unwrap() as usize;
    let lines: Vec<String> = states
        .iter()
        .map(|s| serde_json::json!({"q": s["qpos"], "v": s["qvel"], "tau": vec![0.0; nv]}).to_string())
        .collect();
    fs::write(&input, lines.join("\n") + "\n").unwrap();
    let output = tumble(dir.path())
        .args(["dynamics", model.to_str().unwrap(), "--input", input.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let text = fs::read_to_string(&out).unwrap();
    for (line, s) in text.lines().zip(states) {
        let r: Value = serde_json::from_str(line).unwrap();
        let m: Vec<f64> = r["mass_matrix"].as_array().unwrap().iter().flat_map(numbers).collect();
        assert!(relative(&m, &numbers(&s["mass_matrix"])) <= 1e-10);
        assert!(relative(&numbers(&r["bias"]), &numbers(&s["qfrc_bias"])) <= 1e-10);
        assert!(relative(&numbers(&r["qdd"]), &numbers(&s["qacc"])) <= 1e-10);
    }
}

#[test]
fn closed_loops_are_refused_with_exit_2_naming_the_equality() {
    let gripper = mjcf().join("menagerie/robotiq_2f85/2f85.xml");
    let (code, _, err) = run(&["model", gripper.to_str().unwrap()]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("2f85.xml:173:5: <connect>: not supported (an <equality> constraint"), "{err}");
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.jsonl");
    fs::write(&input, "{\"q\": [], \"v\": []}\n").unwrap();
    let out = dir.path().join("out.jsonl");
    let output = tumble(dir.path())
        .args([
            "dynamics",
            gripper.to_str().unwrap(),
            "--input",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(2));
    assert!(!out.exists());
}

#[test]
fn urdf_flags_are_refused_on_mjcf_files_and_frictionloss_is_read_or_dropped() {
    let ant = mjcf().join("gymnasium/ant.xml");
    let (code, _, err) = run(&["model", ant.to_str().unwrap(), "--floating"]);
    assert_eq!(code, Some(2));
    assert!(err.contains("--floating applies to URDF files"), "{err}");
    let anymal = mjcf().join("menagerie/anymal_c.xml");
    let (code, _, err) = run(&["model", anymal.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{err}");
    assert!(!err.contains("frictionloss"), "{err}");
    let (code, out, err) = run(&["model", anymal.to_str().unwrap(), "--drop-frictionloss", "--json"]);
    assert_eq!(code, Some(0), "{err}");
    let layout: Value = serde_json::from_str(&out).unwrap();
    assert_eq!((layout["nq"].as_u64(), layout["nv"].as_u64()), (Some(19), Some(18)));
    assert!(err.contains("frictionloss") && err.contains("dropped"), "{err}");
}

#[test]
fn run_simulates_an_mjcf_world_with_its_options_and_floor() {
    let dir = tempfile::tempdir().unwrap();
    let ant = mjcf().join("gymnasium/ant.xml");
    let out = dir.path().join("ant.csv");
    let summary = dir.path().join("summary.json");
    let output = tumble(dir.path())
        .args(["run", ant.to_str().unwrap(), "--duration", "2", "--quiet"])
        .arg("--out")
        .arg(&out)
        .arg("--summary")
        .arg(&summary)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{err}");
    let s: Value = serde_json::from_str(&fs::read_to_string(&summary).unwrap()).unwrap();
    // ant.xml's <option timestep="0.01" integrator="RK4">, its free root, its floor plane
    assert_eq!(s["robots"][0]["base"], "floating", "{s}");
    assert_eq!(s["robots"][0]["nv"].as_u64(), Some(14));
    let csv = fs::read_to_string(&out).unwrap();
    assert_eq!(csv.lines().filter(|l| l.contains(",ant/torso,")).count(), 201, "2 s in steps of 0.01 s");
    // the torso has come down onto its legs on the floor, not through it
    let last = csv.lines().rev().find(|l| l.contains(",ant/torso,")).unwrap();
    let z: f64 = last.split(',').nth(4).unwrap().parse().unwrap();
    assert!(z > 0.2 && z < 0.75, "torso z = {z}");
}

#[test]
fn run_refuses_a_broken_mjcf_file_with_its_position() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.xml");
    fs::write(&bad, "<mujoco>\n  <worldbody>\n    <body><joint type=\"hinge\" axis=\"0 0 1\"/><geom type=\"hfield\"/></body>\n  </worldbody>\n</mujoco>\n").unwrap();
    let output = tumble(dir.path()).args(["run", bad.to_str().unwrap(), "--quiet"]).output().unwrap();
    let err = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{err}");
    assert!(err.contains("bad.xml:3:"), "{err}");
}

#[test]
fn run_starts_an_mjcf_world_from_a_keyframe() {
    let dir = tempfile::tempdir().unwrap();
    let keys = mjcf().join("keyframe/keys.xml");
    let out = dir.path().join("keys.csv");
    let output = tumble(dir.path())
        .args(["run", keys.to_str().unwrap(), "--keyframe", "spin", "--duration", "0.01", "--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{err}");
    // the free box's first row: its centre of mass where the key puts it, its velocity
    let csv = fs::read_to_string(&out).unwrap();
    let first: Vec<f64> =
        csv.lines().find(|l| l.contains(",box,")).unwrap().split(',').skip(2).map(|x| x.parse().unwrap()).collect();
    assert_eq!(first[..3], [1.2, -0.3, 0.8]);
    assert!((first[7] - 0.5).abs() < 1e-12 && (first[8] + 1.0).abs() < 1e-12, "{first:?}");
    // an unknown key: exit 2, the keys listed
    let (code, _, err) = run(&["run", keys.to_str().unwrap(), "--keyframe", "jump", "--quiet"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("no keyframe 'jump' (keys: 'spin', 1 (unnamed))"), "{err}");
    // on a scene file: exit 2, pointing at the scene key
    let scene = dir.path().join("s.toml");
    fs::write(&scene, "version = 1\n").unwrap();
    let (code, _, err) = run(&["run", scene.to_str().unwrap(), "--keyframe", "spin", "--quiet"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("applies to an MJCF file") && err.contains("keyframe = \"spin\""), "{err}");
}

/// `tumble model --json` lists the fixed tendons, `L = offset + Σ coef q`: from the JSON alone,
/// MuJoCo's tendon lengths at the fixture's states (the joints have `ref`, so tumble's `q` is
/// MuJoCo's `qpos − qpos0`, and the offset carries `Σ coef ref`).
#[test]
fn model_json_lists_the_fixed_tendons_with_mujocos_lengths() {
    let model = mjcf().join("synthetic/tendons.xml");
    let (code, out, err) = run(&["model", model.to_str().unwrap(), "--json"]);
    assert_eq!(code, Some(0), "{err}");
    let layout: Value = serde_json::from_str(&out).unwrap();
    let tendons = layout["tendons"].as_array().unwrap();
    let names: Vec<&str> = tendons.iter().map(|t| t["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["flex", "band", "drive"]);
    assert_eq!(tendons[1]["stiffness"].as_f64(), Some(4.0));
    let fixture: Value = serde_json::from_str(&fs::read_to_string(mjcf().join("tendons.json")).unwrap()).unwrap();
    let qpos0 = numbers(&fixture["qpos0"]);
    let mut worst: f64 = 0.0;
    for state in fixture["states"].as_array().unwrap() {
        let qpos = numbers(&state["qpos"]);
        for (t, &expected) in tendons.iter().zip(&numbers(&state["ten_length"])) {
            let length = t["offset"].as_f64().unwrap()
                + t["terms"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|term| {
                        let i = term["q_index"].as_u64().unwrap() as usize;
                        term["coef"].as_f64().unwrap() * (qpos[i] - qpos0[i])
                    })
                    .sum::<f64>();
            worst = worst.max((length - expected).abs());
        }
    }
    assert!(worst <= 1e-14, "tendon lengths off by {worst:e}");
    // the table says it too
    let (code, out, _) = run(&["model", model.to_str().unwrap()]);
    assert_eq!(code, Some(0));
    assert!(out.contains("tendon band: L = "), "{out}");
}

/// A fixed tendon that starts outside its range is a warning naming the robot, the tendon, its
/// length and the range, as a joint's is (the run goes on).
#[test]
fn a_tendon_starting_outside_its_range_is_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let xml = r#"<mujoco>
  <worldbody>
    <body name="upper">
      <joint name="a" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.02" mass="1"/>
      <body name="lower" pos="0 0 -0.3">
        <joint name="b" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.02" mass="1"/>
      </body>
    </body>
  </worldbody>
  <tendon>
    <fixed name="band" range="-0.3 0.3" limited="true">
      <joint joint="a" coef="1"/>
      <joint joint="b" coef="1"/>
    </fixed>
  </tendon>
</mujoco>
"#;
    fs::write(dir.path().join("f.xml"), xml).unwrap();
    let scene = |q: &str| {
        format!(
            "version = 1\n[world]\nduration = 0.01\n[[robot]]\nname = \"finger\"\nmjcf = \"f.xml\"\nq = {{ {q} }}\n"
        )
    };
    fs::write(dir.path().join("s.toml"), scene("a = 0.5, b = 0.5")).unwrap();
    let output = tumble(dir.path()).args(["run", "s.toml", "--out", "o.csv"]).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(
        stderr.contains("s.toml:")
            && stderr.contains("robot `finger`: tendon `band` starts at length 1, above its upper limit [-0.3, 0.3]"),
        "{stderr}"
    );
    // inside the range: no warning
    fs::write(dir.path().join("s.toml"), scene("a = 0.1, b = -0.2")).unwrap();
    let output = tumble(dir.path()).args(["run", "s.toml", "--out", "o.csv"]).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    assert!(!stderr.contains("starts at"), "{stderr}");
    // without gravity, a constant torque on `b` drives the tendon onto its upper limit: the report
    // and the summary count the steps the tendon's limit pushed
    let text = "version = 1\n[world]\ndt = 0.001\nduration = 0.5\ngravity = [0, 0, 0]\n[[robot]]\nname = \"finger\"\n\
                mjcf = \"f.xml\"\ntorque = { b = 0.2 }\n";
    fs::write(dir.path().join("s.toml"), text).unwrap();
    let output = tumble(dir.path()).args(["run", "s.toml", "--out", "o.csv", "--summary", "s.json"]).output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("at a tendon limit") && stdout.contains("band ("), "{stdout}");
    let summary: Value = serde_json::from_str(&fs::read_to_string(dir.path().join("s.json")).unwrap()).unwrap();
    let active = summary["robots"][0]["tendon_limits_active"].as_array().unwrap();
    assert_eq!(active.len(), 1, "{summary}");
    assert_eq!(active[0]["tendon"], "band");
    let steps = active[0]["steps"].as_u64().unwrap();
    assert!(steps > 0 && steps <= 500, "{summary}");
}
