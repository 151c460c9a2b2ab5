//! The replay draws robot links with their URDF geometry and shows contacts (`tumble view`,
//! `tumble run --view`):
//!
//! - box, cylinder and sphere `<visual>` elements are parts of the link's body, each at its
//!   `<origin>` in the link frame, and the page's placement (row pose ∘ part pose) puts them where the
//!   kinematics does;
//! - a COLLADA visual falls back to the link's collision geometry (or its inertia box), with one
//!   warning for the robot naming the files;
//! - an STL visual with a mirroring `scale` is a mesh part: its corners those of the file scaled,
//!   welded, still facing out;
//! - `--contacts` puts each sample's contact points and forces in the page, for each frame kept.

mod common;

use assert_cmd::prelude::*;
use common::tumble;
use predicates::str::contains;
use serde_json::Value;
use std::fs;
use std::path::Path;
use tumble::math::{DQuat, DVec3};

/// The replay's data: the JSON object the page holds.
fn data_of(html: &str) -> Value {
    let start = html.find("const DATA = ").expect("a data line") + "const DATA = ".len();
    let end = start + html[start..].find(";\n").unwrap();
    serde_json::from_str(&html[start..end]).unwrap()
}

fn floats(value: &Value) -> Vec<f64> {
    value.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

fn vec3(value: &Value) -> DVec3 {
    let v = floats(value);
    assert_eq!(v.len(), 3, "{value}");
    DVec3::new(v[0], v[1], v[2])
}

/// A quaternion written `[w, x, y, z]`.
fn quat(value: &Value) -> DQuat {
    let q = floats(value);
    assert_eq!(q.len(), 4, "{value}");
    DQuat::from_xyzw(q[1], q[2], q[3], q[0])
}

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).length() < tol
}

/// The same rotation (either sign of the quaternion).
fn same_rotation(a: DQuat, b: DQuat, tol: f64) -> bool {
    a.dot(b).abs() > 1.0 - tol
}

fn body<'a>(data: &'a Value, name: &str) -> &'a Value {
    data["bodies"].as_array().unwrap().iter().find(|b| b["name"] == name).unwrap_or_else(|| panic!("no body {name}"))
}

fn write(dir: &Path, name: &str, text: &str) {
    fs::write(dir.join(name), text).unwrap();
}

/// A fixed base with a box (turned 0.5 rad about z, 0.1 m up), an arm on a revolute joint about x
/// with a cylinder along y (rpy = (π/2, 0, 0)) and a sphere at its end, a link with mass and no
/// geometry, and a massless one.
const PRIMITIVES: &str = r#"<?xml version="1.0"?>
<robot name="prims">
  <link name="base">
    <inertial><mass value="2"/><inertia ixx="0.02" iyy="0.02" izz="0.02"/></inertial>
    <visual><origin xyz="0 0 0.1" rpy="0 0 0.5"/><geometry><box size="0.4 0.2 0.1"/></geometry></visual>
    <collision><geometry><box size="0.4 0.2 0.2"/></geometry></collision>
  </link>
  <link name="arm">
    <inertial><origin xyz="0 0 -0.25"/><mass value="1"/><inertia ixx="0.02" iyy="0.02" izz="0.001"/></inertial>
    <visual><origin xyz="0 0 -0.25" rpy="1.5707963267948966 0 0"/>
      <geometry><cylinder radius="0.03" length="0.5"/></geometry></visual>
    <visual><origin xyz="0 0 -0.5"/><geometry><sphere radius="0.06"/></geometry></visual>
  </link>
  <link name="weight">
    <inertial><mass value="0.5"/><inertia ixx="0.001" iyy="0.002" izz="0.003"/></inertial>
  </link>
  <link name="tip"/>
  <joint name="swing" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0 0 -0.1"/>
    <axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="10" velocity="5"/></joint>
  <joint name="to_weight" type="fixed"><parent link="arm"/><child link="weight"/><origin xyz="0 0 -0.5"/></joint>
  <joint name="to_tip" type="fixed"><parent link="weight"/><child link="tip"/><origin xyz="0 0 -0.1"/></joint>
