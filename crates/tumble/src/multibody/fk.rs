//! Forward kinematics: body poses and velocities from `q` and `v`.
//!
//! Reference: Featherstone (2008), §4.4 (joint transforms) and the first pass of RNEA (Table 5.1).
//!
//! For each body `i` (parents first):
//! - `i_X_λ(i) = X_J(q_i) · X_T(i)` (the joint moves the child relative to the joint frame);
//! - `i_X_0 = i_X_λ(i) · λ(i)_X_0`;
//! - `v_i = i_X_λ(i) v_λ(i) + S_i q̇_i` (body frame).
//!
//! Cost: one 3×3 product per body for the transform, `O(n)` in all.

use super::model::MultibodyModel;
use super::spatial::{Motion, Xform};
use super::workspace::{check_len, LengthError, Workspace};
use crate::math::{DMat3, DVec3};

/// Fills `ws.x_up` and `ws.x_world` from `q` (length nq).
pub fn update_placements(model: &MultibodyModel, ws: &mut Workspace, q: &[f64]) -> Result<(), LengthError> {
    check_len("q", q.len(), model.nq())?;
    placements(model, ws, q);
    Ok(())
}

/// Fills the placements and the body velocities `ws.v` from `q` and `v`.
pub fn forward_kinematics(model: &MultibodyModel, ws: &mut Workspace, q: &[f64], v: &[f64]) -> Result<(), LengthError> {
    check_len("q", q.len(), model.nq())?;
    check_len("v", v.len(), model.nv())?;
    placements(model, ws, q);
    for (i, body) in model.bodies.iter().enumerate() {
        let vi = body.joint.v_index;
        // v_J = S q̇
        let mut v_joint = Motion::ZERO;
        for (k, s) in model.subspace(i).iter().enumerate() {
            v_joint += v[vi + k] * *s;
        }
        // v_i = i_X_λ v_λ + v_J
        ws.v[i] = match body.parent {
            Some(p) => ws.x_up[i].apply_motion(ws.v[p]) + v_joint,
            None => v_joint,
        };
    }
    Ok(())
}

/// `i_X_λ(i)` only (RNEA and ABA need no world poses); lengths already checked.
pub(crate) fn placements_up(model: &MultibodyModel, ws: &mut Workspace, q: &[f64]) {
    for (body, x_up) in model.bodies.iter().zip(ws.x_up.iter_mut()) {
        let j = &body.joint;
        // i_X_λ = X_J(q) X_T
        *x_up = j.kind.transform(&q[j.q_index..j.q_index + j.kind.nq()]).compose(&j.x_tree);
    }
}

/// `i_X_λ(i)` and `i_X_0` for every body (lengths already checked).
pub(crate) fn placements(model: &MultibodyModel, ws: &mut Workspace, q: &[f64]) {
    for (i, body) in model.bodies.iter().enumerate() {
        let j = &body.joint;
        // i_X_λ = X_J(q) X_T
        let x_joint = j.kind.transform(&q[j.q_index..j.q_index + j.kind.nq()]);
        ws.x_up[i] = x_joint.compose(&j.x_tree);
        // i_X_0 = i_X_λ λ_X_0
        ws.x_world[i] = match body.parent {
            Some(p) => ws.x_up[i].compose(&ws.x_world[p]),
            None => ws.x_up[i],
        };
    }
}

/// The pose of body `i` in the world after [`update_placements`]: `(world_from_body rotation,
/// body origin in the world (m))`.
#[inline]
pub fn body_pose_world(ws: &Workspace, i: usize) -> (DMat3, DVec3) {
    let x = &ws.x_world[i];
    (x.rotation_a_from_b(), x.r)
}

/// The pose of frame `f` in the world after [`update_placements`], as `frame_X_0`.
pub fn frame_x_world(model: &MultibodyModel, ws: &Workspace, f: usize) -> Xform {
    let frame = &model.frames[f];
    match frame.body {
        Some(b) => frame.x_from_body.compose(&ws.x_world[b]),
        None => frame.x_from_body,
    }
}
