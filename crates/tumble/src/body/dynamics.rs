//! Newton–Euler equations of a free rigid body (the seed's §3).
//!
//! Translation (3.1)–(3.2): `ẋ = v`, `m v̇ = f_world`.
//!
//! Rotation, two equivalent forms:
//! - body frame, Euler's equations (3.4)–(3.6): `τ_body = I_body α_body + ω_body × (I_body ω_body)`,
//!   solved as `α_body = I_body⁻¹ (τ_body − ω_body × I_body ω_body)`; `I_body` is a constant
//!   diagonal matrix, so its inverse is three reciprocals ([`alpha_body`]);
//! - world frame (3.3): `τ_world = d/dt (I_world ω_world) = I_world α_world + ω_world × I_world ω_world`,
//!   with `I_world = R I_body Rᵀ` (1.2) recomputed and inverted at every evaluation ([`alpha_world`]).
//!
//! The integrators use the body form; the world form is kept for teaching and as a cross-check
//! (the two agree to round-off, see the tests, and `benches/rhs.rs` measures what the body form saves).

use super::{Frame, Loads, MassProperties};
use crate::body::BodyState;
use crate::math::{DMat3, DVec3};

/// Euler's equations in the body frame: `α_body = I_body⁻¹ (τ_body − ω_body × I_body ω_body)` (3.5) (rad/s²).
#[inline]
pub fn alpha_body(inertia_body: DVec3, omega_body: DVec3, torque_body: DVec3) -> DVec3 {
    (torque_body - omega_body.cross(inertia_body * omega_body)) / inertia_body
}

/// Euler's equation in the world frame: `α_world = I_world⁻¹ (τ_world − ω_world × I_world ω_world)` (3.3),
/// recomputing `I_world = R I_body Rᵀ` and its inverse (rad/s²).
#[inline]
pub fn alpha_world(world_from_body: DMat3, inertia_body: DVec3, omega_world: DVec3, torque_world: DVec3) -> DVec3 {
    let inertia_world = crate::math::inertia_world(world_from_body, inertia_body);
    let inv_inertia_world = inertia_world.inverse();
    inv_inertia_world * (torque_world - omega_world.cross(inertia_world * omega_world))
}

/// The resultant external force (world frame, N) and torque about the centre of mass (body frame, N·m)
/// on a body in `state`: gravity `m g`, constant forces and torques, point forces (`τ = p × f`),
/// and damping (`−c m v`, `−c I_body ω_body`).
#[inline]
pub fn resultant(mass: &MassProperties, loads: &Loads, state: &BodyState, gravity_world: DVec3) -> (DVec3, DVec3) {
    let (force_world, torque_body) = applied(mass, loads, state, gravity_world);
    (
        force_world - (loads.linear_damping * mass.mass) * state.velocity,
        torque_body - loads.angular_damping * (mass.inertia_body * state.omega_body),
    )
}

/// The loads that depend on position and orientation only (everything but damping): force (world
/// frame, N) and torque about the centre of mass (body frame, N·m).
#[inline]
pub fn applied(mass: &MassProperties, loads: &Loads, state: &BodyState, gravity_world: DVec3) -> (DVec3, DVec3) {
    let mut force_world = mass.mass * gravity_world + loads.force_world;
    let mut torque_body = loads.torque_body;
    if loads.needs_rotation() {
        let world_from_body = state.orientation;
        let body_from_world = world_from_body.conjugate();
        let mut force_body = loads.force_body;
        torque_body += body_from_world * loads.torque_world;
        for pf in &loads.point_forces {
            // τ_body = p_body × f_body
            let f_body = match pf.frame {
                Frame::Body => pf.force,
                Frame::World => body_from_world * pf.force,
            };
            force_body += f_body;
            torque_body += pf.point_body.cross(f_body);
        }
        force_world += world_from_body * force_body;
    }
    (force_world, torque_body)
}

/// The time derivative of a body's state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StateRate {
    /// `ẋ = v`, world frame (m/s).
    pub velocity: DVec3,
    /// `v̇ = f/m`, world frame (m/s²).
    pub acceleration: DVec3,
    /// `q̇ = ½ q ⊗ (0, ω_body)` as a 4-vector `(x, y, z, w)` (1/s).
    pub orientation_rate: glamx::DVec4,
    /// `ω̇_body = α_body`, body frame (rad/s²).
    pub alpha_body: DVec3,
}

/// The right-hand side of the Newton–Euler ODE (3.7) in the body-frame form.
#[inline]
pub fn state_rate(mass: &MassProperties, loads: &Loads, state: &BodyState, gravity_world: DVec3) -> StateRate {
    let (force_world, torque_body) = resultant(mass, loads, state, gravity_world);
    StateRate {
        velocity: state.velocity,
        acceleration: force_world * mass.inv_mass,
        orientation_rate: crate::math::quat_rate_body(state.orientation, state.omega_body),
        // α_body = I⁻¹ (τ_body − ω_body × I ω_body), with I⁻¹ computed once
        alpha_body: (torque_body - state.omega_body.cross(mass.inertia_body * state.omega_body))
            * mass.inv_inertia_body,
    }
}

#[cfg(test)]
mod tests;
