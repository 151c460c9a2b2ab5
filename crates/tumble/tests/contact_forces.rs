//! The contact impulses the stage reports (`World::contacts().impulses()`, the `force` of
//! `tumble run --contacts`) are the impulses that moved the bodies:
//! - per body and per step, `m Δv = Σ p_on_body + m g dt` (Newton's second law over the step, with
//!   gravity the only other force), through collisions, resting contact and friction;
//! - a box at rest on a plane, flat or inclined within its friction cone, is held by contact
//!   forces that sum to its weight, `Σ F = −m g` (normal and friction together); asleep, it
//!   reports the forces of the step in which it fell asleep;
//! - a ball's collision impulse is `m (1 + e) v` along the normal.

mod contact_support;
use contact_support::*;
use tumble::math::{DQuat, DVec3};
use tumble::{Integrator, World};

const G: DVec3 = DVec3::new(0.0, 0.0, -9.81);

/// The contact impulse on each body over the last step (N·s, world frame).
fn impulse_per_body(w: &World) -> Vec<DVec3> {
    let mut per_body = vec![DVec3::ZERO; w.bodies.len()];
    let stage = w.contacts();
    assert_eq!(stage.contacts().len(), stage.impulses().len());
    for (c, p) in stage.contacts().iter().zip(stage.impulses()) {
        per_body[c.b] += *p;
        per_body[c.a] -= *p;
    }
    per_body
}

/// Steps `w` `n` times, checking `m Δv = Σ p + m g dt` for every free body at every step (relative
/// to the largest momentum change of the step). Returns the largest error seen.
fn check_momentum_balance(w: &mut World, n: usize) -> f64 {
    let dt = w.config.dt;
    let mut worst: f64 = 0.0;
    for _ in 0..n {
        let before: Vec<DVec3> = w.bodies.iter().map(|b| b.state.velocity).collect();
        w.step().unwrap();
        let p = impulse_per_body(w);
        let scale = w.bodies.iter().filter(|b| !b.fixed).map(|b| b.mass.mass * (G.length() * dt)).fold(0.0, f64::max);
        for (i, b) in w.bodies.iter().enumerate() {
            if b.fixed {
                continue;
            }
            let m = b.mass.mass;
            let residual = m * (b.state.velocity - before[i]) - (p[i] + m * G * dt);
            let scale = scale.max(p[i].length());
            worst = worst.max(residual.length() / scale);
        }
    }
    worst
}

#[test]
fn the_reported_impulses_are_what_moved_the_bodies() {
    // a ten-box tower beside balls dropped onto it and the floor: collisions, resting contact and
    // friction, with every integrator the contact stage serves
    for integrator in [Integrator::Rk4, Integrator::SemiImplicitEuler, Integrator::Euler, Integrator::Dopri5] {
        let mut bodies = vec![material(ground(DQuat::IDENTITY), 0.6, 0.3)];
        for k in 0..10 {
            let z = 0.25 + 0.5 * k as f64;
            bodies.push(material(
                cuboid(&format!("box{k}"), DVec3::splat(0.25), 2.0, DVec3::new(0.0, 0.0, z)),
                0.6,
                0.3,
            ));
        }
        for k in 0..6 {
            let x = -1.5 + 0.6 * k as f64;
            let ball = sphere(
                &format!("ball{k}"),
                0.2,
                1.0 + k as f64,
                DVec3::new(x, 0.3 * k as f64 - 0.6, 1.0 + 0.7 * k as f64),
            );
            bodies.push(material(ball, 0.4, 0.6));
        }
        let mut w = world(1.0 / 240.0, G, bodies);
        w.config.integrator = integrator;
        let worst = check_momentum_balance(&mut w, 720);
        assert!(w.contact_collisions() > 0, "{integrator}: the balls must collide");
        assert!(worst < 1e-9, "{integrator}: m Δv − Σ p − m g dt is {worst:.3e} of the step's momentum change");
    }
}

/// The contact forces on body 1 in the last step of `w`, summed (N, world frame).
fn contact_force(w: &World) -> DVec3 {
    let dt = w.config.dt;
    w.contacts().active().map(|(c, p)| if c.b == 1 { p / dt } else { -p / dt }).sum()
}

/// A box on a plane tilted by `tilt` (rad) about x, started at rest on it.
fn box_on_a_slope(tilt: f64) -> World {
    let q = DQuat::from_rotation_x(tilt);
    let n = q * DVec3::Z;
    let floor = material(ground(q), 0.8, 0.0);
    let mut b = material(cuboid("box", DVec3::new(0.3, 0.2, 0.1), 3.0, n * 0.1), 0.8, 0.0);
    b.state.orientation = q;
    let mut w = world(1.0 / 240.0, G, vec![floor, b]);
    w.config.integrator = Integrator::SemiImplicitEuler;
    w
}

