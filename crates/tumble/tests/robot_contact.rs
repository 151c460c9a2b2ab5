//! Robots in contact (issue "Robots in contact", tests 2, 3, 4, 6, 7 and the impact property):
//!
//! - an elastic, frictionless pendulum (and double pendulum) striking the floor again and again keeps
//!   its energy under RK4; with restitution below one or friction its energy never rises;
//! - a floating robot in zero gravity struck by a free ball: total momentum kept;
//! - a quadruped standing under PD: the normal forces carry its weight, the feet neither sink nor
//!   slide, the base does not drift;
//! - a 20-link chain dropped onto the floor comes to rest without sinking or gaining energy;
//! - a robot pushing a box: the box slides as Coulomb friction predicts;
//! - no impact on a random tree ever increases its kinetic energy;
//! - the energy the link contacts take closes the chain drop's energy balance.

mod multibody_common;

use multibody_common::{random_q, random_tree, Base, Rng};
use std::path::{Path, PathBuf};
use tumble::collision::links::Side;
use tumble::contact::{collide, RestitutionLaw};
use tumble::math::DVec3;
use tumble::multibody::contact_point::{collision_matrix, impulse_response, point_jacobian};
use tumble::multibody::{crba, ltdl_factor, Workspace};
use tumble::scene::{self, Scene};
use tumble::World;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A pendulum of 1 kg whose 0.1 m ball (centre 1 m below the pivot) is its collision shape.
const BALL_PENDULUM: &str = r#"<robot name="ball_pendulum">
  <link name="base"/>
  <link name="arm"><inertial><origin xyz="0 0 -1"/><mass value="1"/>
    <inertia ixx="0.004" iyy="0.004" izz="0.004"/></inertial>
    <collision><origin xyz="0 0 -1"/><geometry><sphere radius="0.1"/></geometry></collision></link>
  <joint name="hinge" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="1 0 0"/></joint>
</robot>"#;

/// A double pendulum of two 0.5 m, 1 kg links whose tip carries a 0.05 m ball.
const BALL_DOUBLE_PENDULUM: &str = r#"<robot name="ball_double_pendulum">
  <link name="base"/>
  <link name="upper"><inertial><origin xyz="0 0 -0.25"/><mass value="1"/>
    <inertia ixx="0.02" iyy="0.02" izz="0.001"/></inertial></link>
  <link name="lower"><inertial><origin xyz="0 0 -0.25"/><mass value="1"/>
    <inertia ixx="0.02" iyy="0.02" izz="0.001"/></inertial>
    <collision><origin xyz="0 0 -0.5"/><geometry><sphere radius="0.05"/></geometry></collision></link>
  <joint name="shoulder" type="continuous"><parent link="base"/><child link="upper"/><axis xyz="1 0 0"/></joint>
  <joint name="elbow" type="continuous"><parent link="upper"/><child link="lower"/><origin xyz="0 0 -0.5"/>
    <axis xyz="1 0 0"/></joint>
</robot>"#;

/// A floating three-link arm (0.3 m links of 0.5 kg, box collision shapes) for the momentum test.
const FLOATING_ARM: &str = r#"<robot name="floating_arm">
  <link name="l0"><inertial><origin xyz="0.15 0 0"/><mass value="0.5"/>
    <inertia ixx="0.0005" iyy="0.004" izz="0.004"/></inertial>
    <collision><origin xyz="0.15 0 0"/><geometry><box size="0.3 0.06 0.06"/></geometry></collision></link>
  <link name="l1"><inertial><origin xyz="0.15 0 0"/><mass value="0.5"/>
    <inertia ixx="0.0005" iyy="0.004" izz="0.004"/></inertial>
    <collision><origin xyz="0.15 0 0"/><geometry><box size="0.3 0.06 0.06"/></geometry></collision></link>
  <link name="l2"><inertial><origin xyz="0.15 0 0"/><mass value="0.5"/>
    <inertia ixx="0.0005" iyy="0.004" izz="0.004"/></inertial>
    <collision><origin xyz="0.15 0 0"/><geometry><box size="0.3 0.06 0.06"/></geometry></collision></link>
  <joint name="j1" type="continuous"><parent link="l0"/><child link="l1"/><origin xyz="0.3 0 0"/><axis xyz="0 0 1"/></joint>
  <joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0"/><axis xyz="0 1 0"/></joint>
