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
