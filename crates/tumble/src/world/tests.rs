//! The world step: momentum of free bodies, fixed bodies, time keeping, and divergence reports.

// the one tolerance helper of the unit tests (test modules are private to their parents, so it is
// included by path rather than imported)
#[allow(clippy::duplicate_mod)]
#[path = "../math/tests/support.rs"]
mod support;

use super::*;
use crate::body::MassProperties;
use crate::integrate::Integrator;
use support::{assert_close, EPS};

fn tumbling_body(name: &str) -> RigidBody {
    let mut body = RigidBody::new(name, MassProperties::from_principal(1.5, DVec3::new(1.0, 2.0, 3.0)).unwrap());
    body.state.position = DVec3::new(1.0, -2.0, 0.5);
    body.state.velocity = DVec3::new(0.3, -1.25, 2.0);
    body.state.omega_body = DVec3::new(0.01, 5.0, 0.01);
    body
}

fn world(integrator: Integrator, gravity: DVec3, bodies: Vec<RigidBody>) -> World {
    World::new(WorldConfig { gravity, integrator, ..Default::default() }, bodies)
}

/// With no gravity and no loads, every integrator keeps the linear momentum exactly (bit for bit)
/// while the body tumbles, and moves the centre of mass on a straight line at that velocity.
#[test]
fn free_body_keeps_linear_momentum_exactly() {
    for integrator in Integrator::ALL {
        let mut w = world(integrator, DVec3::ZERO, vec![tumbling_body("free")]);
        let (p0, x0) = (w.linear_momentum(), w.bodies[0].state.position);
        let q0 = w.bodies[0].state.orientation;
        for _ in 0..500 {
            w.step().unwrap();
        }
        assert_eq!(w.linear_momentum(), p0, "{integrator}");
        let expected = x0 + w.time() * w.bodies[0].state.velocity;
        // each step's x ← x + h v rounds once: at most 500 ε |x| in all
        assert_close("x(t) = x0 + v t", w.bodies[0].state.position, expected, 500.0 * EPS, expected.length());
        assert_ne!(w.bodies[0].state.orientation, q0, "{integrator}: the body tumbles");
        assert_eq!(w.steps(), 500);
    }
}

/// Under gravity alone the momentum changes by `m g t` (and a body thrown up falls as a projectile).
#[test]
fn momentum_changes_by_impulse_of_gravity() {
    let g = DVec3::new(0.0, 0.0, -9.81);
    for integrator in Integrator::ALL {
        let mut w = world(integrator, g, vec![tumbling_body("thrown")]);
        let (p0, x0, v0) = (w.linear_momentum(), w.bodies[0].state.position, w.bodies[0].state.velocity);
        for _ in 0..1000 {
            w.step().unwrap();
        }
        let t = w.time();
        assert_close("p(t) = p0 + m g t", w.linear_momentum(), p0 + 1.5 * g * t, 1e-12, p0.length() + 1.5 * 9.81 * t);
        // the exact projectile; first-order methods are off by ½ g t dt
        let x = x0 + v0 * t + 0.5 * g * t * t;
        let tol = if integrator.order() == 1 { 0.5 * 9.81 * t * w.config.dt * 1.01 } else { 1e-12 };
        assert_close("x(t) projectile", w.bodies[0].state.position, x, tol, 1.0);
    }
}

/// A fixed body is never integrated, even with loads and gravity.
#[test]
fn fixed_body_does_not_move() {
    let mut ground = tumbling_body("ground");
    ground.fixed = true;
    ground.loads.torque_body = DVec3::ONE;
    let before = ground.state;
    let mut w = world(Integrator::Rk4, DVec3::new(0.0, 0.0, -9.81), vec![ground, tumbling_body("free")]);
    for _ in 0..10 {
        w.step().unwrap();
    }
    assert_eq!(w.bodies[0].state, before);
    assert_eq!(w.free_bodies().count(), 1);
    // momentum and energy count free bodies only
    assert_eq!(w.linear_momentum(), 1.5 * w.bodies[1].state.velocity);
}

/// Time is `steps · dt`, with no accumulated round-off.
#[test]
fn time_is_steps_times_dt() {
    let mut w = world(Integrator::SemiImplicitEuler, DVec3::ZERO, vec![tumbling_body("a")]);
    w.config.dt = 0.1;
    for _ in 0..30 {
        w.step().unwrap();
    }
    assert_eq!(w.steps(), 30);
    assert_eq!(w.time(), 30.0 * 0.1);
}

