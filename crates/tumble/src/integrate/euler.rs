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
    omega
}
