//! Islands and sleeping (`contact::sleep`): a stack at rest falls asleep and stays exactly where it
//! was, its contacts still carry its weight, and it wakes when a body strikes it, when the caller
//! changes one of its bodies or their loads, or when gravity changes; a body alone in space never
//! sleeps; the energy balance closes; `sleep = false` changes nothing.

mod contact_support;
use contact_support::*;
use tumble::math::{DQuat, DVec3};
use tumble::World;

const G: f64 = 9.81;
const DT: f64 = 1.0 / 60.0;

/// A floor, three unit boxes stacked (1 kg each), and a 0.2 kg ball hanging still 5 m above the
/// stack without gravity (alone in space: it never sleeps).
fn stack_and_ball() -> World {
    let h = DVec3::splat(0.5);
    let mut bodies = vec![material(ground(DQuat::IDENTITY), 0.5, 0.0)];
    for i in 0..3 {
        bodies.push(material(cuboid(&format!("box{i}"), h, 1.0, DVec3::new(0.0, 0.0, 0.5 + i as f64)), 0.5, 0.0));
    }
    let mut ball = material(sphere("ball", 0.25, 0.2, DVec3::new(0.0, 0.0, 8.0)), 0.5, 0.5);
    ball.gravity_scale = 0.0;
    bodies.push(ball);
    let mut w = world(DT, DVec3::new(0.0, 0.0, -G), bodies);
    w.config.integrator = tumble::Integrator::SemiImplicitEuler;
    w
}

fn steps(w: &mut World, n: usize) {
    for _ in 0..n {
        w.step().unwrap();
    }
}

fn asleep(w: &World, i: usize) -> bool {
    w.contacts().sleep().is_asleep(i)
}

#[test]
fn a_stack_at_rest_falls_asleep_and_stays_exactly_put() {
    let mut w = stack_and_ball();
    steps(&mut w, 120);
    assert!((1..=3).all(|i| asleep(&w, i)), "the stack is not asleep after 2 s");
    assert!(!asleep(&w, 4), "the ball alone in space fell asleep");
    assert_eq!(w.contacts().sleep().count(), 3);
    let before: Vec<_> = w.bodies.iter().map(|b| b.state).collect();
    steps(&mut w, 60);
    for (b, s) in w.bodies.iter().zip(&before).take(4) {
        assert_eq!(b.state, *s, "{} moved while asleep", b.name);
    }
    // the kept contacts still carry the stack: the floor's impulse over a step is its weight's
    let floor: f64 = w
        .contacts()
        .contacts()
        .iter()
        .zip(w.contacts().impulses())
        .filter(|(c, _)| c.a == 0 || c.b == 0)
        .map(|(c, p)| if c.b == 0 { -p.z } else { p.z })
        .sum();
    let weight = 3.0 * G * DT;
    eprintln!("floor impulse over a step while asleep: {floor:.6} N·s, weight × dt {weight:.6}");
    assert!((floor - weight).abs() < 1e-3 * weight, "floor impulse {floor}, weight × dt {weight}");
}

#[test]
fn a_ball_striking_the_sleeping_stack_wakes_it_as_if_it_had_never_slept() {
    // the same strike on the stack asleep and on the stack awake (sleep off)
    let strike = |sleep: bool| {
        let mut w = stack_and_ball();
        w.config.contact.sleep = sleep;
        steps(&mut w, 120);
        assert_eq!((1..=3).all(|i| asleep(&w, i)), sleep);
        w.bodies[4].state.velocity = DVec3::new(0.0, 0.0, -6.0);
        let collisions = w.contact_collisions();
        // 5 m - radius to the top face at 6 m/s: the strike is in the 44th step
        steps(&mut w, 60);
        assert!(w.contact_collisions() > collisions, "no collision");
        assert!((1..=3).all(|i| !asleep(&w, i)), "the struck stack is still asleep");
        (w.bodies[4].state.velocity.z, w.bodies[3].state.position.z)
    };
    let (rebound_asleep, top_asleep) = strike(true);
    let (rebound_awake, top_awake) = strike(false);
    eprintln!("ball after the strike: {rebound_asleep:.9} m/s (stack asleep), {rebound_awake:.9} m/s (awake)");
    eprintln!("top box: {top_asleep:.9} m, {top_awake:.9} m");
    assert!(rebound_asleep > 1.0, "the ball did not bounce: {rebound_asleep} m/s");
    assert!((rebound_asleep - rebound_awake).abs() < 1e-3 * rebound_awake.abs());
    assert!((top_asleep - top_awake).abs() < 1e-4);
}