</robot>"#;

/// A pusher: a 0.5 kg paddle (a 0.1 × 0.3 × 0.2 m box) on a prismatic joint along x, its base fixed.
const PUSHER: &str = r#"<robot name="pusher">
  <link name="rail"/>
  <link name="paddle"><inertial><mass value="0.5"/><inertia ixx="0.005" iyy="0.002" izz="0.004"/></inertial>
    <collision><geometry><box size="0.1 0.3 0.2"/></geometry></collision></link>
  <joint name="slide" type="prismatic"><parent link="rail"/><child link="paddle"/><axis xyz="1 0 0"/>
    <limit lower="-10" upper="10" effort="1000" velocity="100"/></joint>
</robot>"#;

/// Loads a scene text written next to the URDF files `urdfs` (name, text) in a fresh directory.
fn scene_with(urdfs: &[(&str, &str)], text: &str) -> (tempfile::TempDir, Scene) {
    let dir = tempfile::tempdir().unwrap();
    for (name, urdf) in urdfs {
        std::fs::write(dir.path().join(name), urdf).unwrap();
    }
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let scene = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    (dir, scene)
}

/// The deepest overlap of the link contacts of the last step (m; 0 when none overlap).
fn link_depth(world: &World) -> f64 {
    world.contacts().links.active().map(|(c, _)| -c.gap).fold(0.0, f64::max)
}

/// The two pendulums: URDF, initial `q`, height of the pivot (m).
const PENDULUMS: [(&str, &str, f64); 2] =
    [(BALL_PENDULUM, "{ hinge = 1.2 }", 1.05), (BALL_DOUBLE_PENDULUM, "{ shoulder = 1.3, elbow = -0.4 }", 1.0)];

fn pendulum_scene(
    (urdf, q, height): (&str, &str, f64),
    restitution: f64,
    friction: f64,
    duration: f64,
) -> (tempfile::TempDir, Scene) {
    let text = format!(
        "version = 1\n[world]\ndt = 0.001\nduration = {duration}\nintegrator = \"rk4\"\nrestitution = {restitution}\n\
         friction = {friction}\n[[body]]\nname = \"ground\"\nshape = {{ type = \"plane\" }}\nfixed = true\n\
         [[robot]]\nname = \"p\"\nurdf = \"p.urdf\"\nposition = [0.0, 0.0, {height}]\nq = {q}\n"
    );
    scene_with(&[("p.urdf", urdf)], &text)
}

/// Steps the world to its duration: the energy at every step and the deepest link overlap (m).
fn run_energies_and_depth(world: &mut World) -> (Vec<f64>, f64) {
    let mut energies = vec![world.energy()];
    let mut depth = 0.0_f64;
    for _ in 0..world.config.step_count() {
        world.step().unwrap();
        energies.push(world.energy());
        depth = depth.max(link_depth(world));
    }
    (energies, depth)
}

/// Steps the world to its duration; per step the energy, and the collisions counted.
fn run_energies(world: &mut World) -> Vec<f64> {
    let mut energies = vec![world.energy()];
    for _ in 0..world.config.step_count() {
        world.step().unwrap();
        energies.push(world.energy());
    }
    energies
}

#[test]
fn an_elastic_frictionless_pendulum_keeps_its_energy_strike_after_strike() {
    for pendulum in PENDULUMS {
        let (_dir, mut scene) = pendulum_scene(pendulum, 1.0, 0.0, 10.0);
        let world = &mut scene.world;
        let energies = run_energies(world);
        let e0 = energies[0];
        let worst = energies.iter().map(|e| ((e - e0) / e0).abs()).fold(0.0, f64::max);
        let strikes = world.contacts().links.impacts;
        println!("elastic strikes: {strikes}, worst relative energy error {worst:e}");
        assert!(strikes >= 4, "the pendulum struck the floor only {strikes} times in 10 s");
        assert!(worst <= 1e-8, "energy drifted by {worst:e} of E₀ over {strikes} elastic strikes");
    }
}

