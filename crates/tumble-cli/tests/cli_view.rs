//! `tumble view` and `tumble run --view`: one self-contained HTML file, its data (bodies, shapes,
//! frames, energy), decimation, the bad inputs, a trajectory cut short. The page in a real browser is
//! tested by `browser.rs`.

mod common;

use assert_cmd::prelude::*;
use common::tumble;
use predicates::prelude::PredicateBooleanExt;
use predicates::str::contains;
use serde_json::Value;
use std::fs;
use std::path::{Path, PathBuf};

fn demo_scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/demo.toml")
}

/// The replay's data: the JSON object the page holds.
fn data_of(html: &str) -> Value {
    let start = html.find("const DATA = ").expect("a data line") + "const DATA = ".len();
    let end = start + html[start..].find(";\n").unwrap();
    serde_json::from_str(&html[start..end]).unwrap()
}

/// Every place where a page could load something from elsewhere.
fn external_references(html: &str) -> Vec<String> {
    let lower = html.to_ascii_lowercase();
    ["http:", "https:", "src=", "href=", "url(", "@import", "fetch(", "xmlhttprequest", "websocket", "import(", "//cdn"]
        .iter()
        .filter(|p| lower.contains(*p))
        .map(|p| p.to_string())
        .collect()
}

fn view(dir: &Path, args: &[&str]) -> assert_cmd::assert::Assert {
    tumble(dir).arg("view").args(args).assert()
}

