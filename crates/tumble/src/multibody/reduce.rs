//! Reduced models: joints locked at a value, as Pinocchio's `buildReducedModel`.
//!
//! Reference: Featherstone (2008), §2.13 and §4.4 (spatial inertias add once expressed in one frame,
//! `I_A = A_X_B* I_B B_X_A`); the Pinocchio documentation of `buildReducedModel` (a locked joint
//! becomes a fixed joint at its reference configuration, its child body merged into its parent).
//!
//! A locked joint `i` at the value `q_i` is a fixed joint with placement
//! `i_X_λ(i) = X_J(q_i) · X_T(i)`, so its body `i` is merged into the body it now moves with, its
//! *owner* `o(i)` (the nearest ancestor whose joint is not locked, or the world):
//!
//! - `i_X_o(i) = i_X_λ(i) · λ(i)_X_o(λ(i))` (the placement in the owner, composed down the chain);
//! - `I_o += i_X_o* I_i i_X_o`, written `Xᵀ I X` in [`RigidInertia::transform_to_a`];
//! - a joint `k` that hangs from a merged body gets `X_T'(k) = X_T(k) · λ(k)_X_o(λ(k))`;
//! - every frame on body `i` (its link, the links fixed to it) moves to the owner:
//!   `frame_X_o = frame_X_i · i_X_o`; the link's own frame becomes [`FrameOrigin::Fixed`] by the
//!   locked joint. Geometries follow their link's frame ([`MultibodyModel::geometry_placement`]).
//!
//! The reduced model's `q` and `v` are the full ones without the locked joints' coordinates, in the
//! same order. With the locked joints at their value and at rest, the reduced mass matrix is the
//! full one's sub-matrix of the kept coordinates and its bias forces the kept rows of the full ones
//! (the test `multibody_reduce` checks both to 1e-12).
//!
//! Cost: `O(n)` once, when the model is built; nothing at run time.

use super::model::{Frame, FrameOrigin, ModelBuilder, ModelError, MultibodyModel};
use super::spatial::Xform;
use super::JointKind;

/// Why a model could not be reduced.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LockError {
    #[error("unknown joint `{joint}` (the model has no movable joint of that name)")]
    UnknownJoint { joint: String },
    #[error("joint `{joint}` is the floating base: it cannot be locked (use a fixed base instead)")]
    FloatingBase { joint: String },
    #[error("joint `{joint}` is locked twice")]
    Twice { joint: String },
    #[error("q has {got} entries, the full model {expected}")]
    Length { got: usize, expected: usize },
    #[error(
        "{} `{}` move{} no mass once reduced: the mass matrix would be singular",
        if joints.len() == 1 { "joint" } else { "joints" },
        joints.join("`, `"),
        if joints.len() == 1 { "s" } else { "" }
    )]
    Massless { joints: Vec<String> },
    #[error("{0}")]
    Model(ModelError),
}

