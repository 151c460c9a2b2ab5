//! An MJCF file as a whole world (`tumble run X.xml`, `scene::load_mjcf_world`):
//!
//! - geoms fixed to the world become fixed bodies with their pose (`euler`, `zaxis`, `fromto`),
//!   childless free bodies scene bodies: a box dropped on a rotated worldbody box comes to rest on
//!   it at the table's top plus its half height, a box on a plane tilted by `zaxis` rests at its half
//!   height from the plane, a `fromto` capsule lies on the floor at its radius;
//! - MuJoCo's contact filter: the pairs it allows on chains with a welded body, a free body,
//!   `<exclude>` pairs and contype/conaffinity masks are those `mujoco` reports in contact
//!   (`fixtures/mjcf/filter/`, `tools/mjcf_filter_fixtures.py`); in a run, a ball whose masks match
//!   no other geom's falls through the floor while its twin lands, an excluded pair passes through
//!   each other, a geom that can collide with nothing is no shape;
//! - a free body the scene format cannot hold stays a robot, with a warning saying why.

use std::path::{Path, PathBuf};
use tumble::multibody::mjcf::{load_mjcf, MjcfOptions};
use tumble::multibody::GeometryRole;
use tumble::scene::{self, Scene};

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/mjcf")
}

/// The world of `xml`, written to a temporary file.
fn world(xml: &str) -> (tempfile::TempDir, Scene) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("world.xml");
    std::fs::write(&path, xml).unwrap();
    let scene = scene::load_mjcf_world(&path).unwrap_or_else(|e| panic!("{e}"));
    (dir, scene)
}

fn run(scene: &mut Scene, seconds: f64) {
    let steps = (seconds / scene.world.config.dt).round() as usize;
    for _ in 0..steps {
        scene.world.step().unwrap();
    }
}

fn body<'a>(scene: &'a Scene, name: &str) -> &'a tumble::body::RigidBody {
    let i = scene.world.body_index(name).unwrap_or_else(|| panic!("no body {name}"));
    &scene.world.bodies[i]
}

#[test]
fn a_free_box_comes_to_rest_on_a_rotated_worldbody_box() {
    // the example of docs/mjcf.md
    let drop = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/mjcf_drop.xml");
    let mut scene = scene::load_mjcf_world(&drop).unwrap();
    assert_eq!(scene.world.robots.len(), 0, "both free bodies are scene bodies");
    assert!(body(&scene, "table").fixed);
    // the box's mass from its density: 500 kg/m³ × 0.1³ m³
    assert!((body(&scene, "cube").mass.mass - 0.5).abs() < 1e-12);
    run(&mut scene, 1.5);
    let cube = body(&scene, "cube");
    let z = cube.state.position.z;
    eprintln!("cube at z = {z:.6} m (table top 0.4 + half height 0.05), |v| = {:.2e}", cube.state.velocity.length());
    assert!((z - 0.45).abs() < 5e-4, "cube z = {z}");
    assert!(cube.state.velocity.length() < 1e-3);
    // it landed flat and stayed on the table
    assert!(cube.state.position.truncate().length() < 0.4);
    let stick = body(&scene, "stick");
    eprintln!("capsule at z = {:.6} m (radius 0.03)", stick.state.position.z);
    assert!((stick.state.position.z - 0.03).abs() < 5e-4);
    // the body keeps the MJCF body's axes, the capsule's axis (`fromto` along body x) lying along world x
    let axis = stick.orientation_user() * tumble::math::DVec3::X;
    assert!(axis.x.abs() > 0.999, "axis {axis:?}");
    // tossed by the key "toss" (1.0 m/s across, 1 m/s up, 6 rad/s about z): it lands on the table,
    // slides and stops on it
    let mut scene = scene::load_mjcf_world_from(&drop, Some("toss")).unwrap();
    assert_eq!(body(&scene, "cube").state.velocity.to_array(), [1.0, 0.2, 1.0]);
    run(&mut scene, 1.5);
    let cube = body(&scene, "cube");
    eprintln!("tossed cube at {:?}, |v| = {:.2e}", cube.state.position.to_array(), cube.state.velocity.length());
    assert!((cube.state.position.z - 0.45).abs() < 5e-4 && cube.state.velocity.length() < 1e-3);
}

