//! Robots in scenes: `[[robot]]` entries loaded, stepped by `World::step` with the world's
//! integrator, and written to trajectories.
//!
//! - a passive double pendulum (`scenes/double_pendulum.toml`) conserves energy under RK4;
//! - a pendulum's small oscillations have the period `2π sqrt(I/(m g l))`, wherever its base is
//!   placed, and a base that turns the axis vertical takes gravity's torque away;
//! - a one-link floating robot moves like the same free rigid body;
//! - PD control reaches its target (with the gravity torque as a constant feed-forward) or settles
//!   where the spring balances gravity (without it);
//! - a diverging robot is reported by name and joint, and the step is undone;
//! - bad `[[robot]]` entries are errors naming the file, line, column and field.

use std::path::{Path, PathBuf};
use tumble::math::{DMat3, DQuat, DVec3};
use tumble::multibody::Control;
use tumble::scene::{self, Format, Scene};
use tumble::trajectory::{self, ReadOptions, TrajectoryWriter};
use tumble::world::Robot;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A pendulum: mass 2 kg, centre of mass 0.5 m below the pivot, `I_c = 0.02` kg·m² about the
/// swing axis x, so `I = I_c + m l² = 0.52` kg·m² about the pivot.
const PENDULUM: &str = r#"<robot name="pendulum">
  <link name="base"/>
  <link name="bob"><inertial><origin xyz="0 0 -0.5"/><mass value="2"/>
    <inertia ixx="0.02" iyy="0.02" izz="0.01"/></inertial></link>
  <joint name="pivot" type="continuous"><parent link="base"/><child link="bob"/><axis xyz="1 0 0"/></joint>
</robot>"#;

/// A scene in a fresh directory holding `pendulum.urdf`; `robot` is the body of the `[[robot]]` table.
fn pendulum_scene(world: &str, robot: &str) -> (tempfile::TempDir, Result<Scene, scene::SceneError>) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("pendulum.urdf"), PENDULUM).unwrap();
    let text = format!("version = 1\n[world]\n{world}\n[[robot]]\nname = \"p\"\nurdf = \"pendulum.urdf\"\n{robot}\n");
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let loaded = scene::load(&path);
    (dir, loaded)
}

/// The energy of `robot` at rest in the neutral configuration (J): the bottom of the potential.
fn rest_energy(robot: &Robot) -> f64 {
    let m = robot.model.clone();
    let control = Control::passive(&m);
    let q = m.neutral_configuration();
    let v = vec![0.0; m.nv()];
    Robot::new("rest", m, control, q, v).unwrap().energy()
}

#[test]
fn passive_double_pendulum_scene_conserves_energy_under_rk4() {
    let mut scene = scene::load(&repo().join("scenes/double_pendulum.toml")).unwrap();
    let world = &mut scene.world;
    world.config.duration = 10.0;
    world.config.dt = 1e-3;
    assert_eq!(world.config.integrator.name(), "rk4");
    assert_eq!(world.robots.len(), 1);
    let e0 = world.energy();
    let swing = e0 - rest_energy(&world.robots[0]);
    assert!(swing > 1.0, "the pendulum must swing: {swing} J above rest");
    let mut worst = 0.0_f64;
    for _ in 0..world.config.step_count() {
        world.step().unwrap();
        worst = worst.max((world.energy() - e0).abs());
    }
    assert!((world.time() - 10.0).abs() < 1e-12);
    let relative_to_swing = worst / swing;
    let relative = worst / e0.abs();
    eprintln!(
        "double pendulum scene, rk4, 10 s at dt = 1e-3: largest |ΔE| = {worst:e} J, {relative_to_swing:e} of the \
         {swing} J above rest, {relative:e} of E0 = {e0} J"
    );
    assert!(relative_to_swing < 1e-8, "relative energy drift {relative_to_swing:e}");
    assert!(world.robots[0].v().iter().any(|x| x.abs() > 0.1), "it should still be moving");
}

