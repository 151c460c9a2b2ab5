//! Inverse dynamics by the recursive Newton–Euler algorithm (RNEA): `τ = M(q) q̈ + C(q, q̇) q̇ + g(q)`.
//!
//! Reference: Featherstone (2008), §5.3, Table 5.1.
//!
//! Inputs: `q` (nq), `v = q̇` (nv), `a = q̈` (nv); gravity from the model (world frame). Output: the
//! joint forces `τ` (nv; N·m for revolute, N for prismatic, `[f; n]` in the child frame for a floating
//! base). Gravity enters as a fictitious upward acceleration of the base, `a_0 = −g`. A joint's
//! armature `a` adds `a q̈` to its coordinates (so that `τ = M q̈ + b` with CRBA's `M`); the bias has none.
//! Cost: `O(n)`; no allocation.

use super::fk::placements_up;
use super::model::MultibodyModel;
use super::spatial::Motion;
use super::workspace::{check_len, LengthError, Workspace};
use crate::math::DVec3;

/// `τ = RNEA(q, v, a)`, written into `tau` (length nv).
pub fn rnea(
    model: &MultibodyModel,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    tau: &mut [f64],
) -> Result<(), LengthError> {
    check_len("a", a.len(), model.nv())?;
    rnea_impl(model, ws, q, v, Some(a), tau)
}

/// The bias forces `b = RNEA(q, v, 0) = C(q, q̇) q̇ + g(q)` (Coriolis, centrifugal and gravity),
/// written into `bias` (length nv).
pub fn bias_forces(
    model: &MultibodyModel,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    bias: &mut [f64],
) -> Result<(), LengthError> {
    rnea_impl(model, ws, q, v, None, bias)
}

/// [`bias_forces`] at the placements `ws.x_up` already in the workspace (those of `q`, as
/// [`crate::multibody::crba`] leaves them): the same result without a second pass of the joint
/// transforms.
pub(crate) fn bias_forces_placed(
    model: &MultibodyModel,
    ws: &mut Workspace,
    v: &[f64],
    bias: &mut [f64],
) -> Result<(), LengthError> {
    check_len("v", v.len(), model.nv())?;
    check_len("tau", bias.len(), model.nv())?;
    recursion(model, ws, v, None, bias);
    Ok(())
}

fn rnea_impl(
    model: &MultibodyModel,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    a: Option<&[f64]>,
    tau: &mut [f64],
) -> Result<(), LengthError> {
    check_len("q", q.len(), model.nq())?;
    check_len("v", v.len(), model.nv())?;
    check_len("tau", tau.len(), model.nv())?;
    placements_up(model, ws, q);
    recursion(model, ws, v, a, tau);
    Ok(())
}

/// Table 5.1's two passes at the placements `ws.x_up` (lengths checked).
fn recursion(model: &MultibodyModel, ws: &mut Workspace, v: &[f64], a: Option<&[f64]>, tau: &mut [f64]) {
    // a_0 = −g: gravity as an upward acceleration of the world
    let a_world = Motion::new(DVec3::ZERO, -model.gravity);
    for (i, body) in model.bodies.iter().enumerate() {
        let vi = body.joint.v_index;
        let s = model.subspace(i);
        // v_J = S q̇,  S q̈
        let mut v_joint = Motion::ZERO;
        let mut a_joint = Motion::ZERO;
        for (k, s_k) in s.iter().enumerate() {
            v_joint += v[vi + k] * *s_k;
            if let Some(a) = a {
                a_joint += a[vi + k] * *s_k;
            }
        }
        let x = &ws.x_up[i];
        let (v_parent, a_parent) = match body.parent {
            Some(p) => (x.apply_motion(ws.v[p]), x.apply_motion(ws.a[p])),
            None => (Motion::ZERO, x.apply_motion(a_world)),
        };
        // v_i = i_X_λ v_λ + S q̇
        let v_i = v_parent + v_joint;
        // a_i = i_X_λ a_λ + S q̈ + v_i ×ₘ v_J   (c_J = 0: S is constant in the child frame)
        let a_i = a_parent + a_joint + v_i.cross_motion(v_joint);
        // f_i = I_i a_i + v_i ×* I_i v_i
        let inertia = &body.inertia;
        ws.f[i] = inertia.mul_motion(a_i) + v_i.cross_force(inertia.mul_motion(v_i));
        ws.v[i] = v_i;
        ws.a[i] = a_i;
    }
    for i in (0..model.nbodies()).rev() {
        let body = &model.bodies[i];
        let vi = body.joint.v_index;
        // τ_i = S_iᵀ f_i (+ armature q̈_i)
        for (k, s_k) in model.subspace(i).iter().enumerate() {
            tau[vi + k] = s_k.dot(ws.f[i]);
        }
        let armature = body.joint.dynamics.armature;
        if let (Some(a), true) = (a, armature != 0.0) {
            for k in vi..vi + body.joint.kind.nv() {
                tau[k] += armature * a[k];
            }
        }
        // f_λ += λ_X_i* f_i
        if let Some(p) = body.parent {
            let f_parent = ws.x_up[i].inv_apply_force(ws.f[i]);
            ws.f[p] += f_parent;
        }
    }
}
