//! Robots in motion: a passive double pendulum conserves energy under RK4; a pendulum's small
//! oscillations have the period `2π sqrt(I/(m g l))`; damping dissipates; PD control holds a target.

use tumble::multibody::{
    kinetic_energy, parse_urdf, potential_energy, Control, Method, MultibodyModel, Simulator, UrdfOptions,
};

fn energy(model: &MultibodyModel, sim: &mut Simulator) -> f64 {
    let (q, v) = (sim.q.clone(), sim.v.clone());
    let ws = sim.workspace();
    kinetic_energy(model, ws, &q, &v).unwrap() + potential_energy(model, ws, &q).unwrap()
}

/// The textbook double pendulum: two 1 m links of 1 kg (centres of mass at their middles, thin-rod
/// inertia `m l²/12` about the swing axis), hanging along −z at `q = 0`, swinging about x.
const DOUBLE_PENDULUM: &str = r#"<robot name="double_pendulum">
  <link name="base"/>
  <link name="upper"><inertial><origin xyz="0 0 -0.5"/><mass value="1"/>
    <inertia ixx="0.0833333333333333" iyy="0.0833333333333333" izz="0.001"/></inertial></link>
  <link name="lower"><inertial><origin xyz="0 0 -0.5"/><mass value="1"/>
    <inertia ixx="0.0833333333333333" iyy="0.0833333333333333" izz="0.001"/></inertial></link>
  <joint name="shoulder" type="continuous"><parent link="base"/><child link="upper"/><axis xyz="1 0 0"/></joint>
  <joint name="elbow" type="continuous"><parent link="upper"/><child link="lower"/>
    <origin xyz="0 0 -1"/><axis xyz="1 0 0"/></joint>
</robot>"#;

fn double_pendulum() -> MultibodyModel {
    parse_urdf(DOUBLE_PENDULUM, "double_pendulum.urdf", UrdfOptions::default()).unwrap()
}

/// The mechanical energy above the resting state (J): the scale of "relative" energy errors (the
/// zero of the potential is arbitrary).
fn energy_above_rest(model: &MultibodyModel, sim: &mut Simulator, e: f64) -> f64 {
    e - potential_energy(model, sim.workspace(), &[0.0, 0.0]).unwrap()
}

/// 10 s of RK4 at `dt = 1e-3` from a large swing: the energy drift stays below 1e-8 of the
/// mechanical energy above rest.
#[test]
fn passive_double_pendulum_conserves_energy_under_rk4() {
    let model = double_pendulum();
    let control = Control::passive(&model);
    let mut sim = Simulator::new(&model, vec![1.0, -0.5], vec![0.0, 0.0]).unwrap();
    let e0 = energy(&model, &mut sim);
    let swing = energy_above_rest(&model, &mut sim, e0);
    let mut worst = 0.0_f64;
    for _ in 0..10_000 {
        sim.step(&model, &control, Method::Rk4, 1e-3).unwrap();
        worst = worst.max((energy(&model, &mut sim) - e0).abs());
    }
    assert!((sim.t - 10.0).abs() < 1e-9);
    let relative = worst / swing;
    eprintln!("double pendulum, rk4, 10 s at dt = 1e-3: largest energy error {relative:e} of {swing} J");
    assert!(relative < 1e-8, "relative energy drift {relative:e} (energy above rest {swing} J)");
    // it moved: not a trivially conserved rest state
    assert!(sim.v.iter().any(|x| x.abs() > 0.1));
}

