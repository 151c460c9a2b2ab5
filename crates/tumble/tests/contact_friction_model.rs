//! The friction model per manifold (`friction_model = "manifold"`: one friction disc at the centre
//! of a manifold's points and one twist row about its normal), against the analytic answers that
//! friction at the points gives: the incline (sticking and sliding), the sliding stop distance, a
//! spinning box's stop time; and the contact impulses it reports.

mod contact_support;
use contact_support::*;
use tumble::contact::FrictionModel;
use tumble::math::{DQuat, DVec3};
use tumble::World;

const G: f64 = 9.81;
const DT: f64 = 1e-3;

fn with_model(mut w: World, model: FrictionModel) -> World {
    w.config.contact.friction_model = model;
    w
}

/// A box of half extents `h` on a plane tilted by `theta` about world x, friction `mu`, no
/// restitution, with `spin` (rad/s) about the plane's normal and `speed` (m/s) along world x; the
/// world and the box's start.
fn on_plane(theta: f64, h: DVec3, mu: f64, spin: f64, speed: f64, model: FrictionModel) -> (World, DVec3) {
    let tilt = DQuat::from_rotation_x(theta);
    let up = tilt * DVec3::Z;
    let start = up * h.z;
    let mut b = material(cuboid("box", h, 1.0, start), mu, 0.0);
    b.state.orientation = tilt;
    b.state.velocity = speed * DVec3::X;
    b.set_omega_world(spin * up);
    let floor = material(ground(tilt), mu, 0.0);
    (with_model(world(DT, DVec3::new(0.0, 0.0, -G), vec![floor, b]), model), start)
}

fn run(w: &mut World, seconds: f64) {
    for _ in 0..(seconds / DT).round() as usize {
        w.step().unwrap();
    }
}

#[test]
fn box_on_an_incline_sticks_when_mu_exceeds_tan_theta() {
    let theta: f64 = 20f64.to_radians();
    let (mut w, start) = on_plane(theta, DVec3::splat(0.25), 1.2 * theta.tan(), 0.0, 0.0, FrictionModel::Manifold);
    run(&mut w, 5.0);
    let creep = (w.bodies[1].state.position - start).length();
    eprintln!("manifold friction, incline 20°, μ = 1.2 tan θ: creep {creep:e} m in 5 s");
    assert!(creep < 1e-3, "creep {creep} m in 5 s");
}

#[test]
fn box_on_an_incline_slides_with_g_sin_minus_mu_cos() {
    let (theta, mu, t): (f64, f64, f64) = (30f64.to_radians(), 0.3, 1.0);
    let (mut w, start) = on_plane(theta, DVec3::splat(0.25), mu, 0.0, 0.0, FrictionModel::Manifold);
    run(&mut w, t);
    let down = DQuat::from_rotation_x(theta) * DVec3::NEG_Y;
    let s = w.bodies[1].state;
    let a = G * (theta.sin() - mu * theta.cos());
    let (a_from_v, a_from_s) = (s.velocity.dot(down) / t, 2.0 * (s.position - start).dot(down) / (t * t));
    eprintln!(
        "manifold friction, incline 30°, μ = 0.3: a from v {a_from_v:.5}, from s {a_from_s:.5}, expected {a:.5} m/s²"
    );
    assert!((a_from_v - a).abs() < 0.01 * a, "acceleration from v: {a_from_v} vs {a} m/s²");
    assert!((a_from_s - a).abs() < 0.01 * a, "acceleration from s: {a_from_s} vs {a} m/s²");
}

#[test]
fn sliding_box_stops_after_v_squared_over_two_mu_g() {
    let (v0, mu) = (3.0, 0.4);
    let h = DVec3::new(0.2, 0.2, 0.1);
    let (mut w, start) = on_plane(0.0, h, mu, 0.0, v0, FrictionModel::Manifold);
    run(&mut w, 1.5 * v0 / (mu * G));
    let s = w.bodies[1].state;
    assert!(s.velocity.length() < 1e-6, "still moving: {:?}", s.velocity);
    let d = (s.position - start).length();
    let expected = v0 * v0 / (2.0 * mu * G);
    eprintln!("manifold friction, slide v0 = 3, μ = 0.4: stopped after {d:.5} m, expected {expected:.5} m");
    assert!((d - expected).abs() < 0.01 * expected, "stopped after {d} m, expected {expected} m");
    let off = (s.position - start).y.atan2((s.position - start).x).to_degrees();
    assert!(off.abs() < 0.01, "left its line by {off}°");
}

