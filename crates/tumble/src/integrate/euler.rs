//! First-order integrators: explicit Euler and semi-implicit (symplectic) Euler.
//!
//! References: E. Hairer, C. Lubich, G. Wanner, *Geometric Numerical Integration*, 2nd ed., §I.1
//! (symplectic Euler); E. Catto, "Numerical methods", GDC 2015 (implicit gyroscopic term).

use super::{euler_stage, renormalize, BodyRhs};
use crate::body::dynamics::resultant;
use crate::body::BodyState;
use crate::math::{quat_exp, DVec3};

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

/// Solves `I (ω' − ω) + h ω' × (I ω') = 0` for `ω'` (body frame, rad/s): one Newton step from
/// `ω' = ω` (Catto's linearisation), its 3×3 system solved by two terms of the Neumann series.
///
/// Residual at `ω`: `F = h ω × I ω`; Jacobian `J = I + h (ω̃ I − (I ω)~) = D + N`. With
/// `D = diag(I1, I2, I3)` and `a = h (I3 − I2)`, `b = h (I1 − I3)`, `c = h (I2 − I1)`:
///
/// ```text
///     [ 0      a ω3   a ω2 ]              [ a ω2 ω3 ]
/// N = [ b ω3   0      b ω1 ],   F   =     [ b ω3 ω1 ]
///     [ c ω2   c ω1   0    ]              [ c ω1 ω2 ]
/// ```
///
/// `δ = J⁻¹ F ≈ D⁻¹ (F − N D⁻¹ F)`, `ω' = ω − δ`. `|D⁻¹ N| = O(h|ω|)`, so the dropped Neumann term
/// and the Newton step's own error are both `O((h|ω|)³)` relative, below the method's `O((h|ω|)²)`
/// local error and below the dissipation of the implicit step, which is what keeps the kinetic
/// energy from growing. No division: `D⁻¹ = I_body⁻¹` is a constant of the body.
#[inline]
pub fn implicit_gyroscopic(inertia_body: DVec3, inv_inertia_body: DVec3, omega_body: DVec3, h: f64) -> DVec3 {
    let (i, w) = (inertia_body, omega_body);
    let (a, b, c) = (h * (i.z - i.y), h * (i.x - i.z), h * (i.y - i.x));
    // F = h ω × I ω
    let residual = DVec3::new(a * w.y * w.z, b * w.z * w.x, c * w.x * w.y);
    // δ₀ = D⁻¹ F ;  δ = D⁻¹ (F − N δ₀)
    let d0 = residual * inv_inertia_body;
    let n_d0 = DVec3::new(a * (w.z * d0.y + w.y * d0.z), b * (w.z * d0.x + w.x * d0.z), c * (w.y * d0.x + w.x * d0.y));
    w - (residual - n_d0) * inv_inertia_body
}