#[test]
fn strikes_with_restitution_below_one_or_friction_never_gain_energy() {
    for (e, mu) in [(0.5, 0.0), (1.0, 0.5), (0.3, 0.8)] {
        for pendulum in PENDULUMS {
            let (_dir, mut scene) = pendulum_scene(pendulum, e, mu, 6.0);
            let world = &mut scene.world;
            let (energies, depth) = run_energies_and_depth(world);
            let e0 = energies[0];
            // between samples (every 10 steps)
            let samples: Vec<f64> = energies.iter().step_by(10).copied().collect();
            let rise = samples.windows(2).map(|w| w[1] - w[0]).fold(f64::NEG_INFINITY, f64::max);
            let lost = e0 - energies.last().unwrap();
            // the resting contact's overlap correction could lift the robot by at most the deepest
            // overlap it had, m |g| d_max (printed for scale)
            let mass: f64 = world.robots[0].model.bodies.iter().map(|b| b.inertia.mass).sum();
            let correction = mass * world.config.gravity.length() * depth;
            println!(
                "e = {e}, μ = {mu}: largest rise between samples {rise:e} J ({:.1e} of E₀), lost {lost:.4} J, \
                 deepest overlap {depth:e} m (m g d = {correction:e} J)",
                rise / e0
            );
            assert!(world.contacts().links.impacts >= 1, "no strike");
            assert!(lost > 0.01 * e0, "e = {e}, μ = {mu}: only {lost} J of {e0} J lost");
            // never a rise beyond the integrator's noise (RK4 keeps a free pendulum to ~1e-14 a step)
            assert!(rise <= 1e-9 * e0, "e = {e}, μ = {mu}: the energy rose by {rise:e} J between samples");
        }
    }
}

#[test]
fn a_floating_robot_struck_by_a_ball_in_zero_gravity_keeps_the_total_momentum() {
    let text = "version = 1\n[world]\ngravity = [0.0, 0.0, 0.0]\ndt = 0.001\nduration = 1.0\nintegrator = \"rk4\"\n\
        restitution = 0.6\nfriction = 0.4\n\
        [[body]]\nname = \"ball\"\nshape = { type = \"sphere\", radius = 0.05 }\ndensity = 2000.0\n\
        position = [0.45, 0.12, 0.5]\nvelocity = [0.0, -3.0, 0.2]\n\
        [[robot]]\nname = \"arm\"\nurdf = \"arm.urdf\"\nbase = \"floating\"\nposition = [0.0, 0.0, 0.5]\n\
        q = { j1 = 0.3, j2 = -0.2 }\n";
    let (_dir, mut scene) = scene_with(&[("arm.urdf", FLOATING_ARM)], text);
    let world = &mut scene.world;
    // every step, contact or not, keeps the total momentum to 1e-10 of its value; over the whole
    // run RK4 itself drifts (the momentum of a tree is linear in v but not in q): that is printed
    let (p0, l0) = (world.linear_momentum(), world.angular_momentum());
    let (mut step_p, mut step_l, mut contact_steps) = (0.0_f64, 0.0_f64, 0);
    for _ in 0..world.config.step_count() {
        let (pb, lb) = (world.linear_momentum(), world.angular_momentum());
        world.step().unwrap();
        let (p, l) = (world.linear_momentum(), world.angular_momentum());
        step_p = step_p.max((p - pb).length() / p0.length());
        step_l = step_l.max((l - lb).length() / l0.length());
        contact_steps += usize::from(world.contacts().links.active().count() > 0);
    }
    let (worst_p, worst_l) =
        ((world.linear_momentum() - p0).length() / p0.length(), (world.angular_momentum() - l0).length() / l0.length());
    println!("{contact_steps} steps in contact; per step |Δp|/|p₀| ≤ {step_p:e}, |ΔL|/|L₀| ≤ {step_l:e}; after 1 s {worst_p:e}, {worst_l:e}");
    let strikes = world.contacts().links.impacts;
    let ball = &world.bodies[0];
    println!("strikes {strikes}; ball velocity after {:?}", ball.state.velocity);
    assert!(strikes >= 1, "the ball never struck the arm");
    assert!(ball.state.velocity.y > -2.0, "the ball went on as if nothing was there: {:?}", ball.state.velocity);
    assert!(contact_steps >= 1);
    assert!(step_p <= 1e-10, "linear momentum changed by {step_p:e} of its initial value in one step");
    assert!(step_l <= 1e-10, "angular momentum changed by {step_l:e} of its initial value in one step");
    assert!(worst_p <= 1e-8 && worst_l <= 1e-8, "momentum drifted by {worst_p:e}, {worst_l:e} over the run");
}