/// The model with the joints named `locked` held at their values in `q_full` (length `nq` of the
/// full model): each becomes a fixed joint at `X_J(q) X_T`, its body merged into the body it now
/// moves with. The kept joints keep their order, names, kinds and limits.
///
/// Errors: an unknown name, the floating base, a name given twice, `q_full` of the wrong length, and
/// kept joints that still move no mass (all of them named).
pub fn reduced_model(model: &MultibodyModel, locked: &[&str], q_full: &[f64]) -> Result<MultibodyModel, LockError> {
    if q_full.len() != model.nq() {
        return Err(LockError::Length { got: q_full.len(), expected: model.nq() });
    }
    let n = model.nbodies();
    let mut is_locked = vec![false; n];
    for &name in locked {
        let i = model.joint_index(name).ok_or_else(|| LockError::UnknownJoint { joint: name.to_string() })?;
        if model.bodies[i].joint.kind == JointKind::Floating {
            return Err(LockError::FloatingBase { joint: name.to_string() });
        }
        if is_locked[i] {
            return Err(LockError::Twice { joint: name.to_string() });
        }
        is_locked[i] = true;
    }

    let mut builder = ModelBuilder::new(model.name.clone());
    // per old body: its owner in the reduced model (None: the world) and i_X_owner
    let mut owner: Vec<(Option<usize>, Xform)> = Vec::with_capacity(n);
    // bodies are parents first, so the parent's owner is known
    for (i, body) in model.bodies.iter().enumerate() {
        let j = &body.joint;
        let (parent_owner, parent_x_owner) = match body.parent {
            Some(p) => owner[p],
            None => (None, Xform::IDENTITY),
        };
        if is_locked[i] {
            // i_X_λ = X_J(q_i) X_T;  i_X_o = i_X_λ · λ_X_o
            let x_joint = j.kind.transform(&q_full[j.q_index..j.q_index + j.kind.nq()]);
            let x_owner = x_joint.compose(&j.x_tree).compose(&parent_x_owner);
            // I_o += i_X_o* I_i i_X_o (for the world: the world frame)
            builder.add_inertia(parent_owner, body.inertia.transform_to_a(&x_owner));
            owner.push((parent_owner, x_owner));
        } else {
            // X_T' = X_T · λ_X_o
            let x_tree = j.x_tree.compose(&parent_x_owner);
            let b = builder
                .add_body(body.name.clone(), parent_owner, j.name.clone(), j.kind, x_tree, body.inertia)
                .map_err(LockError::Model)?;
            builder.set_limits(b, j.limits);
            builder.set_parent_link(b, j.parent_link.clone());
            builder.set_dynamics(b, j.dynamics).map_err(LockError::Model)?;
            owner.push((Some(b), Xform::IDENTITY));
        }
    }
    builder.add_inertia(None, model.world_inertia);
    for w in &model.warnings {
        builder.warn(w.clone());
    }
    for g in &model.geometries {
        builder.add_geometry(g.clone());
    }
    let mut reduced = builder.build_allowing_massless().map_err(LockError::Model)?;
    let massless = reduced.massless_joints();
    if !massless.is_empty() {
        return Err(LockError::Massless { joints: massless.iter().map(|j| j.to_string()).collect() });
    }
    reduced.gravity = model.gravity;
    reduced.locked = model.locked.clone();
    for body in model.bodies.iter().enumerate().filter(|(i, _)| is_locked[*i]).map(|(_, b)| b) {
        let j = &body.joint;
        reduced.locked.push((j.name.clone(), q_full[j.q_index..j.q_index + j.kind.nq()].to_vec()));
    }
    // the frames in the full model's order, each on its owner
    reduced.frames = model.frames.iter().map(|f| reduced_frame(model, f, &owner, &is_locked)).collect();
    // tendons: a locked joint's term is a constant length, L₀ += c q_locked
    reduced.tendons = model
        .tendons
        .iter()
        .map(|t| {
            let mut kept = t.clone();
            kept.terms.clear();
            for term in &t.terms {
                if is_locked[term.body] {
                    kept.offset += term.coef * q_full[term.q_index];
                } else if let Some(b) = owner[term.body].0 {
                    let j = &reduced.bodies[b].joint;
                    kept.terms.push(super::tendon::TendonTerm {
                        body: b,
                        q_index: j.q_index,
                        v_index: j.v_index,
                        ..*term
                    });
                }
            }
            kept
        })
        .collect();
    // each fluid box moves with its owner: inertial_X_owner = inertial_X_body body_X_owner
    reduced.fluid.medium = model.fluid.medium;
    reduced.fluid.boxes = model
        .fluid
        .boxes
        .iter()
        .filter_map(|b| {
            let (owner_body, b_x_owner) = owner[b.body];
            let body = owner_body?;
            Some(super::fluid::FluidBox { body, inertial_from_body: b.inertial_from_body.compose(&b_x_owner), ..*b })
        })
        .collect();
    Ok(reduced)
}

/// A frame of the full model placed on the reduced model's bodies.
fn reduced_frame(model: &MultibodyModel, frame: &Frame, owner: &[(Option<usize>, Xform)], is_locked: &[bool]) -> Frame {
    let Some(b) = frame.body else { return frame.clone() };
    let (body, b_x_owner) = owner[b];
    // frame_X_o = frame_X_b · b_X_o
    let x_from_body = frame.x_from_body.compose(&b_x_owner);
    let origin = match &frame.origin {
        FrameOrigin::Body(i) if is_locked[*i] => {
            let j = &model.bodies[*i].joint;
            FrameOrigin::Fixed { joint: j.name.clone(), parent_link: j.parent_link.clone() }
        }
        FrameOrigin::Body(_) => FrameOrigin::Body(body.expect("a kept body is a body")),
        other => other.clone(),
    };
    Frame { name: frame.name.clone(), body, x_from_body, origin, inertia: frame.inertia }
}

/// For each coordinate of the reduced model, its index in the full model's `q` and `v`:
/// `(q_map, v_map)`, so that `q_reduced[k] = q_full[q_map[k]]`. Joints are matched by name.
///
/// Panics if `reduced` has a joint that `full` has not (it was not reduced from `full`).
pub fn kept_coordinates(full: &MultibodyModel, reduced: &MultibodyModel) -> (Vec<usize>, Vec<usize>) {
    let mut q_map = Vec::with_capacity(reduced.nq());
    let mut v_map = Vec::with_capacity(reduced.nv());
    for body in &reduced.bodies {
        let i = full.joint_index(&body.joint.name).expect("a joint of the reduced model is in the full one");
        let j = &full.bodies[i].joint;
        q_map.extend(j.q_index..j.q_index + j.kind.nq());
        v_map.extend(j.v_index..j.v_index + j.kind.nv());
    }
    (q_map, v_map)
}
