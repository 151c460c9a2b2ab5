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
/// term is taken implicitly, `I (ω' − ω₁) + h ω' × I ω' = 0`, solved by Newton's method
/// ([`implicit_gyroscopic`]); then `q ← q ⊗ exp(h ω'_body)`.
///
/// The implicit gyroscopic step never increases the rotational kinetic energy nor `|L|`: dotting
/// the equation with `ω'` gives `2T' = ω'ᵀ I ω₁ ≤ √(2T' · 2T₁)` (Cauchy–Schwarz in the `I` inner product),
/// so `T' ≤ T₁`; explicit Euler on the same term makes the energy grow.
#[inline]
pub fn semi_implicit_euler_step(rhs: &BodyRhs, state: &mut BodyState, h: f64) {
    let (force_world, torque_body) = resultant(rhs.mass, rhs.loads, state, rhs.gravity_world);
    let inertia_body = rhs.mass.inertia_body;
    // v ← v + h f/m ;  x ← x + h v
    state.velocity += (h / rhs.mass.mass) * force_world;
    state.position += h * state.velocity;
    // ω₁ = ω + h I⁻¹ τ ;  I (ω' − ω₁) + h ω' × I ω' = 0
    let omega_kicked = state.omega_body + h * torque_body / inertia_body;
    state.omega_body = implicit_gyroscopic(inertia_body, omega_kicked, h);
    // q ← q ⊗ exp(h ω'_body)
    state.orientation = renormalize(state.orientation * quat_exp(h * state.omega_body));
}

/// Solves `I (ω' − ω) + h ω' × (I ω') = 0` for `ω'` (body frame, rad/s) by Newton's method from `ω' = ω`.
///
/// Residual `F(ω') = I (ω' − ω) + h ω' × I ω'`, Jacobian `J = I + h (ω̃' I − (I ω')~)`.
/// Two iterations: the first is Catto's single step (error `O(h²|ω|²)` relative), the second brings
/// the residual to `O(h⁴)`, well below the method's own `O(h²)` local error.
///
/// When the body turns by a radian or more per step (`h |ω| ≳ 0.2`), two plain Newton steps can land
/// far from the solution, and only the solution has `T' ≤ T` and `|L'| ≤ |L|`: if the residual is still
/// above `1e-3 |I ω|`, or the energy or `|L|` rose, the solve is redone by continuation in the step ([`finish_implicit_gyroscopic`]).
/// At ordinary steps the residual after two iterations is `O((h|ω|)⁴ |I ω|)`, far below that threshold,
/// and the result is exactly the two-iteration one.
#[inline]
pub fn implicit_gyroscopic(inertia_body: DVec3, omega_body: DVec3, h: f64) -> DVec3 {
    let inertia = DMat3::from_diagonal(inertia_body);
    let mut omega = omega_body;
    for _ in 0..2 {
        let l = inertia_body * omega;
        let residual = inertia_body * (omega - omega_body) + h * omega.cross(l);
        let jacobian = inertia + h * (skew(omega) * inertia - skew(l));
        omega -= jacobian.inverse() * residual;
    }
    // converged (|F| ≤ 1e-3 |L|), and neither T nor |L| rose: compared in squares, no square roots
    let (l_before, l_after) = (inertia_body * omega_body, inertia_body * omega);
    let residual = l_after - l_before + h * omega.cross(l_after);
    let converged = residual.length_squared() <= 1e-6 * l_before.length_squared();
    let kept = omega.dot(l_after) <= omega_body.dot(l_before) && l_after.length_squared() <= l_before.length_squared();
    if !(converged && kept) {
        return finish_implicit_gyroscopic(inertia_body, omega_body, h);
    }
    omega
}

/// Solves `I (ω' − ω) + h ω' × (I ω') = 0` when a body turns by a radian or more per step, by
/// continuation in the step: the solution for `h_k = k h / n` (`n` stages of at most 0.05 rad each,
/// where Newton's method converges fast) starts Newton's method for `h_{k+1}`, following the branch
/// that starts at `ω' = ω` for `h = 0`. Each stage iterates until the Newton update stops shrinking.
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
