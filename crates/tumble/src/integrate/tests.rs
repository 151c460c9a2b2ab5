//! Unit tests of the integrators' building blocks (the whole integrators are tested against exact
//! solutions in `tests/integrators.rs` and `tests/reference_solutions.rs`).

use super::*;
use crate::math::{quat_exp, DVec3};

#[test]
fn names_round_trip_and_unknown_names_are_rejected() {
    for integrator in Integrator::ALL {
        assert_eq!(integrator.name().parse::<Integrator>(), Ok(integrator));
        assert_eq!(integrator.to_string(), integrator.name());
    }
    let err = "leapfrog".parse::<Integrator>().unwrap_err();
    assert!(err.to_string().contains("leapfrog") && err.to_string().contains("splitting4"));
}

#[test]
fn renormalize_squares_the_length_error() {
    let q = quat_exp(DVec3::new(0.3, -1.2, 0.8));
    for eps in [1e-3, 1e-5, 1e-7] {
        let r = renormalize(q * (1.0 + eps));
        // one Newton step of |q|² = 1: the error becomes ~ (3/2) eps²
        assert!((r.length() - 1.0).abs() <= 2.0 * eps * eps + 4.0 * f64::EPSILON, "eps {eps:e}: {}", r.length());
        // and the direction is untouched
        assert!((r.normalize() - q).length() <= 4.0 * f64::EPSILON);
    }
    // far from unit length: exact normalisation
    assert!((renormalize(q * 3.0).length() - 1.0).abs() <= 4.0 * f64::EPSILON);
}

#[test]
fn implicit_gyroscopic_step_solves_its_equation_and_never_adds_energy() {
    let inertia = DVec3::new(1.0, 2.0, 3.0);
    for (omega, h) in
        [(DVec3::new(1.0, 0.5, -0.8), 1e-3), (DVec3::new(0.01, 5.0, 0.01), 1e-2), (DVec3::new(3.0, -2.0, 1.0), 1e-2)]
    {
        let next = euler::implicit_gyroscopic(inertia, inertia.recip(), omega, h);
        let residual = inertia * (next - omega) + h * next.cross(inertia * next);
        let scale = h * (inertia * omega).length() * omega.length();
        // one Newton step: the residual is O((h|ω|)²) of h |Iω| |ω|, below the O(h²) local error of the scheme
        let turn = h * omega.length();
        assert!(residual.length() <= turn * turn * scale, "residual {residual:?} (scale {scale:e}, h|ω| = {turn})");
        let energy = |w: DVec3| w.dot(inertia * w);
        assert!(energy(next) <= energy(omega), "T' = {} > T = {}", energy(next), energy(omega));
        assert!((inertia * next).length() <= (inertia * omega).length());
    }
}

#[test]
fn free_rotation_keeps_world_angular_momentum() {
    let inertia = DVec3::new(1.0, 2.0, 3.0);
    let mut q = quat_exp(DVec3::new(0.2, 0.4, -0.3));
    let mut l_body = inertia * DVec3::new(1.0, 0.5, -0.8);
    let l_world = q * l_body;
    for _ in 0..1000 {
        splitting::free_rotation(inertia.recip(), &mut q, &mut l_body, 0.01);
    }
    assert!((q * l_body - l_world).length() <= 1e-13 * l_world.length());
    assert!((q.length() - 1.0).abs() <= 1e-13);
}

#[test]
fn yoshida_weights_cancel_the_third_order_error() {
    use splitting::{YOSHIDA_W0, YOSHIDA_W1};
    // consistency 2 w1 + w0 = 1 and the 3rd-order condition 2 w1³ + w0³ = 0
    assert!((2.0 * YOSHIDA_W1 + YOSHIDA_W0 - 1.0).abs() <= 4.0 * f64::EPSILON);
    assert!((2.0 * YOSHIDA_W1.powi(3) + YOSHIDA_W0.powi(3)).abs() <= 32.0 * f64::EPSILON);
}

