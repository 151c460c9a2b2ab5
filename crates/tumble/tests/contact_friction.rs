//! Coulomb friction in resting and sliding contact: the incline, the sliding stop distance, the
//! isotropy of friction, and a sphere that slides until it rolls.

mod contact_support;
use contact_support::*;
use tumble::math::{DQuat, DVec3};

const G: f64 = 9.81;

/// A unit box on a plane tilted by `theta` about world x, both with friction `mu`, no restitution;
/// returns the distance slid down the slope (m) after `t` seconds.
fn incline(theta: f64, mu: f64, t: f64) -> (f64, f64) {
    let tilt = DQuat::from_rotation_x(theta);
    let h = DVec3::splat(0.25);
    let up = tilt * DVec3::Z;
    let start = up * 0.25;
    let mut b = material(cuboid("box", h, 1.0, start), mu, 0.0);
    b.state.orientation = tilt;
    let floor = material(ground(tilt), mu, 0.0);
    let mut w = world(1e-3, DVec3::new(0.0, 0.0, -G), vec![floor, b]);
    let down = tilt * DVec3::NEG_Y;
    let steps = (t / 1e-3).round() as usize;
    for _ in 0..steps {
        w.step().unwrap();
    }
    let s = w.bodies[1].state;
    ((s.position - start).dot(down), s.velocity.dot(down))
}

#[test]
fn box_on_an_incline_sticks_when_mu_exceeds_tan_theta() {
    let theta: f64 = 20f64.to_radians();
    let (slid, _) = incline(theta, 1.2 * theta.tan(), 5.0);
    eprintln!("incline 20°, μ = 1.2 tan θ: creep {slid:e} m in 5 s");
    assert!(slid.abs() < 1e-3, "creep {slid} m in 5 s");
}

#[test]
fn box_on_an_incline_slides_with_g_sin_minus_mu_cos() {
    let theta: f64 = 30f64.to_radians();
    let mu = 0.3;
    let t = 1.0;
    let (slid, v) = incline(theta, mu, t);
    let a = G * (theta.sin() - mu * theta.cos());
    let a_from_v = v / t;
    let a_from_s = 2.0 * slid / (t * t);
    eprintln!("incline 30°, μ = 0.3: a from v {a_from_v:.5}, from s {a_from_s:.5}, expected {a:.5} m/s²");
    assert!((a_from_v - a).abs() < 0.01 * a, "acceleration from v: {a_from_v} vs {a} m/s²");
    assert!((a_from_s - a).abs() < 0.01 * a, "acceleration from s: {a_from_s} vs {a} m/s²");
}

/// A box launched at `v0` (m/s) along `direction` on flat ground with friction `mu`; returns the
/// displacement when it has stopped (m).
fn slide(v0: f64, direction: DVec3, mu: f64) -> DVec3 {
    let h = DVec3::new(0.2, 0.2, 0.1);
    let start = DVec3::new(0.0, 0.0, 0.1);
    let mut b = material(cuboid("box", h, 2.0, start), mu, 0.0);
    b.state.velocity = v0 * direction;
    let floor = material(ground(DQuat::IDENTITY), mu, 0.0);
    let mut w = world(1e-3, DVec3::new(0.0, 0.0, -G), vec![floor, b]);
    let t_stop = v0 / (mu * G);
    let steps = (1.5 * t_stop / 1e-3) as usize;
    for _ in 0..steps {
        w.step().unwrap();
    }
    assert!(w.bodies[1].state.velocity.length() < 1e-6, "still moving: {:?}", w.bodies[1].state.velocity);
    w.bodies[1].state.position - start
}

#[test]
fn sliding_box_stops_after_v_squared_over_two_mu_g() {
    let (v0, mu) = (3.0, 0.4);
    let d = slide(v0, DVec3::X, mu).length();
    let expected = v0 * v0 / (2.0 * mu * G);
    eprintln!("slide v0 = 3, μ = 0.4: stopped after {d:.5} m, expected {expected:.5} m");
    assert!((d - expected).abs() < 0.01 * expected, "stopped after {d} m, expected {expected} m");
}

#[test]
fn friction_is_isotropic_a_box_launched_at_30_degrees_keeps_its_direction() {
    let angle = 30f64.to_radians();
    let dir = DVec3::new(angle.cos(), angle.sin(), 0.0);
    let d = slide(3.0, dir, 0.4);
    let off = d.y.atan2(d.x) - angle;
    eprintln!("slide at 30°: direction changed by {:e}°", off.to_degrees());
    assert!(off.abs().to_degrees() < 0.5, "direction changed by {}°", off.to_degrees());
}

#[test]
fn sliding_sphere_ends_rolling_at_five_sevenths() {
    let r = 0.1;
    let v0 = 2.0;
    let mut ball = material(sphere("ball", r, 1.0, DVec3::new(0.0, 0.0, r)), 0.3, 0.0);
    ball.state.velocity = DVec3::new(v0, 0.0, 0.0);
    let floor = material(ground(DQuat::IDENTITY), 0.3, 0.0);
    let mut w = world(1e-3, DVec3::new(0.0, 0.0, -G), vec![floor, ball]);
    for _ in 0..1500 {
        w.step().unwrap();
    }
    let s = w.bodies[1].state;
    let v = s.velocity.x;
    eprintln!(
        "sliding sphere: rolls at {v:.5} m/s, 5/7 v0 = {:.5} m/s, ω r = {:.5} m/s",
        5.0 / 7.0 * v0,
        (s.orientation * s.omega_body).y * r
    );
    assert!((v - 5.0 / 7.0 * v0).abs() < 0.01 * 5.0 / 7.0 * v0, "rolls at {v} m/s, expected 5/7 v0");
    // rolling without slipping: v = ω r
    let omega = s.orientation * s.omega_body;
    assert!((omega.y * r - v).abs() < 1e-3 * v, "ω r = {} vs v = {v}", omega.y * r);
    assert!(w.contact_energy().friction > 0.0);
}
