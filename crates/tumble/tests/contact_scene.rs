//! The contact keys of scene files: `[world]` settings, per-body materials, bad input, and the
//! shared scenes `pyramid` and `balls`.

use tumble::contact::{FrictionModel, RestitutionLaw};
use tumble::scene::{from_str, Format};

fn load(text: &str) -> Result<tumble::scene::Scene, String> {
    from_str(text, "test.toml", Format::Toml).map_err(|e| e.to_string())
}

#[test]
fn world_contact_settings_are_read() {
    let s = load(
        "version = 1\n[world]\nrestitution = 0.3\nfriction = 0.7\nrestitution_law = \"poisson\"\nimpact_speed = 1.5\n\
         contact_iterations = 12\ncontact_substeps = 6\ncontact_slop = 0.001\ncontact_hertz = 45.0\ncontact_damping_ratio = 2.0\nmax_correction_speed = 2.0\ncontacts = false\n",
    )
    .unwrap();
    let c = s.world.config.contact;
    assert_eq!((c.restitution, c.friction, c.law), (0.3, 0.7, RestitutionLaw::Poisson));
    assert_eq!((c.impact_speed, c.iterations, c.slop), (1.5, 12, 0.001));
    assert_eq!((c.substeps, c.hertz, c.damping_ratio), (6, 45.0, 2.0));
    assert_eq!((c.max_correction_speed, c.enabled), (2.0, false));
    let s = load("version = 1\n[world]\nsleep = false\nsleep_speed = 0.05\nsleep_time = 2.0\n").unwrap();
    let c = s.world.config.contact;
    assert_eq!((c.sleep, c.sleep_speed, c.sleep_time), (false, 0.05, 2.0));
    let c = load("version = 1\n").unwrap().world.config.contact;
    assert_eq!((c.sleep, c.sleep_speed, c.sleep_time), (true, 0.01, 0.25));
    assert_eq!(c.friction_model, FrictionModel::Point);
    assert_eq!(c.manifold_reuse, tumble::collision::REUSE_FRACTION);
    let c = load("version = 1\n[world]\nmanifold_reuse = 1e-3\n").unwrap().world.config.contact;
    assert_eq!(c.manifold_reuse, 1e-3);
    for model in [FrictionModel::Point, FrictionModel::Manifold] {
        let text = format!("version = 1\n[world]\nfriction_model = \"{}\"\n", model.name());
        assert_eq!(load(&text).unwrap().world.config.contact.friction_model, model);
    }
}

#[test]
fn bad_contact_settings_name_the_field_and_the_line() {
    let cases = [
        ("restitution = 1.5", "world.restitution"),
        ("friction = -0.1", "world.friction"),
        ("restitution_law = \"newtn\"", "world.restitution_law"),
        ("friction_model = \"manifolds\"", "world.friction_model"),
        ("contact_iterations = 0", "world.contact_iterations"),
        ("contact_slop = -1.0", "world.contact_slop"),
        ("contact_hertz = -2.0", "world.contact_hertz"),
        ("contact_substeps = 0", "world.contact_substeps"),
        ("contact_damping_ratio = -1.0", "world.contact_damping_ratio"),
        ("impact_speed = nan", "world.impact_speed"),
        ("sleep_speed = -1.0", "world.sleep_speed"),
        ("sleep_time = inf", "world.sleep_time"),
        ("sleep = 1", "sleep"),
        ("manifold_reuse = -1e-3", "world.manifold_reuse"),
        ("manifold_reuse = 0.5", "world.manifold_reuse"),
    ];
    for (line, field) in cases {
        let err = load(&format!("version = 1\n[world]\n{line}\n")).unwrap_err();
        assert!(err.contains(field), "`{line}`: {err}");
        assert!(err.contains("test.toml:3:"), "`{line}`: no line in {err}");
    }
    let err = load("version = 1\n[world]\nrestitution_law = \"newtn\"\n").unwrap_err();
    assert!(err.contains("did you mean `newton`"), "{err}");
    let err = load("version = 1\n[world]\nfriction_model = \"manifolds\"\n").unwrap_err();
    assert!(err.contains("did you mean `manifold`") && err.contains("point, manifold"), "{err}");
}