#[test]
fn changing_a_sleeping_body_or_its_loads_wakes_its_island() {
    // a velocity set by the caller
    let mut w = stack_and_ball();
    steps(&mut w, 120);
    assert!(asleep(&w, 3));
    w.bodies[3].state.velocity = DVec3::new(0.5, 0.0, 0.0);
    steps(&mut w, 1);
    assert!((1..=3).all(|i| !asleep(&w, i)), "a pushed box did not wake its island");
    assert!(w.bodies[3].state.position.x > 0.0, "the pushed box did not move");

    // a force on the middle box
    let mut w = stack_and_ball();
    steps(&mut w, 120);
    w.bodies[2].loads.force_world = DVec3::new(50.0, 0.0, 0.0);
    steps(&mut w, 30);
    assert!(!asleep(&w, 2));
    assert!(w.bodies[2].state.position.x > 0.01, "the pushed box stayed at x = {}", w.bodies[2].state.position.x);

    // gravity changed by the caller wakes everything
    let mut w = stack_and_ball();
    steps(&mut w, 120);
    w.config.gravity = DVec3::new(0.0, 0.0, G);
    steps(&mut w, 30);
    assert!((1..=3).all(|i| !asleep(&w, i)));
    assert!(w.bodies[3].state.position.z > 2.6, "the top box did not fall up");

    // moving the floor under the stack
    let mut w = stack_and_ball();
    steps(&mut w, 120);
    w.bodies[0].state.position.z = -0.5;
    steps(&mut w, 30);
    assert!((1..=3).all(|i| !asleep(&w, i)), "the stack slept on above a lowered floor");
    assert!(w.bodies[1].state.position.z < 0.3, "the stack did not fall onto the lowered floor");
}

#[test]
fn a_body_alone_in_space_never_sleeps() {
    // a slow spin about an intermediate axis, far below the sleep speed: torque-free motion
    let mut b = cuboid("spinner", DVec3::new(0.3, 0.2, 0.1), 1.0, DVec3::ZERO);
    b.state.omega_body = DVec3::new(1e-3, 2e-4, 1e-5);
    let mut w = world(DT, DVec3::ZERO, vec![material(ground(DQuat::IDENTITY), 0.5, 0.0), b]);
    w.bodies[1].state.position.z = 5.0;
    let l0 = w.angular_momentum();
    steps(&mut w, 300);
    assert!(!asleep(&w, 1));
    assert!(w.bodies[1].state.omega_body != DVec3::ZERO);
    assert!((w.angular_momentum() - l0).length() < 1e-12, "angular momentum drifted");
}

#[test]
fn the_energy_balance_closes_with_islands_falling_asleep() {
    // boxes dropped from a height onto the floor: collisions, then rest, then sleep
    let h = DVec3::splat(0.5);
    let mut bodies = vec![material(ground(DQuat::IDENTITY), 0.5, 0.0)];
    for i in 0..4 {
        let mut b =
            material(cuboid(&format!("box{i}"), h, 1.0 + i as f64, DVec3::new(1.5 * i as f64, 0.0, 2.0)), 0.5, 0.3);
        b.state.omega_body = DVec3::new(0.3 * i as f64, 0.2, 0.0);
        bodies.push(b);
    }
    let mut w = world(DT, DVec3::new(0.0, 0.0, -G), bodies);
    let e0 = w.energy();
    steps(&mut w, 300);
    assert!(w.contacts().sleep().count() == 4, "{} of 4 asleep", w.contacts().sleep().count());
    let lost = w.contact_energy();
    let balance = e0 - w.energy() - lost.collisions - lost.friction;
    eprintln!("dropped boxes: lost {:.6} J, balance {balance:e} J", lost.collisions + lost.friction);
    assert!(balance.abs() < 1e-9 * (lost.collisions + lost.friction), "balance {balance} J");
}

