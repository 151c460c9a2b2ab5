//! Kinetic and potential energy and the centre of mass of a tree.
//!
//! - `T = ½ Σ v_iᵀ I_i v_i + ½ Σ a_k v_k²` (body frames; Featherstone (2008) §2.13, (2.67); `a_k` the
//!   joints' armature, so that `T = ½ vᵀ M v` with CRBA's `M`) (J);
//! - `V = −Σ m_i g · c_i` with `c_i` the centre of mass of body `i` in the world (J, zero at the
//!   world origin), plus the joint springs' `½ k (q − q_ref)²`; what is fixed to the world is left
//!   out (it is constant);
//! - centre of mass `Σ m_i c_i / Σ m_i` over the moving bodies (world frame, m).

use super::fk::{forward_kinematics, update_placements};
use super::model::MultibodyModel;
use super::workspace::{LengthError, Workspace};
use crate::math::DVec3;

/// Kinetic energy `T(q, v)` (J).
pub fn kinetic_energy(model: &MultibodyModel, ws: &mut Workspace, q: &[f64], v: &[f64]) -> Result<f64, LengthError> {
    forward_kinematics(model, ws, q, v)?;
    // T = ½ Σ v_iᵀ I_i v_i
    let t: f64 = model.bodies.iter().zip(&ws.v).map(|(b, v_i)| b.inertia.kinetic_energy(*v_i)).sum();
    Ok(t + armature_energy(model, v))
}

/// The kinetic energy of the joints' armature (their rotors' reflected inertia), `½ Σ a_k v_k²`
/// (J); zero for a model without armature (every URDF model). `v` has length nv.
pub fn armature_energy(model: &MultibodyModel, v: &[f64]) -> f64 {
    let mut t = 0.0;
    for b in model.bodies.iter().filter(|b| b.joint.dynamics.armature != 0.0) {
        let j = &b.joint;
        t += 0.5 * j.dynamics.armature * v[j.v_index..j.v_index + j.kind.nv()].iter().map(|x| x * x).sum::<f64>();
    }
    t
}

/// Gravitational potential energy `V(q) = −Σ m_i g · c_i` of the moving bodies (J).
pub fn potential_energy(model: &MultibodyModel, ws: &mut Workspace, q: &[f64]) -> Result<f64, LengthError> {
    update_placements(model, ws, q)?;
    let mut v = 0.0;
    for (b, x) in model.bodies.iter().zip(&ws.x_world) {
        // c_i in the world: 0_X_i c_i
        let c_world = x.inv_apply_point(b.inertia.com());
        v -= b.inertia.mass * model.gravity.dot(c_world);
    }
    for b in model.bodies.iter().filter(|b| b.joint.dynamics.stiffness != 0.0) {
        // + ½ k (q − q_ref)²
        let dq = q[b.joint.q_index] - b.joint.dynamics.spring_ref;
        v += 0.5 * b.joint.dynamics.stiffness * dq * dq;
    }
    Ok(v)
}

/// Centre of mass of the moving bodies, world frame (m); the origin if they have no mass.
pub fn center_of_mass(model: &MultibodyModel, ws: &mut Workspace, q: &[f64]) -> Result<DVec3, LengthError> {
    update_placements(model, ws, q)?;
    let mut m = 0.0;
    let mut h = DVec3::ZERO;
    for (b, x) in model.bodies.iter().zip(&ws.x_world) {
        m += b.inertia.mass;
        h += b.inertia.mass * x.inv_apply_point(b.inertia.com());
    }
    Ok(if m > 0.0 { h / m } else { DVec3::ZERO })
}
