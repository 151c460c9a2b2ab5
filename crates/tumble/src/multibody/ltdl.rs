//! The sparse `LᵀDL` factorisation of the mass matrix and solves with it.
//!
//! Reference: Featherstone (2008), §6.5, Table 6.3 (factorisation) and the back- and
//! forward-substitutions that follow it.
//!
//! `M = Lᵀ D L` with `L` unit lower triangular. In a kinematic tree `M_ki ≠ 0` only if `i` lies on
//! the path from `k` to the root, and, numbering parents first, `L` has exactly the same sparsity as
//! `M`'s lower triangle: no fill-in. Every loop below runs over `λ(k), λ(λ(k)), …` (the velocity
//! coordinates towards the root), so the factorisation costs `O(Σ d_k²)` and a solve `O(Σ d_k)`
//! instead of `O(n³)` and `O(n²)`, with `d_k` the depth of coordinate `k`.

use super::model::{MultibodyModel, NONE};
use super::workspace::{check_len, LengthError, Workspace};

/// Why a factorisation or a solve failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FactorError {
    #[error("the mass matrix is not positive definite (pivot {pivot:e} at velocity coordinate {dof})")]
    NotPositiveDefinite { dof: usize, pivot: f64 },
    #[error("the mass matrix has not been computed (call crba first)")]
    NoMassMatrix,
    #[error(transparent)]
    Length(#[from] LengthError),
}

/// Factorises `ws.mass_matrix` into `ws.ltdl` (`L` strictly below the diagonal, `D` on it).
pub fn ltdl_factor(model: &MultibodyModel, ws: &mut Workspace) -> Result<(), FactorError> {
    let nv = model.nv();
    if ws.mass_matrix.nrows() != nv || ws.mass_matrix.ncols() != nv {
        return Err(FactorError::NoMassMatrix);
    }
    if ws.ltdl.nrows() != nv || ws.ltdl.ncols() != nv {
        // same size as the mass matrix, which was allowed: allocate once
        ws.ltdl = ws.mass_matrix.clone();
    }
    let h = &mut ws.ltdl;
    h.copy_from(&ws.mass_matrix);
    for k in (0..nv).rev() {
        let h_kk = h[(k, k)];
        if !(h_kk > 0.0 && h_kk.is_finite()) {
            return Err(FactorError::NotPositiveDefinite { dof: k, pivot: h_kk });
        }
        let mut i = model.dof_parent(k);
        while i != NONE {
            // a = H_ki / H_kk
            let a = h[(k, i)] / h_kk;
            let mut j = i;
            while j != NONE {
                // H_ij = H_ij − a H_kj
                h[(i, j)] -= a * h[(k, j)];
                j = model.dof_parent(j);
            }
            // H_ki = a  (the entry L_ki)
            h[(k, i)] = a;
            i = model.dof_parent(i);
        }
    }
    Ok(())
}

/// Solves `M x = b` in place (`b` becomes `x`) with the factors of [`ltdl_factor`].
pub fn ltdl_solve(model: &MultibodyModel, ws: &Workspace, b: &mut [f64]) -> Result<(), LengthError> {
    let nv = model.nv();
    check_len("b", b.len(), nv)?;
    check_len("LTDL factors (call ltdl_factor first)", ws.ltdl.nrows(), nv)?;
    let h = &ws.ltdl;
    // Lᵀ z = b, from the leaves: z_k is final once every descendant is done. A zero z_k changes
    // nothing above it: a right-hand side with few non-zeros (a contact point's `J_cᵀ e`, non-zero
    // only on the dofs that move its body) walks only their chains
    for k in (0..nv).rev() {
        if b[k] == 0.0 {
            continue;
        }
        let mut i = model.dof_parent(k);
        while i != NONE {
            // b_i −= L_ki z_k
            b[i] -= h[(k, i)] * b[k];
            i = model.dof_parent(i);
        }
    }
    // y = D⁻¹ z
    for (k, b_k) in b.iter_mut().enumerate() {
        *b_k /= h[(k, k)];
    }
    // L x = y, from the root
    for k in 0..nv {
        let mut i = model.dof_parent(k);
        while i != NONE {
            // x_k −= L_ki x_i
            b[k] -= h[(k, i)] * b[i];
            i = model.dof_parent(i);
        }
    }
    Ok(())
}

/// The last two stages of [`ltdl_solve`], `x ← L⁻¹ D⁻¹ x` (after the first stage of the solve,
/// `x ← L⁻ᵀ x`, here or on a chain in [`super::contact_point::delassus`], this completes `x = M⁻¹ b`), on two right-hand sides at once, with
/// `inv_d` the inverse pivots `1 / D_k` (nv): one walk of the tree for both. Lengths checked by the caller.
pub(crate) fn ltdl_solve_lower_pair(
    model: &MultibodyModel,
    ws: &Workspace,
    inv_d: &[f64],
    x: &mut [f64],
    y: &mut [f64],
) {
    let h = &ws.ltdl;
    let nv = x.len();
    for k in 0..nv {
        x[k] *= inv_d[k];
        y[k] *= inv_d[k];
    }
    for k in 0..nv {
        let mut i = model.dof_parent(k);
        while i != NONE {
            let l = h[(k, i)];
            x[k] -= l * x[i];
            y[k] -= l * y[i];
            i = model.dof_parent(i);
        }
    }
}