/// A small deterministic generator (xorshift) for sampled checks.
fn uniform(state: &mut u64, lo: f64, hi: f64) -> f64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    lo + (hi - lo) * ((*state >> 11) as f64 / (1u64 << 53) as f64)
}

#[test]
fn implicit_gyroscopic_step_converges_at_several_radians_per_step() {
    // regression: two plain Newton steps left the energy 5 E0 too high at h |ω| ≈ 3.5
    let mut seed = 0x9e3779b97f4a7c15u64;
    let mut worst_residual: f64 = 0.0;
    for _ in 0..2000 {
        let inertia =
            DVec3::new(uniform(&mut seed, 0.5, 1.0), uniform(&mut seed, 1.0, 2.0), uniform(&mut seed, 2.0, 2.9));
        let omega = DVec3::new(
            uniform(&mut seed, -10.0, 10.0),
            uniform(&mut seed, -10.0, 10.0),
            uniform(&mut seed, -10.0, 10.0),
        );
        let h = uniform(&mut seed, 0.0, 1.0);
        let next = euler::implicit_gyroscopic(inertia, inertia.recip(), omega, h);
        let residual = inertia * (next - omega) + h * next.cross(inertia * next);
        let momentum = (inertia * omega).length();
        worst_residual = worst_residual.max(residual.length() / momentum);
        // the continuation itself converges to round-off
        let solved = euler::finish_implicit_gyroscopic(inertia, omega, h);
        let solved_residual = inertia * (solved - omega) + h * solved.cross(inertia * solved);
        assert!(solved_residual.length() <= 1e-12 * momentum, "continuation: residual {solved_residual:?}, h = {h}");
        let energy = |w: DVec3| w.dot(inertia * w);
        assert!(energy(next) <= energy(omega) * (1.0 + 4.0 * f64::EPSILON), "T rose: ω = {omega:?}, h = {h}");
        assert!(
            (inertia * next).length() <= momentum * (1.0 + 4.0 * f64::EPSILON),
            "|L| rose by {:e}: ω = {omega:?}, h = {h}, residual {:e}",
            (inertia * next).length() / momentum - 1.0,
            residual.length() / momentum
        );
    }
    println!("worst residual {worst_residual:e} |I ω|");
    assert!(worst_residual <= 1e-3, "residual {worst_residual:e} |I ω|");
}

#[test]
fn implicit_gyroscopic_step_is_third_order_close_to_the_exact_solve_at_ordinary_steps() {
    // the linearised step (one Newton step, two Neumann terms) differs from the converged solution by
    // O((h|ω|)³)|ω|: with I = (1, 2, 3), |D⁻¹N| ≤ 2 h|ω| and |δ| ≤ 2 h|ω|²
    let inertia = DVec3::new(1.0, 2.0, 3.0);
    let mut seed = 0x2545f4914f6cdd1du64;
    for _ in 0..1000 {
        let omega =
            DVec3::new(uniform(&mut seed, -5.0, 5.0), uniform(&mut seed, -5.0, 5.0), uniform(&mut seed, -5.0, 5.0));
        let h = uniform(&mut seed, 0.0, 0.1 / omega.length());
        let turn = h * omega.length();
        let next = euler::implicit_gyroscopic(inertia, inertia.recip(), omega, h);
        let exact = euler::finish_implicit_gyroscopic(inertia, omega, h);
        let bound = 16.0 * turn.powi(3) * omega.length() + 8.0 * f64::EPSILON * omega.length();
        assert!((next - exact).length() <= bound, "h|ω| = {turn}: {:e} > {bound:e}", (next - exact).length());
    }
}

