//! Symplectic Lie–Poisson splitting of the free rigid body, with kick–drift–kick for the loads,
//! and its 4th-order composition.
//!
//! References: A. Dullweber, B. Leimkuhler, R. McLachlan, "Symplectic splitting methods for rigid
//! body molecular dynamics", J. Chem. Phys. 107 (1997); R. McLachlan, "Explicit Lie–Poisson
//! integration and the Euler equations", Phys. Rev. Lett. 71 (1993); E. Hairer, C. Lubich,
//! G. Wanner, *Geometric Numerical Integration*, §VII.5; H. Yoshida, "Construction of higher order
//! symplectic integrators", Phys. Lett. A 150 (1990).
//!
//! With `L_body = I_body ω_body` the rotational kinetic energy is `T = Σ_i L_i² / (2 I_i)`. The
//! flow of each term `T_i` alone is an exact rotation about the body axis `i` at the constant rate
//! `L_i / I_i`: with `θ = t L_i / I_i`,
//!
//! `q ← q ⊗ (cos θ/2, sin θ/2 e_i)`, `L_body ← Rot_i(θ)ᵀ L_body` (so `L_world = R L_body` is unchanged).
//!
//! Strang composition of the free flow: `F(h) = X1(h/2) X2(h/2) X3(h) X2(h/2) X1(h/2)`.
//! Loads: `S2(h) = K(h/2) D(h) K(h/2)` where the drift `D` is `x ← x + h v` together with `F(h)`, and
//! the kick `K` integrates the loads with the position and orientation frozen — exactly, including
//! damping: `v̇ = f/m − c v` gives `v ← e^(−ch) v + (1 − e^(−ch))/c · f/m` (and likewise
//! `L̇_body = τ_body − c L_body`).
//! Every sub-step is a rotation or an exact flow: `L_world` of a torque-free body is kept to
//! round-off, `|q| = 1` up to round-off, and the energy error stays bounded for all time.
//! `S4(h) = S2(w1 h) S2(w0 h) S2(w1 h)` with `w1 = 1/(2 − 2^(1/3))`, `w0 = 1 − 2 w1` (Yoshida).

use super::{renormalize, BodyRhs};
use crate::body::dynamics::applied;
use crate::body::BodyState;
use crate::math::{DQuat, DVec3};

/// Yoshida's triple-jump weights: `w1 = 1/(2 − 2^(1/3))`, `w0 = −2^(1/3)/(2 − 2^(1/3))`.
pub const YOSHIDA_W1: f64 = 1.351_207_191_959_657_8;
/// See [`YOSHIDA_W1`].
pub const YOSHIDA_W0: f64 = -1.702_414_383_919_315_3;

/// One step of the second-order splitting `K(h/2) D(h) K(h/2)`.
#[inline]
pub fn splitting_step(rhs: &BodyRhs, state: &mut BodyState, h: f64) {
    let mut l_body = rhs.mass.inertia_body * state.omega_body;
    s2(rhs, state, &mut l_body, h);
    // ω = L / I by division: with the cached reciprocal, the round trip L → ω → L would carry the
    // fixed rounding error of 1/I into |L| at every step, a drift instead of round-off
    state.omega_body = l_body / rhs.mass.inertia_body;
    state.orientation = renormalize(state.orientation);
}

/// One step of the fourth-order composition `S2(w1 h) S2(w0 h) S2(w1 h)`.
#[inline]
pub fn splitting4_step(rhs: &BodyRhs, state: &mut BodyState, h: f64) {
    let mut l_body = rhs.mass.inertia_body * state.omega_body;
    s2(rhs, state, &mut l_body, YOSHIDA_W1 * h);
    s2(rhs, state, &mut l_body, YOSHIDA_W0 * h);
    s2(rhs, state, &mut l_body, YOSHIDA_W1 * h);
    state.omega_body = l_body / rhs.mass.inertia_body;
    state.orientation = renormalize(state.orientation);
}

