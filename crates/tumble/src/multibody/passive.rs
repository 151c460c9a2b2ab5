//! The joints' passive forces: viscous damping and springs, MuJoCo's `qfrc_passive` for joints.
//!
//! Reference: E. Todorov, MuJoCo documentation, *Computation* (passive forces: "spring-dampers"),
//! here per velocity coordinate `k` of a joint with [`JointDynamics`](super::joint::JointDynamics):
//!
//! ```text
//! τ_passive,k = −d v_k − k_s (q_k − q_ref)      (the spring on one-coordinate joints only)
//! ```
//!
//! along each fixed tendon ([`super::tendon`]) `τ += J_tᵀ (−k (L − L_s) − d L̇)`, and the medium's
//! drag on the bodies ([`super::fluid`], MuJoCo's `qfrc_fluid`, which it counts in `qfrc_passive`).
//!
//! Inputs: `q` (nq), `v` (nv); the workspace serves the fluid forces only (a forward-kinematics
//! pass when the medium is not void). Output: `τ_passive` (nv; N·m or N), added to the joint forces
//! by the simulator and by `tumble dynamics`. Only joints with a non-zero coefficient are touched,
//! so a model without any (every URDF model) computes exactly what it did before. Cost `O(n)`.

use super::model::MultibodyModel;
use super::workspace::{check_len, LengthError, Workspace};

/// Adds the passive forces at `(q, v)` to `tau` (lengths nq, nv, nv); `ws`'s placements,
/// velocities and forces are overwritten when the model's medium is not void.
pub fn add_passive_forces(
    model: &MultibodyModel,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    tau: &mut [f64],
) -> Result<(), LengthError> {
    check_len("q", q.len(), model.nq())?;
    check_len("v", v.len(), model.nv())?;
    check_len("tau", tau.len(), model.nv())?;
    add_unchecked(model, ws, q, v, tau);
    Ok(())
}

/// The passive forces at `(q, v)` written into `tau` (lengths nq, nv, nv).
pub fn passive_forces(
    model: &MultibodyModel,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    tau: &mut [f64],
) -> Result<(), LengthError> {
    check_len("tau", tau.len(), model.nv())?;
    tau.fill(0.0);
    add_passive_forces(model, ws, q, v, tau)
}

/// [`add_passive_forces`] with lengths checked by the caller.
pub(crate) fn add_unchecked(model: &MultibodyModel, ws: &mut Workspace, q: &[f64], v: &[f64], tau: &mut [f64]) {
    for body in &model.bodies {
        let j = &body.joint;
        let d = j.dynamics;
        if d.damping != 0.0 {
            for k in j.v_index..j.v_index + j.kind.nv() {
                // τ_k −= d v_k
                tau[k] -= d.damping * v[k];
            }
        }
        if d.stiffness != 0.0 {
            // τ −= k_s (q − q_ref)   (one-coordinate joints: checked by the builder)
            tau[j.v_index] -= d.stiffness * (q[j.q_index] - d.spring_ref);
        }
    }
    // the fixed tendons' springs and dampers, τ += J_tᵀ (−k (L − L_s) − d L̇)
    super::tendon::add_passive_unchecked(model, q, v, tau);
    // the medium's drag, τ += Σ_b J_bᵀ [n; f]_b (nothing when it is void)
    super::fluid::add_unchecked(model, ws, q, v, tau);
}

/// The springs' potential energy `½ Σ k_s (q − q_ref)²` (J), the tendons' springs included.
pub fn spring_energy(model: &MultibodyModel, q: &[f64]) -> Result<f64, LengthError> {
    check_len("q", q.len(), model.nq())?;
    let mut e = 0.0;
    for body in &model.bodies {
        let j = &body.joint;
        if j.dynamics.stiffness != 0.0 {
            let dq = q[j.q_index] - j.dynamics.spring_ref;
            e += 0.5 * j.dynamics.stiffness * dq * dq;
        }
    }
    Ok(e + super::tendon::spring_energy_unchecked(model, q))
}