#[test]
fn a_box_rests_on_a_plane_tilted_by_zaxis() {
    // a plane whose normal leans 20° towards −y; friction 1 > tan 20°: the box sticks
    let (s, c) = 20f64.to_radians().sin_cos();
    let (_dir, mut scene) = world(&format!(
        r#"<mujoco>
  <option timestep="0.001"/>
  <worldbody>
    <geom name="slope" type="plane" size="5 5 0.1" zaxis="0 {} {}"/>
    <body name="block" pos="0 {} {}" zaxis="0 {} {}">
      <freejoint/>
      <geom type="box" size="0.1 0.1 0.05"/>
    </body>
  </worldbody>
</mujoco>"#,
        -s,
        c,
        -s * 0.051,
        c * 0.051,
        -s,
        c
    ));
    run(&mut scene, 1.0);
    let block = body(&scene, "block");
    let normal = tumble::math::DVec3::new(0.0, -s, c);
    let height = block.state.position.dot(normal);
    eprintln!("block {height:.6} m above the slope (half height 0.05), v = {:.2e}", block.state.velocity.length());
    assert!((height - 0.05).abs() < 5e-4, "height {height}");
    assert!(block.state.velocity.length() < 1e-3, "it sticks: v = {:?}", block.state.velocity);
}

#[test]
fn the_contact_filter_allows_the_pairs_mujoco_reports_in_contact() {
    let expected: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fixtures().join("filter/filter.json")).unwrap()).unwrap();
    for model in ["chain", "chain_exclude", "chain_masks"] {
        let mjcf = load_mjcf(&fixtures().join(format!("filter/{model}.xml")), MjcfOptions::default()).unwrap();
        let geoms = &mjcf.model.geometries;
        let mut allowed = Vec::new();
        for a in 0..geoms.len() {
            for b in a + 1..geoms.len() {
                if mjcf.filter.may_collide(a, b) {
                    let mut pair = [geoms[a].name.clone().unwrap(), geoms[b].name.clone().unwrap()];
                    pair.sort();
                    allowed.push(pair);
                }
            }
        }
        allowed.sort();
        let mujoco: Vec<[String; 2]> = serde_json::from_value(expected[model].clone()).unwrap();
        eprintln!("{model}: {} pairs allowed, as mujoco {}", allowed.len(), expected["mujoco"]);
        assert_eq!(allowed, mujoco, "{model}");
    }
}

#[test]
fn masks_and_excludes_decide_what_collides_in_a_run() {
    let (_dir, mut scene) = world(
        r#"<mujoco>
  <option timestep="0.001"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <geom name="ghost_rail" type="capsule" fromto="-1 2 0.1 1 2 0.1" size="0.02" contype="4" conaffinity="0"/>
    <body name="lander" pos="0 0 0.3"><freejoint/><geom type="sphere" size="0.1"/></body>
    <body name="sinker" pos="1 0 0.3"><freejoint/><geom type="sphere" size="0.1" contype="2" conaffinity="2"/></body>
    <body name="bottom" pos="-1 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
    <body name="top" pos="-1 0 0.5"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
    <body name="base" pos="-2 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
    <body name="stacked" pos="-2 0 0.5"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
  </worldbody>
  <contact><exclude body1="top" body2="bottom"/></contact>
</mujoco>"#,
    );
    // the rail's contype 4 meets no conaffinity: it is no collision shape, so no body
    assert!(scene.world.body_index("ghost_rail").is_none());
    run(&mut scene, 1.0);
    let z = |name: &str| body(&scene, name).state.position.z;
    eprintln!(
        "lander {:.4}, sinker {:.4}, top {:.4} (on the floor through `bottom`), stacked {:.4} (on `base`)",
        z("lander"),
        z("sinker"),
        z("top"),
        z("stacked")
    );
    // (1 & 1): lands; (2 & 1) | (1 & 2) = 0: falls through, ½ g t² ≈ 4.9 m
    assert!((z("lander") - 0.1).abs() < 5e-4);
    assert!(z("sinker") < -4.0);
    // the excluded pair passes through each other, both resting on the floor
    assert!((z("top") - 0.1).abs() < 5e-4 && (z("bottom") - 0.1).abs() < 5e-4);
    assert!((z("stacked") - 0.3).abs() < 1e-3);
}

