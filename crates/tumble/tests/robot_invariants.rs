//! The energy and momentum of robots computed from their trajectory rows (`robot/link`: the link
//! frame's origin, orientation and velocities) with the links' own inertias, against the
//! simulator's own (`Robot::energy`, computed from `q` and `v` over the tree's bodies), at every
//! sample written: what `tumble plot --scene` and `tumble view` show is the run's energy.
//!
//! - the passive double pendulum (RK4): the energy error read back is the run's, not round-off;
//! - the Panda under PD control (fixed base with mass, links merged by fixed joints, massless
//!   frames);
//! - a floating-base double pendulum beside a free body (energy and momenta);
//! - the links carry the tree's mass once: their inertias sum to each body's and to the total.

use std::path::{Path, PathBuf};
use tumble::math::DVec3;
use tumble::multibody::RigidInertia;
use tumble::scene;
use tumble::trajectory::derived::{self, InvariantErrors};
use tumble::trajectory::{self, Invariants, ReadOptions, TrajectoryWriter};
use tumble::World;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Steps `world` `steps` times, writing a CSV sample every `every` steps; returns the trajectory
/// read back, the world as it started, and the simulator's invariants at each sample.
fn run(mut world: World, steps: usize, every: usize) -> (trajectory::Trajectory, World, Vec<Invariants>) {
    let start = world.clone();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.csv");
    let file = std::fs::File::create(&path).unwrap();
    let mut writer = TrajectoryWriter::new(file, trajectory::Format::Csv, &world).unwrap();
    let mut expected = Vec::new();
    for step in 0..=steps {
        if step > 0 {
            world.step().unwrap();
        }
        if step % every == 0 {
            writer.write_sample(&world).unwrap();
            expected.push(Invariants::of(&world));
        }
    }
    writer.finish().unwrap();
    let read = trajectory::read(&path, ReadOptions::default()).unwrap();
    (read, start, expected)
}

/// The largest differences between the invariants read back and the simulator's: energy relative
/// to `|E₀|`, momenta relative to their largest magnitude (or absolute when that is zero); and the
/// largest energy error `|E − E₀|/|E₀|` of the run.
fn compare(got: &[Invariants], expected: &[Invariants]) -> (f64, f64, f64, f64) {
    assert_eq!(got.len(), expected.len());
    let e0 = expected[0].energy.abs();
    let p_scale = expected.iter().map(|i| i.linear_momentum.length()).fold(0.0, f64::max).max(1e-300);
    let l_scale = expected.iter().map(|i| i.angular_momentum.length()).fold(0.0, f64::max).max(1e-300);
    let (mut energy, mut linear, mut angular) = (0.0_f64, 0.0_f64, 0.0_f64);
    for (g, e) in got.iter().zip(expected) {
        energy = energy.max((g.energy - e.energy).abs() / e0);
        linear = linear.max((g.linear_momentum - e.linear_momentum).length() / p_scale);
        angular = angular.max((g.angular_momentum - e.angular_momentum).length() / l_scale);
    }
    let run_error = expected.iter().map(|i| (i.energy - expected[0].energy).abs() / e0).fold(0.0, f64::max);
    (energy, linear, angular, run_error)
}

#[test]
fn the_double_pendulum_energy_read_back_is_the_runs() {
    let scene = scene::load(&repo().join("scenes/double_pendulum.toml")).unwrap();
    // 3 s of the scene (RK4, dt = 1 ms), every 10th step as the scene writes it
    let (trajectory, world, expected) = run(scene.world, 3000, 10);
    assert_eq!(trajectory.bodies, ["pendulum/upper", "pendulum/lower", "pendulum/tip"]);
    let got = derived::invariants(&trajectory, &world, "out.csv", "double_pendulum.toml").unwrap();
    let (energy, _, _, run_error) = compare(&got, &expected);
    let read_back = InvariantErrors::of(&got).energy.iter().fold(0.0_f64, |m, e| m.max(e.abs()));
    eprintln!(
        "double pendulum: E₀ = {} J; energy read back vs the simulator's: {energy:e} of E₀; \
         largest energy error: run {run_error:e}, read back {read_back:e}",
        expected[0].energy
    );
    assert!(energy < 1e-14, "{energy:e}");
    // RK4 keeps the energy to about 1e-12 here: the error read back is that, not a spurious one
    assert!(run_error > 1e-14 && run_error < 1e-10, "{run_error:e}");
    assert!((read_back - run_error).abs() < 0.01 * run_error, "{read_back:e} vs {run_error:e}");
}