</robot>
"#;

#[test]
fn primitive_visuals_are_parts_at_their_origins() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "prims.urdf", PRIMITIVES);
    write(
        dir.path(),
        "s.toml",
        "version = 1\n[world]\nduration = 0.2\ndt = 0.001\nsample_every = 10\n\n[[robot]]\nname = \"r\"\n\
         urdf = \"prims.urdf\"\nbase = \"fixed\"\nposition = [0.0, 0.0, 1.0]\nq = { swing = 0.7 }\n",
    );
    tumble(dir.path())
        .args(["run", "s.toml", "--out", "t.csv", "--view", "v.html", "-q"])
        .assert()
        .success()
        .stderr("");
    let data = data_of(&fs::read_to_string(dir.path().join("v.html")).unwrap());

    // the fixed base: a fixed body at its place, its box 0.1 m up and turned 0.5 rad about z
    let base = body(&data, "r/base");
    assert_eq!((&base["index"], &base["drawn"], &base["inertia_box"]), (&Value::Null, &"visual".into(), &false.into()));
    assert!(close(vec3(&base["position"]), DVec3::new(0.0, 0.0, 1.0), 1e-7));
    let parts = base["parts"].as_array().unwrap();
    assert_eq!(parts.len(), 1, "the visual, not the collision box");
    assert_eq!(parts[0]["geometry"]["type"], "box");
    assert!(close(vec3(&parts[0]["geometry"]["half_extents"]), DVec3::new(0.2, 0.1, 0.05), 1e-7));
    assert!(close(vec3(&parts[0]["position"]), DVec3::new(0.0, 0.0, 0.1), 1e-7));
    assert!(same_rotation(quat(&parts[0]["orientation"]), DQuat::from_rotation_z(0.5), 1e-7));

    // the arm: a cylinder (radius 0.03 m, half height 0.25 m) along the link's y, and a sphere
    let arm = body(&data, "r/arm");
    assert_eq!((&arm["drawn"], &arm["marker"]), (&"visual".into(), &false.into()));
    let parts = arm["parts"].as_array().unwrap();
    let kinds: Vec<&str> = parts.iter().map(|p| p["geometry"]["type"].as_str().unwrap()).collect();
    assert_eq!(kinds, ["cylinder", "sphere"]);
    assert_eq!(parts[0]["geometry"]["radius"].as_f64(), Some(0.03));
    assert_eq!(parts[0]["geometry"]["half_height"].as_f64(), Some(0.25));
    assert_eq!(parts[1]["geometry"]["radius"].as_f64(), Some(0.06));
    let cylinder = quat(&parts[0]["orientation"]);
    assert!(same_rotation(cylinder, DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2), 1e-7));
    assert!(close(cylinder * DVec3::Z, DVec3::NEG_Y, 1e-6), "the cylinder's axis along the link's −y");

    // where the page draws them at t = 0 (row pose ∘ part pose) is where the kinematics puts them:
    // the joint 0.1 m under the base, the arm turned 0.7 rad about x
    let index = arm["index"].as_u64().unwrap() as usize;
    let row = floats(&data["frames"][0]);
    let (p, q) = (DVec3::new(row[7 * index], row[7 * index + 1], row[7 * index + 2]), {
        let r = &row[7 * index + 3..7 * index + 7];
        DQuat::from_xyzw(r[1], r[2], r[3], r[0])
    });
    let world_from_arm = DQuat::from_rotation_x(0.7);
    let joint = DVec3::new(0.0, 0.0, 0.9);
    for (part, origin) in parts.iter().zip([DVec3::new(0.0, 0.0, -0.25), DVec3::new(0.0, 0.0, -0.5)]) {
        let drawn = p + q * vec3(&part["position"]);
        assert!(close(drawn, joint + world_from_arm * origin, 1e-6), "{drawn} vs {}", joint + world_from_arm * origin);
    }

    // no geometry: the link with mass is its inertia box, the massless frame a marker
    let weight = body(&data, "r/weight");
    assert_eq!((&weight["drawn"], &weight["inertia_box"]), (&"inertia_box".into(), &true.into()));
    assert_eq!(weight["parts"][0]["geometry"]["type"], "box");
    let tip = body(&data, "r/tip");
    assert_eq!((&tip["drawn"], &tip["marker"]), (&"marker".into(), &true.into()));
    assert_eq!(tip["parts"][0]["geometry"]["type"], "sphere");
}

