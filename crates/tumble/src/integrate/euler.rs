//! First-order integrators: explicit Euler and semi-implicit (symplectic) Euler.
//!
//! References: E. Hairer, C. Lubich, G. Wanner, *Geometric Numerical Integration*, 2nd ed., §I.1
//! (symplectic Euler); E. Catto, "Numerical methods", GDC 2015 (implicit gyroscopic term).

use super::{euler_stage, renormalize, BodyRhs};
use crate::body::dynamics::resultant;
use crate::body::BodyState;
use crate::math::{quat_exp, skew, DMat3, DVec3};

/// Explicit Euler, `y ← y + h f(y)`, every quantity from the start of the step.
///
/// First order, conserves nothing: the kinetic energy of a body tumbling about its intermediate axis
/// grows without bound (that is why it is here: as the baseline).
#[inline]
pub fn euler_step(rhs: &BodyRhs, state: &mut BodyState, h: f64) {
    let rate = rhs.rate(state);
    *state = euler_stage(state, &rate, h);
    state.orientation = renormalize(state.orientation);
}

/// Semi-implicit (symplectic) Euler.
///
/// Translation, symplectic Euler: `v ← v + h f(x, q, v)/m`, then `x ← x + h v`.
/// Rotation: the applied torque kicks `ω` explicitly, `ω₁ = ω + h I⁻¹ τ_body`, then the gyroscopic
/// term is taken implicitly, `I (ω' − ω₁) + h ω' × I ω' = 0`, linearised
/// ([`implicit_gyroscopic`]); then `q ← q ⊗ exp(h ω'_body)`.
///
/// The exact implicit gyroscopic step never increases the rotational kinetic energy nor `|L|`: dotting
/// the equation with `ω'` gives `2T' = ω'ᵀ I ω₁ ≤ √(2T' · 2T₁)` (Cauchy–Schwarz in the `I` inner
/// product), so `T' ≤ T₁`. The linearised solve keeps that behaviour while `h|ω|` is small (its error
/// is of higher order than the dissipation; tested over long tumbling runs); explicit Euler on the
/// same term makes the energy grow.
#[inline]
pub fn semi_implicit_euler_step(rhs: &BodyRhs, state: &mut BodyState, h: f64) {
    let (force_world, torque_body) = resultant(rhs.mass, rhs.loads, state, rhs.gravity_world);
    let inertia_body = rhs.mass.inertia_body;
    // v ← v + h f/m ;  x ← x + h v
    state.velocity += (h * rhs.mass.inv_mass) * force_world;
    state.position += h * state.velocity;
    // ω₁ = ω + h I⁻¹ τ ;  I (ω' − ω₁) + h ω' × I ω' = 0
    let omega_kicked = state.omega_body + h * torque_body * rhs.mass.inv_inertia_body;
    state.omega_body = implicit_gyroscopic(inertia_body, rhs.mass.inv_inertia_body, omega_kicked, h);
    // q ← q ⊗ exp(h ω'_body)
    state.orientation = renormalize(state.orientation * quat_exp(h * state.omega_body));
}