#[test]
fn the_demo_replay_is_one_small_offline_file() {
    let dir = tempfile::tempdir().unwrap();
    tumble(dir.path()).args(["run", "--out", "demo.csv", "--quiet"]).assert().success();
    view(dir.path(), &["demo.csv", "--scene", demo_scene().to_str().unwrap(), "--out", "r.html"]).success();
    let html = fs::read_to_string(dir.path().join("r.html")).unwrap();
    assert_eq!(external_references(&html), Vec::<String>::new(), "the page loads nothing");
    assert!(html.len() < 800_000, "{} bytes", html.len());
    let data = data_of(&html);
    let bodies = data["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), 7, "the floor too");
    assert_eq!(bodies[0]["name"], "flipper");
    assert_eq!(bodies[1]["index"], 1);
    assert_eq!(bodies[0]["parts"][0]["geometry"]["type"], "box");
    assert_eq!(bodies[0]["parts"][0]["geometry"]["half_extents"], serde_json::json!([1.5, 1, 0.5]));
    // 3001 samples, more than the 1000..2000 kept: every other one, and the last
    let times: Vec<f64> = data["times"].as_array().unwrap().iter().map(|t| t.as_f64().unwrap()).collect();
    assert_eq!(times.len(), 1501);
    assert!(times.windows(2).all(|w| w[1] > w[0]));
    assert_eq!(*times.last().unwrap(), 30.0);
    assert!(data["decimation"].as_str().unwrap().contains("1501 of 3001 frames"));
    let frames = data["frames"].as_array().unwrap();
    assert!(frames.iter().all(|f| f.as_array().unwrap().len() == 42), "x, y, z, qw, qx, qy, qz of 6 moving bodies");
    assert_eq!(frames[0][7], 4.0, "the stable box starts at x = 4 m");
    let energy = data["energy"]["values"].as_array().unwrap();
    assert_eq!(energy.len(), 1501);
    assert_eq!(energy[0], 0.0);
    // the splitting keeps the energy until the first landing (t ≈ 0.75 s), then contacts take it out
    let error = |k: usize| energy[k].as_f64().unwrap();
    assert!((0..1501).filter(|&k| times[k] < 0.7).all(|k| error(k).abs() < 1e-9), "energy kept in flight");
    assert!(error(1500) < -1.0, "the landings took energy out: {}", error(1500));
    assert!(data["truncated"].is_null());
}

const SHAPES: &str = r#"
version = 1
[world]
dt = 0.01
duration = 0.5
[[body]]
name = "floor"
fixed = true
shape = { type = "plane" }
[[body]]
name = "wall"
fixed = true
[[body]]
name = "ball"
density = 1000.0
shape = { type = "sphere", radius = 0.2 }
position = [0.0, 0.0, 3.0]
[[body]]
name = "pill"
density = 500.0
shape = { type = "capsule", radius = 0.1, half_height = 0.3 }
position = [2.0, 0.0, 3.0]
[[body]]
name = "can"
density = 500.0
shape = { type = "cylinder", radius = 0.25, half_height = 0.1 }
position = [3.0, 0.0, 3.0]
[[body]]
name = "arm/link1 </script>"
mass = 3.0
inertia = [0.5, 1.0, 1.25]
position = [1.0, 0.0, 3.0]
angular_velocity = [0.0, 0.0, 1.0]
"#;

#[test]
fn shapes_fixed_bodies_and_inertia_boxes() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("s.toml"), SHAPES).unwrap();
    tumble(dir.path()).args(["run", "s.toml", "--out", "s.csv", "--quiet", "--view", "s.html"]).assert().success();
    let html = fs::read_to_string(dir.path().join("s.html")).unwrap();
    assert_eq!(html.matches("</script>").count(), 1, "a body name cannot end the script");
    let data = data_of(&html);
    let bodies = data["bodies"].as_array().unwrap();
    let names: Vec<&str> = bodies.iter().map(|b| b["name"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        ["floor", "ball", "pill", "can", "arm/link1 </script>"],
        "a fixed body without a shape is not drawn"
    );
    assert_eq!(bodies[0]["index"], Value::Null);
    assert_eq!(bodies[0]["parts"][0]["geometry"]["type"], "plane");
    assert_eq!(bodies[1]["parts"][0]["geometry"], serde_json::json!({"type": "sphere", "radius": 0.2}));
    assert_eq!(
        bodies[2]["parts"][0]["geometry"],
        serde_json::json!({"type": "capsule", "radius": 0.1, "half_height": 0.3})
    );
    assert_eq!(
        bodies[3]["parts"][0]["geometry"],
        serde_json::json!({"type": "cylinder", "radius": 0.25, "half_height": 0.1})
    );
    // moments 0.5, 1, 1.25 kg·m² of 3 kg: h1² = 3 (1 + 1.25 − 0.5) / 6, ...
    let arm = &bodies[4];
    assert_eq!(arm["inertia_box"], true);
    let h: Vec<f64> =
        arm["parts"][0]["geometry"]["half_extents"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    let expected = [0.875f64.sqrt(), 0.375f64.sqrt(), 0.125f64.sqrt()];
    for (got, want) in h.iter().zip(expected) {
        assert!((got - want).abs() < 1e-6, "{h:?}");
    }
    assert_eq!(arm["index"], 3);
}

#[test]
fn large_trajectories_are_decimated() {
    let dir = tempfile::tempdir().unwrap();
    tumble(dir.path()).args(["run", "--duration", "5", "--out", "d.csv", "--quiet"]).assert().success();
    let scene = demo_scene();
    view(dir.path(), &["d.csv", "--scene", scene.to_str().unwrap(), "--out", "d.html", "--max-frames", "40"]).success();
    let data = data_of(&fs::read_to_string(dir.path().join("d.html")).unwrap());
    let n = data["times"].as_array().unwrap().len();
    assert!((40..=81).contains(&n), "{n} frames");
    assert_eq!(data["times"][n - 1], 5.0);
}

#[test]
fn a_trajectory_cut_short_shows_what_is_there() {
    let dir = tempfile::tempdir().unwrap();
    tumble(dir.path()).args(["run", "--duration", "2", "--out", "d.csv", "--quiet"]).assert().success();
    let text = fs::read_to_string(dir.path().join("d.csv")).unwrap();
    fs::write(dir.path().join("d.csv"), &text[..text.len() / 2]).unwrap();
    let scene = demo_scene();
    view(dir.path(), &["d.csv", "--scene", scene.to_str().unwrap(), "--out", "d.html"])
        .success()
        .stderr(contains("cut short"));
    let data = data_of(&fs::read_to_string(dir.path().join("d.html")).unwrap());
    assert!(data["truncated"].as_str().unwrap().starts_with("the trajectory ends early"));
    let last = data["times"].as_array().unwrap().last().unwrap().as_f64().unwrap();
    assert!(last > 0.5 && last < 1.5, "up to the cut: {last}");
}

#[test]
fn bad_input_is_exit_2_naming_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    tumble(dir.path()).args(["run", "--duration", "1", "--out", "d.csv", "--quiet"]).assert().success();
    let scene = demo_scene();
    let scene = scene.to_str().unwrap();
    fs::write(dir.path().join("s.toml"), SHAPES).unwrap();
    view(dir.path(), &["d.csv", "--scene", "s.toml", "--out", "x.html"])
        .code(2)
        // the demo's `ball` is in both; its other bodies are not in SHAPES, and SHAPES's others not in it
        .stderr(
            contains("not moving bodies of the scene s.toml: `flipper`, `stable`, `box`, `capsule`, `cylinder`;")
                .and(contains("lacks moving bodies of the scene s.toml: `pill`, `can`, `arm/link1 </script>`")),
        );
    fs::write(dir.path().join("cols.csv"), "t,body,x,y,z,vx,vy,vz,wx,wy,wz\n").unwrap();
    view(dir.path(), &["cols.csv", "--scene", scene, "--out", "x.html"])
        .code(2)
        .stderr(contains("missing columns `qw`, `qx`, `qy`, `qz`"));
    view(dir.path(), &["d.csv", "--scene", scene, "--out", "x.svg"]).code(2).stderr(contains("use FILE.html"));
    view(dir.path(), &["d.csv", "--scene", "nope.toml", "--out", "x.html"]).code(2).stderr(contains("nope.toml"));
    assert!(!dir.path().join("x.html").exists() && !dir.path().join("x.svg").exists());
    // the trajectory must be read back: not a device
    std::os::unix::fs::symlink("/dev/null", dir.path().join("null.csv")).unwrap();
    tumble(dir.path())
        .args(["run", "--out", "null.csv", "--view", "x.html"])
        .assert()
        .code(2)
        .stderr(contains("--plot/--view read the trajectory back, but --out null.csv is not a regular file"));
    assert!(!dir.path().join("x.html").exists());
}

