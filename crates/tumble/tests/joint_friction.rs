//! Dry joint friction (MJCF `frictionloss` `F`): a bounded impulse `|λ| ≤ F h` per step, target
//! velocity zero, solved with the joint limits at the end of the step (`multibody::limits`) or with
//! the contact rows when resting contact holds the tree (`contact::links`). Analytic checks:
//!
//! - a slide started at `v₀` decelerates at `a = F/m`: it stops after `T = m v₀/F` (to one step) and
//!   covers `d* = m v₀²/(2F)`, less `v₀ h/2` for semi-implicit Euler (`d ∈ [d* − v₀h/2,
//!   d* − v₀h/2 + a h²/8]`), `d ∈ [d*, d* + a h²/8]` for RK4 (the constant force is exact); then stays;
//! - a pendulum displaced where `m g l sin θ < F` stays exactly where it is (semi-implicit Euler);
//!   displaced further it swings and comes to rest at an angle with `m g l |sin θ| ≤ F`;
//! - the mechanical energy of a damped, frictional double pendulum (RK4) falls: it never rises over a
//!   step by more than 1e-7 J (4e-8 J measured, once in 10 s: at a turning point of one joint while
//!   the other sticks, through the coupling of the rows; a single row never adds energy), where the
//!   end-velocity rule alone rose by 1e-6 J;
//! - friction acts with the joint limits off; a joint pushed against its limit with friction stays
//!   at the limit;
//! - a leg standing on the floor holds its knee by friction (no sag) and folds without it;
//! - the MJCF reader reads `frictionloss` (also in `mjcf_reader.rs`).

use tumble::multibody::mjcf::{parse_mjcf, MjcfOptions};
use tumble::multibody::{kinetic_energy, potential_energy, Method, MultibodyModel, Simulator};
use tumble::scene;

const METHODS: [Method; 3] = [Method::Rk4, Method::SemiImplicitEuler, Method::Euler];
const G: f64 = 9.81;

fn mjcf(text: &str) -> MultibodyModel {
    parse_mjcf(text, "test.xml", MjcfOptions::default()).unwrap_or_else(|e| panic!("{e}")).model
}

/// A 2 kg cart on a slide along x (gravity along −z, across the slide) with friction loss `f` (N).
fn slide(f: f64) -> MultibodyModel {
    mjcf(&format!(
        r#"<mujoco><worldbody><body name="cart"><joint name="x" type="slide" axis="1 0 0" frictionloss="{f}"/>
           <inertial pos="0 0 0" mass="2" diaginertia="0.01 0.01 0.01"/></body></worldbody></mujoco>"#
    ))
}