/// Upward zero crossings of the pivot angle, linearly interpolated, over four periods.
fn period(scene: &mut Scene) -> f64 {
    let world = &mut scene.world;
    let dt = world.config.dt;
    let mut crossings = Vec::new();
    let mut previous = world.robots[0].q()[0];
    while crossings.len() < 5 {
        world.step().unwrap();
        let q = world.robots[0].q()[0];
        if previous < 0.0 && q >= 0.0 {
            crossings.push(world.time() - dt * q / (q - previous));
        }
        previous = q;
        assert!(world.time() < 20.0, "no oscillation");
    }
    (crossings[4] - crossings[0]) / 4.0
}

#[test]
fn pendulum_small_oscillation_period_wherever_the_base_is() {
    let expected = 2.0 * std::f64::consts::PI * (0.52_f64 / (2.0 * 9.81 * 0.5)).sqrt();
    // the base placed at the origin, and moved and turned about the vertical (gravity's axis)
    let s = std::f64::consts::FRAC_1_SQRT_2;
    for pose in ["", &format!("position = [1.0, -2.0, 3.0]\norientation = [{s}, 0.0, 0.0, {s}]")] {
        let (_dir, loaded) =
            pendulum_scene("dt = 1e-4\nintegrator = \"rk4\"", &format!("q = {{ pivot = -0.01 }}\n{pose}"));
        let mut scene = loaded.unwrap();
        let measured = period(&mut scene);
        let relative = (measured - expected).abs() / expected;
        eprintln!("pendulum period {measured} s, 2π sqrt(I/(m g l)) = {expected} s, relative {relative:e} ({pose:?})");
        assert!(relative < 1e-3, "period {measured} s, expected {expected} s");
    }
}

#[test]
fn a_base_pose_places_the_links_and_turns_gravity_with_the_axis() {
    // turned 90° about z: the pivot axis (x) becomes the world's y axis, the base sits at [1, -2, 3]
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let (_dir, loaded) = pendulum_scene(
        "",
        &format!("position = [1.0, -2.0, 3.0]\norientation = [{s}, 0.0, 0.0, {s}]\nq = {{ pivot = 0.3 }}"),
    );
    let scene = loaded.unwrap();
    let robot = &scene.world.robots[0];
    assert_eq!(robot.link_names(), ["p/bob"]);
    let link = robot.link_state(0);
    assert!((link.position - DVec3::new(1.0, -2.0, 3.0)).length() < 1e-15);
    // world_from_link = Rz(90°) Rx(0.3)
    let expected = DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2) * DQuat::from_rotation_x(0.3);
    assert!(link.orientation.dot(expected).abs() > 1.0 - 1e-15, "{:?} vs {expected:?}", link.orientation);
    // potential: the centre of mass at 3 − 0.5 cos 0.3 above the world origin
    let v = 2.0 * 9.81 * (3.0 - 0.5 * 0.3_f64.cos());
    assert!((scene.world.energy() - v).abs() < 1e-12, "{} vs {v}", scene.world.energy());

    // turned 90° about y: the pivot axis becomes vertical and gravity exerts no torque about it
    let (_dir, loaded) =
        pendulum_scene("duration = 1.0", &format!("orientation = [{s}, 0.0, {s}, 0.0]\nq = {{ pivot = 0.3 }}"));
    let mut scene = loaded.unwrap();
    for _ in 0..1000 {
        scene.world.step().unwrap();
    }
    let q = scene.world.robots[0].q()[0];
    assert!((q - 0.3).abs() < 1e-12, "a vertical axis: the angle should stay 0.3 rad, got {q}");
}

/// One link, its centre of mass at the link origin, a full inertia tensor in link axes.
const BRICK: &str = r#"<robot name="brick">
  <link name="brick"><inertial><origin xyz="0 0 0"/><mass value="3"/>
    <inertia ixx="0.4" ixy="0.05" ixz="-0.02" iyy="0.3" iyz="0.03" izz="0.2"/></inertial></link>
</robot>"#;