/// A mesh body is drawn as its own triangles, about its centre of mass.
#[test]
fn a_mesh_body_is_drawn_as_its_triangles() {
    let dir = tempfile::tempdir().unwrap();
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tumble/tests/fixtures/meshes/cube.obj");
    fs::copy(&fixture, dir.path().join("cube.obj")).unwrap();
    let scene = "version = 1\n[world]\nduration = 0.1\n\n[[body]]\nname = \"part\"\ndensity = 1000.0\n\
                 shape = { type = \"mesh\", file = \"cube.obj\" }\nangular_velocity_body = [0.0, 1.0, 0.0]\n";
    fs::write(dir.path().join("part.toml"), scene).unwrap();
    tumble(dir.path())
        .args(["run", "part.toml", "--out", "part.csv", "--view", "part.html", "--quiet"])
        .assert()
        .success();
    let data = data_of(&fs::read_to_string(dir.path().join("part.html")).unwrap());
    let geometry = &data["bodies"][0]["parts"][0]["geometry"];
    assert_eq!(geometry["type"], "mesh");
    let vertices = geometry["vertices"].as_array().unwrap();
    let triangles = geometry["triangles"].as_array().unwrap();
    assert_eq!((vertices.len(), triangles.len()), (8, 12), "a cube: 8 corners, 12 triangles");
    // centred on the centre of mass
    let centroid: Vec<f64> =
        (0..3).map(|k| vertices.iter().map(|v| v[k].as_f64().unwrap()).sum::<f64>() / vertices.len() as f64).collect();
    assert!(centroid.iter().all(|c| c.abs() < 1e-6), "{centroid:?}");
}

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name)
}