#[test]
fn sleep_off_leaves_every_body_awake() {
    let mut w = stack_and_ball();
    w.config.contact.sleep = false;
    steps(&mut w, 200);
    assert_eq!(w.contacts().sleep().count(), 0);
}

/// The stack of [`stack_and_ball`] without the ball: every free body can sleep.
fn stack_alone() -> World {
    let mut w = stack_and_ball();
    w.bodies.truncate(4);
    w
}

#[test]
fn a_world_entirely_asleep_is_at_rest_and_steps_as_the_full_step_would() {
    // one world takes the steps at rest; its twin is borrowed mutably before each step (nothing
    // changed), which makes every step go through the whole contact stage
    let (mut rest, mut full) = (stack_alone(), stack_alone());
    for k in 0..300 {
        if k >= 120 {
            // asleep since about 1 s: a step or two later the world is at rest
            if k >= 125 {
                assert!(rest.at_rest(), "step {k}: the sleeping stack is not at rest");
            }
            let _ = &mut *full.bodies;
            assert!(!full.at_rest());
        }
        rest.step().unwrap();
        full.step().unwrap();
    }
    assert_eq!(rest.bodies.to_vec(), full.bodies.to_vec());
    assert_eq!(rest.time(), full.time());
    assert_eq!(rest.contacts().contacts(), full.contacts().contacts());
    assert_eq!(rest.contacts().impulses(), full.contacts().impulses());
    // then the same push on both: the same trajectories
    for w in [&mut rest, &mut full] {
        w.bodies[3].state.velocity = DVec3::new(0.5, 0.0, 0.0);
        assert!(!w.at_rest());
        steps(w, 90);
    }
    assert!(rest.bodies[3].state.position.x > 0.01, "the pushed box did not move");
    assert_eq!(rest.bodies.to_vec(), full.bodies.to_vec());
}

#[test]
fn a_world_at_rest_wakes_on_every_change_the_caller_can_make() {
    let at_rest = || {
        let mut w = stack_alone();
        steps(&mut w, 150);
        assert!(w.at_rest(), "the stack is not at rest after 2.5 s");
        assert!((1..=3).all(|i| asleep(&w, i)));
        w
    };
    let awake_after = |w: &mut World, n: usize| {
        steps(w, n);
        (1..=3).all(|i| !asleep(w, i))
    };
    // a force, through the loads
    let mut w = at_rest();
    w.bodies[2].loads.force_world = DVec3::new(50.0, 0.0, 0.0);
    assert!(awake_after(&mut w, 1), "a force did not wake the world at rest");
    // gravity, through the config (not a borrow of the bodies)
    let mut w = at_rest();
    w.config.gravity = DVec3::new(0.0, 0.0, G);
    assert!(!w.at_rest());
    assert!(awake_after(&mut w, 1), "a change of gravity did not wake the world at rest");
    // sleeping switched off
    let mut w = at_rest();
    w.config.contact.sleep = false;
    assert!(awake_after(&mut w, 1), "sleep = false left the world asleep");
    // the floor moved
    let mut w = at_rest();
    w.bodies[0].state.position.z = -0.5;
    assert!(awake_after(&mut w, 1), "a lowered floor did not wake the world at rest");
    steps(&mut w, 30);
    assert!(w.bodies[1].state.position.z < 0.3, "the stack did not fall onto the lowered floor");
    // a new body dropped in
    let mut w = at_rest();
    let mut ball = material(sphere("ball", 0.25, 0.2, DVec3::new(0.0, 0.0, 4.0)), 0.5, 0.5);
    ball.state.velocity = DVec3::new(0.0, 0.0, -3.0);
    w.bodies.push(ball);
    assert!(!w.at_rest());
    steps(&mut w, 30);
    assert!(w.contact_collisions() > 0, "the dropped ball never struck the stack");
    assert!((1..=3).all(|i| !asleep(&w, i)), "the struck stack is still asleep");
    // a different time step
    let mut w = at_rest();
    w.config.dt = DT / 2.0;
    assert!(!w.at_rest(), "a new time step kept the world at rest");
}
