//! MJCF robots in scenes: `[[robot]] mjcf = "X.xml"` with its actuators driven by `ctrl`.
//!
//! - a pendulum held by a `position` actuator settles where the servo balances gravity,
//!   `k_p (u − qpos) = m g l sin q` (with the joint's `ref`: `qpos = q + ref`), and one driven by a
//!   `motor` where `g u = m g l sin q`; `ctrlrange` clamps the control;
//! - the Gymnasium Ant under zero control, let go above the floor, comes to rest on it, its ankles
//!   (outside their ranges at the start) not pushed in by the contact stage's limit rows; at its
//!   file's `dt` = 10 ms its energy, with what the soft rows' springs store, never rises;
//! - bad entries name the file, line and field.

use std::path::Path;
use tumble::scene::{self, Scene, SceneError};

/// A pendulum: mass 2 kg, centre of mass 0.5 m below the pivot, hinge about x with `ref`, a
/// position servo (`kp` 50) and a motor (gear 2) on it, joint damping to settle it.
fn pendulum_xml(reference: f64) -> String {
    format!(
        r#"<mujoco model="servo">
  <compiler angle="radian"/>
  <worldbody>
    <body name="bob">
      <joint name="pivot" type="hinge" axis="1 0 0" damping="10" ref="{reference}"/>
      <inertial pos="0 0 -0.5" mass="2" diaginertia="0.02 0.02 0.01"/>
    </body>
  </worldbody>
  <actuator>
    <position name="servo" joint="pivot" kp="50" ctrlrange="-1 1"/>
    <motor name="push" joint="pivot" gear="2"/>
  </actuator>
</mujoco>"#
    )
}

fn load(files: &[(&str, &str)], robot: &str, duration: f64) -> (tempfile::TempDir, Result<Scene, SceneError>) {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    let text = format!("version = 1\n[world]\ndt = 1e-3\nduration = {duration}\n[[robot]]\nname = \"p\"\n{robot}\n");
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let loaded = scene::load(&path);
    (dir, loaded)
}

fn settle(robot: &str, reference: f64) -> f64 {
    let xml = pendulum_xml(reference);
    let (_dir, loaded) = load(&[("servo.xml", &xml)], robot, 6.0);
    let mut scene = loaded.unwrap();
    for _ in 0..scene.world.config.step_count() {
        scene.world.step().unwrap();
    }
    let (q, v) = (scene.world.robots[0].q()[0], scene.world.robots[0].v()[0]);
    assert!(v.abs() < 1e-8, "still moving: v = {v}");
    q
}

#[test]
fn a_position_servo_settles_where_it_balances_gravity() {
    let mgl = 2.0 * 9.81 * 0.5;
    for reference in [0.0, 0.2] {
        let q = settle("mjcf = \"servo.xml\"\nctrl = { servo = 0.6 }", reference);
        // k_p (u − (q + ref)) = m g l sin q
        let residual = 50.0 * (0.6 - (q + reference)) - mgl * q.sin();
        eprintln!("servo to 0.6 with ref {reference}: q = {q}, residual {residual:e} N·m");
        assert!(q > 0.05 && q < 0.6 - reference, "q = {q}");
        assert!(residual.abs() < 1e-7, "residual {residual}");
    }
    // the control is clamped to ctrlrange [−1, 1]
    let q = settle("mjcf = \"servo.xml\"\nctrl = { servo = 3.0 }", 0.0);
    let residual = 50.0 * (1.0 - q) - mgl * q.sin();
    assert!(residual.abs() < 1e-7, "clamped to 1: q = {q}, residual {residual}");
}

#[test]
fn a_motor_holds_a_constant_torque_and_unnamed_actuators_start_at_zero() {
    // the servo at u = 0 pulls to qpos = 0; the motor's g u = 0.6 N·m against it and gravity:
    // 0.6 = k_p q + m g l sin q
    let q = settle("mjcf = \"servo.xml\"\nctrl = { push = 0.3 }", 0.0);
    let residual = 0.6 - 50.0 * q - 2.0 * 9.81 * 0.5 * q.sin();
    eprintln!("motor 0.3 (gear 2) against the servo at 0: q = {q}, residual {residual:e}");
    assert!(q > 0.0 && residual.abs() < 1e-7, "q = {q}, residual {residual}");
    // one number drives every actuator: k_p (u − q) + g u = m g l sin q
    let q = settle("mjcf = \"servo.xml\"\nctrl = 0.5", 0.0);
    let residual = 50.0 * (0.5 - q) + 2.0 * 0.5 - 2.0 * 9.81 * 0.5 * q.sin();
    assert!(residual.abs() < 1e-7, "q = {q}, residual {residual}");
}

