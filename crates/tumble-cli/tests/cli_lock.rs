//! `lock` through the command line: `tumble check` lists the locked joints and the reduced layout,
//! `tumble run` writes the reduced `q` and `v`, and a bad `lock` is exit 2 naming the file, line,
//! column and field, with nothing written.

mod common;

use common::{files, tumble};
use std::fs;
use std::path::Path;

/// A scene in `dir` with the repository's Panda and `keys` in its `[[robot]]`.
fn write_scene(dir: &Path, keys: &str) -> String {
    let urdf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/robots/panda.urdf");
    let text = format!(
        "version = 1\n[world]\nduration = 0.1\n[[robot]]\nname = \"panda\"\nurdf = \"{}\"\n{keys}\n",
        urdf.display()
    );
    fs::write(dir.join("scene.toml"), text).unwrap();
    "scene.toml".to_string()
}

#[test]
fn check_and_run_speak_the_reduced_layout() {
    let dir = tempfile::tempdir().unwrap();
    let keys =
        "q = { panda_joint4 = -1.5 }\nlock = [\"panda_joint4\", \"panda_finger_joint1\", \"panda_finger_joint2\"]";
    let scene = write_scene(dir.path(), keys);
    let output = tumble(dir.path()).args(["check", &scene]).output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("nq = 6, nv = 6"), "{stdout}");
    assert!(stdout.contains("locked: panda_joint4 at [-1.5], panda_finger_joint1 at [0]"), "{stdout}");
    assert!(!stdout.contains("panda_joint4 (revolute)"), "{stdout}");
    let output = tumble(dir.path()).args(["run", &scene, "--out", "p.jsonl", "--quiet"]).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let text = fs::read_to_string(dir.path().join("p.jsonl")).unwrap();
    let last: serde_json::Value = serde_json::from_str(text.lines().last().unwrap()).unwrap();
    assert_eq!(last["robots"][0]["q"].as_array().unwrap().len(), 6);
    assert_eq!(last["robots"][0]["v"].as_array().unwrap().len(), 6);
    let names: Vec<&str> = last["bodies"].as_array().unwrap().iter().map(|b| b["name"].as_str().unwrap()).collect();
    assert!(names.contains(&"panda/panda_link4") && names.contains(&"panda/panda_rightfinger"), "{names:?}");
}

#[test]
fn a_bad_lock_is_exit_2_with_its_position_and_nothing_written() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write_scene(dir.path(), "lock = [\"panda_joint4\", \"panda_jiont5\"]");
    let before = files(dir.path());
    let output = tumble(dir.path()).args(["run", &scene, "--out", "p.csv", "--quiet"]).output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("scene.toml:7:25: robot[0].lock: unknown joint `panda_jiont5`"), "{stderr}");
    assert!(stderr.contains("did you mean `panda_joint5`?"), "{stderr}");
    assert_eq!(files(dir.path()), before, "nothing written");
}

/// `tumble` in `dir` with `args`: exit status, standard output and standard error.
fn run(dir: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    let output = tumble(dir).args(args).output().unwrap();
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    (output.status.code(), text(&output.stdout), text(&output.stderr))
}

fn panda_urdf() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/robots/panda.urdf").to_string_lossy().into_owned()
}

/// `tumble model --lock`: the reduced layout (nq = nv = 6), the locked joints listed as fixed with
/// the values they are held at, the mass unchanged; the table says the same.
#[test]
fn model_lock_prints_the_reduced_layout() {
    let dir = tempfile::tempdir().unwrap();
    let urdf = panda_urdf();
    let lock = "panda_joint4=-1.5,panda_finger_joint1,panda_finger_joint2";
    let (code, stdout, stderr) = run(dir.path(), &["model", &urdf, "--json"]);
    assert_eq!(code, Some(0), "{stderr}");
    let full: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let (code, stdout, stderr) = run(dir.path(), &["model", &urdf, "--json", "--lock", lock]);
    assert_eq!(code, Some(0), "{stderr}");
    let reduced: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!((reduced["nq"].as_u64(), reduced["nv"].as_u64()), (Some(6), Some(6)));
    let (m_reduced, m_full) = (reduced["total_mass"].as_f64().unwrap(), full["total_mass"].as_f64().unwrap());
    assert!((m_reduced - m_full).abs() <= 1e-14 * m_full, "total mass {m_reduced} against {m_full}");
    let joints = reduced["joints"].as_array().unwrap();
    let kind = |name: &str| joints.iter().find(|j| j["name"] == name).map(|j| j["type"].as_str().unwrap().to_string());
    assert_eq!(kind("panda_joint4").as_deref(), Some("fixed"));
    assert_eq!(kind("panda_joint5").as_deref(), Some("revolute"));
    let locked = reduced["locked"].as_array().unwrap();
    assert_eq!(locked.len(), 3);
    assert_eq!((locked[0]["name"].as_str(), locked[0]["q"][0].as_f64()), (Some("panda_joint4"), Some(-1.5)));
    assert_eq!((locked[1]["name"].as_str(), locked[1]["q"][0].as_f64()), (Some("panda_finger_joint1"), Some(0.0)));
    // the repeated form is the same
    let args =
        ["model", &urdf, "--json", "--lock", "panda_joint4=-1.5", "--lock", "panda_finger_joint1,panda_finger_joint2"];
    let (code, stdout, _) = run(dir.path(), &args);
    assert_eq!(code, Some(0));
    assert_eq!(serde_json::from_str::<serde_json::Value>(&stdout).unwrap(), reduced);
    let (code, stdout, stderr) = run(dir.path(), &["model", &urdf, "--lock", lock]);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stdout.contains("nq = 6, nv = 6"), "{stdout}");
    assert!(stdout.contains("locked: panda_joint4 at [-1.5], panda_finger_joint1 at [0.0]"), "{stdout}");
}