/// The time a box of half extents `h` spinning at `spin` on flat ground takes to stop (s), and its
/// drift from its start (m).
fn spin_down(h: DVec3, mu: f64, spin: f64, model: FrictionModel) -> (f64, f64) {
    let (mut w, start) = on_plane(0.0, h, mu, spin, 0.0, model);
    let mut t = 0.0;
    while w.bodies[1].state.omega_world().z > 1e-6 * spin {
        w.step().unwrap();
        t += DT;
        assert!(t < 10.0, "still spinning at {:?}", w.bodies[1].state.omega_world());
    }
    (t, (w.bodies[1].state.position - start).length())
}

/// A box spinning about the vertical on its face: friction at its four corners, each at the distance
/// `ρ = √(h_x² + h_y²)` from the axis and carrying a quarter of the weight, gives the torque
/// `μ m g ρ`; with `I_zz = m ρ²/3` the spin falls at `α = 3 μ g/ρ` and stops after `ω₀ ρ/(3 μ g)`.
/// The twist row of the manifold model holds `μ ρ̄ Σλ_n` with `ρ̄` the mean distance of the points
/// from their centre — the same torque here — and stops the box at the same time as friction at
/// the points does.
#[test]
fn spinning_box_stops_after_omega_rho_over_three_mu_g() {
    let (h, mu, spin) = (DVec3::new(0.3, 0.2, 0.1), 0.5, 6.0);
    let rho = (h.x * h.x + h.y * h.y).sqrt();
    let expected = spin * rho / (3.0 * mu * G);
    let (t_manifold, drift) = spin_down(h, mu, spin, FrictionModel::Manifold);
    let (t_point, drift_point) = spin_down(h, mu, spin, FrictionModel::Point);
    eprintln!(
        "spin-down: manifold {t_manifold:.4} s (drift {drift:e} m), point {t_point:.4} s (drift {drift_point:e} m), expected {expected:.4} s"
    );
    assert!((t_manifold - expected).abs() < 0.01 * expected, "manifold: {t_manifold} s, expected {expected} s");
    assert!((t_point - expected).abs() < 0.01 * expected, "point: {t_point} s, expected {expected} s");
    // it spins in place: the centre moves by less than 1e-3 of the path of a corner, ω₀ ρ t/2
    let path = 0.5 * spin * rho * expected;
    assert!(drift < 1e-3 * path, "the spinning box drifted {drift} m (a corner's path {path} m)");
}

/// A box at rest on the incline: the contacts' reported impulses over a step add up to the
/// weight's `m g dt` (against gravity), in both models, and the friction part to `m g sin θ dt`
/// along the slope.
#[test]
fn reported_impulses_add_up_to_the_weight_in_both_models() {
    let theta: f64 = 20f64.to_radians();
    for model in [FrictionModel::Manifold, FrictionModel::Point] {
        let (mut w, _) = on_plane(theta, DVec3::splat(0.25), 0.8, 0.0, 0.0, model);
        w.config.contact.sleep = false;
        run(&mut w, 1.0);
        let total: DVec3 = w.contacts().active().map(|(c, p)| if c.b == 1 { p } else { -p }).sum();
        let weight = DVec3::new(0.0, 0.0, G * DT);
        let up = DQuat::from_rotation_x(theta) * DVec3::Z;
        let along = total - total.dot(up) * up;
        eprintln!("{model:?}: impulses {total:?} N·s, along the slope {:.6e}", along.length());
        assert!((total - weight).length() < 1e-6 * weight.length(), "{model:?}: {total:?} against {weight:?}");
        assert!((along.length() - G * theta.sin() * DT).abs() < 1e-6 * G * DT, "{model:?}: friction {along:?}");
    }
}