fn floats(value: &Value) -> Vec<f64> {
    value.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

/// The largest `|value|` of the replay's energy series, and the run summary's largest energy error.
fn energy_errors(data: &Value, summary: &Path) -> (f64, f64) {
    let shown = floats(&data["energy"]["values"]).iter().fold(0.0_f64, |m, e| m.max(e.abs()));
    let summary: Value = serde_json::from_str(&fs::read_to_string(summary).unwrap()).unwrap();
    (shown, summary["energy"]["max_relative_error"].as_f64().unwrap())
}

/// The double pendulum: the links are drawn as their inertia boxes at their centres of mass (the
/// rows hold the link frames, 0.5 m above), the massless `tip` and `base` as markers, and the energy
/// error is the run's (RK4: about 5e-12), not a spurious one.
#[test]
fn robot_links_are_drawn_as_inertia_boxes_at_their_centres_of_mass() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_path("double_pendulum.toml");
    tumble(dir.path())
        .args(["run", scene.to_str().unwrap(), "--out", "dp.csv", "--summary", "dp.json", "--quiet"])
        .assert()
        .success();
    view(dir.path(), &["dp.csv", "--scene", scene.to_str().unwrap(), "--out", "dp.html"]).success();
    let html = fs::read_to_string(dir.path().join("dp.html")).unwrap();
    assert_eq!(external_references(&html), Vec::<String>::new());
    let data = data_of(&html);
    let bodies = data["bodies"].as_array().unwrap();
    let names: Vec<&str> = bodies.iter().map(|b| b["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["pendulum/upper", "pendulum/lower", "pendulum/tip", "pendulum/base"]);
    let indices: Vec<&Value> = bodies.iter().map(|b| &b["index"]).collect();
    assert_eq!(indices, [&Value::from(0), &Value::from(1), &Value::from(2), &Value::Null]);
    assert!(bodies.iter().all(|b| b["robot"] == "pendulum"));
    // 1 kg, I = (1/12, 1/12, 0.001) kg·m² about the centre of mass 0.5 m down the link:
    // h_x² = h_y² = 3 · 0.001 / 2, h_z² = 3 (1/6 − 0.001) / 2
    for link in &bodies[..2] {
        assert_eq!((link["inertia_box"].as_bool(), link["marker"].as_bool()), (Some(true), Some(false)));
        let part = &link["parts"][0];
        assert_eq!(part["geometry"]["type"], "box");
        let h = floats(&part["geometry"]["half_extents"]);
        let want = [0.0015f64.sqrt(), 0.0015f64.sqrt(), (1.5 * (1.0 / 6.0 - 0.001f64)).sqrt()];
        assert!(h.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-6), "{h:?}");
        assert_eq!(floats(&part["position"]), [0.0, 0.0, -0.5], "at the centre of mass, in the link frame");
        assert_eq!(floats(&part["orientation"]), [1.0, 0.0, 0.0, 0.0]);
    }
    for marker in &bodies[2..] {
        assert_eq!((marker["inertia_box"].as_bool(), marker["marker"].as_bool()), (Some(false), Some(true)));
        assert_eq!(marker["parts"][0]["geometry"]["type"], "sphere");
    }
    // the pivot, fixed to the world 2.5 m up
    assert_eq!(floats(&bodies[3]["position"]), [0.0, 0.0, 2.5]);
    // one hue: every colour is a multiple of the palette's first, or lighter for markers
    let upper = floats(&bodies[0]["color"]);
    let lower = floats(&bodies[1]["color"]);
    assert!((lower[0] / upper[0] - lower[2] / upper[2]).abs() < 1e-3 && lower[0] < upper[0], "{upper:?} {lower:?}");
    // frames: x, y, z, qw, qx, qy, qz of the 3 moving links; the lower link's frame is at the elbow
    let frames = data["frames"].as_array().unwrap();
    assert!(frames.iter().all(|f| f.as_array().unwrap().len() == 21));
    let elbow = floats(&frames[0]).into_iter().skip(7).take(3).collect::<Vec<_>>();
    assert!((elbow[1] - 1f64.sin()).abs() < 1e-6 && (elbow[2] - (2.5 - 1f64.cos())).abs() < 1e-6, "{elbow:?}");
    let (shown, summary) = energy_errors(&data, &dir.path().join("dp.json"));
    eprintln!("double pendulum: largest energy error shown {shown:e}, in the summary {summary:e}");
    assert!(summary > 0.0 && summary < 1e-10, "{summary:e}");
    assert!((shown - summary).abs() < 0.01 * summary, "shown {shown:e} vs the summary's {summary:e}");
    let label = data["energy"]["label"].as_str().unwrap();
    assert!(label.contains("of the bodies and robot links") && !label.contains("control"), "passive: {label}");
    assert!(data["title"].as_str().unwrap().contains("1 robot (3 moving links)"));
}

/// The Panda: its fixed base (`panda_link0`, 0.63 kg) is a fixed body, the hand (fixed to link 8,
/// with its own mass) a box of its own, the massless frames markers; the page stays small.
#[test]
fn the_panda_replay_has_its_base_hand_and_frames() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_path("panda.toml");
    tumble(dir.path())
        .args(["run", scene.to_str().unwrap(), "--out", "p.csv", "--summary", "p.json", "--view", "p.html", "-q"])
        .assert()
        .success();
    let html = fs::read_to_string(dir.path().join("p.html")).unwrap();
    eprintln!("panda replay (3 s, 301 samples, 12 moving links): {} bytes", html.len());
    assert!(html.len() < 400_000, "{} bytes", html.len());
    let data = data_of(&html);
    let bodies = data["bodies"].as_array().unwrap();
    let find = |name: &str| bodies.iter().find(|b| b["name"] == name).unwrap_or_else(|| panic!("{name}"));
    let base = find("panda/panda_link0");
    assert_eq!((&base["index"], &base["inertia_box"]), (&Value::Null, &Value::Bool(true)));
    assert_eq!(find("panda/panda_hand")["inertia_box"], true);
    for frame in ["panda/panda_link8", "panda/panda_hand_tcp"] {
        assert_eq!(find(frame)["marker"], true, "{frame}");
    }
    assert_eq!(bodies.len(), 13, "12 moving links and the base");
    let moving = bodies.iter().filter(|b| !b["index"].is_null()).count();
    assert!(data["frames"].as_array().unwrap().iter().all(|f| f.as_array().unwrap().len() == 7 * moving));
    // PD control and damping do work: the energy changes, and the replay shows the summary's change
    let (shown, summary) = energy_errors(&data, &dir.path().join("p.json"));
    assert!(summary > 1e-3 && (shown - summary).abs() < 1e-3 * summary, "shown {shown:e}, summary {summary:e}");
    let label = data["energy"]["label"].as_str().unwrap();
    assert!(label.ends_with("(robots under control or damping: the change includes their work)"), "{label}");
}