#[test]
fn a_one_link_floating_robot_moves_like_the_same_free_body() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("brick.urdf"), BRICK).unwrap();
    let orientation = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    let (velocity, omega) = (DVec3::new(1.0, -0.5, 4.0), DVec3::new(0.3, 2.0, -1.1));
    // the robot's base velocity is in the base frame: [Rᵀ v; Rᵀ ω]
    let (v_base, w_base) = (orientation.inverse() * velocity, orientation.inverse() * omega);
    let q = [orientation.w, orientation.x, orientation.y, orientation.z];
    let text = format!(
        r#"version = 1
[world]
dt = 1e-3
duration = 2.0
integrator = "rk4"
[[body]]
name = "body"
mass = 3.0
inertia_tensor = [[0.4, 0.05, -0.02], [0.05, 0.3, 0.03], [-0.02, 0.03, 0.2]]
position = [0.5, 1.0, 2.0]
orientation = {q:?}
velocity = {:?}
angular_velocity = {:?}
[[robot]]
name = "robot"
urdf = "brick.urdf"
base = "floating"
position = [0.5, 1.0, 2.0]
orientation = {q:?}
v = {{ root_joint = [{}, {}, {}, {}, {}, {}] }}
"#,
        velocity.to_array(),
        omega.to_array(),
        v_base.x,
        v_base.y,
        v_base.z,
        w_base.x,
        w_base.y,
        w_base.z,
    );
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let mut scene = scene::load(&path).unwrap();
    let world = &mut scene.world;
    let mut worst = [0.0_f64; 4];
    for step in 0..=2000 {
        if step > 0 {
            world.step().unwrap();
        }
        let body = &world.bodies[0];
        let link = world.robots[0].link_state(0);
        let r_body = DMat3::from_quat(body.orientation_user());
        let r_link = DMat3::from_quat(link.orientation);
        let errors = [
            (link.position - body.state.position).length(),
            (r_link - r_body).to_cols_array().iter().fold(0.0_f64, |m, x| m.max(x.abs())),
            (link.velocity - body.state.velocity).length(),
            (link.angular_velocity - body.state.omega_world()).length(),
        ];
        for (w, e) in worst.iter_mut().zip(errors) {
            *w = w.max(e);
        }
    }
    eprintln!("floating one-link robot vs free body over 2 s (position, rotation, velocity, ω): {worst:?}");
    // the two integrate different coordinates with RK4 at dt = 1e-3: they agree to its truncation error
    assert!(worst.iter().all(|e| *e < 1e-9), "{worst:?}");
    // it fell and spun: the comparison is not of two resting states
    assert!(world.bodies[0].state.position.z < 2.0 - 5.0);
    // energy and momentum of the robot equal those of the body
    let body = &world.bodies[0];
    let robot = &world.robots[0];
    assert!((robot.energy() - (body.kinetic_energy() + body.potential_energy(world.config.gravity))).abs() < 1e-8);
    assert!((robot.angular_momentum() - body.angular_momentum_world()).length() < 1e-8);
    assert!((robot.linear_momentum() - 3.0 * body.state.velocity).length() < 1e-9);
}

#[test]
fn pd_control_reaches_its_target_with_gravity_feed_forward() {
    // τ = m g l sin q* holds the pendulum at q* against gravity once the PD terms vanish
    let target = 0.6_f64;
    let feed_forward = 2.0 * 9.81 * 0.5 * target.sin();
    let (_dir, loaded) = pendulum_scene(
        "duration = 5.0",
        &format!(
            "torque = {{ pivot = {feed_forward} }}\npd = {{ pivot = {{ target = {target}, kp = 50.0, kd = 10.0 }} }}"
        ),
    );
    let mut scene = loaded.unwrap();
    for _ in 0..scene.world.config.step_count() {
        scene.world.step().unwrap();
    }
    let (q, v) = (scene.world.robots[0].q()[0], scene.world.robots[0].v()[0]);
    eprintln!("PD with feed-forward after 5 s: q = {q} (target {target}), v = {v:e}");
    assert!((q - target).abs() < 1e-9 && v.abs() < 1e-8, "q = {q}, v = {v}");

    // without it the pendulum settles where the spring balances gravity: kp (q* − q) = m g l sin q
    let (_dir, loaded) =
        pendulum_scene("duration = 5.0", &format!("pd = {{ pivot = {{ target = {target}, kp = 50.0, kd = 10.0 }} }}"));
    let mut scene = loaded.unwrap();
    for _ in 0..scene.world.config.step_count() {
        scene.world.step().unwrap();
    }
    let q = scene.world.robots[0].q()[0];
    let residual = 50.0 * (target - q) - 9.81 * q.sin();
    eprintln!("PD without feed-forward: q = {q}, kp (q* − q) − m g l sin q = {residual:e} N·m");
    assert!(q < target - 0.05, "gravity must pull it below the target: {q}");
    assert!(residual.abs() < 1e-7, "{residual}");
}

