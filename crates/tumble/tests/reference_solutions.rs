//! The integrators against the exact torque-free solution (Jacobi elliptic functions,
//! `tumble::analytic`): observed order, `dopri5`'s tolerance, long-time agreement, conservation over
//! 10⁵ steps and the intermediate-axis flip interval.
//!
//! Errors are angular-velocity errors, `|ω_body − ω_exact| / |ω_body(0)|`. A body spun near its
//! intermediate axis is the hard case: it spends most of its time near an unstable rotation, where
//! any error in phase is amplified, and it flips quickly, where a phase error becomes a large error
//! in `ω`.

mod common;

use common::*;
use tumble::analytic::{AsymmetricTop, Regime};
use tumble::integrate::Tolerances;
use tumble::math::DVec3;
use tumble::{Integrator, World};

/// Errors against the exact solution over a run of `duration` seconds.
struct Errors {
    /// The largest relative angular-velocity error, `|ω − ω_exact| / |ω(0)|`.
    max_omega: f64,
    /// The relative angular-velocity error at the end.
    final_omega: f64,
    /// The largest orientation error: the angle of `q_exact⁻¹ q` (rad).
    max_orientation: f64,
    /// The orientation error at the end (rad).
    final_orientation: f64,
}

fn errors(world: &mut World, duration: f64) -> Errors {
    let s0 = world.bodies[0].state;
    let top = AsymmetricTop::new(INERTIA, s0.omega_body).unwrap().with_orientation(s0.orientation);
    let scale = s0.omega_body.length();
    let steps = (duration / world.config.dt).round() as u64;
    let mut e = Errors { max_omega: 0.0, final_omega: 0.0, max_orientation: 0.0, final_orientation: 0.0 };
    run(world, steps, |w| {
        let s = &w.bodies[0].state;
        e.final_omega = (s.omega_body - top.omega_body(w.time())).length() / scale;
        e.final_orientation = rotation_angle_between(s.orientation, top.orientation(w.time()));
        e.max_omega = e.max_omega.max(e.final_omega);
        e.max_orientation = e.max_orientation.max(e.final_orientation);
    });
    e
}

/// The largest relative angular-velocity error over a run of `duration` seconds, and the error at the end.
fn omega_errors(world: &mut World, duration: f64) -> (f64, f64) {
    let e = errors(world, duration);
    (e.max_omega, e.final_omega)
}

#[test]
fn observed_order_on_a_tumbling_body() {
    // error at t = 4 s for dt, dt/2, dt/4; the time steps keep every error far above round-off
    let cases = [
        (Integrator::Euler, 0.01),
        (Integrator::SemiImplicitEuler, 0.01),
        (Integrator::Rk4, 0.04),
        (Integrator::Splitting, 0.02),
        (Integrator::Splitting4, 0.04),
    ];
    let mut report = String::new();
    let mut failed = false;
    for (integrator, dt) in cases {
        let runs: Vec<Errors> = [dt, dt / 2.0, dt / 4.0]
            .iter()
            .map(|&h| {
                let mut world = torque_free(integrator, h, TUMBLING);
                errors(&mut world, 4.0)
            })
            .collect();
        let expected = integrator.order() as f64;
        for pair in runs.windows(2) {
            for (what, coarse, fine) in [
                ("ω", pair[0].final_omega, pair[1].final_omega),
                ("orientation", pair[0].final_orientation, pair[1].final_orientation),
            ] {
                let p = observed_order(coarse, fine);
                report += &format!(
                    "{integrator}: {what} errors {coarse:.3e} → {fine:.3e}, order {p:.3} (expected {expected})\n"
                );
                failed |= (p - expected).abs() > 0.3;
            }
        }
    }
    println!("{report}");
    assert!(!failed, "observed order outside ±0.3 of the theory:\n{report}");
}

#[test]
fn dopri5_error_scales_with_its_tolerance() {
    // Criterion: with the output step large enough (dt = 0.5 s) that the tolerance, not dt, sets the
    // internal step, and atol = 1e-3 rtol, the largest relative ω error over 20 s of tumbling stays
    // below 5 rtol, and the error falls in proportion to rtol (log-log slope 1 ± 0.2) over six decades.
    let rtols = [1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11];
    let mut errors = Vec::new();
    for rtol in rtols {
        let mut world = torque_free(Integrator::Dopri5, 0.5, TUMBLING);
        world.config.tolerances = Tolerances { rtol, atol: 1e-3 * rtol };
        let (max_error, _) = omega_errors(&mut world, 20.0);
        assert!(max_error <= 5.0 * rtol, "rtol {rtol:e}: max error {max_error:.3e} > 5 rtol");
        errors.push(max_error);
    }
    let n = rtols.len();
    let slope = (errors[0] / errors[n - 1]).log10() / (rtols[0] / rtols[n - 1]).log10();
    assert!((slope - 1.0).abs() <= 0.2, "error ∝ rtol^{slope:.3}, errors {errors:?}");
}