/// `scenes/quadruped.toml` held for `duration` seconds.
fn quadruped(duration: f64) -> Scene {
    let mut scene = scene::load(&repo().join("scenes/quadruped.toml")).unwrap_or_else(|e| panic!("{e}"));
    scene.world.config.duration = duration;
    scene
}

#[test]
fn a_quadruped_stands_under_pd_without_sinking_sliding_or_drifting() {
    let mut scene = quadruped(20.0);
    let world = &mut scene.world;
    let robot = world.robot_index("quad").unwrap();
    let mass: f64 = world.robots[robot].model.bodies.iter().map(|b| b.inertia.mass).sum();
    let weight = mass * world.config.gravity.length();
    let feet: Vec<usize> = (0..world.robots[robot].link_names().len())
        .filter(|&k| world.robots[robot].link_names()[k].ends_with("_foot"))
        .collect();
    assert_eq!(feet.len(), 4);
    let base = world.robots[robot].link_names().iter().position(|n| n == "quad/base").unwrap();
    let steps = world.config.step_count();
    let settle = (1.0 / world.config.dt).round() as u64;
    let (mut worst_force, mut worst_depth, mut worst_slide, mut worst_drift) = (0.0_f64, 0.0_f64, 0.0_f64, 0.0_f64);
    let mut anchors: Vec<DVec3> = Vec::new();
    let mut base_anchor = DVec3::ZERO;
    for step in 1..=steps {
        world.step().unwrap();
        worst_depth = worst_depth.max(link_depth(world));
        if step < settle {
            continue;
        }
        let r = &world.robots[robot];
        let positions: Vec<DVec3> = feet.iter().map(|&k| r.link_state(k).position).collect();
        let base_position = r.link_state(base).position;
        if step == settle {
            anchors = positions;
            base_anchor = base_position;
            continue;
        }
        // the normal forces of the step: Σ force·n over the ground contacts
        let normal: f64 = world
            .contacts()
            .links
            .active()
            .filter(|(c, _)| matches!(c.a, Side::Body(_)))
            .map(|(c, p)| p.dot(c.normal_world) / world.config.dt)
            .sum();
        worst_force = worst_force.max((normal - weight).abs() / weight);
        for (p, a) in positions.iter().zip(&anchors) {
            worst_slide = worst_slide.max(((*p - *a) * DVec3::new(1.0, 1.0, 0.0)).length());
        }
        worst_drift = worst_drift.max((base_position - base_anchor).length());
    }
    println!(
        "quadruped, 20 s: normal forces within {:.4} % of the weight ({weight:.3} N), depth {:.3} mm, \
         feet slide {:.2e} m, base drifts {:.2e} m",
        100.0 * worst_force,
        1e3 * worst_depth,
        worst_slide,
        worst_drift
    );
    assert!(worst_force <= 0.005, "normal forces off the weight by {:.3} %", 100.0 * worst_force);
    assert!(worst_depth < 1e-3, "a foot sank {worst_depth} m");
    assert!(worst_slide <= 1e-4, "a foot slid {worst_slide} m after the first second");
    assert!(worst_drift <= 1e-4, "the base drifted {worst_drift} m after the first second");
}