/// `tumble dynamics --lock`: the reduced mass matrix and bias are the full model's, at the full `q`
/// with the locked values, rows and columns of the free joints (to 1e-12), and `M q̈ + b = τ` holds
/// for the reduced `q̈`.
#[test]
fn dynamics_lock_is_the_full_model_restricted_to_the_free_joints() {
    let dir = tempfile::tempdir().unwrap();
    let urdf = panda_urdf();
    // free joints: 1, 2, 3, 5, 6, 7 (full indices 0, 1, 2, 4, 5, 6); locked: 4 at −1.5, the fingers at 0.01
    let free = [0_usize, 1, 2, 4, 5, 6];
    let q_red = [0.3, -0.4, 0.2, 0.1, 1.7, -0.6];
    let v_red = [0.5, -0.2, 0.3, 0.9, -0.4, 0.7];
    let tau_red = [1.0, -2.0, 0.5, 0.3, -0.2, 0.1];
    let mut q_full = vec![0.0; 9];
    let mut v_full = vec![0.0; 9];
    for (k, &i) in free.iter().enumerate() {
        q_full[i] = q_red[k];
        v_full[i] = v_red[k];
    }
    (q_full[3], q_full[7], q_full[8]) = (-1.5, 0.01, 0.01);
    let write = |name: &str, line: serde_json::Value| {
        fs::write(dir.path().join(name), format!("{line}\n")).unwrap();
    };
    write("full.jsonl", serde_json::json!({"q": q_full, "v": v_full}));
    write("reduced.jsonl", serde_json::json!({"q": q_red, "v": v_red, "tau": tau_red}));
    let (code, _, stderr) = run(dir.path(), &["dynamics", &urdf, "--input", "full.jsonl", "--out", "full_out.jsonl"]);
    assert_eq!(code, Some(0), "{stderr}");
    let lock = "panda_joint4=-1.5,panda_finger_joint1=0.01,panda_finger_joint2=0.01";
    let args = ["dynamics", &urdf, "--lock", lock, "--input", "reduced.jsonl", "--out", "reduced_out.jsonl"];
    let (code, _, stderr) = run(dir.path(), &args);
    assert_eq!(code, Some(0), "{stderr}");
    let read = |name: &str| -> serde_json::Value {
        serde_json::from_str(fs::read_to_string(dir.path().join(name)).unwrap().lines().next().unwrap()).unwrap()
    };
    let (full, reduced) = (read("full_out.jsonl"), read("reduced_out.jsonl"));
    let number = |v: &serde_json::Value| v.as_f64().unwrap();
    let (m_full, m_red) = (&full["mass_matrix"], &reduced["mass_matrix"]);
    let mut worst = 0.0_f64;
    for (r, &i) in free.iter().enumerate() {
        for (c, &j) in free.iter().enumerate() {
            worst = worst.max((number(&m_red[r][c]) - number(&m_full[i][j])).abs());
        }
        worst = worst.max((number(&reduced["bias"][r]) - number(&full["bias"][i])).abs());
    }
    let mut residual = 0.0_f64;
    for r in 0..6 {
        let row: f64 = (0..6).map(|c| number(&m_red[r][c]) * number(&reduced["qdd"][c])).sum();
        residual = residual.max((row + number(&reduced["bias"][r]) - tau_red[r]).abs());
    }
    println!("dynamics --lock: M and bias off the full model's by {worst:e}; M q̈ + b − τ = {residual:e}");
    assert!(worst <= 1e-12, "the reduced M or bias differs from the full model's by {worst}");
    assert!(residual <= 1e-10, "M q̈ + b − τ = {residual}");
}

/// A bad `--lock`: exit 2 naming the flag and the joint, nothing written.
#[test]
fn a_bad_lock_flag_is_exit_2_naming_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let urdf = panda_urdf();
    for (lock, says) in [
        ("panda_jiont5", "--lock: unknown joint `panda_jiont5` (movable joints: panda_joint1,"),
        ("panda_joint8", "--lock: joint `panda_joint8` is fixed already"),
        ("panda_joint4=abc", "--lock panda_joint4=abc: the value must be a finite number"),
        ("panda_joint4,panda_joint4", "--lock: joint `panda_joint4` is locked twice"),
    ] {
        let before = files(dir.path());
        let (code, stdout, stderr) = run(dir.path(), &["model", &urdf, "--lock", lock]);
        assert_eq!(code, Some(2), "{lock}: {stderr}");
        assert!(stderr.contains(says), "{lock}: {stderr}");
        assert!(stdout.is_empty() && files(dir.path()) == before, "{lock}: something was written");
    }
}