/// A state that is already NaN is reported, by every integrator, as a [`Diverged`] naming the body,
/// the step and the time — not a panic, and the world's clock does not advance.
#[test]
fn nan_state_is_reported_not_panicked() {
    for integrator in Integrator::ALL {
        let mut bad = tumbling_body("broken");
        bad.state.omega_body.y = f64::NAN;
        let mut w = world(integrator, DVec3::new(0.0, 0.0, -9.81), vec![tumbling_body("fine"), bad]);
        w.config.dt = 0.01;
        let err = w.step().unwrap_err().diverged().cloned().unwrap();
        assert_eq!(err.body, "broken", "{integrator}");
        assert_eq!(err.step, 1, "{integrator}");
        assert_eq!(err.time, 0.01, "{integrator}");
        assert!(
            err.quantity.contains("not finite") || err.quantity.contains("adaptive integrator failed"),
            "{integrator}: {}",
            err.quantity
        );
        assert_eq!(w.steps(), 0, "{integrator}: a failed step is not counted");
        // the failed step is undone for every body, the ones stepped before the broken one included
        assert_eq!(w.bodies[0].state, tumbling_body("fine").state, "{integrator}: the body before was not restored");
        assert!(w.bodies[1].state.omega_body.y.is_nan() && w.bodies[1].state.position == DVec3::new(1.0, -2.0, 0.5));
        let message = err.to_string();
        assert!(message.contains("`broken`") && message.contains("step 1"), "{message}");
    }
}

/// An absurd torque spins a ball up until `|ω|` passes [`MAX_STATE_MAGNITUDE`] = 1e10 rad/s: the
/// report names the body, the angular velocity, and the first step beyond the bound.
///
/// With `dt = 2⁻¹⁰ s`, `τ = 2³⁰ N·m` and `I = 1 kg·m²` (no gyroscopic term for a ball) every step adds
/// exactly `2²⁰ rad/s`, so `|ω|` first exceeds 1e10 at step `⌈1e10 / 2²⁰⌉ = 9537`.
#[test]
fn runaway_spin_is_reported_at_the_right_step() {
    // dopri5 is left out: it resolves the ever faster rotation with ever smaller internal steps
    for integrator in [Integrator::Euler, Integrator::SemiImplicitEuler, Integrator::Rk4, Integrator::Splitting] {
        let mut ball = RigidBody::new("spinner", MassProperties::from_principal(1.0, DVec3::ONE).unwrap());
        ball.loads.torque_body = DVec3::new(0.0, 0.0, 2f64.powi(30));
        let mut w = world(integrator, DVec3::ZERO, vec![ball]);
        w.config.dt = 2f64.powi(-10);
        let err = loop {
            if let Err(e) = w.step() {
                break e.diverged().cloned().unwrap();
            }
            assert!(w.steps() < 20_000, "{integrator}: never reported");
        };
        assert_eq!(err.body, "spinner");
        assert_eq!(err.step, 9537, "{integrator}: {err}");
        assert_eq!(err.time, 9537.0 * 2f64.powi(-10));
        assert!(err.quantity.starts_with("|angular velocity|"), "{integrator}: {}", err.quantity);
        assert_eq!(w.steps(), 9536);
        // the state left behind is the last finite one: step 9536, |ω| = 9536 · 2²⁰ rad/s exactly
        assert!(w.bodies[0].state.is_finite());
        assert_eq!(w.bodies[0].state.omega_body.length(), 9536.0 * 2f64.powi(20), "{integrator}");
    }
}

/// Under `semi_implicit_euler` the step keeps the moving bodies in its own layout from the second
/// step after the bodies were last changed (the first that finds them as the step before left
/// them), drops it when they are changed, and does not make it with a body asleep or a robot.
#[test]
fn the_free_body_layout_is_made_when_the_bodies_stay_unchanged_for_a_step() {
    let mut w = world(Integrator::SemiImplicitEuler, DVec3::new(0.0, 0.0, -9.81), vec![tumbling_body("a")]);
    w.step().unwrap();
    assert_eq!(w.pack_seal(), 0, "the first step goes by rows");
    w.step().unwrap();
    let seal = w.bodies.seal();
    assert!(seal != 0 && w.pack_seal() == seal, "made at the second step");
    w.step().unwrap();
    assert_eq!((w.bodies.seal(), w.pack_seal()), (seal, seal), "kept");
    w.bodies[0].state.velocity.x += 1.0;
    w.step().unwrap();
    assert_ne!(w.pack_seal(), w.bodies.seal(), "changed: by rows");
    w.step().unwrap();
    assert_eq!(w.pack_seal(), w.bodies.seal(), "made again");
    // a change every other step: the blocks made once pay for nothing, so the step waits for two
    // unchanged steps before making them again, and goes by rows
    for cycle in 0..10 {
        w.bodies[0].state.velocity.x += 1.0;
        w.step().unwrap();
        w.step().unwrap();
        if cycle > 0 {
            assert_eq!(w.pack_seal(), 0, "cycle {cycle}: not made");
        }
    }
    // (the cycle's second step was the first unchanged one)
    w.step().unwrap();
    assert_eq!(w.pack_seal(), w.bodies.seal(), "made at the second unchanged step");
    // another integrator changes the bodies by its own pass
    w.config.integrator = Integrator::Rk4;
    w.step().unwrap();
    assert_eq!(w.bodies.seal(), 0);
}
