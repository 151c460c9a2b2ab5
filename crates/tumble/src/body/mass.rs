//! Mass properties: mass and principal moments of inertia about the centre of mass.
//!
//! A body's inertia is kept as its three principal moments `I_body = diag(I1, I2, I3)` (kg·m²), the
//! form in which Euler's equations are cheapest: `I_body` and its inverse are constants (seed §3).
//! A full symmetric tensor given in the user's body axes is diagonalised once,
//! `I_user = P diag(I1, I2, I3) Pᵀ`, and `P = user_from_body` is kept so that files keep speaking
//! of the axes the user gave.

use crate::math::{DMat3, DQuat, DVec3};
use glamx::DSymmetricEigen3;
use std::f64::consts::PI;

/// Relative tolerance of the triangle inequality and of the symmetry check (`1e-9 · max moment`).
pub const INERTIA_RELATIVE_TOLERANCE: f64 = 1e-9;

/// Why a mass or inertia was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MassError {
    #[error("mass must be finite and > 0 (got {mass})")]
    NonPositiveMass { mass: f64 },
    #[error("inertia must be finite (got {moments:?})")]
    NonFiniteInertia { moments: [f64; 3] },
    #[error("inertia must be positive definite: principal moments {moments:?}")]
    NotPositiveDefinite { moments: [f64; 3] },
    #[error(
        "principal moments {moments:?} violate the triangle inequality I1 + I2 ≥ I3 \
         (short by {short_by_percent:.3}% of the largest); no rigid body has such moments"
    )]
    TriangleInequality { moments: [f64; 3], short_by_percent: f64 },
    #[error("inertia tensor must be symmetric (largest asymmetry {asymmetry:e})")]
    NotSymmetric { asymmetry: f64 },
}

/// Mass and inertia of a rigid body about its centre of mass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// Mass (kg).
    pub mass: f64,
    /// Principal moments of inertia about the centre of mass, body (principal) axes (kg·m²).
    pub inertia_body: DVec3,
    /// Rotation from the principal body axes to the axes the user gave (identity for principal input).
    pub user_from_body: DQuat,
    /// `1/m` (1/kg), kept beside `m` because the integrators need it every step.
    pub inv_mass: f64,
    /// `I_body⁻¹`, the reciprocal principal moments (1/(kg·m²)), computed once (seed §3).
    pub inv_inertia_body: DVec3,
}

impl MassProperties {
    /// Mass (kg) and principal moments (kg·m²) in the user's axes, which are then the principal axes.
    pub fn from_principal(mass: f64, moments: DVec3) -> Result<Self, MassError> {
        check_mass(mass)?;
        check_principal_moments(moments)?;
        Ok(Self::new_unchecked(mass, moments, DQuat::IDENTITY))
    }

    /// Mass (kg) and a full symmetric inertia tensor about the centre of mass in the user's axes (kg·m²).
    /// The tensor is diagonalised; the eigenvalues (not only the diagonal) are checked.
    pub fn from_tensor(mass: f64, tensor_user: DMat3) -> Result<Self, MassError> {
        check_mass(mass)?;
        let cols = tensor_user.to_cols_array();
        if cols.iter().any(|x| !x.is_finite()) {
            return Err(MassError::NonFiniteInertia {
                moments: [tensor_user.x_axis.x, tensor_user.y_axis.y, tensor_user.z_axis.z],
            });
        }
        let scale = cols.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let asym = (tensor_user - tensor_user.transpose()).to_cols_array();
        let asymmetry = asym.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        if asymmetry > INERTIA_RELATIVE_TOLERANCE * scale {
            return Err(MassError::NotSymmetric { asymmetry });
        }
        let off_diagonal = tensor_user.y_axis.x.abs() + tensor_user.z_axis.x.abs() + tensor_user.z_axis.y.abs();
        if off_diagonal == 0.0 {
            let moments = DVec3::new(tensor_user.x_axis.x, tensor_user.y_axis.y, tensor_user.z_axis.z);
            return Self::from_principal(mass, moments);
        }
        // the eigen-solver has absolute thresholds (1e-20): give it the tensor scaled to unit size
        let symmetric = (0.5 / scale) * (tensor_user + tensor_user.transpose());
        let eigen = DSymmetricEigen3::new(symmetric);
        let mut axes = eigen.eigenvectors;
        // a proper rotation: det = +1
        if axes.determinant() < 0.0 {
            axes.z_axis = -axes.z_axis;
        }
        // one step of re-orthonormalisation keeps the frame a rotation to round-off
        let x = axes.x_axis.normalize();
        let y = (axes.y_axis - x * x.dot(axes.y_axis)).normalize();
        let z = x.cross(y);
        // its closed-form cubic loses half the digits at a double root: polish with Jacobi rotations
        let (moments, axes) = jacobi_polish(symmetric, DMat3::from_cols(x, y, z));
        let moments = moments * scale;
        let user_from_body = DQuat::from_mat3(&axes).normalize();
        check_principal_moments(moments)?;
        Ok(Self::new_unchecked(mass, moments, user_from_body))
    }