/// Regression: `ω = L · (1/I)` at the end of each splitting step carried the fixed rounding error of
/// the cached reciprocal into `|L|` at every step, a drift of about 2e-17 per step (2e-11 after 10⁶
/// steps); with `ω = L / I` the error is a random walk of round-off.
#[test]
fn splitting_keeps_the_angular_momentum_without_drift_over_a_million_steps() {
    let mass = crate::MassProperties::from_principal(1.0, DVec3::new(1.0, 2.0, 3.0)).unwrap();
    let loads = crate::body::Loads::default();
    let rhs = BodyRhs { mass: &mass, loads: &loads, gravity_world: DVec3::ZERO };
    let mut state = crate::BodyState { omega_body: DVec3::new(1.0, 0.5, -0.8), ..crate::BodyState::REST };
    let l_world = |s: &crate::BodyState| s.orientation * (mass.inertia_body * s.omega_body);
    let l0 = l_world(&state);
    let mut hint = 0.0;
    for _ in 0..1_000_000 {
        advance_body(Integrator::Splitting, Tolerances::default(), &rhs, &mut state, 0.01, &mut hint).unwrap();
    }
    let error = (l_world(&state) - l0).length() / l0.length();
    assert!(error <= 5e-12, "|ΔL|/|L| = {error:e} after 10⁶ steps");
}

/// The blocks' step ([`batch::step_blocks`]) in the portable lanes and in the dispatched ones (AVX
/// or AVX-512 where the CPU has them) against the scalar step, bit for bit over 100 steps: 19
/// bodies (two full blocks and one of three), spins fast enough for the implicit solve's
/// continuation and `quat_exp`'s `sin_cos`, a quaternion far from unit length.
#[test]
fn the_blocks_step_gives_the_scalar_bits_in_every_kind_of_lanes() {
    use crate::body::{MassProperties, RigidBody};
    use batch::{step_blocks, step_blocks_portable, Block, BLOCK};
    let bodies: Vec<RigidBody> = (0..19)
        .map(|i| {
            let f = i as f64 / 19.0;
            let mass = MassProperties::from_principal(1.0 + f, DVec3::new(1.0, 2.0 + f, 2.5 + f)).unwrap();
            let mut body = RigidBody::new(format!("b{i}"), mass);
            body.state.position = DVec3::new(f, -2.0 * f, 3.0);
            body.state.velocity = DVec3::new(0.5, f, -1.0);
            body.state.orientation = quat_exp(DVec3::new(f, 0.3, -f));
            body.state.omega_body = DVec3::new(0.3, 2.0 + 5.0 * f, 0.1) * if i % 5 == 0 { 800.0 } else { 1.0 };
            body.gravity_scale = 1.0 - f;
            body.loads.force_world = DVec3::new(f, 0.0, 1.0);
            body.loads.torque_body = DVec3::new(0.0, f, 0.2);
            body.loads.linear_damping = 0.1 * f;
            body.loads.angular_damping = 0.05;
            if i == 7 {
                body.state.orientation *= 1.01;
            }
            body
        })
        .collect();
    let (gravity, h) = (DVec3::new(0.1, 0.0, -9.81), 1e-3);
    let indices: Vec<usize> = (0..bodies.len()).collect();
    let blocks: Vec<Block> = indices.chunks(BLOCK).map(|group| Block::new(&bodies, group)).collect();
    let mut reference = bodies.clone();
    let mut runs = [(bodies.clone(), blocks.clone()), (bodies, blocks)];
    for step in 0..100 {
        for body in &mut reference {
            let rhs = BodyRhs { mass: &body.mass, loads: &body.loads, gravity_world: body.gravity(gravity) };
            euler::semi_implicit_euler_step(&rhs, &mut body.state, h);
        }
        let parity = step % 2;
        let [(portable, portable_blocks), (dispatched, dispatched_blocks)] = &mut runs;
        assert_eq!(step_blocks_portable(portable_blocks, parity, portable, gravity, h), Ok(()));
        assert_eq!(step_blocks(dispatched_blocks, parity, dispatched, gravity, h), Ok(()));
        let bits = |b: &RigidBody| {
            let (x, q, v, w) = (b.state.position, b.state.orientation, b.state.velocity, b.state.omega_body);
            [x.x, x.y, x.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, w.x, w.y, w.z].map(f64::to_bits)
        };
        for (name, list) in [("portable", &*portable), ("dispatched", &*dispatched)] {
            for (a, b) in list.iter().zip(&reference) {
                assert_eq!(bits(a), bits(b), "{name}, step {step}, {}", a.name);
            }
        }
    }
}