/// A rigid pendulum: mass 2 kg, centre of mass 0.5 m below the pivot, `I_c = 0.02` kg·m² about the
/// axis; `I = I_c + m l² = 0.52`, `T = 2π sqrt(0.52 / (2 · 9.81 · 0.5))`, from a 0.01 rad swing.
#[test]
fn pendulum_small_oscillation_period() {
    let urdf = r#"<robot name="pendulum">
  <link name="base"/>
  <link name="bob"><inertial><origin xyz="0 0 -0.5"/><mass value="2"/>
    <inertia ixx="0.02" iyy="0.02" izz="0.01"/></inertial></link>
  <joint name="pivot" type="continuous"><parent link="base"/><child link="bob"/><axis xyz="1 0 0"/></joint>
</robot>"#;
    let model = parse_urdf(urdf, "pendulum.urdf", UrdfOptions::default()).unwrap();
    let expected = 2.0 * std::f64::consts::PI * (0.52_f64 / (2.0 * 9.81 * 0.5)).sqrt();
    let control = Control::passive(&model);
    let mut sim = Simulator::new(&model, vec![0.01], vec![0.0]).unwrap();
    let dt = 1e-4;
    // upward zero crossings of the angle, linearly interpolated
    let mut crossings = Vec::new();
    let mut previous = sim.q[0];
    while crossings.len() < 4 {
        sim.step(&model, &control, Method::Rk4, dt).unwrap();
        let q = sim.q[0];
        if previous < 0.0 && q >= 0.0 {
            crossings.push(sim.t - dt * q / (q - previous));
        }
        previous = q;
        assert!(sim.t < 20.0, "no oscillation");
    }
    let period = (crossings[3] - crossings[0]) / 3.0;
    let relative = (period - expected).abs() / expected;
    eprintln!("pendulum period {period} s, expected {expected} s, relative error {relative:e}");
    assert!(relative < 1e-3, "period {period} s, expected {expected} s ({:.4} %)", 100.0 * relative);
}

#[test]
fn damping_dissipates_energy_monotonically() {
    let model = double_pendulum();
    let mut control = Control::passive(&model);
    control.damping = vec![0.2, 0.2];
    let mut sim = Simulator::new(&model, vec![1.0, -0.5], vec![0.0, 0.0]).unwrap();
    let mut e = energy(&model, &mut sim);
    let e0 = e;
    for _ in 0..3000 {
        sim.step(&model, &control, Method::Rk4, 1e-3).unwrap();
        let e_next = energy(&model, &mut sim);
        assert!(e_next <= e + 1e-12 * e0.abs(), "energy rose from {e} to {e_next} at t = {}", sim.t);
        e = e_next;
    }
    let swing = energy_above_rest(&model, &mut sim, e0);
    assert!(e < e0 - 0.1 * swing, "damping removed too little: {e0} → {e}");
}

/// PD control plus the gravity torque at the target holds the double pendulum at the target.
#[test]
fn pd_control_reaches_its_target() {
    let model = double_pendulum();
    let target = [0.4, -0.3];
    let mut control = Control::passive(&model);
    control.kp = vec![100.0, 100.0];
    control.kd = vec![20.0, 20.0];
    control.q_target = target.to_vec();
    // gravity compensation at the target: τ = g(q*)
    let mut ws = tumble::multibody::Workspace::new(&model);
    let mut g = vec![0.0; 2];
    tumble::multibody::bias_forces(&model, &mut ws, &target, &[0.0, 0.0], &mut g).unwrap();
    control.tau = g;
    let mut sim = Simulator::new(&model, vec![0.0, 0.0], vec![0.0, 0.0]).unwrap();
    for _ in 0..20_000 {
        sim.step(&model, &control, Method::SemiImplicitEuler, 1e-3).unwrap();
    }
    for (k, (q, t)) in sim.q.iter().zip(target).enumerate() {
        assert!((q - t).abs() < 1e-6, "q[{k}] = {q} vs {t}");
        assert!(sim.v[k].abs() < 1e-5);
    }
}

/// A floating body integrated by the simulator keeps a unit quaternion and falls at `g`.
#[test]
fn floating_base_falls_freely() {
    let urdf = r#"<robot name="box"><link name="box"><inertial><mass value="1"/>
        <inertia ixx="0.1" iyy="0.2" izz="0.25"/></inertial></link></robot>"#;
    let model = parse_urdf(urdf, "box.urdf", UrdfOptions { floating: true, ..Default::default() }).unwrap();
    let control = Control::passive(&model);
    let q0 = vec![0.0, 0.0, 10.0, 1.0, 0.0, 0.0, 0.0];
    let mut sim = Simulator::new(&model, q0, vec![0.0, 0.0, 0.0, 1.0, 2.0, 0.5]).unwrap();
    for _ in 0..1000 {
        sim.step(&model, &control, Method::Rk4, 1e-3).unwrap();
    }
    let norm: f64 = sim.q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
    assert!((norm - 1.0).abs() < 1e-14);
    // z = 10 − ½ g t² at t = 1 s (the centre of mass is the base origin)
    assert!((sim.q[2] - (10.0 - 0.5 * 9.81)).abs() < 1e-9, "z = {}", sim.q[2]);
}