/// A trajectory naming a link the robot lacks, a robot the scene lacks, or a link fixed to the
/// world: exit 2, each named, nothing written.
#[test]
fn a_link_or_robot_the_scene_lacks_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_path("double_pendulum.toml");
    let scene = scene.to_str().unwrap();
    tumble(dir.path()).args(["run", scene, "--duration", "0.1", "--out", "dp.csv", "-q"]).assert().success();
    let text = fs::read_to_string(dir.path().join("dp.csv")).unwrap();
    fs::write(dir.path().join("nolink.csv"), text.replace(",pendulum/lower,", ",pendulum/nolink,")).unwrap();
    view(dir.path(), &["nolink.csv", "--scene", scene, "--out", "x.html"])
        .code(2)
        .stderr(contains("the trajectory does not match the scene"))
        .stderr(contains("`pendulum/nolink`").and(contains("lacks moving bodies of the scene")))
        .stderr(contains("`pendulum/lower`"))
        .stderr(contains("robot `pendulum` has no moving link `nolink` (its moving links: `upper`, `lower`, `tip`)"));
    fs::write(dir.path().join("arm.csv"), text.replace(",pendulum/", ",arm/")).unwrap();
    view(dir.path(), &["arm.csv", "--scene", scene, "--out", "x.html"])
        .code(2)
        .stderr(contains("`arm/upper`").and(contains("the scene has no robot `arm` (its robots: `pendulum`)")));
    fs::write(dir.path().join("base.csv"), text.replace(",pendulum/tip,", ",pendulum/base,")).unwrap();
    view(dir.path(), &["base.csv", "--scene", scene, "--out", "x.html"])
        .code(2)
        .stderr(contains("`base` of robot `pendulum` is fixed to the world (never written)"));
    // the robot's trajectory against a scene without it, and the other way round
    view(dir.path(), &["dp.csv", "--scene", demo_scene().to_str().unwrap(), "--out", "x.html"])
        .code(2)
        .stderr(contains("`pendulum/upper`").and(contains("the scene has no robot `pendulum`")));
    tumble(dir.path()).args(["run", "--duration", "0.1", "--out", "demo.csv", "-q"]).assert().success();
    view(dir.path(), &["demo.csv", "--scene", scene, "--out", "x.html"])
        .code(2)
        .stderr(contains("`flipper`, `stable`").and(contains("`pendulum/upper`, `pendulum/lower`, `pendulum/tip`")));
    assert!(!dir.path().join("x.html").exists());
}