#[test]
fn a_free_body_the_scene_cannot_hold_stays_a_robot_and_says_why() {
    let (_dir, scene) = world(
        r#"<mujoco>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <body name="lopsided" pos="0 0 1">
      <freejoint/>
      <inertial pos="0 0 0.05" mass="1" diaginertia="0.01 0.01 0.01"/>
      <geom type="sphere" size="0.1"/>
    </body>
    <body name="ball" pos="1 0 1"><freejoint/><geom type="sphere" size="0.1"/></body>
  </worldbody>
</mujoco>"#,
    );
    assert!(scene.world.body_index("ball").is_some());
    assert!(scene.world.body_index("lopsided").is_none());
    assert_eq!(scene.world.robots.len(), 1);
    assert_eq!(scene.world.robots[0].model.bodies.len(), 1, "{:?}", scene.world.robots[0].model.bodies);
    let why = scene.warnings.iter().find(|w| w.contains("'lopsided'")).expect("a warning");
    assert!(why.contains("kept as a floating robot") && why.contains("centre of mass"), "{why}");
}

#[test]
fn the_gymnasium_worlds_lose_what_cannot_collide() {
    // inverted_pendulum.xml: every geom contype 0, conaffinity 1: nothing collides, the rail is no body
    let mjcf = fixtures().join("gymnasium/inverted_pendulum.xml");
    let scene = scene::load_mjcf_world(&mjcf).unwrap();
    assert!(scene.world.bodies.is_empty(), "{:?}", scene.world.bodies.iter().map(|b| &b.name).collect::<Vec<_>>());
    let links = &scene.world.contacts().links.colliders;
    assert!(links.is_empty(), "{links:?}");
    // ant.xml: the floor a fixed body, not a robot link; the ant's geoms (conaffinity 0) touch the floor only
    let scene = scene::load_mjcf_world(&fixtures().join("gymnasium/ant.xml")).unwrap();
    assert!(body(&scene, "floor").fixed);
    let robot = &scene.world.robots[0];
    assert!(robot.model.geometries.iter().all(|g| g.link != "world"));
    assert!(robot.model.geometries.iter().filter(|g| g.role == GeometryRole::Collision).count() > 10);
}

#[test]
fn leave_out_names_only_childless_free_bodies() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("two.xml"),
        r#"<mujoco><worldbody>
  <body name="arm"><joint type="hinge"/><geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.05"/></body>
  <body name="ball" pos="1 0 1"><freejoint/><geom type="sphere" size="0.1"/></body>
</worldbody></mujoco>"#,
    )
    .unwrap();
    let scene_text = |leave_out: &str| {
        format!("version = 1\n[[robot]]\nname = \"r\"\nmjcf = \"two.xml\"\nleave_out = {leave_out}\n")
    };
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, scene_text("[\"world\", \"arm\"]")).unwrap();
    let e = scene::load(&path).unwrap_err().to_string();
    eprintln!("{e}");
    assert!(e.contains("scene.toml:5:") && e.contains("robot[0].leave_out"), "{e}");
    assert!(e.contains("cannot leave out body 'arm'") && e.contains("'ball'"), "{e}");
    std::fs::write(&path, scene_text("[\"world\", \"ball\"]")).unwrap();
    let scene = scene::load(&path).unwrap();
    let model = &scene.world.robots[0].model;
    assert_eq!(model.bodies.len(), 1, "the ball is left out");
    assert_eq!(model.bodies[0].name, "arm");
}