#[test]
fn the_gymnasium_ant_comes_to_rest_on_the_floor() {
    let ant = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/mjcf/gymnasium/ant.xml");
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "version = 1\n[world]\ndt = 1e-3\nduration = 3.0\nintegrator = \"semi_implicit_euler\"\n\
         [[body]]\nname = \"ground\"\nshape = {{ type = \"plane\" }}\nfixed = true\n\
         [[robot]]\nname = \"ant\"\nmjcf = {:?}\nposition = [0.0, 0.0, 0.8]\n",
        ant.display().to_string()
    );
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let mut scene = scene::load(&path).unwrap();
    let steps = scene.world.config.step_count();
    // a passive robot under zero control: its energy (the joints' armature counted, ½ a v²) never
    // rises above its lowest value so far; without the armature's share the legs' sag, taken up by
    // the floor, looked like a 0.03 J gain
    let (mut lowest, mut gain) = (f64::INFINITY, 0.0_f64);
    for _ in 0..steps {
        scene.world.step().unwrap();
        let e = scene.world.robots[0].energy();
        lowest = lowest.min(e);
        gain = gain.max(e - lowest);
    }
    eprintln!("ant: largest energy gain {gain:.2e} J");
    assert!(gain <= 1e-9, "the ant gained {gain} J");
    let robot = &scene.world.robots[0];
    let (q, v) = (robot.q(), robot.v());
    assert!(q.iter().chain(v).all(|x| x.is_finite()));
    let speed = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    // the lowest point of the ant's collision geometry
    let lowest = scene.world.contacts().links.contacts().iter().map(|c| c.gap).fold(f64::INFINITY, f64::min);
    eprintln!("ant after 3 s: torso z = {:.4} m, |v| = {speed:.2e}, deepest gap {lowest:.2e} m", q[2]);
    assert!(q[2] > 0.1 && q[2] < 0.8, "torso height {}", q[2]);
    assert!(speed < 1e-2, "|v| = {speed}");
    assert!(lowest > -2e-3, "penetration {lowest}");
    // its ankles start outside their ranges (qpos0 = 0, ranges 30°–70°): the joint-limit rows of
    // the contact stage stop them going further out without pushing them in, so the resting
    // contacts take energy out (before they pushed, and put 0.8–1.0 J in)
    let lost = scene.world.contact_energy();
    eprintln!("ant: collisions took {:.3} J, resting contacts {:.3} J", lost.collisions, lost.friction);
    assert!(lost.friction >= 0.0 && lost.collisions >= 0.0, "{lost:?}");
}

/// The Ant as its file runs it (`dt` = 10 ms, RK4), dropped on its floor under zero control: its
/// energy counted with the springs of the soft rows that hold it never rises. The robot's own
/// `T + V` does rise (2.19e-5 J, from t = 2.77 s): when its leg tips land (t = 2.58 s) they lift
/// the torso 4 mm, the torso settles back 9 µm, pressing the tips 48.9 µm into the floor where the
/// contact rows' springs hold its weight at 44 µm, and the ankles' limit rows past their floor;
/// over the next 0.3 s those springs give 2.2e-5 J back, raising the robot 2.4 µm. A spring–damper
/// contact does that; the system's energy is the robot's plus what the springs store
/// (`World::contact_elastic_energy`), and that never rises.
#[test]
fn the_gymnasium_ant_at_its_files_step_gains_no_energy() {
    let ant = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/mjcf/gymnasium/ant.xml");
    let mut scene = scene::load(&ant).unwrap();
    assert_eq!((scene.world.config.dt, scene.world.config.integrator), (0.01, tumble::Integrator::Rk4));
    let energy = |w: &tumble::World| w.robots[0].energy() + w.contact_elastic_energy();
    let (mut lowest, mut gain) = (energy(&scene.world), 0.0_f64);
    let (mut robot_lowest, mut robot_gain, mut stored) = (f64::INFINITY, 0.0_f64, 0.0_f64);
    for _ in 0..400 {
        scene.world.step().unwrap();
        let e = energy(&scene.world);
        lowest = lowest.min(e);
        gain = gain.max(e - lowest);
        let t = scene.world.robots[0].energy();
        robot_lowest = robot_lowest.min(t);
        robot_gain = robot_gain.max(t - robot_lowest);
        stored = stored.max(scene.world.contact_elastic_energy());
    }
    eprintln!(
        "ant at dt = 10 ms: largest gain {gain:.2e} J (the robot's T + V alone: {robot_gain:.2e} J; \
         the springs held up to {stored:.2e} J)"
    );
    assert!(gain <= 1e-6, "the ant gained {gain} J");
    let lowest_gap = scene.world.contacts().links.contacts().iter().map(|c| c.gap).fold(f64::INFINITY, f64::min);
    assert!(lowest_gap > -2e-3, "penetration {lowest_gap}");
}