#[test]
fn bad_body_materials_and_shapes_are_rejected() {
    let body = |extra: &str| format!("version = 1\n[[body]]\nname = \"b\"\nmass = 1.0\n{extra}\n");
    let cases = [
        ("shape = { type = \"sphere\", radius = 0.0 }", "shape.radius"),
        ("shape = { type = \"box\", half_extents = [1.0, -1.0, 1.0] }", "shape.half_extents"),
        ("shape = { type = \"plane\" }", "shape"),
        ("shape = { type = \"sphere\", radius = 1.0 }\nrestitution = 1.2", "restitution"),
        ("shape = { type = \"sphere\", radius = 1.0 }\nfriction = -0.5", "friction"),
    ];
    for (extra, field) in cases {
        let err = load(&body(extra)).unwrap_err();
        assert!(err.contains(&format!("body[0].{field}")), "`{extra}`: {err}");
    }
    // a moving body with neither a shape nor an inertia
    let err = load("version = 1\n[[body]]\nname = \"b\"\nmass = 1.0\n").unwrap_err();
    assert!(err.contains("body[0].mass"), "{err}");
}

#[test]
fn shared_scenes_load_with_their_body_counts() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let pyramid = tumble::scene::load(&root.join("pyramid.toml")).unwrap();
    assert_eq!(pyramid.world.free_bodies().count(), 210);
    assert_eq!(pyramid.world.config.contact.friction, 0.5);
    let balls = tumble::scene::load(&root.join("balls.toml")).unwrap();
    assert_eq!(balls.world.free_bodies().count(), 1000);
}

#[test]
fn bodies_listed_in_no_collide_pass_through_each_other() {
    let scene = |filter: &str| {
        format!(
            "version = 1\n[world]\ngravity = [0.0, 0.0, 0.0]\ndt = 0.001\n\
             [[body]]\nname = \"a\"\nmass = 1.0\nshape = {{ type = \"sphere\", radius = 0.5 }}\nvelocity = [1.0, 0.0, 0.0]\n{filter}\n\
             [[body]]\nname = \"b\"\nmass = 1.0\nshape = {{ type = \"sphere\", radius = 0.5 }}\nposition = [2.0, 0.0, 0.0]\n"
        )
    };
    let run = |text: String| {
        let mut w = load(&text).unwrap().world;
        for _ in 0..2000 {
            w.step().unwrap();
        }
        w.bodies[1].state.velocity.x
    };
    assert!(run(scene("")) > 0.1, "without a filter the spheres collide and b moves");
    assert_eq!(run(scene("no_collide = [\"b\"]")), 0.0, "with the filter b is never touched");
    let err = load(&scene("no_collide = [\"bb\"]")).unwrap_err();
    assert!(err.contains("body[0].no_collide") && err.contains("did you mean `b`"), "{err}");
    // a name far from every body: the hint lists them
    let err = load(&scene("no_collide = [\"zzzz\"]")).unwrap_err();
    assert!(err.starts_with("test.toml:10:14: body[0].no_collide: names no body of the scene (got \"zzzz\")"), "{err}");
    assert!(err.contains("hint: the bodies: `a`, `b`\n") || err.ends_with("hint: the bodies: `a`, `b`"), "{err}");
}

#[test]
fn a_dangling_no_collide_name_lists_the_first_bodies_of_a_large_scene() {
    // 1 + 3·3 = 10 bodies: the hint shows the first 8 and counts the rest
    let text = "version = 1\n\
        [[body]]\nname = \"a\"\nmass = 1.0\nshape = { type = \"sphere\", radius = 0.5 }\nno_collide = [\"zzzz\"]\n\
        [[grid]]\ncount = [3, 3, 1]\nspacing = [2.0, 2.0, 2.0]\norigin = [5.0, 0.0, 0.0]\n\
        [grid.body]\nname = \"ball\"\nmass = 1.0\nshape = { type = \"sphere\", radius = 0.5 }\n";
    let err = load(text).unwrap_err();
    assert!(err.starts_with("test.toml:6:14: body[0].no_collide: names no body of the scene (got \"zzzz\")"), "{err}");
    let hint = err.lines().find(|l| l.starts_with("hint: ")).unwrap_or_else(|| panic!("no hint: {err}"));
    assert_eq!(
        hint,
        "hint: the bodies: `a`, `ball_0_0_0`, `ball_0_1_0`, `ball_0_2_0`, `ball_1_0_0`, `ball_1_1_0`, `ball_1_2_0`, \
         `ball_2_0_0`, … and 2 more"
    );
}