/// `fixtures/mjcf/keyframe/keys.json` (`tools/mjcf_keyframe_fixtures.py`): MuJoCo's state at each key.
fn keys() -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(fixtures().join("keyframe/keys.json")).unwrap()).unwrap()
}

fn numbers(v: &serde_json::Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

#[test]
fn a_keyframe_starts_the_world_where_mujoco_puts_it() {
    use tumble::multibody::mjcf::{load_mjcf_leaving_out, LeaveOut};
    let path = fixtures().join("keyframe/keys.xml");
    let expected = &keys()["keys"]["spin"];
    let scene = scene::load_mjcf_world_from(&path, Some("spin")).unwrap_or_else(|e| panic!("{e}"));
    assert!(scene.warnings.iter().any(|w| w.contains("time=\"1.5\"") && w.contains("starts at t = 0")));
    // the free box, a scene body: its centre of mass, frame and velocities as mj_forward has them
    let b = body(&scene, "box");
    let q = b.orientation_user();
    let xquat = numbers(&expected["box_xquat"]);
    let sign = if q.w * xquat[0] < 0.0 { -1.0 } else { 1.0 };
    let errors = [
        max_diff(&b.state.position.to_array(), &numbers(&expected["box_xipos"])),
        max_diff(&[sign * q.w, sign * q.x, sign * q.y, sign * q.z], &xquat),
        max_diff(&b.state.velocity.to_array(), &numbers(&expected["box_linear_world"])),
        max_diff(&b.state.omega_world().to_array(), &numbers(&expected["box_angular_world"])),
    ];
    eprintln!("box at the key 'spin': position, orientation, velocity, angular velocity off by {errors:?}");
    assert!(errors.iter().all(|&e| e < 1e-14), "{errors:?}");
    // the tree, a robot without the box: its state back in MuJoCo's layout is the key's
    let robot = &scene.world.robots[0];
    let split =
        load_mjcf_leaving_out(&path, MjcfOptions::default(), &LeaveOut { world: true, bodies: vec!["box".into()] })
            .unwrap();
    let (qpos, qvel) = split.layout.state_to_mujoco(robot.q(), robot.v()).unwrap();
    let (qpos_err, qvel_err) =
        (max_diff(&qpos, &numbers(&expected["qpos"])[7..]), max_diff(&qvel, &numbers(&expected["qvel"])[6..]));
    eprintln!("robot at the key: qpos off by {qpos_err:.1e}, qvel by {qvel_err:.1e}");
    assert!(qpos_err < 1e-15 && qvel_err < 1e-14, "{qpos_err} {qvel_err}");
    let ctrl: Vec<f64> = robot.actuators.iter().map(|a| a.ctrl).collect();
    assert_eq!(ctrl, numbers(&expected["ctrl"]));
}

#[test]
fn a_scene_robot_starts_from_a_keyframe_by_name_or_index() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.toml");
    let keys = keys();
    for (key, given) in [("spin", "\"spin\""), ("1", "\"1\"")] {
        let text = format!(
            "version = 1\n[[robot]]\nname = \"k\"\nmjcf = {:?}\nkeyframe = {given}\n",
            fixtures().join("keyframe/keys.xml").display().to_string()
        );
        std::fs::write(&path, text).unwrap();
        let scene = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        // the whole file is the robot here (the box one of its two free roots)
        let mjcf = load_mjcf(&fixtures().join("keyframe/keys.xml"), MjcfOptions::default()).unwrap();
        let robot = &scene.world.robots[0];
        let (qpos, qvel) = mjcf.layout.state_to_mujoco(robot.q(), robot.v()).unwrap();
        let expected = &keys["keys"][key];
        assert!(max_diff(&qpos, &numbers(&expected["qpos"])) < 1e-15, "{key}: {qpos:?}");
        assert!(max_diff(&qvel, &numbers(&expected["qvel"])) < 1e-14, "{key}");
        let ctrl: Vec<f64> = robot.actuators.iter().map(|a| a.ctrl).collect();
        assert_eq!(ctrl, numbers(&expected["ctrl"]), "{key}");
    }
}