/// Solves `I (ω' − ω) + h ω' × (I ω') = 0` for `ω'` (body frame, rad/s).
///
/// The ordinary case is one Newton step from `ω' = ω` (Catto's linearisation), its 3×3 system solved
/// by two terms of the Neumann series. Residual at `ω`: `F = h ω × I ω`; Jacobian
/// `J = I + h (ω̃ I − (I ω)~) = D + N`. With `D = diag(I1, I2, I3)` and `a = h (I3 − I2)`,
/// `b = h (I1 − I3)`, `c = h (I2 − I1)`:
///
/// ```text
///     [ 0      a ω3   a ω2 ]              [ a ω2 ω3 ]
/// N = [ b ω3   0      b ω1 ],   F   =     [ b ω3 ω1 ]
///     [ c ω2   c ω1   0    ]              [ c ω1 ω2 ]
/// ```
///
/// `δ = J⁻¹ F ≈ D⁻¹ (F − N D⁻¹ F)`, `ω' = ω − δ`. `|D⁻¹ N| = O(h|ω|)`, so the dropped Neumann term and
/// the Newton step's own error are both `O((h|ω|)³)` relative: below the method's `O((h|ω|)²)` local
/// error, and a fraction `O(h|ω|)` of the energy the exact implicit step dissipates. No division:
/// `D⁻¹ = I_body⁻¹` is a constant of the body.
///
/// Only the exact solution is sure to have `T' ≤ T` and `|L'| ≤ |L|`. So the result is accepted when
/// neither `T` nor `|L|` rose by more than round-off (compared in squares: no square roots) and, for
/// steps that are not small, its residual is below `1e-3 |I ω|`; otherwise — when a body turns by a sizeable fraction of a radian per step — the equation is
/// solved to convergence by continuation in the step ([`finish_implicit_gyroscopic`]).
#[inline]
pub fn implicit_gyroscopic(inertia_body: DVec3, inv_inertia_body: DVec3, omega_body: DVec3, h: f64) -> DVec3 {
    let (i, w) = (inertia_body, omega_body);
    let (a, b, c) = (h * (i.z - i.y), h * (i.x - i.z), h * (i.y - i.x));
    // F = h ω × I ω
    let residual = DVec3::new(a * w.y * w.z, b * w.z * w.x, c * w.x * w.y);
    // δ₀ = D⁻¹ F ;  δ = D⁻¹ (F − N δ₀) ;  ω' = ω − δ
    let d0 = residual * inv_inertia_body;
    let n_d0 = DVec3::new(a * (w.z * d0.y + w.y * d0.z), b * (w.z * d0.x + w.x * d0.z), c * (w.y * d0.x + w.x * d0.y));
    let omega = w - (residual - n_d0) * inv_inertia_body;
    // accept when T' ≤ T and |L'| ≤ |L| (up to round-off: where the dissipation is below an ulp the
    // comparison is a coin toss), and, unless the step is small (|D⁻¹N| ≤ ε = h|ω|·ΔI/I_min below
    // 0.05, where the linearisation is accurate by construction), when |F(ω')| ≤ 1e-3 |I ω|
    let (l_before, l_after) = (i * w, i * omega);
    let round_off = 1.0 + 4.0 * f64::EPSILON;
    let kept = omega.dot(l_after) <= w.dot(l_before) * round_off
        && l_after.length_squared() <= l_before.length_squared() * round_off;
    let spread = (i.max_element() - i.min_element()) * inv_inertia_body.max_element();
    let small = h * h * w.length_squared() * spread * spread <= 0.05 * 0.05;
    let converged = small || {
        let residual_after = l_after - l_before + h * omega.cross(l_after);
        residual_after.length_squared() <= 1e-6 * l_before.length_squared()
    };
    if converged && kept {
        omega
    } else {
        finish_implicit_gyroscopic(inertia_body, omega_body, h)
    }
}

/// Solves `I (ω' − ω) + h ω' × (I ω') = 0` when a body turns by a radian or more per step, by
/// continuation in the step: the solution for `h_k = k h / n` (`n` stages of at most 0.05 rad each,
/// where Newton's method converges fast) starts Newton's method for `h_{k+1}`, following the branch
/// that starts at `ω' = ω` for `h = 0`. Each stage iterates until the Newton update stops shrinking.
#[cold]
#[inline(never)]
pub fn finish_implicit_gyroscopic(inertia_body: DVec3, omega_body: DVec3, h: f64) -> DVec3 {
    let inertia = DMat3::from_diagonal(inertia_body);
    let stages = (h * omega_body.length() / 0.05).ceil().clamp(1.0, 10_000.0) as usize;
    let mut omega = omega_body;
    for stage in 1..=stages {
        let h_stage = h * stage as f64 / stages as f64;
        let mut previous_update = f64::INFINITY;
        for _ in 0..20 {
            let l = inertia_body * omega;
            let residual = inertia_body * (omega - omega_body) + h_stage * omega.cross(l);
            let jacobian = inertia + h_stage * (skew(omega) * inertia - skew(l));
            let update = jacobian.inverse() * residual;
            omega -= update;
            let size = update.length();
            if size == 0.0 || size >= 0.5 * previous_update {
                break;
            }
            previous_update = size;
        }
    }
    omega
}