fn e_line() -> String {
    error("mjcf = \"servo.xml\"\nctrl = { sevro = 1.0 }")
}

fn error(robot: &str) -> String {
    let xml = pendulum_xml(0.0);
    let (_dir, loaded) =
        load(&[("servo.xml", &xml), ("arm.urdf", "<robot name=\"a\"><link name=\"l\"/></robot>")], robot, 1.0);
    match loaded {
        Ok(_) => panic!("accepted: {robot}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_mjcf_robot_entries_name_the_field() {
    let e = error("mjcf = \"servo.xml\"\nurdf = \"arm.urdf\"");
    assert!(e.contains("robot[0].urdf") && e.contains("both"), "{e}");
    let e = error("mjcf = \"servo.xml\"\nbase = \"floating\"");
    assert!(e.contains("robot[0].base") && e.contains("MJCF file decides the base"), "{e}");
    let e = error("mjcf = \"servo.xml\"\nctrl = { sevro = 1.0 }");
    assert!(e.contains("robot[0].ctrl.sevro") && e.contains("did you mean `servo`"), "{e}");
    let e = error("urdf = \"arm.urdf\"\nctrl = 1.0");
    assert!(e.contains("robot[0].ctrl") && e.contains("MJCF"), "{e}");
    let e = error("mjcf = \"servo.xml\"\npd = { pivot = { target = 0.1, kp = 5.0 } }");
    assert!(e.contains("drives joint `pivot`"), "{e}");
    let e = error("mjcf = \"missing.xml\"");
    assert!(e.contains("robot[0].mjcf") && e.contains("missing.xml"), "{e}");
    // the scene file's line and column (line 8: the entry's second line)
    assert!(e_line().contains("scene.toml:8:18"), "{}", e_line());
}

/// A robot's kinetic energy counts its joints' armature: `T = ½ vᵀ M v` with the mass matrix of
/// the dynamics (CRBA, `M_kk += a_k`), for the Gymnasium Ant (armature 1 on its eight hinges).
#[test]
fn a_robots_kinetic_energy_counts_the_armature() {
    let ant = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/mjcf/gymnasium/ant.xml");
    let dir = tempfile::tempdir().unwrap();
    let text =
        format!("version = 1\n[world]\ndt = 1e-3\n[[robot]]\nname = \"ant\"\nmjcf = {:?}\n", ant.display().to_string());
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let mut scene = scene::load(&path).unwrap();
    let robot = &mut scene.world.robots[0];
    let nv = robot.model.nv();
    let mut q = robot.q().to_vec();
    for (k, x) in q.iter_mut().enumerate().skip(7) {
        *x = 0.1 * k as f64;
    }
    let v: Vec<f64> = (0..nv).map(|k| 0.3 * (k as f64 + 1.0).sin()).collect();
    robot.set_state(&q, &v);
    let mut ws = tumble::multibody::Workspace::new(&robot.model);
    let m = tumble::multibody::crba(&robot.model, &mut ws, &q).unwrap().clone();
    let vm = nalgebra::DVector::from_column_slice(&v);
    let half_vmv = 0.5 * vm.dot(&(&m * &vm));
    let t = robot.kinetic_energy();
    assert!((t - half_vmv).abs() <= 1e-12 * half_vmv, "T = {t}, ½ vᵀ M v = {half_vmv}");
}

/// The Gymnasium swimmer (`<option density="4000" viscosity="0.1">`) in a scene: under zero control,
/// set gliding and flexing, the medium's drag only takes energy out (its motion is horizontal, so
/// its energy is all kinetic), and takes most of it within a second.
#[test]
fn the_gymnasium_swimmer_glides_to_a_stop_in_its_medium() {
    let swimmer = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/mjcf/gymnasium/swimmer.xml");
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "version = 1\n[world]\ndt = 1e-3\nduration = 1.0\nintegrator = \"rk4\"\n[[robot]]\nname = \"swimmer\"\nmjcf = {:?}\n",
        swimmer.display().to_string()
    );
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let mut scene = scene::load(&path).unwrap();
    assert!(scene.world.robots[0].model.fluid.is_active());
    let robot = &mut scene.world.robots[0];
    let q = robot.q().to_vec();
    let v = [1.0, -0.5, 0.8, 2.0, -1.5];
    robot.set_state(&q, &v);
    let start = robot.energy();
    let mut previous = start;
    for _ in 0..scene.world.config.step_count() {
        scene.world.step().unwrap();
        let e = scene.world.robots[0].energy();
        assert!(e <= previous + 1e-12 * start, "the energy rose from {previous} to {e} J");
        previous = e;
    }
    eprintln!("swimmer: kinetic energy {start:.3} J → {previous:.3e} J after 1 s");
    assert!(previous < 0.5 * start, "the drag took too little: {start} → {previous} J");
}