/// Two bodies `a` and `b`, the second at `position`, each written as `shape`, plus `extra` lines on `b`.
fn pair(shape_a: &str, shape_b: &str, position: &str, extra: &str) -> String {
    format!(
        "version = 1\n[world]\ngravity = [0.0, 0.0, 0.0]\n\
         [[body]]\nname = \"a\"\nmass = 1.0\nshape = {shape_a}\n\
         [[body]]\nname = \"b\"\nmass = 1.0\nshape = {shape_b}\nposition = {position}\n{extra}\n"
    )
}

#[test]
fn deep_overlaps_at_the_start_are_warnings_naming_both_bodies_and_the_depth() {
    let cube = "{ type = \"box\", half_extents = [0.5, 0.5, 0.5] }";
    // 0.3 m of overlap: reported at b's position, with the depth and the threshold
    let s = load(&pair(cube, cube, "[0.7, 0.0, 0.0]", "")).unwrap();
    assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
    let w = &s.warnings[0];
    assert!(w.starts_with("test.toml:12:12: body[1].position: body `b` overlaps body `a` by 0.3 m"), "{w}");
    assert!(w.contains("deeper than 0.01 m") && w.contains("max_correction_speed = 3 m/s"), "{w}");
    // 5 mm: below 1 cm, not reported; nor is any overlap when contacts are off or the pair excluded
    assert!(load(&pair(cube, cube, "[0.995, 0.0, 0.0]", "")).unwrap().warnings.is_empty());
    let off = pair(cube, cube, "[0.7, 0.0, 0.0]", "").replace("[world]\n", "[world]\ncontacts = false\n");
    assert!(load(&off).unwrap().warnings.is_empty());
    let excluded = pair(cube, cube, "[0.7, 0.0, 0.0]", "no_collide = [\"a\"]");
    assert!(load(&excluded).unwrap().warnings.is_empty());
    // small bodies: 10 % of the smaller bounding radius (a 5 cm ball 6 mm into the floor)
    let floor = "version = 1\n[[body]]\nname = \"floor\"\nfixed = true\nshape = { type = \"plane\" }\n\
                 [[body]]\nname = \"pebble\"\nmass = 0.1\nshape = { type = \"sphere\", radius = 0.05 }\n";
    let s = load(&format!("{floor}position = [0.0, 0.0, 0.044]\n")).unwrap();
    assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
    assert!(s.warnings[0].contains("body `pebble` overlaps body `floor` by 0.006 m"), "{:?}", s.warnings);
    assert!(s.warnings[0].contains("deeper than 0.005 m"), "{:?}", s.warnings);
    assert!(load(&format!("{floor}position = [0.0, 0.0, 0.046]\n")).unwrap().warnings.is_empty());
    // grid copies are placed at their grid
    let grid = "version = 1\n[[grid]]\ncount = [2, 1, 1]\nspacing = [0.5, 1.0, 1.0]\n[grid.body]\nname = \"g\"\n\
                mass = 1.0\nshape = { type = \"sphere\", radius = 0.5 }\n";
    let s = load(grid).unwrap();
    assert!(
        s.warnings[0].contains("grid[0].body: body `g_1_0_0` overlaps body `g_0_0_0` by 0.5 m"),
        "{:?}",
        s.warnings
    );
}

#[test]
fn the_shared_scenes_start_without_deep_overlaps() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    for entry in std::fs::read_dir(&root).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let scene = tumble::scene::load(&path).unwrap();
            let overlaps: Vec<&String> = scene.warnings.iter().filter(|w| w.contains("overlaps")).collect();
            assert!(overlaps.is_empty(), "{}: {overlaps:?}", path.display());
        }
    }
}

