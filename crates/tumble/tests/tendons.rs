//! Fixed tendons in simulation (MJCF `<tendon><fixed>`, `multibody::tendon`):
//!
//! - a `position` actuator on a tendon `L = c₁ q₁ + c₂ q₂` over two hinges with springs `k_i`
//!   settles where `k_i q_i = c_i f` and `f = k_p (u − L)`, i.e. `f = k_p u / (1 + k_p Σ c_i²/k_i)`;
//!   with a `forcerange` below that force, at `f = f_max`;
//! - a tendon spring without damping keeps the robot's energy (its `½ k (L − L_s)²` counted);
//! - locking a joint keeps its term as a constant length.

use std::path::Path;
use tumble::multibody::mjcf::{parse_mjcf, MjcfOptions};
use tumble::multibody::reduced_model;
use tumble::scene::{self, Scene};

const K1: f64 = 3.0;
const K2: f64 = 5.0;
const C1: f64 = 1.0;
const C2: f64 = 0.6;
const KP: f64 = 4.0;

/// Two hinges about y in a row (springs `K1`, `K2` to 0, damping), a tendon over both, a servo on
/// it with `forcerange` given by `force_range`.
fn finger_xml(force_range: &str, tendon_extra: &str) -> String {
    format!(
        r#"<mujoco model="finger">
  <compiler angle="radian"/>
  <worldbody>
    <body name="a">
      <joint name="j1" type="hinge" axis="0 1 0" stiffness="{K1}" damping="0.5"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03"/>
      <body name="b" pos="0.3 0 0">
        <joint name="j2" type="hinge" axis="0 1 0" stiffness="{K2}" damping="0.5"/>
        <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.02"/>
      </body>
    </body>
  </worldbody>
  <tendon>
    <fixed name="flex" {tendon_extra}>
      <joint joint="j1" coef="{C1}"/>
      <joint joint="j2" coef="{C2}"/>
    </fixed>
  </tendon>
  <actuator>
    <position name="servo" tendon="flex" kp="{KP}" {force_range}/>
  </actuator>
</mujoco>"#
    )
}

fn run(xml: &str, world: &str, ctrl: f64, duration: f64) -> (tempfile::TempDir, Scene) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("finger.xml"), xml).unwrap();
    let text = format!(
        "version = 1\n[world]\n{world}duration = {duration}\ngravity = [0.0, 0.0, 0.0]\n[[robot]]\nname = \"f\"\nmjcf = \"finger.xml\"\nctrl = {{ servo = {ctrl} }}\n"
    );
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let mut scene = scene::load(&path).unwrap();
    for _ in 0..scene.world.config.step_count() {
        scene.world.step().unwrap();
    }
    (dir, scene)
}

#[test]
fn a_tendon_servo_settles_where_the_joint_springs_balance_it() {
    let u = 0.5;
    let s = C1 * C1 / K1 + C2 * C2 / K2;
    let f = KP * u / (1.0 + KP * s);
    let (_dir, scene) = run(&finger_xml("", ""), "dt = 1e-3\n", u, 20.0);
    let r = &scene.world.robots[0];
    let (q, v) = (r.q(), r.v());
    assert!(v.iter().all(|x| x.abs() < 1e-9), "still moving: {v:?}");
    let want = [C1 * f / K1, C2 * f / K2];
    for (got, want) in q.iter().zip(want) {
        assert!((got - want).abs() < 1e-9, "q = {q:?}, expected {want} (f = {f})");
    }

    // a forcerange under that force holds the tendon at f_max
    let f_max = 0.5 * f;
    let (_dir, scene) = run(&finger_xml(&format!("forcerange=\"{} {}\"", -f_max, f_max), ""), "dt = 1e-3\n", u, 20.0);
    let q = scene.world.robots[0].q();
    for (got, want) in q.iter().zip([C1 * f_max / K1, C2 * f_max / K2]) {
        assert!((got - want).abs() < 1e-9, "clamped: q = {q:?}, expected {want}");
    }
}