    fn new_unchecked(mass: f64, inertia_body: DVec3, user_from_body: DQuat) -> Self {
        Self { mass, inertia_body, user_from_body, inv_mass: 1.0 / mass, inv_inertia_body: inertia_body.recip() }
    }

    /// The inertia tensor in the user's axes, `P I_body Pᵀ` (kg·m²).
    pub fn inertia_user(&self) -> DMat3 {
        crate::math::inertia_world(DMat3::from_quat(self.user_from_body), self.inertia_body)
    }
}

/// Eigenvalues and eigenvectors (columns, a rotation) of a finite symmetric 3×3 tensor, with no
/// physical check: the same solver as [`MassProperties::from_tensor`] (closed form, then Jacobi
/// sweeps), for tensors that may be indefinite. The zero tensor gives zeros and the identity.
pub fn symmetric_eigen(tensor: DMat3) -> (DVec3, DMat3) {
    let scale = tensor.to_cols_array().iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    if scale == 0.0 || !scale.is_finite() {
        return (DVec3::new(tensor.x_axis.x, tensor.y_axis.y, tensor.z_axis.z), DMat3::IDENTITY);
    }
    let symmetric = (0.5 / scale) * (tensor + tensor.transpose());
    let axes = DSymmetricEigen3::new(symmetric).eigenvectors;
    let x = axes.x_axis.normalize();
    let y = (axes.y_axis - x * x.dot(axes.y_axis)).normalize();
    let z = x.cross(y);
    let start = if x.is_finite() && y.is_finite() { DMat3::from_cols(x, y, z) } else { DMat3::IDENTITY };
    let (moments, axes) = jacobi_polish(symmetric, start);
    (moments * scale, axes)
}

/// Diagonalises the symmetric `a` starting from the orthonormal, nearly diagonalising frame `p`
/// (det +1): cyclic Jacobi rotations on `D = Pᵀ A P` until its off-diagonal entries are round-off.
/// Returns the diagonal of `D` (eigenvalues) and the rotated frame `P` (eigenvectors as columns,
/// still det +1), accurate to a few ε·‖A‖ even at repeated eigenvalues.
///
/// Reference: G. H. Golub, C. F. Van Loan, *Matrix Computations*, 4th ed., §8.5 (the symmetric
/// Schur decomposition and the cyclic Jacobi method).
fn jacobi_polish(a: DMat3, p: DMat3) -> (DVec3, DMat3) {
    let mut d = p.transpose() * a * p;
    let mut v = p;
    for _sweep in 0..8 {
        let off = d.y_axis.x.abs() + d.z_axis.x.abs() + d.z_axis.y.abs();
        let diag = d.x_axis.x.abs() + d.y_axis.y.abs() + d.z_axis.z.abs();
        if off <= 1e-18 * diag {
            break;
        }
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            let d_ij = d.col(j)[i];
            if d_ij == 0.0 {
                continue;
            }
            // the rotation J in the (i, j) plane that zeroes d_ij: t = tan θ, the smaller root
            let theta = (d.col(j)[j] - d.col(i)[i]) / (2.0 * d_ij);
            let t = theta.signum() / (theta.abs() + theta.hypot(1.0));
            let c = 1.0 / t.hypot(1.0);
            let s = t * c;
            let mut rotation = DMat3::IDENTITY;
            rotation.col_mut(i)[i] = c;
            rotation.col_mut(i)[j] = -s;
            rotation.col_mut(j)[i] = s;
            rotation.col_mut(j)[j] = c;
            // D ← Jᵀ D J (what is left at (i, j) is round-off), V ← V J
            d = rotation.transpose() * d * rotation;
            d.col_mut(j)[i] = 0.0;
            d.col_mut(i)[j] = 0.0;
            v *= rotation;
        }
    }
    (DVec3::new(d.x_axis.x, d.y_axis.y, d.z_axis.z), v)
}