/// A link whose visual is COLLADA (not read) and whose collision is a box; a link whose visual is
/// COLLADA and has no collision; a link whose visual STL is missing, with a collision sphere.
const COLLADA: &str = r#"<?xml version="1.0"?>
<robot name="dae">
  <link name="base">
    <inertial><mass value="2"/><inertia ixx="0.02" iyy="0.03" izz="0.04"/></inertial>
    <visual><geometry><mesh filename="meshes/base.dae"/></geometry></visual>
    <collision><origin xyz="0 0 0.05"/><geometry><box size="0.3 0.2 0.1"/></geometry></collision>
  </link>
  <link name="arm">
    <inertial><origin xyz="0 0 -0.2"/><mass value="1"/><inertia ixx="0.02" iyy="0.02" izz="0.001"/></inertial>
    <visual><geometry><mesh filename="meshes/arm.dae"/></geometry></visual>
  </link>
  <link name="hand">
    <inertial><mass value="0.2"/><inertia ixx="0.001" iyy="0.001" izz="0.001"/></inertial>
    <visual><geometry><mesh filename="meshes/missing.stl"/></geometry></visual>
    <collision><origin xyz="0 0 -0.03"/><geometry><sphere radius="0.04"/></geometry></collision>
  </link>
  <joint name="swing" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="1 0 0"/>
    <limit lower="-3" upper="3" effort="10" velocity="5"/></joint>
  <joint name="to_hand" type="fixed"><parent link="arm"/><child link="hand"/><origin xyz="0 0 -0.4"/></joint>
</robot>
"#;

#[test]
fn a_collada_visual_falls_back_to_the_collision_geometry_with_one_warning() {
    let dir = tempfile::tempdir().unwrap();
    fs::create_dir(dir.path().join("meshes")).unwrap();
    write(dir.path(), "meshes/base.dae", "<?xml version=\"1.0\"?><COLLADA/>\n");
    write(dir.path(), "meshes/arm.dae", "<?xml version=\"1.0\"?><COLLADA/>\n");
    write(dir.path(), "dae.urdf", COLLADA);
    write(
        dir.path(),
        "s.toml",
        "version = 1\n[world]\nduration = 0.1\nsample_every = 10\n\n[[robot]]\nname = \"r\"\nurdf = \"dae.urdf\"\n\
         base = \"fixed\"\nposition = [0.0, 0.0, 1.0]\n",
    );
    tumble(dir.path()).args(["run", "s.toml", "--out", "t.csv", "-q"]).assert().success();
    let out = tumble(dir.path())
        .args(["view", "t.csv", "--scene", "s.toml", "--out", "v.html"])
        .assert()
        .success()
        .stderr(contains("warning: robot `r`: meshes are not drawn"))
        .stderr(contains("COLLADA (.dae) is not read: convert it to STL or OBJ: meshes/base.dae (link 'base', <visual> line 5), meshes/arm.dae (link 'arm', <visual> line 10)"))
        .stderr(contains("missing (the path tried: "))
        .stderr(contains("missing.stl): meshes/missing.stl (link 'hand', <visual> line 14)"));
    let stderr = String::from_utf8(out.get_output().stderr.clone()).unwrap();
    assert_eq!(stderr.lines().filter(|l| l.starts_with("warning: robot")).count(), 1, "one warning: {stderr}");
    let data = data_of(&fs::read_to_string(dir.path().join("v.html")).unwrap());
    // the base: its collision box, 5 cm up
    let base = body(&data, "r/base");
    assert_eq!(base["drawn"], "collision");
    assert_eq!(base["parts"][0]["geometry"]["type"], "box");
    assert!(close(vec3(&base["parts"][0]["geometry"]["half_extents"]), DVec3::new(0.15, 0.1, 0.05), 1e-7));
    assert!(close(vec3(&base["parts"][0]["position"]), DVec3::new(0.0, 0.0, 0.05), 1e-7));
    // the arm has no collision geometry: its inertia box
    let arm = body(&data, "r/arm");
    assert_eq!((&arm["drawn"], &arm["inertia_box"]), (&"inertia_box".into(), &true.into()));
    // the hand: its collision sphere, 3 cm down
    let hand = body(&data, "r/hand");
    assert_eq!(hand["drawn"], "collision");
    assert_eq!(hand["parts"][0]["geometry"]["radius"].as_f64(), Some(0.04));
    assert!(close(vec3(&hand["parts"][0]["position"]), DVec3::new(0.0, 0.0, -0.03), 1e-7));
}