#[inline]
fn s2(rhs: &BodyRhs, state: &mut BodyState, l_body: &mut DVec3, h: f64) {
    let loaded = rhs.gravity_world != DVec3::ZERO || !rhs.loads.is_empty();
    if loaded {
        kick(rhs, state, l_body, 0.5 * h);
    }
    // drift: x ← x + h v, and the free rotation F(h)
    state.position += h * state.velocity;
    free_rotation(rhs.mass.inv_inertia_body, &mut state.orientation, l_body, h);
    if loaded {
        kick(rhs, state, l_body, 0.5 * h);
    }
}

/// The free rotation `X1(h/2) X2(h/2) X3(h) X2(h/2) X1(h/2)`: exact sub-rotations about the
/// principal axes (`inv_inertia_body`: the reciprocal principal moments, 1/(kg·m²)).
#[inline]
pub fn free_rotation(inv_inertia_body: DVec3, orientation: &mut DQuat, l_body: &mut DVec3, h: f64) {
    axis_rotation::<0>(inv_inertia_body, orientation, l_body, 0.5 * h);
    axis_rotation::<1>(inv_inertia_body, orientation, l_body, 0.5 * h);
    axis_rotation::<2>(inv_inertia_body, orientation, l_body, h);
    axis_rotation::<1>(inv_inertia_body, orientation, l_body, 0.5 * h);
    axis_rotation::<0>(inv_inertia_body, orientation, l_body, 0.5 * h);
}

/// The exact flow of `T_i = L_i²/(2 I_i)` for a time `t`: a rotation by `θ = t L_i / I_i` about body axis `i`.
#[inline]
fn axis_rotation<const I: usize>(inv_inertia_body: DVec3, q: &mut DQuat, l_body: &mut DVec3, t: f64) {
    let theta = t * l_body[I] * inv_inertia_body[I];
    let (s, c) = (0.5 * theta).sin_cos();
    // q ← q ⊗ (cos θ/2, sin θ/2 e_i)
    let r = match I {
        0 => DQuat::from_xyzw(s, 0.0, 0.0, c),
        1 => DQuat::from_xyzw(0.0, s, 0.0, c),
        _ => DQuat::from_xyzw(0.0, 0.0, s, c),
    };
    *q *= r;
    // L ← Rot_i(θ)ᵀ L: the two other components turn by −θ
    let (j, k) = ((I + 1) % 3, (I + 2) % 3);
    let (cos_t, sin_t) = (c * c - s * s, 2.0 * s * c);
    let (lj, lk) = (l_body[j], l_body[k]);
    l_body[j] = cos_t * lj + sin_t * lk;
    l_body[k] = -sin_t * lj + cos_t * lk;
}

/// The kick: loads integrated for a time `t` with `x` and `q` frozen, damping included exactly.
#[inline]
fn kick(rhs: &BodyRhs, state: &mut BodyState, l_body: &mut DVec3, t: f64) {
    let loads = rhs.loads;
    let (force_world, torque_body) = applied(rhs.mass, loads, state, rhs.gravity_world);
    // v̇ = f/m − c v  ⇒  v ← e^(−ct) v + φ(c, t) f/m,   φ(c, t) = (1 − e^(−ct))/c
    state.velocity = decay(loads.linear_damping, t) * state.velocity
        + phi(loads.linear_damping, t) * (force_world * rhs.mass.inv_mass);
    // L̇ = τ − c L  ⇒  L ← e^(−ct) L + φ(c, t) τ
    *l_body = decay(loads.angular_damping, t) * *l_body + phi(loads.angular_damping, t) * torque_body;
}

#[inline]
fn decay(c: f64, t: f64) -> f64 {
    if c == 0.0 {
        1.0
    } else {
        (-c * t).exp()
    }
}

/// `(1 − e^(−ct))/c`, which tends to `t` as `c → 0`.
#[inline]
fn phi(c: f64, t: f64) -> f64 {
    if c == 0.0 {
        t
    } else {
        -(-c * t).exp_m1() / c
    }
}