#[test]
fn damping_from_the_urdf_or_the_scene_dissipates() {
    let dp = |damping: &str| {
        let text = std::fs::read_to_string(repo().join("scenes/double_pendulum.toml")).unwrap();
        let text = text.replace("damping = 0.0 ", &format!("damping = {damping} "));
        assert!(text.contains(damping));
        let origin = repo().join("scenes/double_pendulum.toml");
        let mut scene = scene::from_str(&text, origin.to_str().unwrap(), Format::Toml).unwrap();
        let e0 = scene.world.energy();
        for _ in 0..2000 {
            scene.world.step().unwrap();
        }
        (scene.world.robots[0].control.damping.clone(), e0 - scene.world.energy())
    };
    let (c, lost) = dp("\"urdf\"");
    assert_eq!(c, [0.05, 0.05]);
    assert!(lost > 0.01, "{lost}");
    let (c, lost_more) = dp("{ elbow = 0.5 }");
    assert_eq!(c, [0.0, 0.5]);
    assert!(lost_more > 0.01, "{lost_more}");
}

#[test]
fn a_diverging_robot_is_named_with_its_joint_and_the_step_is_undone() {
    let (_dir, loaded) = pendulum_scene("dt = 0.01", "torque = { pivot = 1e12 }");
    let mut scene = loaded.unwrap();
    let world = &mut scene.world;
    let error = loop {
        let (q, v, t) = (world.robots[0].q().to_vec(), world.robots[0].v().to_vec(), world.time());
        match world.step() {
            Ok(()) => assert!(world.time() < 1.0, "no divergence"),
            Err(e) => {
                assert_eq!(world.robots[0].q(), q);
                assert_eq!(world.robots[0].v(), v);
                assert_eq!(world.time(), t);
                break e.diverged().cloned().unwrap();
            }
        }
    };
    let message = error.to_string();
    eprintln!("{message}");
    assert_eq!(error.body, "p");
    assert!(message.contains("joint `pivot`") && message.contains("exceeds"), "{message}");
    assert_eq!(error.step, world.steps() + 1);
}

#[test]
fn csv_rows_named_robot_link_read_back_exactly() {
    let mut scene = scene::load(&repo().join("scenes/double_pendulum.toml")).unwrap();
    let world = &mut scene.world;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.csv");
    let mut writer =
        TrajectoryWriter::new(std::fs::File::create(&path).unwrap(), trajectory::Format::Csv, world).unwrap();
    writer.write_sample(world).unwrap();
    for _ in 0..100 {
        world.step().unwrap();
    }
    writer.write_sample(world).unwrap();
    writer.finish().unwrap();
    let read = trajectory::read(&path, ReadOptions::default()).unwrap();
    assert_eq!(read.bodies, ["pendulum/upper", "pendulum/lower", "pendulum/tip"]);
    assert_eq!(read.frames.len(), 2);
    let robot = &world.robots[0];
    for (k, sample) in read.frames[1].states.iter().enumerate() {
        let link = robot.link_state(k);
        assert_eq!(sample.position, link.position);
        assert_eq!(sample.velocity, link.velocity);
        assert_eq!(sample.angular_velocity, link.angular_velocity);
        assert!(sample.orientation.dot(link.orientation).abs() > 1.0 - 1e-15);
    }
    // the tip is 1 m beyond the lower link's origin, along the lower link
    let (lower, tip) = (robot.link_state(1), robot.link_state(2));
    assert!(((tip.position - lower.position).length() - 1.0).abs() < 1e-14);
}