#[test]
fn a_chain_dropped_onto_the_floor_comes_to_rest_without_sinking_or_gaining_energy() {
    let mut scene = scene::load(&repo().join("scenes/chain.toml")).unwrap_or_else(|e| panic!("{e}"));
    let world = &mut scene.world;
    world.config.duration = 5.0;
    let mut energy = world.energy();
    let initial = energy;
    let (mut worst_rise, mut worst_depth) = (0.0_f64, 0.0_f64);
    for _ in 0..world.config.step_count() {
        world.step().unwrap();
        let e = world.energy();
        assert!(e.is_finite());
        worst_rise = worst_rise.max(e - energy);
        energy = e;
        worst_depth = worst_depth.max(link_depth(world));
    }
    let kinetic = world.robots[0].kinetic_energy();
    println!(
        "chain: {} contacts at the end, depth {:.3} mm, largest energy rise in a step {worst_rise:e} J, kinetic {kinetic:e} J",
        world.contacts().links.active().count(),
        1e3 * worst_depth
    );
    assert!(worst_depth < 2e-3, "the chain sank {worst_depth} m into the floor");
    assert!(kinetic < 1e-6, "the chain is not at rest after 5 s: T = {kinetic} J");
    assert!(worst_rise <= 1e-9 * initial.abs(), "the chain gained {worst_rise} J in one step (E₀ = {initial} J)");
}

#[test]
fn a_box_pushed_by_a_robot_slides_as_coulomb_friction_predicts() {
    // the paddle (0.5 kg) pushes a 1 kg box on the floor with a constant joint force of 10 N; the
    // paddle floats 5 mm above the floor and is frictionless (μ = √(0 · 0.5) against the box), the
    // box slides on the floor with μ = 0.5
    let text =
        "version = 1\n[world]\ndt = 0.001\nduration = 1.5\nintegrator = \"rk4\"\nfriction = 0.5\nrestitution = 0.0\n\
        [[body]]\nname = \"ground\"\nshape = { type = \"plane\" }\nfixed = true\n\
        [[body]]\nname = \"box\"\nshape = { type = \"box\", half_extents = [0.1, 0.1, 0.1] }\nmass = 1.0\n\
        position = [0.2, 0.0, 0.1]\n\
        [[robot]]\nname = \"pusher\"\nurdf = \"pusher.urdf\"\nposition = [0.0, 0.0, 0.105]\n\
        torque = { slide = 10.0 }\nfriction = 0.0\n";
    let (_dir, mut scene) = scene_with(&[("pusher.urdf", PUSHER)], text);
    let world = &mut scene.world;
    let (m_box, m_paddle, force, mu, g) = (1.0, 0.5, 10.0, 0.5, 9.81);
    let box_index = world.body_index("box").unwrap();
    let (mut v_start, mut t_start) = (None, 0.0);
    let mut push = Vec::new();
    for step in 1..=world.config.step_count() {
        world.step().unwrap();
        let t = world.time();
        if (0.5..=1.5).contains(&t) {
            let v = world.bodies[box_index].state.velocity.x;
            if v_start.is_none() {
                v_start = Some(v);
                t_start = t;
            }
            let paddle_force: f64 = world
                .contacts()
                .links
                .active()
                .filter(|(c, _)| c.a == Side::Body(box_index))
                .map(|(_, p)| -p.x / world.config.dt)
                .sum();
            push.push(paddle_force);
        }
        let _ = step;
    }
    let v_end = world.bodies[box_index].state.velocity.x;
    let measured = (v_end - v_start.unwrap()) / (world.time() - t_start);
    // the paddle and the box move together: a = (F − μ m g) / (m + m_paddle)
    let predicted = (force - mu * m_box * g) / (m_box + m_paddle);
    let mean_push = push.iter().sum::<f64>() / push.len() as f64;
    // on the box alone: a = (F_push − μ m g) / m
    let from_push = (mean_push - mu * m_box * g) / m_box;
    println!(
        "box: a = {measured:.5} m/s², predicted {predicted:.5}; the paddle pushes {mean_push:.4} N → {from_push:.5}"
    );
    assert!((measured - predicted).abs() <= 0.01 * predicted, "a = {measured}, predicted {predicted}");
    assert!((measured - from_push).abs() <= 0.01 * predicted, "a = {measured}, from the push {from_push}");
}