#[test]
fn bad_keyframes_are_errors_that_say_where_and_what() {
    let path = fixtures().join("keyframe/keys.xml");
    let e = scene::load_mjcf_world_from(&path, Some("jump")).unwrap_err().to_string();
    assert!(e.contains("no keyframe 'jump' (keys: 'spin', 1 (unnamed))"), "{e}");
    // in a scene: at the key, with the file's keys
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("scene.toml");
    let text =
        format!("version = 1\n[[robot]]\nname = \"k\"\nmjcf = {:?}\nkeyframe = \"jump\"\n", path.display().to_string());
    std::fs::write(&scene_path, text).unwrap();
    let e = scene::load(&scene_path).unwrap_err().to_string();
    assert!(e.contains("scene.toml:5:") && e.contains("robot[0].keyframe") && e.contains("'spin'"), "{e}");
    // a qpos of the wrong size, at its attribute
    let bad = dir.path().join("bad.xml");
    std::fs::write(
        &bad,
        "<mujoco>\n<worldbody><body><joint type=\"hinge\"/><geom size=\"0.1\"/></body></worldbody>\n<keyframe>\n  <key name=\"k\" qpos=\"0 1\"/>\n</keyframe>\n</mujoco>\n",
    )
    .unwrap();
    let e = scene::load_mjcf_world(&bad).unwrap_err().to_string();
    assert!(e.contains("bad.xml:4:") && e.contains("<key qpos>") && e.contains("expected 1 numbers"), "{e}");
}

#[test]
fn the_world_of_a_file_filters_contacts_as_mujoco_does() {
    // every geom of the fixtures overlaps every other at the origin: MuJoCo's contacts are the
    // pairs its filter allows; tumble's world of the same file must allow the same, except the
    // robot's own link pairs touching in the initial pose, which self-collision leaves out (with a
    // warning naming each)
    let expected: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(fixtures().join("filter/filter.json")).unwrap()).unwrap();
    for model in ["chain", "chain_exclude", "chain_masks"] {
        let scene = scene::load_mjcf_world(&fixtures().join(format!("filter/{model}.xml"))).unwrap();
        let w = &scene.world;
        let links = &w.contacts().links.colliders;
        // a geom's side in tumble's world: a scene body, or a link collider (`None`: no shape, a
        // geom that collides with nothing of the file)
        let side = |geom: &str| -> Option<Result<usize, usize>> {
            match geom {
                "ground" | "f" | "f2" => w.body_index(if geom == "ground" { "ground" } else { "F" }).map(Ok),
                link => w.link_shapes_named(&format!("{model}/{}", link.to_uppercase())).map(|l| Err(l[0])),
            }
        };
        let touching = |a: usize, b: usize| {
            let (x, y) = (&links.links()[a].name, &links.links()[b].name);
            scene.warnings.iter().any(|t| {
                (t.contains(&format!("`{x}` and `{y}`")) || t.contains(&format!("`{y}` and `{x}`")))
                    && t.contains("touch")
            })
        };
        let geoms = ["ground", "a", "w", "c", "d", "f", "f2"];
        let mujoco: Vec<[String; 2]> = serde_json::from_value(expected[model].clone()).unwrap();
        for (k, a) in geoms.iter().enumerate() {
            for b in &geoms[k + 1..] {
                let mut pair = [a.to_string(), b.to_string()];
                pair.sort();
                let in_mujoco = mujoco.contains(&pair);
                let (Some(sa), Some(sb)) = (side(a), side(b)) else {
                    assert!(!in_mujoco, "{model}: {a}–{b} collide in MuJoCo, but one of them is no shape");
                    continue;
                };
                let tumble = match (sa, sb) {
                    (Ok(i), Ok(j)) => {
                        i != j && !(w.bodies[i].fixed && w.bodies[j].fixed) && !w.contacts().is_excluded(i, j)
                    }
                    (Ok(i), Err(l)) | (Err(l), Ok(i)) => links.links()[l].enabled && !links.is_body_excluded(l, i),
                    (Err(l), Err(m)) => links.pair_allowed(l, m) || (in_mujoco && touching(l, m)),
                };
                assert_eq!(tumble, in_mujoco, "{model}: {a}–{b}");
            }
        }
    }
}