#[test]
fn an_stl_visual_is_a_mesh_part_mirrored_by_its_scale() {
    let dir = tempfile::tempdir().unwrap();
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tumble/tests/fixtures/meshes/cube.stl");
    fs::copy(&fixture, dir.path().join("cube.stl")).unwrap();
    let urdf = r#"<?xml version="1.0"?>
<robot name="m">
  <link name="base"/>
  <link name="block">
    <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial>
    <visual><origin xyz="0.1 0.2 0.3"/><geometry><mesh filename="cube.stl" scale="0.1 -0.2 0.3"/></geometry></visual>
  </link>
  <joint name="slide" type="prismatic"><parent link="base"/><child link="block"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="5"/></joint>
</robot>
"#;
    write(dir.path(), "m.urdf", urdf);
    write(
        dir.path(),
        "s.toml",
        "version = 1\n[world]\nduration = 0.1\n\n[[robot]]\nname = \"r\"\nurdf = \"m.urdf\"\nbase = \"fixed\"\n",
    );
    tumble(dir.path())
        .args(["run", "s.toml", "--out", "t.csv", "--view", "v.html", "-q"])
        .assert()
        .success()
        .stderr("");
    let data = data_of(&fs::read_to_string(dir.path().join("v.html")).unwrap());
    let block = body(&data, "r/block");
    assert_eq!(block["drawn"], "visual");
    let part = &block["parts"][0];
    assert!(close(vec3(&part["position"]), DVec3::new(0.1, 0.2, 0.3), 1e-7));
    let geometry = &part["geometry"];
    assert_eq!(geometry["type"], "mesh");
    let vertices: Vec<DVec3> = geometry["vertices"].as_array().unwrap().iter().map(vec3).collect();
    let triangles: Vec<[usize; 3]> = geometry["triangles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| {
            let t = floats(t);
            [t[0] as usize, t[1] as usize, t[2] as usize]
        })
        .collect();
    // the file's 36 corners welded to the cube's 8
    assert_eq!((vertices.len(), triangles.len()), (8, 12));
    let soup = tumble::mesh::read::read_file(&fixture, &Default::default()).unwrap();
    let scale = DVec3::new(0.1, -0.2, 0.3);
    for v in &soup.vertices {
        assert!(vertices.iter().any(|w| close(*w, *v * scale, 1e-6)), "corner {} not drawn", *v * scale);
    }
    // mirrored, the triangles still face out: the signed volume is that of the file times |sx sy sz|
    let volume = |corners: &dyn Fn(usize) -> [DVec3; 3], n: usize| -> f64 {
        (0..n)
            .map(|k| {
                let [a, b, c] = corners(k);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    };
    let file_volume = volume(&|k| soup.triangles[k].map(|i| soup.vertices[i as usize]), soup.triangles.len());
    let drawn_volume = volume(&|k| triangles[k].map(|i| vertices[i]), triangles.len());
    assert!(file_volume > 0.0);
    assert!((drawn_volume - file_volume * 0.1 * 0.2 * 0.3).abs() < 1e-6, "{drawn_volume} vs {file_volume}");
}

fn contact_lines(path: &Path) -> Vec<Value> {
    fs::read_to_string(path).unwrap().lines().map(|l| serde_json::from_str(l).unwrap()).collect()
}

/// The bouncing ball with `--contacts`: every frame of the page carries the points and forces of
/// the sample at its time; `tumble view --contacts` writes the same overlay; without it there is none.
#[test]
fn the_contacts_overlay_carries_the_points_of_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bounce.toml");
    let scene = scene.to_str().unwrap();
    tumble(dir.path())
        .args(["run", scene, "--out", "b.csv", "--contacts", "c.jsonl", "--view", "run.html", "-q"])
        .assert()
        .success();
    let samples = contact_lines(&dir.path().join("c.jsonl"));
    let data = data_of(&fs::read_to_string(dir.path().join("run.html")).unwrap());
    let overlay = &data["contacts"];
    assert_eq!(overlay["source"], "c.jsonl");
    assert_eq!(overlay["reference_of"], "the moving bodies' weight");
    // the ball: 800 kg/m³, radius 0.1 m, g = 9.81 m/s²
    let weight = 800.0 * 4.0 / 3.0 * std::f64::consts::PI * 1e-3 * 9.81;
    assert!((overlay["reference"].as_f64().unwrap() / weight - 1.0).abs() < 1e-6);
    let times = floats(&data["times"]);
    let frames = overlay["frames"].as_array().unwrap();
    assert_eq!(frames.len(), times.len());
    let mut with_contacts = 0;
    for (t, frame) in times.iter().zip(frames) {
        // the page writes times with f32 precision: the sample nearest the frame's time
        let gap = |s: &&Value| (s["t"].as_f64().unwrap() - t).abs();
        let sample = samples.iter().min_by(|a, b| gap(a).total_cmp(&gap(b))).unwrap();
        assert!(gap(&sample) < 1e-6 * t.max(1.0), "no sample at t = {t}");
        let want: Vec<f64> = sample["contacts"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|c| floats(&c["point"]).into_iter().chain(floats(&c["force"])))
            .collect();
        let got = floats(frame);
        assert_eq!(got.len(), want.len(), "t = {t}");
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() <= 1e-6 * w.abs().max(1.0), "t = {t}: {g} vs {w}");
        }
        with_contacts += usize::from(!got.is_empty());
    }
    assert!(with_contacts > 100, "the ball rests on the floor: {with_contacts} frames with contacts");
    assert_eq!(overlay["most"], 1);

    // `tumble view --contacts`: the same overlay; without it, none
    tumble(dir.path())
        .args(["view", "b.csv", "--scene", scene, "--contacts", "c.jsonl", "--out", "view.html"])
        .assert()
        .success();
    let view = data_of(&fs::read_to_string(dir.path().join("view.html")).unwrap());
    assert_eq!(view["contacts"]["frames"], data["contacts"]["frames"]);
    tumble(dir.path()).args(["view", "b.csv", "--scene", scene, "--out", "none.html"]).assert().success();
    assert!(data_of(&fs::read_to_string(dir.path().join("none.html")).unwrap())["contacts"].is_null());
}

/// A contacts file with a bad line is exit 2, naming the line and the field; nothing is written.
#[test]
fn a_bad_contacts_file_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bounce.toml");
    let scene = scene.to_str().unwrap();
    tumble(dir.path()).args(["run", scene, "--duration", "0.1", "--out", "b.csv", "-q"]).assert().success();
    write(dir.path(), "c.jsonl", "{\"t\": 0, \"contacts\": []}\n{\"t\": 0.1, \"contacts\": [{\"point\": [0, 0]}]}\n");
    tumble(dir.path())
        .args(["view", "b.csv", "--scene", scene, "--contacts", "c.jsonl", "--out", "v.html"])
        .assert()
        .code(2)
        .stderr(contains("c.jsonl:2: `contacts[0].point` is not three finite numbers"));
    assert!(!dir.path().join("v.html").exists());
}