/// The largest energy error of a run of the tendon spring alone from `q = (0.4, −0.3)` at rest, RK4
/// at `dt`, and the energy at the start.
fn spring_run(dt: f64) -> (f64, f64) {
    // no joint damping, no actuator
    let xml = remove_actuators(&finger_xml("", "stiffness=\"7\" springlength=\"0.2\"").replace("damping=\"0.5\"", ""));
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("finger.xml"), &xml).unwrap();
    let text = format!(
        "version = 1\n[world]\ndt = {dt:e}\nduration = 3\nintegrator = \"rk4\"\ngravity = [0.0, 0.0, 0.0]\n[[robot]]\nname = \"f\"\nmjcf = \"finger.xml\"\nq = {{ j1 = 0.4, j2 = -0.3 }}\n"
    );
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let mut scene = scene::load(&path).unwrap();
    let e0 = scene.world.robots[0].energy();
    let mut largest = 0.0_f64;
    let mut moved = 0.0_f64;
    for _ in 0..scene.world.config.step_count() {
        scene.world.step().unwrap();
        largest = largest.max((scene.world.robots[0].energy() - e0).abs());
        moved = moved.max(scene.world.robots[0].kinetic_energy());
    }
    assert!(moved > 0.3 * e0, "the springs moved the joints: largest kinetic energy {moved} J of {e0} J");
    (largest, e0)
}

#[test]
fn a_tendon_spring_without_damping_keeps_the_energy() {
    // at rest the energy is the springs': ½ k₁ q₁² + ½ k₂ q₂² + ½ k_t (L − L_s)²
    let (q1, q2) = (0.4, -0.3);
    let stretch = C1 * q1 + C2 * q2 - 0.2;
    let springs = 0.5 * K1 * q1 * q1 + 0.5 * K2 * q2 * q2 + 0.5 * 7.0 * stretch * stretch;
    let (error_coarse, e0) = spring_run(1e-3);
    assert!((e0 - springs).abs() < 1e-14, "energy at rest {e0} J, the springs' {springs} J");
    // what is left is RK4's truncation: it falls as dt⁴ (16× for half the step; ≥ 10× asked)
    let (error_fine, _) = spring_run(5e-4);
    eprintln!("energy error: {error_coarse:.2e} J at dt = 1 ms, {error_fine:.2e} J at 0.5 ms (of {e0} J)");
    assert!(error_coarse < 1e-6 * e0, "energy drifted by {error_coarse} J of {e0} J");
    assert!(error_fine * 10.0 < error_coarse, "the error does not fall as RK4's: {error_coarse} → {error_fine} J");
}

fn remove_actuators(xml: &str) -> String {
    let start = xml.find("<actuator>").unwrap();
    let end = xml.find("</actuator>").unwrap() + "</actuator>".len();
    format!("{}{}", &xml[..start], &xml[end..])
}

#[test]
fn locking_a_joint_keeps_its_term_as_a_constant_length() {
    let xml = finger_xml("", "stiffness=\"2\"");
    let mjcf = parse_mjcf(&xml, Path::new("finger.xml").to_str().unwrap(), MjcfOptions::default()).unwrap();
    let full = &mjcf.model;
    let q_full = [0.3, -0.7];
    let reduced = reduced_model(full, &["j1"], &q_full).unwrap();
    assert_eq!(reduced.nq(), 1);
    let t_full = &full.tendons[0];
    let t_reduced = &reduced.tendons[0];
    assert_eq!(t_reduced.terms.len(), 1);
    assert_eq!(t_reduced.terms[0].q_index, 0);
    assert!((t_reduced.length(&[-0.7]) - t_full.length(&q_full)).abs() < 1e-15);
    assert!((t_reduced.length(&[0.1]) - t_full.length(&[0.3, 0.1])).abs() < 1e-15);
}