/// A convex body is drawn as its hull; a compound as one part per shape, at its pose about the
/// centre of mass.
#[test]
fn convex_and_compound_bodies_are_drawn_part_by_part() {
    let dir = tempfile::tempdir().unwrap();
    let scene = "version = 1\n[world]\nduration = 0.1\n\n\
                 [[body]]\nname = \"gem\"\ndensity = 1000.0\n\
                 shape = { type = \"convex\", points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]] }\n\n\
                 [[body]]\nname = \"dumbbell\"\ndensity = 1000.0\nposition = [3.0, 0.0, 0.0]\n\
                 shapes = [\n  { type = \"sphere\", radius = 0.2, position = [-0.5, 0.0, 0.0] },\n\
                 { type = \"sphere\", radius = 0.2, position = [0.5, 0.0, 0.0] },\n\
                 { type = \"capsule\", radius = 0.05, half_height = 0.5, orientation = [0.7071067811865476, 0.0, 0.7071067811865476, 0.0] },\n]\n";
    fs::write(dir.path().join("s.toml"), scene).unwrap();
    tumble(dir.path()).args(["run", "s.toml", "--out", "s.csv", "--view", "s.html", "--quiet"]).assert().success();
    let data = data_of(&fs::read_to_string(dir.path().join("s.html")).unwrap());
    let gem = &data["bodies"][0]["parts"];
    assert_eq!(gem.as_array().unwrap().len(), 1);
    assert_eq!(gem[0]["geometry"]["type"], "convex_hull");
    assert_eq!(gem[0]["geometry"]["vertices"].as_array().unwrap().len(), 4);
    assert_eq!(gem[0]["geometry"]["triangles"].as_array().unwrap().len(), 4);
    let parts = data["bodies"][1]["parts"].as_array().unwrap();
    let kinds: Vec<&str> = parts.iter().map(|p| p["geometry"]["type"].as_str().unwrap()).collect();
    assert_eq!(kinds, ["sphere", "sphere", "capsule"]);
    assert_eq!(parts[0]["position"], serde_json::json!([-0.5, 0, 0]));
    assert_eq!(parts[1]["position"], serde_json::json!([0.5, 0, 0]));
    assert_eq!(parts[2]["orientation"], serde_json::json!([0.70710677, 0, 0.70710677, 0]));
}

/// `tumble run X.xml --view` draws the MJCF world's geometry: the floor, and each link of the
/// Gymnasium Ant with its geoms placed as the file places them (the torso's sphere, a leg's capsule
/// from `fromto`: centred halfway, its axis along `from − to`, half length half the distance).
#[test]
fn the_replay_draws_an_mjcf_worlds_geometry() {
    let dir = tempfile::tempdir().unwrap();
    let ant = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tumble/tests/fixtures/mjcf/gymnasium/ant.xml");
    tumble(dir.path())
        .args(["run", ant.to_str().unwrap(), "--duration", "0.1", "--out", "ant.csv", "--view", "ant.html", "-q"])
        .assert()
        .success();
    let data = data_of(&fs::read_to_string(dir.path().join("ant.html")).unwrap());
    let bodies = data["bodies"].as_array().unwrap();
    let named =
        |name: &str| bodies.iter().find(|b| b["name"] == name).unwrap_or_else(|| panic!("no {name}: {bodies:?}"));
    assert_eq!(named("floor")["parts"][0]["geometry"]["type"], "plane");
    let torso = &named("ant/torso")["parts"][0]["geometry"];
    assert_eq!((torso["type"].as_str(), torso["radius"].as_f64()), (Some("sphere"), Some(0.25)));
    // aux_1_geom: fromto="0 0 0 0.2 0.2 0", size 0.08
    let part = &named("ant/front_left_leg")["parts"][0];
    let g = &part["geometry"];
    assert_eq!((g["type"].as_str(), g["radius"].as_f64()), (Some("capsule"), Some(0.08)));
    let f = |v: &Value| v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect::<Vec<f64>>();
    assert!((g["half_height"].as_f64().unwrap() - 0.1 * 2f64.sqrt()).abs() < 1e-6, "{g}");
    let p = f(&part["position"]);
    assert!((p[0] - 0.1).abs() < 1e-6 && (p[1] - 0.1).abs() < 1e-6 && p[2].abs() < 1e-6, "{p:?}");
    // the capsule's axis, the z axis of [w, x, y, z]: along ±(1, 1, 0)/√2
    let [w, x, y, z] = f(&part["orientation"])[..] else { panic!("a quaternion") };
    let axis = [2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y)];
    let s = 0.5f64.sqrt();
    assert!((axis[0].abs() - s).abs() < 1e-6 && (axis[1] - axis[0]).abs() < 1e-6 && axis[2].abs() < 1e-6, "{axis:?}");
    // every moving link of the Ant is drawn with its geom
    let links = bodies.iter().filter(|b| b["robot"] == "ant" && !b["index"].is_null()).count();
    assert_eq!(links, 13);
}