#[test]
fn json_lines_carry_q_and_v_per_robot() {
    let scene = scene::load(&repo().join("scenes/double_pendulum.toml")).unwrap();
    let mut writer = TrajectoryWriter::new(Vec::new(), trajectory::Format::JsonLines, &scene.world).unwrap();
    writer.write_sample(&scene.world).unwrap();
    let text = String::from_utf8(writer.finish().unwrap()).unwrap();
    let line: serde_json::Value = serde_json::from_str(text.trim()).unwrap();
    assert_eq!(line["bodies"].as_array().unwrap().len(), 3);
    assert_eq!(line["bodies"][2]["name"], "pendulum/tip");
    assert_eq!(line["robots"][0]["name"], "pendulum");
    assert_eq!(line["robots"][0]["q"], serde_json::json!([1.0, -0.5]));
    assert_eq!(line["robots"][0]["v"], serde_json::json!([0.0, 0.0]));
}

/// The message of a scene error for `robot` (the `[[robot]]` table's keys) with `pendulum.urdf`.
fn robot_error(robot: &str) -> String {
    let (_dir, loaded) = pendulum_scene("", robot);
    match loaded {
        Ok(_) => panic!("accepted: {robot}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_robot_entries_name_the_file_line_and_field() {
    let e = robot_error("q = { pivto = 0.1 }");
    assert!(e.contains("scene.toml:7:15: ") && e.contains("robot[0].q.pivto: unknown joint `pivto`"), "{e}");
    assert!(e.contains("did you mean `pivot`?"), "{e}");
    let e = robot_error("urdf_file = \"x\"");
    assert!(e.contains("unknown key `urdf_file`") && e.contains("did you mean `urdf`?"), "{e}");
    let e = robot_error("base = \"floting\"");
    assert!(e.contains("robot[0].base") && e.contains("did you mean `floating`?"), "{e}");
    let e = robot_error("base = \"floating\"\nq = { root_joint = [0.0, 0.0, 1.0, 1.0, 0.0, 0.0] }");
    assert!(e.contains("robot[0].q.root_joint: a floating joint takes 7 numbers"), "{e}");
    assert!(e.contains("got 6 numbers"), "{e}");
    let e = robot_error("base = \"floating\"\nq = { root_joint = [0.0, 0.0, 1.0, 2.0, 0.0, 0.0, 0.0] }");
    assert!(e.contains("unit quaternion"), "{e}");
    let e = robot_error("v = { pivot = nan }");
    assert!(e.contains("robot[0].v.pivot: must be finite"), "{e}");
    let e = robot_error("pd = { pivot = { target = 0.1, kp = -1.0 } }");
    assert!(e.contains("robot[0].pd.pivot.kp: must be finite and ≥ 0"), "{e}");
    let e = robot_error("pd = { pivot = { target = 0.1, kp = 1.0, kdd = 1.0 } }");
    assert!(e.contains("unknown key `kdd`") && e.contains("did you mean `kd`?"), "{e}");
    let e = robot_error("damping = \"urfd\"");
    assert!(e.contains("robot[0].damping"), "{e}");
    let e = robot_error("damping = { pivot = -0.1 }");
    assert!(e.contains("robot[0].damping.pivot: must be finite and ≥ 0"), "{e}");
    let e = robot_error("position = [0.0, inf, 0.0]");
    assert!(e.contains("robot[0].position: must be finite"), "{e}");
    let e = robot_error("torque = { pivot = [1.0, 2.0] }");
    assert!(e.contains("robot[0].torque.pivot"), "{e}");
}

#[test]
fn robot_nan_and_inf_are_rejected_at_their_key() {
    // each case: the `[[robot]]` line (line 7 of the scene), what the error holds, the value it points at
    let cases = [
        ("orientation = [nan, 0.0, 0.0, 0.0]", "robot[0].orientation: must be finite (a quaternion [w, x, y, z])", "["),
        ("torque = { pivot = nan }", "robot[0].torque.pivot: must be finite (got [NaN])", "nan"),
        ("pd = { pivot = { target = nan, kp = 1.0 } }", "robot[0].pd.pivot.target: must be finite (got NaN)", "nan"),
        (
            "pd = { pivot = { target = 0.0, kp = 1.0, target_velocity = inf } }",
            "robot[0].pd.pivot.target_velocity: must be finite (got inf)",
            "inf",
        ),
        ("friction = nan", "robot[0].friction: must be finite and ≥ 0 (got NaN)", "nan"),
        ("friction = -0.1", "robot[0].friction: must be finite and ≥ 0 (got -0.1)", "-"),
        ("restitution = nan", "robot[0].restitution: must be in [0, 1] (got NaN)", "nan"),
        ("restitution = 1.5", "robot[0].restitution: must be in [0, 1] (got 1.5)", "1.5"),
        ("q = { pivot = inf }", "robot[0].q.pivot: must be finite (got [inf])", "inf"),
    ];
    for (line, problem, value) in cases {
        let e = robot_error(line);
        let at = format!("scene.toml:7:{}: {problem}", line.find(value).unwrap() + 1);
        assert!(e.contains(&at), "{line}: {e}");
    }
}

#[test]
fn robot_no_collide_names_are_checked_with_or_without_collision_geometry() {
    // the pendulum has no collision geometry: its names are checked all the same
    let e = robot_error("no_collide = [[\"bob\", \"ghost\"]]");
    assert!(e.contains("scene.toml:7:14: robot[0].no_collide: names no link of robot `p` (got \"ghost\")"), "{e}");
    assert!(e.ends_with("hint: its links: `base`, `bob`"), "{e}");
    let e = robot_error("no_collide = [[\"bb\"]]");
    assert!(e.contains("robot[0].no_collide: names no link of robot `p` (got \"bb\")"), "{e}");
    assert!(e.ends_with("hint: did you mean `bob`?"), "{e}");
    // a link without collision geometry touches nothing: naming it is a warning, not an error
    let (_dir, loaded) = pendulum_scene("", "no_collide = [[\"bob\"]]");
    let warnings = loaded.unwrap().warnings;
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("scene.toml:7:14: robot[0].no_collide: link `bob` of robot `p` has no collision"));

    // the same pendulum with a box on `bob`
    let dir = tempfile::tempdir().unwrap();
    let boxed = PENDULUM.replace(
        "<inertia ixx=\"0.02\" iyy=\"0.02\" izz=\"0.01\"/></inertial>",
        "<inertia ixx=\"0.02\" iyy=\"0.02\" izz=\"0.01\"/></inertial>\n    \
         <collision><origin xyz=\"0 0 -0.5\"/><geometry><box size=\"0.1 0.1 0.1\"/></geometry></collision>",
    );
    assert_ne!(boxed, PENDULUM);
    std::fs::write(dir.path().join("boxed.urdf"), boxed).unwrap();
    let path = dir.path().join("scene.toml");
    let load = |no_collide: &str| {
        let text = format!("version = 1\n[[robot]]\nname = \"p\"\nurdf = \"boxed.urdf\"\nno_collide = {no_collide}\n");
        std::fs::write(&path, text).unwrap();
        scene::load(&path)
    };
    let ok = load("[[\"bob\"]]").unwrap();
    assert!(ok.warnings.is_empty(), "{:?}", ok.warnings);
    assert_eq!(ok.world.contacts().links.colliders.links().len(), 1);
    let e = load("[[\"bob\", \"ghost\"]]").unwrap_err().to_string();
    assert!(e.contains("scene.toml:5:14: robot[0].no_collide: names no link of robot `p` (got \"ghost\")"), "{e}");
    assert!(e.ends_with("hint: its links: `base`, `bob`"), "{e}");
    let e = load("[[\"bb\"]]").unwrap_err().to_string();
    assert!(e.ends_with("hint: did you mean `bob`?"), "{e}");
    let warned = load("[[\"base\", \"bob\"]]").unwrap();
    assert_eq!(warned.warnings.len(), 1, "{:?}", warned.warnings);
    assert!(warned.warnings[0].contains("robot[0].no_collide: link `base` of robot `p` has no collision geometry"));
}

#[test]
fn missing_and_broken_urdf_files_are_reported_with_their_positions() {
    let dir = tempfile::tempdir().unwrap();
    let scene_text = |urdf: &str| format!("version = 1\n[[robot]]\nname = \"r\"\nurdf = \"{urdf}\"\n");
    let path = dir.path().join("s.toml");
    std::fs::write(&path, scene_text("nowhere.urdf")).unwrap();
    let e = scene::load(&path).unwrap_err().to_string();
    assert!(e.contains("s.toml:4:8: robot[0].urdf:") && e.contains("nowhere.urdf") && e.contains("cannot read"), "{e}");
    // a joint naming a missing link: the URDF's own line and column
    std::fs::write(
        dir.path().join("bad.urdf"),
        "<robot name=\"b\">\n  <link name=\"a\"/>\n  <joint name=\"j\" type=\"continuous\">\n    <parent link=\"a\"/><child link=\"zz\"/>\n  </joint>\n</robot>\n",
    )
    .unwrap();
    std::fs::write(&path, scene_text("bad.urdf")).unwrap();
    let e = scene::load(&path).unwrap_err().to_string();
    assert!(e.contains("s.toml:4:8: robot[0].urdf: ") && e.contains("bad.urdf:4:23: <child>"), "{e}");
    assert!(e.contains("child link 'zz', which does not exist"), "{e}");
}

#[test]
fn robot_names_are_unique_among_bodies_and_robots() {
    let (_dir, loaded) = pendulum_scene("", "");
    assert!(loaded.is_ok());
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("pendulum.urdf"), PENDULUM).unwrap();
    let path = dir.path().join("s.toml");
    let body = "[[body]]\nname = \"p\"\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\n";
    std::fs::write(&path, format!("version = 1\n{body}[[robot]]\nname = \"p\"\nurdf = \"pendulum.urdf\"\n")).unwrap();
    let e = scene::load(&path).unwrap_err().to_string();
    assert!(e.contains("robot[0].name: duplicate name: already used by body[0].name"), "{e}");
    let robot = "[[robot]]\nname = \"r\"\nurdf = \"pendulum.urdf\"\n";
    std::fs::write(&path, format!("version = 1\n{robot}{robot}")).unwrap();
    let e = scene::load(&path).unwrap_err().to_string();
    assert!(e.contains("robot[1].name: duplicate name: already used by robot[0].name"), "{e}");
}