#[test]
fn no_impact_on_a_random_tree_increases_its_kinetic_energy() {
    let mut rng = Rng::new(7);
    let mut worst = f64::NEG_INFINITY;
    for case in 0..300 {
        let base = if case % 2 == 0 { Base::Fixed } else { Base::Floating };
        let model = random_tree(&mut rng, 1 + case % 9, base, case % 3 == 0);
        let q = random_q(&mut rng, &model);
        let v = rng.vector(model.nv(), 2.0);
        let nv = model.nv();
        let mut ws = Workspace::new(&model);
        let m = crba(&model, &mut ws, &q).unwrap().clone();
        ltdl_factor(&model, &mut ws).unwrap();
        let body = rng.below(model.nbodies());
        let point = rng.vec3(1.0);
        let (mut jac, mut w) = (vec![0.0; 3 * nv], vec![0.0; 3 * nv]);
        point_jacobian(&model, &ws, body, point, &mut jac).unwrap();
        impulse_response(&model, &ws, &jac, &mut w).unwrap();
        let k = collision_matrix(&jac, &w, nv);
        let k = k + 1e-12 * (k.x_axis.x + k.y_axis.y + k.z_axis.z) * tumble::math::DMat3::IDENTITY;
        let u = tumble::multibody::contact_point::point_velocity(&jac, &v);
        // a normal against which the point approaches
        let n = (rng.unit() - 1.5 * u.normalize_or_zero()).normalize();
        let (mu, e) = (rng.range(0.0, 1.5), rng.range(0.0, 1.0));
        let law = [RestitutionLaw::Stronge, RestitutionLaw::Newton, RestitutionLaw::Poisson][case % 3];
        let Some(impact) = collide(k, n, u, mu, e, law) else { continue };
        let mut v_after = v.clone();
        tumble::multibody::contact_point::apply_impulse(&w, impact.impulse_world, &mut v_after);
        let kinetic = |x: &[f64]| {
            let x = nalgebra::DVector::from_column_slice(x);
            0.5 * x.dot(&(&m * &x))
        };
        let (t0, t1) = (kinetic(&v), kinetic(&v_after));
        worst = worst.max((t1 - t0) / t0.max(1e-12));
        assert!(
            t1 <= t0 * (1.0 + 1e-12) + 1e-15,
            "case {case}: T rose from {t0} to {t1} ({law:?}, μ = {mu}, e = {e}, K = {k:?}, n = {n:?}, u = {u:?}, p = {:?})",
            impact.impulse_world
        );
    }
    println!("largest relative change of T in an impact: {worst:e}");
}

/// The run report's energy balance with robots in contact: the chain of `scenes/chain.toml`, its
/// joint damping taken out (else the damping's work while falling is in no book), dropped onto the
/// floor for 3 s. The energy its link collisions and its resting link contacts took
/// (`World::contact_energy`) closes the balance `E₀ − E − lost` to a small share of what was lost.
#[test]
fn the_energy_taken_by_link_contacts_closes_the_chain_drops_balance() {
    let mut scene = scene::load(&repo().join("scenes/chain.toml")).unwrap_or_else(|e| panic!("{e}"));
    let world = &mut scene.world;
    world.config.duration = 3.0;
    world.robots[0].control.damping.fill(0.0);
    let initial = world.energy();
    let mut worst = 0.0_f64;
    for _ in 0..world.config.step_count() {
        world.step().unwrap();
        let lost = world.contact_energy();
        worst = worst.max((initial - world.energy() - lost.collisions - lost.friction).abs());
    }
    let lost = world.contact_energy();
    let total = lost.collisions + lost.friction;
    let balance = initial - world.energy() - total;
    println!(
        "chain balance: E₀ = {initial:.6} J, E = {:.6} J, collisions {} ({:.6} J), resting {:.6} J; E₀ − E − lost = \
         {balance:e} J ({:.2e} of the energy lost), worst along the way {worst:e} J",
        world.energy(),
        world.contact_collisions(),
        lost.collisions,
        lost.friction,
        balance.abs() / total
    );
    assert!(total > 0.5 * (initial - world.energy()), "the contacts' books hold too little: {total} J");
    // what remains is RK4's own error in the violent steps right after a strike (the links whip
    // round): 2.9 and 4.5 µJ in the two steps after the strike at 0.306 s, in which no contact acts
    assert!(worst <= 1e-5 * total, "the balance is off by {worst} J of {total} J lost");
}

