//! `tumble mass MESH [--density RHO] [--scale S]`: the contract's JSON on stdout; faults exit 2 with
//! the file and the problem, nothing on stdout.

mod common;

use common::{files, json_close, tumble};
use std::path::PathBuf;

fn fixture(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tumble/tests/fixtures/meshes").join(name).display().to_string()
}

/// Runs `tumble ARGS` in an empty directory; returns (status, stdout, stderr).
fn mass(args: &[&str]) -> (i32, String, String) {
    let dir = tempfile::tempdir().unwrap();
    let output = tumble(dir.path()).arg("mass").args(args).output().unwrap();
    assert!(files(dir.path()).is_empty(), "{args:?} created {:?}", files(dir.path()));
    let text = |b: Vec<u8>| String::from_utf8(b).unwrap();
    (output.status.code().unwrap_or(-1), text(output.stdout), text(output.stderr))
}

/// The JSON of a successful run, checked against the contract's keys.
fn ok(args: &[&str]) -> (serde_json::Value, String) {
    let (status, stdout, stderr) = mass(args);
    assert_eq!(status, 0, "{args:?}: {stderr}");
    let value: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let keys: Vec<&str> = value.as_object().unwrap().keys().map(String::as_str).collect();
    let mut expected = ["volume", "mass", "center_of_mass", "inertia", "principal_moments", "principal_axes"];
    let mut sorted = keys.clone();
    sorted.sort_unstable();
    expected.sort_unstable();
    assert_eq!(sorted, expected, "{stdout}");
    // the keys are printed in the contract's order
    let at = |k: &str| stdout.find(&format!("\"{k}\"")).unwrap();
    assert!(at("volume") < at("mass") && at("mass") < at("center_of_mass") && at("inertia") < at("principal_moments"));
    (value, stderr)
}

fn bad(args: &[&str]) -> String {
    let (status, stdout, stderr) = mass(args);
    assert_eq!(status, 2, "{args:?}: {stderr}");
    assert!(stdout.is_empty(), "{args:?}: {stdout}");
    assert!(stderr.starts_with("error: "), "{args:?}: {stderr}");
    stderr
}

#[test]
fn a_unit_cube_of_water_by_default() {
    let (v, stderr) = ok(&[&fixture("cube.obj")]);
    assert!(stderr.is_empty(), "{stderr}");
    assert!(json_close(&v["volume"], 1.0));
    assert!(json_close(&v["mass"], 1000.0));
    for k in 0..3 {
        assert!(json_close(&v["center_of_mass"][k], 0.5));
        assert!(json_close(&v["principal_moments"][k], 1000.0 / 6.0));
        for j in 0..3 {
            let expected = if j == k { 1000.0 / 6.0 } else { 0.0 };
            assert!(json_close(&v["inertia"][k][j], expected), "{}", v["inertia"]);
        }
    }
}

#[test]
fn density_and_scale_are_applied() {
    let (v, _) = ok(&[&fixture("cube.stl"), "--density", "2.5", "--scale", "0.1"]);
    assert!(json_close(&v["volume"], 1e-3), "{}", v["volume"]);
    assert!(json_close(&v["mass"], 2.5e-3));
    assert!(json_close(&v["center_of_mass"][2], 0.05));
}

#[test]
fn principal_axes_are_orthonormal_and_rebuild_the_tensor() {
    let (v, _) = ok(&[&fixture("box.stl"), "--density", "1"]);
    let num = |x: &serde_json::Value| x.as_f64().unwrap();
    let axes: Vec<[f64; 3]> = (0..3).map(|i| [0, 1, 2].map(|j| num(&v["principal_axes"][i][j]))).collect();
    let moments: Vec<f64> = (0..3).map(|i| num(&v["principal_moments"][i])).collect();
    assert!(moments[0] <= moments[1] && moments[1] <= moments[2], "{moments:?}");
    for a in 0..3 {
        for b in 0..3 {
            let dot: f64 = (0..3).map(|k| axes[a][k] * axes[b][k]).sum();
            assert!((dot - if a == b { 1.0 } else { 0.0 }).abs() < 1e-14, "{axes:?}");
            let rebuilt: f64 = (0..3).map(|k| moments[k] * axes[k][a] * axes[k][b]).sum();
            assert!((rebuilt - num(&v["inertia"][a][b])).abs() < 1e-14 * moments[2], "{}", v["inertia"]);
        }
    }
}

#[test]
fn an_inside_out_mesh_is_flipped_with_a_warning() {
    let (v, stderr) = ok(&[&fixture("inside_out.stl")]);
    assert!(
        stderr.starts_with("warning: ") && stderr.contains("inside_out.stl") && stderr.contains("flipped"),
        "{stderr}"
    );
    assert!(json_close(&v["volume"], 1.0));
}

#[test]
fn faults_name_the_file_and_the_problem() {
    let cases = [
        ("open_box.obj", "4 open edges"),
        ("flipped_face.obj", "not consistently oriented: 3 edges"),
        ("nan.obj", "line 8 is not finite"),
        ("empty.stl", "the file is empty"),
        ("truncated.stl", "header says 12 triangles"),
        ("bad_index.obj", "line 22"),
        ("missing.obj", "cannot read"),
        ("cube.ply", "cannot tell the mesh format"),
    ];
    for (name, problem) in cases {
        let stderr = bad(&[&fixture(name)]);
        assert!(stderr.contains(&fixture(name)) && stderr.contains(problem), "{name}: {stderr}");
    }
}

#[test]
fn bad_flags_are_rejected() {
    for density in ["0", "-1", "nan", "inf"] {
        assert!(bad(&[&fixture("cube.obj"), "--density", density]).contains("--density: must be finite and > 0"));
    }
    assert!(bad(&[&fixture("cube.obj"), "--scale", "0"]).contains("--scale"));
    assert!(bad(&[&fixture("cube.obj"), "--max-triangles", "11"]).contains("too many triangles: 12, the limit is 11"));
    assert!(bad(&[]).contains("<MESH>"));
}

#[test]
fn a_scene_with_a_mesh_body_runs() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(fixture("torus.obj"), dir.path().join("torus.obj")).unwrap();
    let scene = "version = 1\n[world]\ngravity = [0, 0, 0]\nduration = 0.1\n[[body]]\nname = \"ring\"\n\
                 density = 1000.0\nshape = { type = \"mesh\", file = \"torus.obj\" }\nangular_velocity = [1.0, 2.0, 3.0]\n";
    std::fs::write(dir.path().join("ring.toml"), scene).unwrap();
    let output = tumble(dir.path()).args(["run", "ring.toml", "--quiet", "--out", "ring.csv"]).output().unwrap();
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let csv = std::fs::read_to_string(dir.path().join("ring.csv")).unwrap();
    assert_eq!(common::parse_csv(&csv).len(), 101);
}
