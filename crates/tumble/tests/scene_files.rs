//! Every scene in `scenes/` loads, validates and takes a step; the built-in demo is `scenes/demo.toml`.

use std::path::PathBuf;
use tumble::math::DVec3;
use tumble::scene;

fn scenes_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

#[test]
fn every_scene_file_loads_and_steps() {
    let mut names = Vec::new();
    let entries = std::fs::read_dir(scenes_dir()).expect("scenes/ exists");
    for entry in entries {
        let path = entry.expect("a directory entry").path();
        if scene::Format::from_path(&path).is_none() {
            continue;
        }
        let loaded = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        // the URDFs of example-robot-data are shipped as published (scenes/robots/example-robot-data):
        // their non-URDF elements, sensor links of 1 g with a radius of gyration of 0.3 m, and the
        // report of the inertias that `balance_inertia = true` replaced are the warnings they give
        let vendor = |w: &String| {
            w.contains("robots/example-robot-data/")
                && (w.contains(": ignored <") || w.contains("radius of gyration") || w.contains("inertia balanced"))
        };
        let unexpected: Vec<&String> = loaded.warnings.iter().filter(|w| !vendor(w)).collect();
        assert!(unexpected.is_empty(), "{}: {:?}", path.display(), unexpected);
        // a scene has bodies or robots (`[[robot]]`)
        let first = match (loaded.world.bodies.first(), loaded.world.robots.first()) {
            (Some(body), _) => body.name.clone(),
            (None, Some(robot)) => robot.name.clone(),
            (None, None) => panic!("{}: no bodies and no robots", path.display()),
        };
        assert!(loaded.describe().contains(&first));
        let mut world = loaded.world;
        world.step().unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        names.push(path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default());
    }
    names.sort();
    let expected = ["asymmetric_top.toml", "demo.toml", "many.toml", "projectile.toml", "symmetric_top.toml"];
    for expected in expected.iter().chain(&["double_pendulum.toml", "panda.toml"]) {
        assert!(names.iter().any(|n| n == expected), "{expected} missing from {names:?}");
    }
}

#[test]
fn the_demo_is_the_intermediate_axis_flip() {
    let demo = scene::demo();
    let from_file = scene::load(&scenes_dir().join("demo.toml")).expect("demo.toml");
    assert_eq!(demo.world.bodies, from_file.world.bodies);
    assert_eq!(demo.world.config, from_file.world.config);
    let c = demo.world.config;
    assert_eq!(c.gravity, DVec3::new(0.0, 0.0, -9.81));
    assert_eq!((c.duration, c.dt, c.sample_every), (30.0, 1e-3, 10));
    // the flipping pair floats (its rotation is that of free fall), the others fall onto the floor
    let names: Vec<&str> = demo.world.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["flipper", "stable", "floor", "box", "capsule", "cylinder", "ball"]);
    assert_eq!(demo.world.bodies[0].gravity_scale, 0.0);
    assert_eq!(demo.world.bodies[1].gravity_scale, 0.0);
    assert!(demo.world.bodies[2].fixed);
    assert!(demo.world.bodies[3..].iter().all(|b| b.gravity_scale == 1.0 && !b.fixed));
    assert!(demo.warnings.is_empty(), "{:?}", demo.warnings);
    let flipper = &demo.world.bodies[0];
    let i = flipper.mass.inertia_body;
    assert!(i.x < i.y && i.y < i.z, "three distinct moments, intermediate about y: {i:?}");
    // spun near the intermediate axis
    let w = flipper.state.omega_body;
    assert!(w.y.abs() > 100.0 * w.x.abs().max(w.z.abs()), "{w:?}");
    let stable = &demo.world.bodies[1];
    let w = stable.state.omega_body;
    assert!(w.z.abs() > 100.0 * w.x.abs().max(w.y.abs()), "{w:?}");
}

#[test]
fn many_has_ten_thousand_free_bodies_and_a_thousand_steps() {
    let many = scene::load(&scenes_dir().join("many.toml")).expect("many.toml");
    assert_eq!(many.world.bodies.len(), 10_000);
    assert!(many.world.bodies.iter().all(|b| !b.fixed));
    assert_eq!(many.world.config.step_count(), 1000);
    assert_eq!(many.world.config.sample_every, 1000);
}

/// The first TOML example and the JSON example of `docs/scene-format.md` are valid scenes.
#[test]
fn the_examples_in_the_format_doc_load() {
    let doc = std::fs::read_to_string(scenes_dir().join("../docs/scene-format.md")).expect("the format doc");
    let block = |fence: &str| -> String {
        let start = doc.find(fence).unwrap_or_else(|| panic!("no {fence} block")) + fence.len();
        let end = doc[start..].find("```").expect("a closing fence") + start;
        doc[start..end].to_string()
    };
    let toml = scene::from_str(&block("```toml\n"), "doc.toml", scene::Format::Toml).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(toml.world.bodies[0].name, "racket");
    let json = scene::from_str(&block("```json\n"), "doc.json", scene::Format::Json).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(json.world.bodies.len(), 1 + 8);
    // the compound example, after `version = 1`
    let compound =
        format!("version = 1\n[[body]]\nname = \"dumbbell\"{}", block("```toml\n[[body]]\nname = \"dumbbell\""));
    let dumbbell = scene::from_str(&compound, "doc.toml", scene::Format::Toml).unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(&dumbbell.world.bodies[0].shape, Some(tumble::body::Shape::Compound(c)) if c.parts.len() == 3));
}

/// The demo shows what it says: the box spun about its intermediate axis flips over and over in
/// 30 s; the one spun about its major axis does not.
#[test]
fn the_demo_flips() {
    let mut world = scene::demo().world;
    let steps = world.config.step_count();
    let mut flips = 0;
    let mut last_sign = world.bodies[0].state.omega_body.y.signum();
    let mut stable_min_wz = f64::INFINITY;
    for _ in 0..steps {
        world.step().expect("the demo does not diverge");
        let sign = world.bodies[0].state.omega_body.y.signum();
        if sign != last_sign {
            flips += 1;
            last_sign = sign;
        }
        stable_min_wz = stable_min_wz.min(world.bodies[1].state.omega_body.z);
    }
    assert!(flips >= 3, "the intermediate-axis spin flipped {flips} times in 30 s");
    assert!(stable_min_wz > 4.9, "the major-axis spin wandered: min ω_z = {stable_min_wz}");
}

/// `projectile.toml` follows the parabola its comment states.
#[test]
fn the_projectile_follows_the_parabola() {
    let mut world = scene::load(&scenes_dir().join("projectile.toml")).expect("projectile.toml").world;
    let ball = &world.bodies[0];
    let m = 1000.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.1f64.powi(3);
    assert!((ball.mass.mass - m).abs() < 1e-12 * m);
    for _ in 0..world.config.step_count() {
        world.step().expect("steps");
    }
    let t = world.time();
    let p = world.bodies[0].state.position;
    let expected = DVec3::new(10.0 * t, 0.0, 10.0 * t - 0.5 * 9.81 * t * t);
    assert!((p - expected).length() < 1e-9, "{p:?} != {expected:?} at t = {t}");
    assert!((world.bodies[0].state.omega_world() - DVec3::new(0.0, 20.0, 0.0)).length() < 1e-9);
}