#[test]
fn the_panda_energy_read_back_is_the_runs() {
    let scene = scene::load(&repo().join("scenes/panda.toml")).unwrap();
    let (trajectory, world, expected) = run(scene.world, 1000, 10);
    // rows for the links that move, merged ones (the hand, massless frames) included
    assert!(trajectory.bodies.iter().any(|b| b == "panda/panda_hand"));
    assert!(!trajectory.bodies.iter().any(|b| b == "panda/panda_link0"), "the fixed base has no row");
    let got = derived::invariants(&trajectory, &world, "out.csv", "panda.toml").unwrap();
    let (energy, _, _, run_error) = compare(&got, &expected);
    eprintln!("panda: E₀ = {} J; read back vs the simulator's: {energy:e} of E₀", expected[0].energy);
    assert!(energy < 1e-13, "{energy:e}");
    // PD control and damping do work: the energy changes, and the change is read back
    assert!(run_error > 1e-3, "{run_error:e}");
    // a fixed base: the robot's momentum is not counted, as in the summary
    assert!(got.iter().all(|i| i.angular_momentum == DVec3::ZERO && i.linear_momentum == DVec3::ZERO));
}

#[test]
fn a_floating_robot_beside_a_body_reads_back_energy_and_momenta() {
    // the double pendulum on a base with mass (a massless floating base could turn about the
    // shoulder axis at no cost: its articulated inertia would be singular)
    let text = std::fs::read_to_string(repo().join("scenes/robots/double_pendulum.urdf")).unwrap();
    let base =
        r#"<link name="base"><inertial><mass value="3"/><inertia ixx="0.1" iyy="0.2" izz="0.25"/></inertial></link>"#;
    let dir = tempfile::tempdir().unwrap();
    let urdf = dir.path().join("flyer.urdf");
    std::fs::write(&urdf, text.replace(r#"<link name="base"/>"#, base)).unwrap();
    let text = format!(
        r#"version = 1
[world]
dt = 1e-3
integrator = "rk4"
[[body]]
name = "brick"
mass = 2.0
inertia = [0.1, 0.2, 0.25]
position = [3.0, 0.0, 1.0]
velocity = [0.5, 0.0, 2.0]
angular_velocity = [0.3, 1.0, -0.2]
[[robot]]
name = "flyer"
urdf = {urdf:?}
base = "floating"
position = [0.0, 1.0, 2.0]
orientation = [0.5, 0.5, 0.5, 0.5]
q = {{ shoulder = 0.7, elbow = -1.2 }}
v = {{ root_joint = [0.4, -0.3, 1.5, 0.8, -0.6, 1.1], shoulder = 2.0, elbow = -3.0 }}
"#
    );
    let path = dir.path().join("flyer.toml");
    std::fs::write(&path, text).unwrap();
    let scene = scene::load(&path).unwrap();
    assert!(scene.world.robots[0].floating);
    let (trajectory, world, expected) = run(scene.world, 2000, 20);
    let got = derived::invariants(&trajectory, &world, "out.csv", "flyer.toml").unwrap();
    let (energy, linear, angular, _) = compare(&got, &expected);
    eprintln!("floating robot and a body: read back vs the simulator's: E {energy:e}, p {linear:e}, L {angular:e}");
    assert!(energy < 1e-13 && linear < 1e-13 && angular < 1e-13, "{energy:e} {linear:e} {angular:e}");
    // the floating robot's momentum is counted: it is not the brick's alone
    let brick = 2.0 * DVec3::new(0.5, 0.0, 2.0);
    assert!((got[0].linear_momentum - brick).length() > 0.1);
}

#[test]
fn the_links_carry_the_trees_mass_once() {
    for file in ["scenes/panda.toml", "scenes/double_pendulum.toml"] {
        let scene = scene::load(&repo().join(file)).unwrap();
        let model = &scene.world.robots[0].model;
        for (i, body) in model.bodies.iter().enumerate() {
            // Σ over the links fixed to body i of body_X_linkᵀ-transformed inertias = the body's
            let mut sum = RigidInertia::ZERO;
            for frame in model.frames.iter().filter(|f| f.body == Some(i)) {
                sum += frame.inertia.transform_to_a(&frame.x_from_body);
            }
            let scale = body.inertia.mass.max(1e-9);
            assert!((sum.mass - body.inertia.mass).abs() <= 1e-12 * scale, "{file} body {}", body.name);
            assert!((sum.h - body.inertia.h).length() <= 1e-12 * scale, "{file} body {}", body.name);
            let d = (sum.i_o - body.inertia.i_o).to_cols_array().iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            assert!(d <= 1e-12 * scale, "{file} body {}: {d:e}", body.name);
        }
        let links: f64 = model.frames.iter().map(|f| f.inertia.mass).sum();
        assert!((links - model.total_mass).abs() < 1e-12 * model.total_mass, "{file}: {links} vs {}", model.total_mass);
    }
}