/// The box of [`box_on_a_slope`] after 480 steps (2 s) with sleeping off, so that every step is
/// solved: the contact forces of the last step, summed, its speed and its number of active contacts.
fn resting_box_forces(tilt: f64) -> (DVec3, f64, usize) {
    let mut w = box_on_a_slope(tilt);
    w.config.contact.sleep = false;
    for _ in 0..480 {
        w.step().unwrap();
    }
    (contact_force(&w), w.bodies[1].state.velocity.length(), w.contacts().active().count())
}

#[test]
fn a_box_at_rest_is_held_by_forces_that_sum_to_its_weight() {
    let weight = 3.0 * G.length();
    // flat, and tilted to 0.5 rad (tan 0.5 = 0.55 < μ = 0.8: it sticks)
    for tilt in [0.0, 0.2, 0.5] {
        let (force, speed, active) = resting_box_forces(tilt);
        assert!(speed < 1e-6, "tilt {tilt}: the box should be at rest, speed {speed:.3e} m/s");
        assert!(active >= 3, "tilt {tilt}: a box on a plane rests on several points, got {active}");
        let expected = -3.0 * G;
        let err = (force - expected).length() / weight;
        assert!(err < 1e-6, "tilt {tilt}: contact forces {force:?} N against the weight's {expected:?} N ({err:.2e})");
        if tilt > 0.0 {
            // friction carries the slope's share: the force is not along the plane's normal
            let n = DQuat::from_rotation_x(tilt) * DVec3::Z;
            let tangential = (force - force.dot(n) * n).length();
            assert!((tangential / weight - tilt.sin()).abs() < 1e-6, "tilt {tilt}: friction {tangential} N");
        }
    }
}

/// With sleeping on (the default), the box falls asleep once still for `sleep_time`, and from then
/// on the contact forces reported are those of the step in which it fell asleep, bit for bit: the
/// solver's forces of that step, which still carry what is left of the settling (about 1e-6 of the
/// weight at the default 0.25 s, printed; 2.5e-9 at 0.5 s, 1e-14 after 1 s awake).
#[test]
fn a_sleeping_box_reports_the_forces_of_the_step_it_fell_asleep_in() {
    let weight = 3.0 * G.length();
    for tilt in [0.0, 0.5] {
        let mut w = box_on_a_slope(tilt);
        assert!(w.config.contact.sleep);
        let mut onset = None;
        for k in 0..480_usize {
            w.step().unwrap();
            if onset.is_none() && w.contacts().sleep().count() == 1 {
                onset = Some((k, contact_force(&w)));
            }
        }
        let (k, at_onset) = onset.expect("the box falls asleep within 2 s");
        let expected_k = (w.config.contact.sleep_time / w.config.dt).round() as usize;
        assert!(
            k.abs_diff(expected_k) <= 2,
            "tilt {tilt}: asleep at step {k}, still from the start: about {expected_k}"
        );
        assert_eq!(contact_force(&w), at_onset, "tilt {tilt}: the kept forces are the onset step's");
        assert_eq!(w.bodies[1].state.velocity, DVec3::ZERO);
        let err = (at_onset + 3.0 * G).length() / weight;
        println!("tilt {tilt}: asleep at step {k}; its forces against the weight: {err:.2e}");
        assert!(err < 1e-3, "tilt {tilt}: contact forces {at_onset:?} N hold the box ({err:.2e} of its weight off)");
    }
}

#[test]
fn a_collision_impulse_is_m_one_plus_e_v() {
    let (m, e) = (2.0, 0.6);
    let ball = material(sphere("ball", 0.1, m, DVec3::new(0.0, 0.0, 1.1)), 0.0, e);
    let floor = material(ground(DQuat::IDENTITY), 0.0, e);
    let mut w = world(1e-3, G, vec![floor, ball]);
    // the exact-parabola integrator: the approach speed at the impact is √(2 g h)
    w.config.integrator = Integrator::Rk4;
    while w.contact_collisions() == 0 {
        w.step().unwrap();
    }
    let v_impact = (2.0 * G.length() * 1.0).sqrt();
    let active: Vec<_> = w.contacts().active().collect();
    assert_eq!(active.len(), 1);
    let (c, p) = active[0];
    assert_eq!((c.a, c.b), (0, 1));
    let expected = m * (1.0 + e) * v_impact;
    assert!((p.z - expected).abs() < 1e-9 * expected, "impulse {p:?} N·s, expected {expected} along z");
    assert!(p.x.abs() + p.y.abs() < 1e-12);
}