#[test]
fn json_scenes_take_the_same_robot_keys() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("pendulum.urdf"), PENDULUM).unwrap();
    let path = dir.path().join("s.json");
    std::fs::write(
        &path,
        r#"{"version": 1, "robot": [{"name": "p", "urdf": "pendulum.urdf", "q": {"pivot": 0.2},
            "pd": {"pivot": {"target": 0.0, "kp": 5, "kd": 1}}, "damping": {"pivot": 0.1}}]}"#,
    )
    .unwrap();
    let scene = scene::load(&path).unwrap();
    let robot = &scene.world.robots[0];
    assert_eq!(robot.q(), [0.2]);
    assert_eq!((robot.control.kp[0], robot.control.kd[0], robot.control.damping[0]), (5.0, 1.0, 0.1));
    std::fs::write(&path, r#"{"version": 1, "robot": [{"name": "p", "urdf": "pendulum.urdf", "q": {"elbow": 1}}]}"#)
        .unwrap();
    let e = scene::load(&path).unwrap_err().to_string();
    assert!(e.contains("robot[0].q.elbow: unknown joint `elbow`") && e.contains("movable joints: `pivot`"), "{e}");
}

#[test]
fn the_world_integrator_chooses_the_robot_method() {
    use tumble::multibody::Method;
    use tumble::world::robot_method;
    use tumble::Integrator;
    assert_eq!(robot_method(Integrator::Euler), Method::Euler);
    assert_eq!(robot_method(Integrator::SemiImplicitEuler), Method::SemiImplicitEuler);
    for i in [Integrator::Rk4, Integrator::Dopri5, Integrator::Splitting, Integrator::Splitting4] {
        assert_eq!(robot_method(i), Method::Rk4, "{i}");
    }
    // a small swing of the pendulum for 5 s at dt = 1e-3: explicit Euler gains energy, semi-implicit
    // Euler keeps it within a bounded oscillation, RK4 keeps it to its truncation error
    let drift = |integrator: &str| {
        let (_dir, loaded) =
            pendulum_scene(&format!("integrator = \"{integrator}\"\nduration = 5.0"), "q = { pivot = 0.3 }");
        let mut scene = loaded.unwrap();
        let e0 = scene.world.energy();
        let swing = e0 - rest_energy(&scene.world.robots[0]);
        let mut worst = 0.0_f64;
        for _ in 0..scene.world.config.step_count() {
            scene.world.step().unwrap();
            worst = worst.max((scene.world.energy() - e0).abs());
        }
        ((scene.world.energy() - e0) / swing, worst / swing)
    };
    let (euler_final, _) = drift("euler");
    let (_, semi) = drift("semi_implicit_euler");
    let (_, rk4) = drift("rk4");
    let (_, splitting) = drift("splitting");
    eprintln!("energy error of the swing: euler final {euler_final:e}, semi-implicit max {semi:e}, rk4 {rk4:e}");
    assert!(euler_final > 0.05, "explicit Euler gains energy: {euler_final}");
    assert!(semi < 0.01 && semi < euler_final, "semi-implicit Euler: {semi}");
    assert!(rk4 < 1e-9, "{rk4}");
    assert_eq!(splitting, rk4, "splitting runs robots with RK4");
}

