//! The Jacobian of a frame: `v_frame = J(q) q̇`.
//!
//! Reference: Featherstone (2008), §4.5 (the columns of `J` are the motion subspaces of the joints
//! on the path to the root, transformed into the frame).
//!
//! Column `k` of `J`, for a velocity coordinate `k` of a joint `j` on the frame's root path, is
//! `f_X_j S_k` with `f_X_j = f_X_0 · (j_X_0)⁻¹`; the other columns are zero. The rows are the
//! spatial velocity `[ω; v]` of the frame, in the frame's own axes, `v` being the velocity of its
//! origin (rad/s, m/s per unit of `q̇`).

use super::fk::{frame_x_world, update_placements};
use super::model::MultibodyModel;
use super::workspace::{check_len, LengthError, Workspace};
use nalgebra::DMatrix;

/// Fills `jac` (6 × nv) with the Jacobian of frame `frame` (an index into `model.frames`).
pub fn frame_jacobian(
    model: &MultibodyModel,
    ws: &mut Workspace,
    q: &[f64],
    frame: usize,
    jac: &mut DMatrix<f64>,
) -> Result<(), LengthError> {
    if frame >= model.frames.len() {
        return Err(LengthError {
            what: "frames (the frame index is past the end)",
            expected: frame + 1,
            got: model.frames.len(),
        });
    }
    check_len("jacobian rows", jac.nrows(), 6)?;
    check_len("jacobian columns", jac.ncols(), model.nv())?;
    update_placements(model, ws, q)?;
    jac.fill(0.0);
    let x_frame = frame_x_world(model, ws, frame);
    let mut body = model.frames[frame].body;
    while let Some(j) = body {
        // f_X_j = f_X_0 · (j_X_0)⁻¹
        let f_x_j = x_frame.compose(&ws.x_world[j].inverse());
        let vj = model.bodies[j].joint.v_index;
        for (k, s_k) in model.subspace(j).iter().enumerate() {
            // J_k = f_X_j S_k
            let col = f_x_j.apply_motion(*s_k).to_array();
            for (r, value) in col.iter().enumerate() {
                jac[(r, vj + k)] = *value;
            }
        }
        body = model.bodies[j].parent;
    }
    Ok(())
}
