//! The joint-space mass matrix `M(q)` by the composite-rigid-body algorithm (CRBA).
//!
//! Reference: Featherstone (2008), §6.2, Table 6.2.
//!
//! - `I^c_i = I_i + Σ_{children j} i_X_j* I^c_j j_X_i` (composite inertia of the subtree of `i`,
//!   body `i`'s frame), children before parents;
//! - `F = I^c_i S_i`, `M_ii = S_iᵀ F`; then walking up, `F ← λ(j)_X_j* F`, `M_ij = Fᵀ S_j = M_jiᵀ`
//!   for every ancestor `j` of `i`.
//!
//! Only the entries of `M` on the same root path are non-zero; the others are set to 0. Input: `q`
//! (nq). Output: `ws.mass_matrix` (nv × nv, kg·m² for revolute pairs). Cost: `O(n d)` with `d` the
//! depth of the tree; no allocation.

use super::fk::placements;
use super::model::MultibodyModel;
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
    let n = model.nbodies();
    for (i, body) in model.bodies.iter().enumerate() {
        // I^c_i = I_i
        ws.ic[i] = body.inertia;
    }
    ws.mass_matrix.fill(0.0);
    for i in (0..n).rev() {
        let body = &model.bodies[i];
        if let Some(p) = body.parent {
            // I^c_λ += λ_X_i* I^c_i i_X_λ
            let ic_in_parent = ws.ic[i].transform_to_a(&ws.x_up[i]);
            ws.ic[p] += ic_in_parent;
        }
        let vi = body.joint.v_index;
        for (k, s_k) in model.subspace(i).iter().enumerate() {
            let row = vi + k;
            // F = I^c_i S_i
            let mut f = ws.ic[i].mul_motion(*s_k);
            // M_ii = S_iᵀ F
            for (l, s_l) in model.subspace(i).iter().enumerate() {
                ws.mass_matrix[(row, vi + l)] = s_l.dot(f);
            }
            let mut j = i;
            while let Some(p) = model.bodies[j].parent {
                // F = λ(j)_X_j* F;  j = λ(j)
                f = ws.x_up[j].inv_apply_force(f);
                j = p;
                // M_ij = Fᵀ S_j,  M_ji = M_ij
                let vj = model.bodies[j].joint.v_index;
                for (l, s_l) in model.subspace(j).iter().enumerate() {
                    let m = s_l.dot(f);
                    ws.mass_matrix[(row, vj + l)] = m;
                    ws.mass_matrix[(vj + l, row)] = m;
                }
            }
        }
    }
    Ok(&ws.mass_matrix)
}
