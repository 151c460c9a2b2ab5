//! Joint position limits and effort limits on trees, with every robot integrator:
//!
//! - a joint held against its limit by a constant torque stays within 1e-4 of it, at rest (a single
//!   pendulum, and a joint in the middle of a swinging chain);
//! - a joint swung into its limit at speed stops there: no rebound, no passing through, energy never
//!   rises;
//! - two limited joints at their limits at once (coupled through `M⁻¹`) are both held;
//! - limits that never come near leave the trajectory bit-identical to limits off; limits off let
//!   a joint pass;
//! - a joint that starts outside its limit is stopped going further out and may come back, without
//!   a kick;
//! - a PD with a huge gain applies at most the effort limit; damping is not clamped.

use tumble::multibody::{
    kinetic_energy, parse_urdf, potential_energy, Control, Method, MultibodyModel, Simulator, UrdfOptions,
};

const METHODS: [Method; 3] = [Method::Rk4, Method::SemiImplicitEuler, Method::Euler];

/// A pendulum swinging about x: 2 kg, centre of mass 0.5 m below the pivot, `I = 0.52` kg·m² about
/// the pivot; `q ∈ [−0.5, 0.5]` rad, effort 5 N·m.
const PENDULUM: &str = r#"<robot name="pendulum">
  <link name="base"/>
  <link name="bob"><inertial><origin xyz="0 0 -0.5"/><mass value="2"/>
    <inertia ixx="0.02" iyy="0.02" izz="0.01"/></inertial></link>
  <joint name="pivot" type="revolute"><parent link="base"/><child link="bob"/><axis xyz="1 0 0"/>
    <limit lower="-0.5" upper="0.5" effort="5" velocity="10"/></joint>
</robot>"#;