/// A robot link wakes a sleeping body: the paddle, driven by a small constant joint force (0.5 N on
/// 0.5 kg), reaches a box lying 0.55 m away on the floor after about 1 s, by which time the box has
/// been still for its `sleep_time` and fallen asleep. The box must wake by the step of the paddle's
/// first push (the link's contact wakes the island as it comes within reach), never sleep while
/// pushed, be moved by the strike, and end where it ends with sleeping off.
#[test]
fn a_robot_link_wakes_a_sleeping_box() {
    let run = |sleep: bool| {
        let text = format!(
            "version = 1\n[world]\ndt = 0.001\nduration = 2.0\nintegrator = \"rk4\"\nfriction = 0.5\nrestitution = 0.0\n\
            sleep = {sleep}\n\
            [[body]]\nname = \"ground\"\nshape = {{ type = \"plane\" }}\nfixed = true\n\
            [[body]]\nname = \"box\"\nshape = {{ type = \"box\", half_extents = [0.1, 0.1, 0.1] }}\nmass = 1.0\n\
            position = [0.7, 0.0, 0.1]\n\
            [[robot]]\nname = \"pusher\"\nurdf = \"pusher.urdf\"\nposition = [0.0, 0.0, 0.105]\n\
            torque = {{ slide = 0.5 }}\nfriction = 0.0\n"
        );
        let (_dir, mut scene) = scene_with(&[("pusher.urdf", PUSHER)], &text);
        let world = &mut scene.world;
        let b = world.body_index("box").unwrap();
        let (mut asleep_at, mut woke_at, mut first_push, mut asleep_while_pushed) = (None, None, None, 0);
        for step in 1..=world.config.step_count() {
            let asleep_before = world.contacts().sleep().is_asleep(b);
            world.step().unwrap();
            let asleep = world.contacts().sleep().is_asleep(b);
            if asleep && asleep_at.is_none() {
                asleep_at = Some(step);
            }
            if asleep_before && !asleep && first_push.is_none() {
                woke_at = Some(step);
            }
            let pushed = world.contacts().links.active().any(|(c, p)| c.a == Side::Body(b) && p != DVec3::ZERO);
            if pushed {
                first_push.get_or_insert(step);
                asleep_while_pushed += asleep as u32;
            }
        }
        (world.bodies[b].state.position, asleep_at, woke_at, first_push, asleep_while_pushed)
    };
    let (end, asleep_at, woke_at, first_push, asleep_while_pushed) = run(true);
    let (end_awake, never, _, first_push_awake, _) = run(false);
    println!(
        "box asleep at step {asleep_at:?}, woke at {woke_at:?}, first pushed at {first_push:?} ({first_push_awake:?} with \
         sleeping off); ends at x = {:.6} m, {:.6} m with sleeping off ({:.2e} m apart)",
        end.x,
        end_awake.x,
        (end - end_awake).length()
    );
    assert_eq!(never, None, "a box slept with sleeping off");
    let (asleep_at, first_push) = (asleep_at.expect("the box never fell asleep"), first_push.expect("never pushed"));
    assert!(asleep_at < first_push, "the box fell asleep at step {asleep_at}, after the first push {first_push}");
    let woke_at = woke_at.expect("the box was pushed but never woke before");
    assert!(woke_at <= first_push, "woke at step {woke_at}, after the first push at {first_push}");
    assert_eq!(asleep_while_pushed, 0, "the box slept in steps in which the paddle pushed it");
    // 0.5 N cannot hold the box sliding (μ m g = 4.9 N): the paddle's strike moves it, then the box
    // and the paddle stop against the floor's friction
    assert!(end.x > 0.71, "the strike did not move the box: it ends at x = {}", end.x);
    assert!((end - end_awake).length() < 1e-3, "sleeping moved the box's end by {} m", (end - end_awake).length());
}