/// A pendulum about y: 1 kg at 0.5 m below the pivot (`m g l = 4.905` N·m), friction loss `f`
/// (N·m), limited to `range` (rad) if given.
fn pendulum(f: f64, range: Option<(f64, f64)>) -> MultibodyModel {
    let range = range.map(|(lo, hi)| format!(r#"limited="true" range="{lo} {hi}""#)).unwrap_or_default();
    mjcf(&format!(
        r#"<mujoco><compiler angle="radian"/><worldbody><body name="bob">
           <joint name="pivot" type="hinge" axis="0 1 0" frictionloss="{f}" {range}/>
           <inertial pos="0 0 -0.5" mass="1" diaginertia="1e-3 1e-3 1e-3"/></body></worldbody></mujoco>"#
    ))
}

fn energy(model: &MultibodyModel, sim: &mut Simulator) -> f64 {
    let (q, v) = (sim.q.clone(), sim.v.clone());
    let ws = sim.workspace();
    kinetic_energy(model, ws, &q, &v).unwrap() + potential_energy(model, ws, &q).unwrap()
}

/// Runs the slide from `v₀` until it stops: (stop time (s), distance (m)); asserts it then stays.
fn slide_run(model: &MultibodyModel, method: Method, h: f64, v0: f64) -> (f64, f64) {
    let control = tumble::multibody::Control::passive(model);
    let mut sim = Simulator::new(model, vec![0.0], vec![v0]).unwrap();
    let mut stop = None;
    for step in 1..=5000 {
        sim.step(model, &control, method, h).unwrap();
        assert!(sim.v[0] >= -1e-12, "{method:?}: friction reversed the motion, v = {}", sim.v[0]);
        if sim.v[0].abs() < 1e-9 {
            stop = Some((step as f64 * h, sim.q[0]));
            break;
        }
    }
    let (t, d) = stop.unwrap_or_else(|| panic!("{method:?}: never stopped"));
    for _ in 0..1000 {
        sim.step(model, &control, method, h).unwrap();
    }
    assert!((sim.q[0] - d).abs() < 1e-12 && sim.v[0].abs() < 1e-12, "{method:?}: moved after stopping");
    (t, d)
}

#[test]
fn a_slide_stops_after_m_v0_over_f_having_covered_m_v0_squared_over_2f() {
    let (m, f, v0, h) = (2.0, 2.9, 1.5, 1e-3);
    let model = slide(f);
    let (t_stop, d_star, a) = (m * v0 / f, m * v0 * v0 / (2.0 * f), f / m);
    for method in METHODS {
        let (t, d) = slide_run(&model, method, h, v0);
        // the window of the distance the discretisation gives (module doc), with round-off
        let (lo, hi) = match method {
            Method::SemiImplicitEuler => (d_star - v0 * h / 2.0, d_star - v0 * h / 2.0 + a * h * h / 8.0),
            Method::Rk4 => (d_star, d_star + a * h * h / 8.0),
            // explicit Euler moves with the old velocity: d* + v₀h/2 less up to a h²/8 … + a h
            Method::Euler => (d_star + v0 * h / 2.0 - a * h * h, d_star + v0 * h / 2.0 + a * h * h),
        };
        eprintln!(
            "{method:?}: stopped at {t:.4} s (m v0/F = {t_stop:.4} s), d = {d:.9} m (d* = {d_star:.9}), window \
             [{:.3e}, {:.3e}] about d*",
            lo - d_star,
            hi - d_star
        );
        assert!((t - t_stop).abs() <= h + 1e-12, "{method:?}: stopped at {t} s, expected {t_stop} s");
        assert!(d >= lo - 1e-12 && d <= hi + 1e-12, "{method:?}: d = {d} not in [{lo}, {hi}]");
    }
}

#[test]
fn friction_acts_with_the_joint_limits_off_and_on_alike() {
    let model = slide(2.9);
    let control = tumble::multibody::Control::passive(&model);
    let mut off = Simulator::new(&model, vec![0.0], vec![1.5]).unwrap();
    off.set_joint_limits(&model, false);
    assert!(off.joint_limits().is_some_and(|s| !s.has_limits()), "the friction rows exist with limits off");
    let mut on = Simulator::new(&model, vec![0.0], vec![1.5]).unwrap();
    on.set_joint_limits(&model, true);
    for _ in 0..2000 {
        off.step(&model, &control, Method::SemiImplicitEuler, 1e-3).unwrap();
        on.step(&model, &control, Method::SemiImplicitEuler, 1e-3).unwrap();
    }
    assert!(off.v[0].abs() < 1e-9, "friction did not stop the slide with limits off: v = {}", off.v[0]);
    assert_eq!((off.q.clone(), off.v.clone()), (on.q, on.v));
    // without friction the slide keeps going
    let free = slide(0.0);
    let mut sim = Simulator::new(&free, vec![0.0], vec![1.5]).unwrap();
    assert!(sim.joint_limits().is_none());
    for _ in 0..2000 {
        sim.step(&free, &control, Method::SemiImplicitEuler, 1e-3).unwrap();
    }
    assert_eq!(sim.v[0], 1.5);
}

#[test]
fn a_pendulum_within_its_friction_sticks_exactly() {
    // m g l sin θ = 4.905 sin 0.15 = 0.733 N·m < F = 1 N·m
    let model = pendulum(1.0, None);
    let control = tumble::multibody::Control::passive(&model);
    for method in METHODS {
        let mut sim = Simulator::new(&model, vec![0.15], vec![0.0]).unwrap();
        let mut worst = 0.0_f64;
        for _ in 0..5000 {
            sim.step(&model, &control, method, 1e-3).unwrap();
            worst = worst.max((sim.q[0] - 0.15).abs()).max(sim.v[0].abs());
        }
        eprintln!("{method:?}: held at 0.15 rad within {worst:.2e} (rad, rad/s) over 5 s");
        // exact but for round-off with the Euler methods; RK4's acceleration is not constant over
        // the step (O(h⁴) per step)
        let tolerance = if method == Method::Rk4 { 1e-6 } else { 1e-12 };
        assert!(worst <= tolerance, "{method:?}: moved by {worst}");
    }
}

#[test]
fn a_pendulum_beyond_its_friction_swings_and_rests_where_gravity_is_within_it() {
    let (f, mgl) = (1.0, 0.5 * G);
    let model = pendulum(f, None);
    let control = tumble::multibody::Control::passive(&model);
    for method in [Method::Rk4, Method::SemiImplicitEuler] {
        let mut sim = Simulator::new(&model, vec![1.0], vec![0.0]).unwrap();
        let mut moved = 0.0_f64;
        for _ in 0..20_000 {
            sim.step(&model, &control, method, 1e-3).unwrap();
            moved = moved.max((sim.q[0] - 1.0).abs());
        }
        let rest = sim.q[0];
        for _ in 0..1000 {
            sim.step(&model, &control, method, 1e-3).unwrap();
        }
        let torque = mgl * rest.sin().abs();
        eprintln!("{method:?}: swung {moved:.3} rad, rests at {rest:.6} rad: m g l |sin θ| = {torque:.6} ≤ F = {f}");
        assert!(moved > 0.5, "{method:?}: it did not swing");
        assert!(sim.v[0].abs() < 1e-9 && (sim.q[0] - rest).abs() < 1e-6, "{method:?}: not at rest");
        assert!(torque <= f * (1.0 + 1e-9), "{method:?}: rests where gravity {torque} exceeds F");
    }
}

/// A double pendulum (two 1 kg, 0.5 m links about y) with damping and friction loss.
fn double_pendulum(f: f64) -> MultibodyModel {
    mjcf(&format!(
        r#"<mujoco><compiler angle="radian"/><default><joint type="hinge" axis="0 1 0" damping="0.02" frictionloss="{f}"/></default>
           <worldbody><body name="upper"><joint name="shoulder"/>
           <inertial pos="0 0 -0.25" mass="1" diaginertia="0.021 0.021 0.001"/>
           <body name="lower" pos="0 0 -0.5"><joint name="elbow"/>
           <inertial pos="0 0 -0.25" mass="1" diaginertia="0.021 0.021 0.001"/></body></body></worldbody></mujoco>"#
    ))
}

#[test]
fn the_energy_of_a_frictional_double_pendulum_never_rises() {
    let model = double_pendulum(0.3);
    let control = tumble::multibody::Control::passive(&model);
    let mut sim = Simulator::new(&model, vec![1.6, -0.8], vec![0.0, 3.0]).unwrap();
    let e0 = energy(&model, &mut sim);
    let mut e = e0;
    let mut worst = f64::NEG_INFINITY;
    for _ in 0..10_000 {
        sim.step(&model, &control, Method::Rk4, 1e-3).unwrap();
        let next = energy(&model, &mut sim);
        worst = worst.max(next - e);
        e = next;
    }
    eprintln!("E: {e0:.6} J → {e:.6} J in 10 s; largest rise over a step {worst:.2e} J");
    // RK4 moves a joint by h ū over a step: a force opposing the end velocity works along ū where
    // the joint turns back within the step; the rows bound that per row (module `limits`), what
    // the coupling of two rows leaves is below this
    assert!(worst <= 1e-7, "the energy rose by {worst} J in a step");
    assert!(e < e0 - 1.0, "friction and damping took too little: {e0} → {e}");
}

#[test]
fn a_joint_pushed_against_its_limit_with_friction_stays_at_the_limit() {
    // gravity and a 10 N·m push take the pendulum to its upper limit 0.5 rad; friction 0.5 N·m
    let model = pendulum(0.5, Some((-0.5, 0.5)));
    let mut control = tumble::multibody::Control::passive(&model);
    control.tau[0] = 10.0;
    for method in METHODS {
        let mut sim = Simulator::new(&model, vec![0.0], vec![0.0]).unwrap();
        sim.set_joint_limits(&model, true);
        let mut worst = 0.0_f64;
        for step in 0..3000 {
            sim.step(&model, &control, method, 1e-3).unwrap();
            assert!(sim.q[0] <= 0.5 + 1e-4, "{method:?}: passed its limit: {}", sim.q[0]);
            if step >= 1000 {
                worst = worst.max((sim.q[0] - 0.5).abs());
            }
        }
        eprintln!("{method:?}: held within {worst:.2e} rad of the limit, v = {:.2e}", sim.v[0]);
        assert!(worst < 1e-4 && sim.v[0].abs() < 1e-6, "{method:?}: not held at the limit: {worst}");
    }
}

/// The leg of `scenes/leg_friction.xml` (a 4 kg torso on a vertical slide, a hip and a knee about
/// y, the foot right below the hip on the floor, the knee bent by ≈ 4 N·m) with friction loss `f`
/// (N·m) on its hip and knee.
fn leg(f: f64) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/leg_friction.xml");
    let text = std::fs::read_to_string(path).unwrap();
    let default = r#"<joint type="hinge" axis="0 1 0" frictionloss="10"/>"#;
    assert!(text.contains(default));
    text.replace(default, &format!(r#"<joint type="hinge" axis="0 1 0" frictionloss="{f}"/>"#))
}

/// The leg with friction loss `f` set on the floor: the torso's drop (m) in the first 0.5 s
/// (landing, the foot's overlap taken up) and then in `seconds`, and whether resting contact held
/// it in the last step.
fn leg_sag(f: f64, seconds: f64) -> (f64, f64, bool) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("leg.xml");
    std::fs::write(&path, leg(f)).unwrap();
    let mut scene = scene::load_mjcf_world(&path).unwrap_or_else(|e| panic!("{e}"));
    let world = &mut scene.world;
    assert_eq!(world.robots.len(), 1);
    let z0 = world.robots[0].q()[0];
    let settle = (0.5 / world.config.dt).round() as usize;
    for _ in 0..settle {
        world.step().unwrap();
    }
    // from where it settled (the foot's overlap taken up)
    let z1 = world.robots[0].q()[0];
    for _ in 0..((seconds / world.config.dt).round() as usize) {
        world.step().unwrap();
    }
    let held = world.contacts().links.active().count() > 0;
    let z = world.robots[0].q()[0];
    eprintln!("F = {f} N·m: the torso dropped {:.3e} m in 0.5 s, then {:.3e} m in {seconds} s", z0 - z1, z1 - z);
    (z0 - z1, z1 - z, held)
}

#[test]
fn a_leg_on_the_floor_holds_its_joints_by_friction_and_folds_without() {
    // F = 10 N·m holds the knee's ≈ 4 N·m: only the foot's overlap (< 1 mm), then nothing
    let (landing, sag, held) = leg_sag(10.0, 1.0);
    assert!(held, "the foot left the floor");
    assert!(landing < 1e-3, "the leg gave {landing} m on landing with friction holding its joints");
    assert!(sag.abs() < 1e-6, "the leg sagged {sag} m with friction holding its joints");
    // F = 0: the knee folds
    let (landing, _, _) = leg_sag(0.0, 1.0);
    assert!(landing > 0.05, "the leg without friction did not fold: {landing} m");
}

#[test]
fn anymal_c_loads_with_its_frictionloss() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/mjcf/menagerie/anymal_c.xml");
    let model =
        tumble::multibody::mjcf::load_mjcf(&path, MjcfOptions::default()).unwrap_or_else(|e| panic!("{e}")).model;
    let with: Vec<f64> = model.bodies.iter().map(|b| b.joint.dynamics.friction_loss).filter(|&f| f > 0.0).collect();
    assert_eq!(with, vec![0.1; 12], "the twelve leg joints have frictionloss 0.1");
    let dropped = tumble::multibody::mjcf::load_mjcf(&path, MjcfOptions { drop_frictionloss: true }).unwrap().model;
    assert!(dropped.bodies.iter().all(|b| b.joint.dynamics.friction_loss == 0.0));
}