#[test]
fn link_velocities_are_the_rates_of_the_link_poses() {
    // central differences of the link rows over ±1e-5 s against the written velocities, for the
    // body frames and for the `tip` link merged into `lower` 1 m beyond its origin
    let mut scene = scene::load(&repo().join("scenes/double_pendulum.toml")).unwrap();
    scene.world.config.dt = 1e-5;
    for _ in 0..30_000 {
        scene.world.step().unwrap();
    }
    let states = |world: &tumble::World| (0..3).map(|k| world.robots[0].link_state(k)).collect::<Vec<_>>();
    let before = states(&scene.world);
    scene.world.step().unwrap();
    let now = states(&scene.world);
    scene.world.step().unwrap();
    let after = states(&scene.world);
    let h = 1e-5;
    for k in 0..3 {
        let rate = (after[k].position - before[k].position) / (2.0 * h);
        let error = (rate - now[k].velocity).length();
        // ω from the quaternion rate: ω = 2 q̇ q* (q and −q are the same rotation: align the signs)
        let align = |q: DQuat| if q.dot(now[k].orientation) < 0.0 { -q } else { q };
        let q_dot = (align(after[k].orientation) - align(before[k].orientation)) / (2.0 * h);
        let omega = 2.0 * (q_dot * now[k].orientation.conjugate()).xyz();
        let omega_error = (omega - now[k].angular_velocity).length();
        eprintln!(
            "link {k}: |v| = {}, difference {error:e}; |ω| = {}, difference {omega_error:e}",
            now[k].velocity.length(),
            now[k].angular_velocity.length()
        );
        assert!(error < 1e-6 * (1.0 + now[k].velocity.length()), "link {k}: {error:e}");
        assert!(omega_error < 1e-6 * (1.0 + now[k].angular_velocity.length()), "link {k}: {omega_error:e}");
    }
    assert!(now[2].velocity.length() > 0.5, "the tip should be moving");
}