/// Two bodies `a` and `b` of `shape_a` and `shape_b` at the same point: in zero gravity at the
/// origin, or (`floor`) both resting on a floor under gravity, centres 0.5 m up. `dt = 1 ms`.
fn coincident(shape_a: &str, shape_b: &str, floor: bool) -> String {
    let (gravity, floor, z) = if floor {
        ("[0.0, 0.0, -9.81]", "[[body]]\nname = \"floor\"\nfixed = true\nshape = { type = \"plane\" }\n", 0.5)
    } else {
        ("[0.0, 0.0, 0.0]", "", 0.0)
    };
    format!(
        "version = 1\n[world]\ngravity = {gravity}\ndt = 0.001\n{floor}\
         [[body]]\nname = \"a\"\nmass = 1.0\nshape = {shape_a}\nposition = [0.0, 0.0, {z:?}]\n\
         [[body]]\nname = \"b\"\nmass = 1.0\nshape = {shape_b}\nposition = [0.0, 0.0, {z:?}]\n"
    )
}

/// Coincident centres (two unit boxes, two spheres of radius 0.5, a sphere inside a box), with and
/// without gravity and a floor. The load warns once, naming the pair and its 1 m depth. For 2 s:
/// every state finite, no body faster than `max_correction_speed + g t`, the pair's first normal of
/// unit length, the bodies apart at the end (less than 1 mm of overlap, the scale of what the
/// contacts hold under load), and a second run bit-identical. Two coincident spheres have no
/// direction of their own: parry gives the first body's +y axis, so they part along ±y.
#[test]
fn coincident_bodies_are_warned_once_and_separate_finitely_and_deterministically() {
    let cube = "{ type = \"box\", half_extents = [0.5, 0.5, 0.5] }";
    let ball = "{ type = \"sphere\", radius = 0.5 }";
    for (shape_a, shape_b, what) in
        [(cube, cube, "two boxes"), (ball, ball, "two spheres"), (cube, ball, "a sphere in a box")]
    {
        for floor in [false, true] {
            let text = coincident(shape_a, shape_b, floor);
            let run = || {
                let scene = load(&text).unwrap();
                let mut w = scene.world;
                let (a, b) = (w.body_index("a").unwrap(), w.body_index("b").unwrap());
                let cap = w.config.contact.max_correction_speed;
                let g = w.config.gravity.length();
                let mut first_normal = None;
                for step in 1..=2000 {
                    w.step().unwrap();
                    let t = step as f64 * w.config.dt;
                    for body in &w.bodies {
                        let s = &body.state;
                        assert!(
                            s.position.is_finite() && s.velocity.is_finite() && s.omega_body.is_finite(),
                            "{what}, floor {floor}, step {step}: {s:?}"
                        );
                        let speed = s.velocity.length();
                        assert!(speed <= cap + g * t + 1e-12, "{what}, floor {floor}: {speed} m/s at t = {t} s");
                    }
                    if step == 1 {
                        let pair = w.contacts().contacts().iter().find(|c| (c.a, c.b) == (a, b));
                        first_normal = Some(pair.expect("the pair is in contact").normal_world);
                    }
                }
                // the pair's deepest overlap at the end, from the contacts of the final state
                let bodies = w.bodies.clone();
                let mut contacts = Vec::new();
                let colliders = w.contact_stage().colliders_mut(&bodies);
                colliders.find_contacts(&bodies, 0.0, tumble::math::DVec3::ZERO, 0.0, &mut contacts);
                let overlap = contacts.iter().filter(|c| (c.a, c.b) == (a, b)).map(|c| -c.gap).fold(0.0, f64::max);
                (scene.warnings, first_normal.unwrap(), overlap, w.state_hash(), bodies[a].state.position)
            };
            let (warnings, normal, overlap, hash, end_a) = run();
            eprintln!(
                "{what}, floor {floor}: first normal {normal}, overlap at the end {overlap:.2e} m, a ends at {end_a}"
            );
            assert_eq!(warnings.len(), 1, "{what}, floor {floor}: {warnings:?}");
            assert!(warnings[0].contains("body `b` overlaps body `a` by 1 m at the start"), "{what}: {warnings:?}");
            assert!((normal.length() - 1.0).abs() < 1e-12, "{what}, floor {floor}: normal {normal}");
            if shape_b == ball && shape_a == ball {
                assert_eq!(normal, tumble::math::DVec3::Y, "{what}, floor {floor}");
            }
            assert!(overlap < 1e-3, "{what}, floor {floor}: still {overlap} m deep after 2 s");
            assert_eq!(hash, run().3, "{what}, floor {floor}: a second run differs");
        }
    }
}