#[test]
fn rk4_and_dopri5_follow_the_jacobi_solution_for_20_seconds() {
    // 1e-8 relative for rk4 at dt = 1e-3 and for dopri5 at rtol = 1e-10, atol = 1e-13 (dt = 0.5 s: the
    // tolerance chooses the steps), from a generic state and from both sides of the separatrix
    // (and the orientation to 1e-8 rad)
    for omega0 in [TUMBLING, NEAR_AXIS2_ABOUT_3, NEAR_AXIS2_ABOUT_1] {
        let mut rk4 = torque_free(Integrator::Rk4, 1e-3, omega0);
        let mut dopri5 = torque_free(Integrator::Dopri5, 0.5, omega0);
        dopri5.config.tolerances = Tolerances { rtol: 1e-10, atol: 1e-13 };
        for (name, world) in [("rk4", &mut rk4), ("dopri5", &mut dopri5)] {
            let e = errors(world, 20.0);
            println!(
                "{name} from {omega0:?}: max ω error {:.3e}, max orientation error {:.3e} rad",
                e.max_omega, e.max_orientation
            );
            assert!(e.max_omega <= 1e-8, "{name} from {omega0:?}: max relative ω error {:.3e} over 20 s", e.max_omega);
            assert!(
                e.max_orientation <= 1e-8,
                "{name} from {omega0:?}: max orientation error {:.3e} rad",
                e.max_orientation
            );
        }
    }
}

#[test]
fn splitting_keeps_angular_momentum_and_bounded_energy_over_1e5_steps() {
    for omega0 in [NEAR_AXIS2_ABOUT_3, NEAR_AXIS2_ABOUT_1] {
        let dt = 0.01;
        let steps: u64 = 100_000;
        let mut world = torque_free(Integrator::Splitting, dt, omega0);
        let l0 = world.angular_momentum();
        let e0 = world.energy();
        let (mut magnitude_error, mut direction_error): (f64, f64) = (0.0, 0.0);
        let mut energy_error_by_tenth = [0.0f64; 10];
        let mut step = 0;
        run(&mut world, steps, |w| {
            let l = w.angular_momentum();
            magnitude_error = magnitude_error.max((l.length() - l0.length()).abs() / l0.length());
            // the angle between L and L(0)
            direction_error = direction_error.max(l.normalize().cross(l0.normalize()).length());
            let tenth = (step * 10 / steps) as usize;
            energy_error_by_tenth[tenth] = energy_error_by_tenth[tenth].max(((w.energy() - e0) / e0).abs());
            step += 1;
        });
        assert!(magnitude_error <= 1e-12, "{omega0:?}: |L_world| relative error {magnitude_error:.3e}");
        assert!(direction_error <= 1e-12, "{omega0:?}: L_world direction error {direction_error:.3e} rad");
        // bounded, not drifting: the last tenth's worst energy error is no worse than the first's
        // (5 % slack), and stays a small multiple of the 2nd-order scale (h |ω|)² = 2.5e-3
        let (first, last) = (energy_error_by_tenth[0], energy_error_by_tenth[9]);
        assert!(last <= 1.05 * first, "{omega0:?}: energy error grew from {first:.3e} to {last:.3e}");
        let worst = energy_error_by_tenth.iter().cloned().fold(0.0, f64::max);
        assert!(worst <= 0.1 * (dt * omega0.length()).powi(2), "{omega0:?}: energy error {worst:.3e}");
    }
}

/// Times (s) at which `ω2` changes sign, linearly interpolated between steps.
fn flip_times(world: &mut World, duration: f64) -> Vec<f64> {
    let dt = world.config.dt;
    let mut previous = world.bodies[0].state.omega_body.y;
    let mut flips = Vec::new();
    run(world, (duration / dt).round() as u64, |w| {
        let current = w.bodies[0].state.omega_body.y;
        if current * previous < 0.0 {
            let t_before = w.time() - dt;
            flips.push(t_before + dt * previous / (previous - current));
        }
        previous = current;
    });
    flips
}

#[test]
fn intermediate_axis_flip_interval_is_2k_over_lambda() {
    for (omega0, regime) in [(NEAR_AXIS2_ABOUT_3, Regime::AboutAxis3), (NEAR_AXIS2_ABOUT_1, Regime::AboutAxis1)] {
        let top = AsymmetricTop::new(INERTIA, omega0).unwrap();
        assert_eq!(top.regime(), regime);
        let exact = top.flip_interval();
        for integrator in [Integrator::Splitting, Integrator::Rk4] {
            let mut world = torque_free(integrator, 1e-3, omega0);
            let flips = flip_times(&mut world, 60.0);
            // 60 s hold eleven or twelve flip intervals
            assert!(flips.len() >= 11, "{integrator}: only {} flips in 60 s", flips.len());
            for pair in flips.windows(2) {
                let interval = pair[1] - pair[0];
                assert!(
                    (interval / exact - 1.0).abs() <= 1e-3,
                    "{integrator} from {omega0:?}: flip interval {interval:.7} s vs 2K/λ = {exact:.7} s"
                );
            }
        }
    }
}

#[test]
fn analytic_flip_interval_reproduces_the_worked_numbers() {
    let a = AsymmetricTop::new(INERTIA, NEAR_AXIS2_ABOUT_3).unwrap();
    assert_within(a.flip_interval(), 5.0259291, 1e-7, "flip interval, M² > 2E I2");
    let b = AsymmetricTop::new(INERTIA, NEAR_AXIS2_ABOUT_1).unwrap();
    assert_within(b.flip_interval(), 5.2660277, 1e-7, "flip interval, M² < 2E I2");
    // the analytic ω starts where the world starts
    for omega0 in [NEAR_AXIS2_ABOUT_3, NEAR_AXIS2_ABOUT_1, TUMBLING, DVec3::new(-0.3, -2.0, 1.7)] {
        let top = AsymmetricTop::new(INERTIA, omega0).unwrap();
        assert!((top.omega_body(0.0) - omega0).length() <= 1e-12 * omega0.length());
    }
}
