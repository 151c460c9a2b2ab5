//! The joint-space mass matrix `M(q)` by the composite-rigid-body algorithm (CRBA).
//!
//! Reference: Featherstone (2008), §6.2, Table 6.2, here with every quantity expressed in world
//! coordinates (as Pinocchio does), which turns the walk up the tree from a chain of transforms into
//! a chain of dot products:
//!
//! - `S⁰_i = 0_X_i S_i` (the motion subspace in world coordinates) and `I⁰_i = 0_X_i* I_i i_X_0`;
//! - `I^c_i = I⁰_i + Σ_{children j} I^c_j` (composite inertia of the subtree of `i`), leaves first;
//! - `F = I^c_i S⁰_i`, `M_ii = S⁰_iᵀ F + a_i` (`a_i` the joint's armature, zero unless given), and
//!   `M_ij = M_ji = S⁰_jᵀ F` for every ancestor `j` of `i`.
//!
//! (Table 6.2 in body coordinates transforms `F` at every step up: `F ← λ(j)_X_j* F`; the products
//! `S_jᵀ F` are frame-independent, so both give the same `M`.) Entries of `M` whose two coordinates
//! are not on one root path are zero and never written. Input: `q` (nq). Output: `ws.mass_matrix`
//! (nv × nv; kg·m² for two rotations, kg·m for a rotation and a translation, kg for two
//! translations). Cost: `O(n d)` with `d` the depth of the tree; no allocation after the first call.

use super::fk::placements;
use super::model::{MultibodyModel, NONE};
use super::workspace::{check_len, ensure_square, LengthError, TooLarge, Workspace};

/// Why the mass matrix could not be computed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CrbaError {
    #[error(transparent)]
    Length(#[from] LengthError),
    #[error(transparent)]
    TooLarge(#[from] TooLarge),
}

/// Computes `M(q)` into `ws.mass_matrix` and returns it (the matrix is allocated on the first call).
pub fn crba<'w>(
    model: &MultibodyModel,
    ws: &'w mut Workspace,
    q: &[f64],
) -> Result<&'w nalgebra::DMatrix<f64>, CrbaError> {
    check_len("q", q.len(), model.nq())?;
    ensure_square(&mut ws.mass_matrix, model.nv())?;
    placements(model, ws, q);
    for (i, body) in model.bodies.iter().enumerate() {
        let x = &ws.x_world[i];
        // I⁰_i = 0_X_i* I_i i_X_0
        ws.ic[i] = body.inertia.transform_to_a(x);
        let vi = body.joint.v_index;
        for (k, s_k) in model.subspace(i).iter().enumerate() {
            // S⁰ = 0_X_i S
            ws.s_world[vi + k] = x.inv_apply_motion(*s_k);
        }
    }
    let m = &mut ws.mass_matrix;
    for i in (0..model.nbodies()).rev() {
        let body = &model.bodies[i];
        let vi = body.joint.v_index;
        let armature = body.joint.dynamics.armature;
        for k in vi..vi + body.joint.kind.nv() {
            // F = I^c_i S⁰_k
            let f = ws.ic[i].mul_motion(ws.s_world[k]);
            // M_kk = S⁰_kᵀ F + armature
            m[(k, k)] = ws.s_world[k].dot(f);
            if armature != 0.0 {
                m[(k, k)] += armature;
            }
            let mut l = model.dof_parent(k);
            while l != NONE {
                // M_kl = M_lk = S⁰_lᵀ F, for l on the path to the root
                let m_kl = ws.s_world[l].dot(f);
                m[(k, l)] = m_kl;
                m[(l, k)] = m_kl;
                l = model.dof_parent(l);
            }
        }
        if let Some(p) = body.parent {
            // I^c_λ += I^c_i (both in world coordinates)
            let ic = ws.ic[i];
            ws.ic[p] += ic;
        }
    }
    Ok(&ws.mass_matrix)
}
