//! A sphere dropped on a plane: rebound height `e² h` (Stronge's law without friction), and the
//! elastic bounce that keeps its height.

mod contact_support;
use contact_support::*;
use tumble::math::{DQuat, DVec3};

const G: f64 = 9.81;
const R: f64 = 0.1;

/// Drops a sphere from a clearance `h` (m) with restitution `e`; returns the apex clearances of
/// the first `bounces` rebounds (m).
fn apexes(h: f64, e: f64, bounces: usize, dt: f64) -> Vec<f64> {
    let ball = material(sphere("ball", R, 1.0, DVec3::new(0.0, 0.0, R + h)), 0.0, e);
    let floor = material(ground(DQuat::IDENTITY), 0.0, e);
    let mut w = world(dt, DVec3::new(0.0, 0.0, -G), vec![floor, ball]);
    let mut out = Vec::new();
    let mut rising = false;
    let mut top = f64::NEG_INFINITY;
    let t_end = (2.0 * h / G).sqrt() * 2.0 * (bounces as f64 + 1.0) + 1.0;
    while w.time() < t_end && out.len() < bounces {
        w.step().unwrap();
        let s = w.bodies[1].state;
        if s.velocity.z > 0.0 {
            rising = true;
            top = top.max(s.position.z - R);
        } else if rising {
            top = top.max(s.position.z - R);
            out.push(top);
            rising = false;
            top = f64::NEG_INFINITY;
        }
        if e == 0.0 && w.time() > 2.0 * (2.0 * h / G).sqrt() {
            out.push((s.position.z - R).max(top));
            break;
        }
    }
    out
}

#[test]
fn rebound_height_is_e_squared_h() {
    let h = 1.0;
    for e in [0.5, 0.9] {
        let first = apexes(h, e, 1, 1e-3)[0];
        let expected = e * e * h;
        println!("rebound e = {e}, h = {h} m, dt = 1e-3: {first:.7} m (e² h = {expected} m)");
        let rel = (first - expected).abs() / expected;
        assert!(rel < 0.01, "e = {e}: rebound {first} m, expected {expected} m (relative error {rel:e})");
    }
}

#[test]
fn perfectly_inelastic_sphere_stays_down() {
    let h = 1.0;
    let a = apexes(h, 0.0, 1, 1e-3);
    // e² h = 0: within 1 % of the drop height
    assert!(a[0].abs() < 0.01 * h, "rebound {} m after an e = 0 impact", a[0]);
}

#[test]
fn elastic_bounces_keep_their_height_and_never_rise() {
    let h = 1.0;
    let a = apexes(h, 1.0, 10, 1e-3);
    println!("e = 1, ten bounces from {h} m: {a:.8?} m");
    assert_eq!(a.len(), 10, "ten bounces: {a:?}");
    for (i, &top) in a.iter().enumerate() {
        assert!((top - h).abs() < 0.005 * h, "bounce {i}: apex {top} m, dropped from {h} m");
        assert!(top <= h * (1.0 + 1e-9), "bounce {i}: apex {top} m above the drop height {h} m");
    }
}

#[test]
fn bounce_at_a_coarse_step_still_reaches_e_squared_h() {
    // dt = 1/60: the collision time inside the step is found, not rounded to the step
    let h = 1.0;
    let e = 0.9;
    let first = apexes(h, e, 1, 1.0 / 60.0)[0];
    println!("rebound e = {e}, h = {h} m, dt = 1/60: {first:.7} m (e² h = {} m)", e * e * h);
    let rel = (first - e * e * h).abs() / (e * e * h);
    assert!(rel < 0.01, "rebound {first} m, expected {} m", e * e * h);
}