#[test]
fn a_robots_self_collision_follows_the_files_filter() {
    // a chain of four links apart from each other: A–C are not parent and child, so they collide
    // unless their masks or an <exclude> say otherwise; A–B and B–C never (parent and child); A–D
    // always (so the robot's self-collision is on)
    let chain = |c_masks: &str, extra: &str| {
        format!(
            r#"<mujoco model="arm"><worldbody>
  <geom name="floor" type="plane" size="5 5 0.1" pos="0 0 -1" conaffinity="3"/>
  <body name="A"><joint type="hinge"/><geom type="sphere" size="0.1"/>
    <body name="B" pos="0.5 0 0"><joint type="hinge"/><geom type="sphere" size="0.1"/>
      <body name="C" pos="0.5 0 0"><joint type="hinge"/><geom type="sphere" size="0.1" {c_masks}/>
        <body name="D" pos="0.5 0 0"><joint type="hinge"/><geom type="sphere" size="0.1"/></body>
      </body>
    </body>
  </body>
</worldbody>{extra}</mujoco>"#
        )
    };
    for (c_masks, extra, a_c) in [
        ("", "", Some(true)),
        // (2 & 1) | (1 & 1) ≠ 0
        (r#"contype="2" conaffinity="1""#, "", Some(true)),
        // (1 & 0) | (2 & 1) = 0 with A, (2 & 3) ≠ 0 with the floor
        (r#"contype="2" conaffinity="0""#, "", Some(false)),
        ("", r#"<contact><exclude body1="A" body2="C"/></contact>"#, Some(false)),
        // 4 meets nothing: C is no collision shape at all
        (r#"contype="4" conaffinity="4""#, "", None),
    ] {
        let (_dir, scene) = world(&chain(c_masks, extra));
        let links = &scene.world.contacts().links.colliders;
        let id = |l: &str| scene.world.link_shapes_named(&format!("arm/{l}")).map(|l| l[0]);
        let (a, b) = (id("A").unwrap(), id("B").unwrap());
        assert_eq!(id("C").map(|c| links.pair_allowed(a, c)), a_c, "{c_masks} {extra}");
        assert!(!links.pair_allowed(a, b), "parent and child");
        assert!(links.pair_allowed(a, id("D").unwrap()));
        if let Some(c) = id("C") {
            assert!(!links.pair_allowed(b, c), "parent and child");
        }
    }
}

#[test]
fn a_geom_that_collides_with_nothing_needs_no_collision_shape() {
    // an ellipsoid (no collision shape in tumble) whose contype meets no conaffinity: no error
    let (_dir, scene) = world(
        r#"<mujoco><worldbody>
  <geom name="floor" type="plane" size="5 5 0.1"/>
  <geom name="egg" type="ellipsoid" size="0.1 0.2 0.3" pos="0 0 1" contype="8" conaffinity="0"/>
  <body name="ball" pos="1 0 1"><freejoint/><geom type="sphere" size="0.1"/></body>
</worldbody></mujoco>"#,
    );
    assert!(scene.world.body_index("egg").is_none() && scene.world.body_index("ball").is_some());
}