/// A fixed-base rig: a 0.4 × 0.4 × 0.2 m box on its root link `base`, a plate welded to it (a
/// fixed joint, so it moves with the world too), and a 0.1 m wheel of 1 kg turning about x on an
/// axle through its centre: the bottom of the wheel moves only along y, so along the floor's normal
/// its effective mass is infinite (`K_nn = 0`).
const RIG: &str = r#"<robot name="rig">
  <link name="base"><collision><geometry><box size="0.4 0.4 0.2"/></geometry></collision></link>
  <link name="plate"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial>
    <collision><origin xyz="0 0 -0.02"/><geometry><box size="0.4 0.4 0.1"/></geometry></collision></link>
  <joint name="weld" type="fixed"><parent link="base"/><child link="plate"/><origin xyz="1 0 0"/></joint>
  <link name="wheel"><inertial><mass value="1"/><inertia ixx="0.004" iyy="0.004" izz="0.004"/></inertial>
    <collision><geometry><sphere radius="0.1"/></geometry></collision></link>
  <joint name="axle" type="continuous"><parent link="base"/><child link="wheel"/><origin xyz="-1 0 0"/>
    <axis xyz="1 0 0"/></joint>
</robot>"#;

/// Links that cannot move against the normal touching fixed bodies: the rig's base and plate sink
/// 5 and 7 cm into the floor and the base 10 cm into a fixed block (pairs that both move with the
/// world are never paired), and its spinning wheel sinks 5 cm into the floor, a contact of zero
/// effective mass along the normal. For 1 s: no NaN, no impulse on any of them, and the wheel, which
/// the floor can neither push nor rub (no normal impulse, so no friction), turns on at its 5 rad/s.
#[test]
fn links_that_cannot_move_along_the_normal_take_no_impulse_from_fixed_bodies() {
    let text = "version = 1\n[world]\ndt = 0.001\nduration = 1.0\nintegrator = \"rk4\"\nfriction = 0.8\n\
                [[body]]\nname = \"ground\"\nshape = { type = \"plane\" }\nfixed = true\n\
                [[body]]\nname = \"block\"\nshape = { type = \"box\", half_extents = [0.2, 0.2, 0.2] }\nfixed = true\n\
                position = [0.0, 0.3, 0.05]\n\
                [[robot]]\nname = \"rig\"\nurdf = \"rig.urdf\"\nposition = [0.0, 0.0, 0.05]\nq = { axle = 0.7 }\n\
                v = { axle = 5.0 }\n";
    let (_dir, mut scene) = scene_with(&[("rig.urdf", RIG)], text);
    let world = &mut scene.world;
    let wheel = world.link_shapes_named("rig/wheel").unwrap();
    let (mut wheel_contacts, mut other_contacts) = (0, 0);
    for step in 0..world.config.step_count() {
        world.step().unwrap();
        let robot = &world.robots[0];
        assert!(
            robot.q().iter().chain(robot.v()).all(|x| x.is_finite()),
            "step {step}: {:?} {:?}",
            robot.q(),
            robot.v()
        );
        let links = &world.contacts().links;
        for (c, p) in links.contacts().iter().zip(links.impulses()) {
            assert!(p.is_finite(), "step {step}: {c:?}: {p}");
            assert_eq!(*p, DVec3::ZERO, "step {step}: an impulse on {c:?}");
            match c.b {
                Side::Link(l) if wheel.contains(&l) => wheel_contacts += 1,
                _ => other_contacts += 1,
            }
        }
    }
    let robot = &world.robots[0];
    eprintln!(
        "wheel contacts {wheel_contacts}, others {other_contacts}; axle q = {}, v = {}",
        robot.q()[0],
        robot.v()[0]
    );
    assert_eq!(other_contacts, 0, "a link fixed to the world was paired with a fixed body");
    assert_eq!(wheel_contacts, 1000, "the wheel touched the floor at every step");
    assert_eq!(robot.v()[0], 5.0, "the floor changed the wheel's speed");
}