fn check_mass(mass: f64) -> Result<(), MassError> {
    if mass.is_finite() && mass > 0.0 {
        Ok(())
    } else {
        Err(MassError::NonPositiveMass { mass })
    }
}

/// Principal moments must be finite, positive and satisfy `I1 + I2 ≥ I3` for every ordering
/// (a relative tolerance of [`INERTIA_RELATIVE_TOLERANCE`] of the largest moment absorbs round-off,
/// so thin rods and flat plates, which sit on the bound, are accepted).
pub fn check_principal_moments(moments: DVec3) -> Result<(), MassError> {
    let m = moments.to_array();
    if m.iter().any(|x| !x.is_finite()) {
        return Err(MassError::NonFiniteInertia { moments: m });
    }
    if m.iter().any(|&x| x <= 0.0) {
        return Err(MassError::NotPositiveDefinite { moments: m });
    }
    let largest = moments.max_element();
    let sum = m[0] + m[1] + m[2];
    // the tightest ordering is the largest moment against the other two
    let slack = sum - 2.0 * largest;
    if slack < -INERTIA_RELATIVE_TOLERANCE * largest {
        return Err(MassError::TriangleInequality { moments: m, short_by_percent: -slack / largest * 100.0 });
    }
    Ok(())
}

/// Mass (kg) and principal moments (kg·m²) of a solid sphere of radius `r` (m), density `rho` (kg/m³):
/// `m = 4/3 π r³ ρ`, `I = 2/5 m r²`.
pub fn solid_sphere(rho: f64, r: f64) -> (f64, DVec3) {
    let m = 4.0 / 3.0 * PI * r.powi(3) * rho;
    (m, DVec3::splat(0.4 * m * r * r))
}

/// A solid box of half extents `h` (m): `m = 8 hx hy hz ρ`, `Ix = m (hy² + hz²)/3`, …
pub fn solid_box(rho: f64, h: DVec3) -> (f64, DVec3) {
    let m = 8.0 * h.x * h.y * h.z * rho;
    let s = h * h;
    (m, DVec3::new(s.y + s.z, s.x + s.z, s.x + s.y) * (m / 3.0))
}

/// A solid cylinder of radius `r` and half height `hh` (m), axis body z:
/// `m = 2π r² hh ρ`, `Iz = m r²/2`, `Ix = Iy = m (3r² + (2hh)²)/12`.
pub fn solid_cylinder(rho: f64, r: f64, hh: f64) -> (f64, DVec3) {
    let m = 2.0 * PI * r * r * hh * rho;
    let i_axial = 0.5 * m * r * r;
    let i_perp = m * (3.0 * r * r + 4.0 * hh * hh) / 12.0;
    (m, DVec3::new(i_perp, i_perp, i_axial))
}

/// A solid capsule (a cylinder of radius `r`, half height `hh`, capped by two hemispheres), axis body z.
///
/// Cylinder `m_c = 2π r² hh ρ`, hemispheres together `m_s = 4/3 π r³ ρ`;
/// `Iz = m_c r²/2 + 2/5 m_s r²`;
/// `Ix = m_c (3r² + 4hh²)/12 + m_s (2/5 r² + hh² + 3/4 hh r)` (each hemisphere's centroid sits
/// `3r/8` beyond the cylinder's end; parallel-axis theorem).
pub fn solid_capsule(rho: f64, r: f64, hh: f64) -> (f64, DVec3) {
    let m_c = 2.0 * PI * r * r * hh * rho;
    let m_s = 4.0 / 3.0 * PI * r.powi(3) * rho;
    let i_axial = 0.5 * m_c * r * r + 0.4 * m_s * r * r;
    let i_perp = m_c * (3.0 * r * r + 4.0 * hh * hh) / 12.0 + m_s * (0.4 * r * r + hh * hh + 0.75 * hh * r);
    (m_c + m_s, DVec3::new(i_perp, i_perp, i_axial))
}

#[cfg(test)]
mod tests;
