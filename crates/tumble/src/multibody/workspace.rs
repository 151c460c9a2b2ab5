//! The mutable workspace of the algorithms, allocated once per model.
//!
//! Every algorithm writes its intermediate quantities here (the names are Featherstone's), so no
//! call allocates. After [`fk`](super::fk::forward_kinematics) the poses and velocities stay
//! readable: `x_world[i]` is `i_X_0` and `v[i]` the velocity of body `i` in its own frame.

use super::model::MultibodyModel;
use super::spatial::{ArticulatedInertia, Force, Motion, RigidInertia, Xform};
use nalgebra::DMatrix;

/// Inputs of the wrong length for the model.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{what} has length {got}, the model needs {expected}")]
pub struct LengthError {
    /// Which argument (`q`, `v`, `a`, `tau`, ...).
    pub what: &'static str,
    pub expected: usize,
    pub got: usize,
}

/// The largest `nv` for which a dense `nv × nv` matrix is allocated (8 · 16384² bytes = 2 GiB).
pub const MAX_DENSE_NV: usize = 16_384;

/// A dense `nv × nv` matrix the workspace will not allocate.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("a dense {nv} × {nv} matrix is too large (at most {MAX_DENSE_NV} degrees of freedom); use ABA and RNEA")]
pub struct TooLarge {
    pub nv: usize,
}

/// Makes `m` an `nv × nv` matrix (allocating on the first call only).
pub(crate) fn ensure_square(m: &mut DMatrix<f64>, nv: usize) -> Result<(), TooLarge> {
    if m.nrows() != nv || m.ncols() != nv {
        if nv > MAX_DENSE_NV {
            return Err(TooLarge { nv });
        }
        *m = DMatrix::zeros(nv, nv);
    }
    Ok(())
}

/// Checks the length of one argument.
#[inline]
pub(crate) fn check_len(what: &'static str, got: usize, expected: usize) -> Result<(), LengthError> {
    if got == expected {
        Ok(())
    } else {
        Err(LengthError { what, expected, got })
    }
}

/// Scratch space for the recursive algorithms (one per model and thread).
#[derive(Debug, Clone)]
pub struct Workspace {
    /// `i_X_λ(i)`: parent → body `i` (Plücker).
    pub x_up: Vec<Xform>,
    /// `i_X_0`: world → body `i`.
    pub x_world: Vec<Xform>,
    /// Body velocities `v[i]`, body frame.
    pub v: Vec<Motion>,
    /// Body accelerations `a[i]`, body frame (including the fictitious `−g` of the base).
    pub a: Vec<Motion>,
    /// Velocity-product accelerations `c[i] = v[i] ×ₘ v_J[i]`.
    pub c: Vec<Motion>,
    /// Forces `f[i]` (RNEA) and bias forces `p^A[i]` (ABA), body frame.
    pub f: Vec<Force>,
    /// Articulated-body inertias `I^A[i]`, body frame.
    pub ia: Vec<ArticulatedInertia>,
    /// Composite-rigid-body inertias `I^c[i]`, body frame.
    pub ic: Vec<RigidInertia>,
    /// Motion subspace columns in world coordinates, `0_X_i S` (CRBA), one per velocity coordinate.
    pub s_world: Vec<Motion>,
    /// `U = I^A S`, one column per velocity coordinate.
    pub u_cols: Vec<Force>,
    /// `u = τ − Sᵀ p^A`, one entry per velocity coordinate.
    pub u: Vec<f64>,
    /// `D⁻¹ = (Sᵀ U)⁻¹` per joint, packed `nv_j × nv_j` blocks (row-major).
    pub d_inv: Vec<f64>,
    /// The joint-space mass matrix `M` (CRBA), `nv × nv`; allocated by the first call of
    /// [`crba`](super::crba::crba) (empty before), so that models too large for a dense `M` can still
    /// use the `O(n)` algorithms.
    pub mass_matrix: DMatrix<f64>,
    /// The LTDL factors of `M` (unit lower `L` below the diagonal, `D` on it); allocated by the first
    /// factorisation.
    pub ltdl: DMatrix<f64>,
    /// Scratch of length `nv`.
    pub tmp: Vec<f64>,
}

impl Workspace {
    /// A workspace sized for `model`.
    pub fn new(model: &MultibodyModel) -> Self {
        let n = model.nbodies();
        let nv = model.nv();
        Self {
            x_up: vec![Xform::IDENTITY; n],
            x_world: vec![Xform::IDENTITY; n],
            v: vec![Motion::ZERO; n],
            a: vec![Motion::ZERO; n],
            c: vec![Motion::ZERO; n],
            f: vec![Force::ZERO; n],
            ia: vec![ArticulatedInertia::ZERO; n],
            ic: vec![RigidInertia::ZERO; n],
            s_world: vec![Motion::ZERO; nv],
            u_cols: vec![Force::ZERO; nv],
            u: vec![0.0; nv],
            d_inv: vec![0.0; model.block_len()],
            mass_matrix: DMatrix::zeros(0, 0),
            ltdl: DMatrix::zeros(0, 0),
            tmp: vec![0.0; nv],
        }
    }
}