/// A chain of four 1 kg, 0.5 m links swinging about x; joints `j0`, `j2`, `j3` continuous, `j1`
/// limited to `[−0.3, 0.4]` rad; `both` makes `j2` limited to `[−0.2, 0.25]` as well.
fn chain(both: bool) -> MultibodyModel {
    let link = |name: &str| {
        format!(
            r#"<link name="{name}"><inertial><origin xyz="0 0 -0.25"/><mass value="1"/>
               <inertia ixx="0.0208" iyy="0.0208" izz="0.001"/></inertial></link>"#
        )
    };
    let joint = |name: &str, parent: &str, child: &str, limit: Option<(f64, f64)>, first: bool| {
        let origin = if first { "" } else { r#"<origin xyz="0 0 -0.5"/>"# };
        match limit {
            Some((lo, hi)) => format!(
                r#"<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>{origin}
                   <axis xyz="1 0 0"/><limit lower="{lo}" upper="{hi}" effort="100" velocity="10"/></joint>"#
            ),
            None => format!(
                r#"<joint name="{name}" type="continuous"><parent link="{parent}"/><child link="{child}"/>{origin}
                   <axis xyz="1 0 0"/></joint>"#
            ),
        }
    };
    let urdf = format!(
        "<robot name=\"chain\"><link name=\"base\"/>{}{}{}{}{}{}{}{}</robot>",
        link("l0"),
        link("l1"),
        link("l2"),
        link("l3"),
        joint("j0", "base", "l0", None, true),
        joint("j1", "l0", "l1", Some((-0.3, 0.4)), false),
        joint("j2", "l1", "l2", both.then_some((-0.2, 0.25)), false),
        joint("j3", "l2", "l3", None, false),
    );
    parse_urdf(&urdf, "chain.urdf", UrdfOptions::default()).unwrap()
}

fn pendulum() -> MultibodyModel {
    parse_urdf(PENDULUM, "pendulum.urdf", UrdfOptions::default()).unwrap()
}

fn energy(model: &MultibodyModel, sim: &mut Simulator) -> f64 {
    let (q, v) = (sim.q.clone(), sim.v.clone());
    let ws = sim.workspace();
    kinetic_energy(model, ws, &q, &v).unwrap() + potential_energy(model, ws, &q).unwrap()
}

fn limited(model: &MultibodyModel, q: Vec<f64>, v: Vec<f64>) -> Simulator {
    let mut sim = Simulator::new(model, q, v).unwrap();
    sim.set_joint_limits(model, true);
    sim
}

/// The pendulum at rest at `q = 0`, pushed by 20 N·m (more than gravity's 4.7 N·m at the limit)
/// towards its upper limit 0.5 rad: after the approach, every step ends within 1e-4 rad of the
/// limit, for 10 s, and its velocity is below 1e-4 of the one step of free acceleration `a h`
/// (`a = (20 − 4.70) / 0.52` rad/s²) that a limit acting only on velocities would leave.
#[test]
fn a_torque_holds_the_pendulum_at_its_limit_with_every_integrator() {
    let model = pendulum();
    let mut control = Control::passive(&model);
    control.tau[0] = 20.0;
    for method in METHODS {
        let mut sim = limited(&model, vec![0.0], vec![0.0]);
        let (mut worst_q, mut worst_v, mut beyond) = (0.0_f64, 0.0_f64, 0.0_f64);
        for step in 0..10_000 {
            sim.step(&model, &control, method, 1e-3).unwrap();
            beyond = beyond.max(sim.q[0] - 0.5);
            if step >= 1_000 {
                worst_q = worst_q.max((sim.q[0] - 0.5).abs());
                worst_v = worst_v.max(sim.v[0].abs());
            }
        }
        eprintln!(
            "{method:?}: held at the limit: |q − 0.5| ≤ {worst_q:.2e} rad, |v| ≤ {worst_v:.2e} rad/s, past it by at most \
             {beyond:.2e} rad"
        );
        assert!(worst_q < 1e-4, "{method:?}: the joint left its limit by {worst_q:e} rad");
        assert!(beyond < 1e-4, "{method:?}: the joint passed its limit by {beyond:e} rad");
        let a_h = (20.0 - 2.0 * 9.81 * 0.5 * 0.5_f64.sin()) / 0.52 * 1e-3;
        assert!(worst_v < 1e-4 * a_h, "{method:?}: the held joint moves at {worst_v:e} rad/s (a h = {a_h:e})");
    }
}

/// The same in a swinging chain: `j1` pushed by 60 N·m against its upper limit 0.4 rad while the
/// chain swings about `j0` and `j3` flails (released from 1 rad, damped 0.5 N·m·s/rad): within 1e-4
/// rad of the limit at every step after the approach, never past it by 1e-4.
#[test]
fn a_torque_holds_a_joint_of_a_swinging_chain_at_its_limit() {
    let model = chain(false);
    let mut control = Control::passive(&model);
    control.tau[1] = 60.0;
    for k in [0, 2, 3] {
        control.damping[k] = 0.5;
    }
    for method in METHODS {
        let mut sim = limited(&model, vec![1.0, 0.0, 0.3, -0.5], vec![0.0; 4]);
        let (mut worst_q, mut beyond) = (0.0_f64, 0.0_f64);
        for step in 0..10_000 {
            sim.step(&model, &control, method, 1e-3).unwrap();
            beyond = beyond.max(sim.q[1] - 0.4);
            if step >= 1_000 {
                worst_q = worst_q.max((sim.q[1] - 0.4).abs());
            }
        }
        eprintln!(
            "{method:?}: chain joint j1 held: |q − 0.4| ≤ {worst_q:.2e} rad, past it by at most {beyond:.2e} rad; \
             final q = {:?}",
            sim.q
        );
        assert!(worst_q < 1e-4, "{method:?}: j1 left its limit by {worst_q:e} rad");
        assert!(beyond < 1e-4, "{method:?}: j1 passed its limit by {beyond:e} rad");
        // the rest of the chain moved: the limit held against real dynamics
        assert!((sim.q[0] - 1.0).abs() > 0.1);
    }
}

/// No gravity: the pendulum turns at 5 rad/s into its upper limit. It stops there in the step it
/// arrives (q exactly at the limit, v = 0) and stays: no rebound, no passing through, with every
/// integrator.
#[test]
fn a_joint_swung_into_its_limit_stops_there_without_rebound() {
    let mut model = pendulum();
    model.gravity = tumble::math::DVec3::ZERO;
    let control = Control::passive(&model);
    for method in METHODS {
        let mut sim = limited(&model, vec![0.0], vec![5.0]);
        let mut arrived = None;
        for step in 0..1_000 {
            sim.step(&model, &control, method, 1e-3).unwrap();
            assert!(sim.q[0] <= 0.5 + 1e-12, "{method:?}: passed the limit: q = {}", sim.q[0]);
            assert!(sim.v[0] >= 0.0, "{method:?}: rebound at step {step}: v = {}", sim.v[0]);
            if arrived.is_none() && sim.q[0] >= 0.5 - 1e-12 {
                arrived = Some(step);
            }
            if arrived.is_some_and(|a| step > a + 1) {
                assert_eq!(sim.v[0], 0.0, "{method:?}: still moving at step {step}");
                assert!((sim.q[0] - 0.5).abs() < 1e-12, "{method:?}: q = {}", sim.q[0]);
            }
        }
        // 0.5 rad at 5 rad/s: 100 steps of 1 ms
        let arrived = arrived.expect("never reached the limit");
        eprintln!("{method:?}: reached the limit at step {arrived}, then q = {}, v = {}", sim.q[0], sim.v[0]);
        assert!((99..=101).contains(&arrived), "{method:?}: arrived at step {arrived}");
    }
}

/// With gravity, RK4: the pendulum hangs at rest and is kicked to 8 rad/s; it strikes its upper
/// limit, stops (the impact takes its kinetic energy), falls back, swings to the lower limit,
/// strikes it and so on. The energy never rises from one step to the next by more than RK4's own
/// error (1e-9 of the initial energy), and falls at each strike.
#[test]
fn energy_never_rises_through_strikes_on_the_limits() {
    let model = pendulum();
    let control = Control::passive(&model);
    let mut sim = limited(&model, vec![0.0], vec![8.0]);
    let e0 = energy(&model, &mut sim);
    let scale = e0 - potential_energy(&model, sim.workspace(), &[0.0]).unwrap();
    let mut previous = e0;
    let mut worst_rise = 0.0_f64;
    for _ in 0..5_000 {
        sim.step(&model, &control, Method::Rk4, 1e-3).unwrap();
        let e = energy(&model, &mut sim);
        worst_rise = worst_rise.max(e - previous);
        previous = e;
        assert!(sim.q[0].abs() <= 0.5 + 1e-12, "passed a limit: q = {}", sim.q[0]);
    }
    let lost = e0 - previous;
    eprintln!("strikes: energy lost {lost:.4} J of {scale:.4} J above rest; largest rise in a step {worst_rise:.2e} J");
    assert!(worst_rise <= 1e-9 * scale, "the energy rose by {worst_rise:e} J in a step");
    // the first strike alone takes ½ I ω² minus the potential climbed: most of the swing
    assert!(lost > 0.5 * scale, "lost only {lost} J of {scale} J");
}

/// The chain with `j1` and `j2` both limited and both pushed into their upper limits (60 and 30
/// N·m): the two rows couple (`(M⁻¹)_12 ≠ 0`) and both joints are held within 1e-4 rad.
#[test]
fn two_joints_at_their_limits_at_once_are_both_held() {
    let model = chain(true);
    let mut control = Control::passive(&model);
    control.tau[1] = 60.0;
    control.tau[2] = 30.0;
    for k in [0, 3] {
        control.damping[k] = 0.5;
    }
    for method in METHODS {
        let mut sim = limited(&model, vec![0.8, 0.0, 0.0, -0.5], vec![0.0; 4]);
        let (mut worst, mut beyond) = ([0.0_f64; 2], [0.0_f64; 2]);
        for step in 0..10_000 {
            sim.step(&model, &control, method, 1e-3).unwrap();
            for (k, limit) in [(1, 0.4), (2, 0.25)] {
                beyond[k - 1] = beyond[k - 1].max(sim.q[k] - limit);
                if step >= 1_000 {
                    worst[k - 1] = worst[k - 1].max((sim.q[k] - limit).abs());
                }
            }
        }
        let solver = sim.joint_limits().unwrap();
        eprintln!(
            "{method:?}: j1, j2 held within {worst:?} rad, past by at most {beyond:?}; steps at the limit {:?}",
            solver.active_steps()
        );
        for k in 0..2 {
            assert!(worst[k] < 1e-4, "{method:?}: joint {} left its limit by {:e}", k + 1, worst[k]);
            assert!(beyond[k] < 1e-4, "{method:?}: joint {} passed its limit by {:e}", k + 1, beyond[k]);
        }
        assert!(solver.active_steps().iter().all(|&n| n >= 9_000));
    }
}

/// Limits that never come near change nothing, bit for bit; limits off let the joint pass.
#[test]
fn limits_far_away_change_nothing_and_limits_off_let_the_joint_pass() {
    let model = chain(true);
    let control = Control::passive(&model);
    for method in METHODS {
        // a small swing about j0 only: j1 and j2 stay well inside their limits
        let mut on = limited(&model, vec![0.1, 0.0, 0.0, 0.0], vec![0.0; 4]);
        let mut off = Simulator::new(&model, vec![0.1, 0.0, 0.0, 0.0], vec![0.0; 4]).unwrap();
        for _ in 0..2_000 {
            on.step(&model, &control, method, 1e-3).unwrap();
            off.step(&model, &control, method, 1e-3).unwrap();
            assert_eq!((&on.q, &on.v), (&off.q, &off.v), "{method:?}");
        }
    }
    let model = pendulum();
    let mut control = Control::passive(&model);
    control.tau[0] = 20.0;
    let mut off = Simulator::new(&model, vec![0.0], vec![0.0]).unwrap();
    for _ in 0..1_000 {
        off.step(&model, &control, Method::Rk4, 1e-3).unwrap();
    }
    assert!(off.q[0] > 1.0, "without limits the joint turns past 0.5 rad: q = {}", off.q[0]);
}

/// No gravity: the pendulum starts at 0.7 rad, above its upper limit 0.5. Moving out at 1 rad/s it
/// is stopped where it is (not pulled back to 0.5: no kick, no energy gained); moving in at 1 rad/s
/// it comes back freely.
#[test]
fn a_joint_outside_its_limit_is_stopped_going_out_and_comes_back_freely() {
    let mut model = pendulum();
    model.gravity = tumble::math::DVec3::ZERO;
    let control = Control::passive(&model);
    for method in METHODS {
        let mut out = limited(&model, vec![0.7], vec![1.0]);
        for _ in 0..100 {
            out.step(&model, &control, method, 1e-3).unwrap();
            assert_eq!(out.v[0], 0.0, "{method:?}");
            assert_eq!(out.q[0], 0.7, "{method:?}: moved from where it started");
        }
        let mut back = limited(&model, vec![0.7], vec![-1.0]);
        for _ in 0..100 {
            back.step(&model, &control, method, 1e-3).unwrap();
        }
        assert_eq!(back.v[0], -1.0, "{method:?}");
        assert!((back.q[0] - 0.6).abs() < 1e-12, "{method:?}: q = {}", back.q[0]);
    }
}

/// No gravity, semi-implicit Euler (`v₁ = v₀ + h τ / I`, so one step measures the applied force):
/// a PD of gain 1e6 towards 1 rad applies exactly the URDF effort 5 N·m and reports the clamp; the
/// same PD without effort limits applies its full 1e6 N·m; damping (passive) is not clamped.
#[test]
fn effort_limits_clamp_commanded_forces_but_not_damping() {
    let mut model = pendulum();
    model.gravity = tumble::math::DVec3::ZERO;
    let inertia = 0.52;
    let h = 1e-3;
    let applied = |control: &Control, v0: f64| {
        let mut sim = Simulator::new(&model, vec![0.0], vec![v0]).unwrap();
        sim.step(&model, control, Method::SemiImplicitEuler, h).unwrap();
        (inertia * (sim.v[0] - v0) / h, sim.clamped()[0])
    };
    let mut pd = Control::passive(&model);
    pd.kp[0] = 1e6;
    pd.q_target[0] = 1.0;
    let (unclamped, flagged) = applied(&pd, 0.0);
    assert!((unclamped - 1e6).abs() < 1e-6 * 1e6, "without effort limits: {unclamped} N·m");
    assert!(!flagged);
    pd.set_effort_limits(&model);
    assert_eq!(pd.effort, vec![5.0]);
    let (clamped, flagged) = applied(&pd, 0.0);
    eprintln!("PD of gain 1e6: {unclamped:.6e} N·m unclamped, {clamped} N·m clamped");
    assert!((clamped - 5.0).abs() < 1e-9, "clamped: {clamped} N·m");
    assert!(flagged);
    // a constant torque beyond the limit, the other way
    let mut constant = Control::passive(&model);
    constant.tau[0] = -50.0;
    constant.set_effort_limits(&model);
    let (tau, flagged) = applied(&constant, 0.0);
    assert!((tau + 5.0).abs() < 1e-9 && flagged, "{tau}");
    // damping of 1000 N·m·s/rad at 1 rad/s: −1000 N·m, not clamped, and nothing reported
    let mut damped = Control::passive(&model);
    damped.damping[0] = 1000.0;
    damped.set_effort_limits(&model);
    let (tau, flagged) = applied(&damped, 1.0);
    assert!((tau + 1000.0).abs() < 1e-6 * 1000.0 + 1.0, "damping applied {tau} N·m");
    assert!(!flagged);
}

/// A revolute joint whose limits are equal, `lower = upper = 0.3` rad: a joint held at one angle.
/// Both rows are on the same coordinate, so `K = [[k, −k], [−k, k]]` is singular (projected
/// Gauss–Seidel, not pivoting, solves it). The pendulum starts there, at rest or swung at 2 rad/s,
/// under gravity (4.7 N·m·sin 0.3 pulls it down) and a torque of 5 N·m either way, with every
/// integrator, for 1000 steps: every state finite, the joint at 0.3 rad and at rest (both rows
/// active hold it exactly: to 1e-12, round-off).
#[test]
fn a_joint_with_equal_limits_is_held_without_nan() {
    let urdf = PENDULUM.replace(r#"lower="-0.5" upper="0.5""#, r#"lower="0.3" upper="0.3""#);
    let model = parse_urdf(&urdf, "pendulum.urdf", UrdfOptions::default()).unwrap();
    assert_eq!(model.bodies[0].joint.limits.position, Some((0.3, 0.3)));
    for method in METHODS {
        for (tau, v0) in [(5.0, 0.0), (-5.0, 0.0), (0.0, 2.0), (5.0, -2.0)] {
            let mut control = Control::passive(&model);
            control.tau[0] = tau;
            let mut sim = limited(&model, vec![0.3], vec![v0]);
            let (mut worst_q, mut worst_v) = (0.0_f64, 0.0_f64);
            for step in 0..1000 {
                sim.step(&model, &control, method, 1e-3).unwrap();
                assert!(
                    sim.q[0].is_finite() && sim.v[0].is_finite(),
                    "{method:?}, step {step}: {:?} {:?}",
                    sim.q,
                    sim.v
                );
                worst_q = worst_q.max((sim.q[0] - 0.3).abs());
                worst_v = worst_v.max(sim.v[0].abs());
            }
            eprintln!(
                "{method:?}, τ = {tau} N·m, v₀ = {v0} rad/s: |q − 0.3| ≤ {worst_q:.2e} rad, |v| ≤ {worst_v:.2e} rad/s"
            );
            assert!(worst_q <= 1e-12, "{method:?}, τ = {tau}, v₀ = {v0}: the joint left 0.3 rad by {worst_q:e}");
            assert!(worst_v <= 1e-12, "{method:?}, τ = {tau}, v₀ = {v0}: the held joint moves at {worst_v:e} rad/s");
        }
    }
}
