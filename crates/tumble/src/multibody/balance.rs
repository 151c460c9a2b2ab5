//! Physical rotational inertias, and the nearest physical one to a tensor that is not.
//!
//! A rotational inertia about the centre of mass is *physical* when some distribution of
//! non-negative mass has it: its principal moments `λ₁, λ₂, λ₃` satisfy the three triangle
//! inequalities `λᵢ + λⱼ ≥ λₖ`. These imply `λᵢ ≥ 0` (add two of them), so the positive
//! semi-definite limits are physical too: a thin rod (one moment zero) and a point mass (all zero).
//! Round-off is absorbed by a relative tolerance of [`INERTIA_RELATIVE_TOLERANCE`] of the largest
//! moment.
//!
//! The set of physical tensors is a convex cone that rotations map to itself (it depends on the
//! eigenvalues only). For such a set the nearest member in the Frobenius norm `‖I − I'‖_F` keeps
//! the eigenvectors and moves the eigenvalues to the nearest point of the eigenvalue set:
//! `I' = P diag(π(λ)) Pᵀ`, `π` the Euclidean projection onto the polyhedral cone
//! `C = {λ : λ₁ + λ₂ − λ₃ ≥ 0, λ₁ − λ₂ + λ₃ ≥ 0, −λ₁ + λ₂ + λ₃ ≥ 0}`.
//!
//! References: A. S. Lewis, "Convex analysis on the Hermitian matrices", SIAM J. Optim. 6 (1996)
//! (projections onto spectral sets keep the eigenvectors); P. M. Wensing, S. Kim, J.-J. E. Slotine,
//! "Linear matrix inequalities for physically consistent inertial parameter identification", IEEE
//! RA-L 3 (2018) (the triangle inequalities as the condition of physical consistency).
//!
//! When only `λ₁ + λ₂ ≥ λ₃` fails (λ sorted, all ≥ 0: the usual case), `π` moves the moments along
//! the normal `(1, 1, −1)`: the two smaller rise and the largest falls, each by a third of the
//! shortfall `d = λ₃ − λ₁ − λ₂`, which leaves `λ₁ + λ₂ = λ₃`. The mass and the centre of mass never
//! change; a link with zero mass can only have the zero tensor.

use crate::body::mass::{symmetric_eigen, INERTIA_RELATIVE_TOLERANCE};
use crate::math::{DMat3, DVec3};

/// What is wrong with a rotational inertia (principal moments in kg·m², in the order found).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InertiaDefect {
    /// A principal moment is negative (beyond round-off).
    NotPositiveSemiDefinite { moments: [f64; 3] },
    /// The moments are non-negative but `λ₁ + λ₂ < λ₃`; `short_by` is `λ₃ − λ₁ − λ₂` over `λ₃`.
    TriangleInequality { moments: [f64; 3], short_by: f64 },
    /// Inertia without mass.
    MasslessWithTensor { moments: [f64; 3] },
}

impl InertiaDefect {
    /// Whether the defect leaves the tensor positive definite: the triangle inequality violated
    /// while every principal moment stays above round-off (`1e-9` of the largest). Such a link still
    /// has a positive-definite spatial inertia (a camera's or a sensor's inertia box written with one
    /// moment too large), so the mass matrix of the robot stays positive definite.
    pub fn is_positive_definite(&self) -> bool {
        match self {
            Self::TriangleInequality { moments, .. } => {
                let largest = moments.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
                moments.iter().all(|&x| x > INERTIA_RELATIVE_TOLERANCE * largest)
            }
            Self::NotPositiveSemiDefinite { .. } | Self::MasslessWithTensor { .. } => false,
        }
    }
}

impl std::fmt::Display for InertiaDefect {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            Self::NotPositiveSemiDefinite { moments } => {
                write!(f, "principal moments {moments:?} kg·m²: one is negative (not positive semi-definite)")
            }
            Self::TriangleInequality { moments, short_by } => write!(
                f,
                "principal moments {moments:?} kg·m² violate the triangle inequality I1 + I2 ≥ I3 (short by \
                 {:.3}% of the largest); no rigid body has such moments",
                short_by * 100.0
            ),
            Self::MasslessWithTensor { moments } => {
                write!(f, "mass 0 with principal moments {moments:?} kg·m²: a body without mass has no inertia")
            }
        }
    }
}

/// A tensor replaced by its nearest physical one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Balanced {
    /// The physical tensor, in the axes of the input (kg·m²).
    pub tensor: DMat3,
    /// Principal moments before (kg·m²).
    pub before: [f64; 3],
    /// Principal moments after, along the same principal axes (kg·m²).
    pub after: [f64; 3],
    /// `‖I − I'‖_F / ‖I‖_F`.
    pub relative_change: f64,
}

/// `None` when `tensor` (symmetric, finite, about the centre of mass) is a physical inertia for a
/// body of mass `mass` (kg); else what is wrong.
pub fn inertia_defect(mass: f64, tensor: DMat3) -> Option<InertiaDefect> {
    let (moments, _) = symmetric_eigen(tensor);
    let m = moments.to_array();
    if mass == 0.0 && tensor != DMat3::ZERO {
        return Some(InertiaDefect::MasslessWithTensor { moments: m });
    }
    let largest = m.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    let tol = INERTIA_RELATIVE_TOLERANCE * largest;
    if m.iter().any(|&x| x < -tol) {
        return Some(InertiaDefect::NotPositiveSemiDefinite { moments: m });
    }
    let slack = m[0] + m[1] + m[2] - 2.0 * moments.max_element();
    if slack < -tol {
        return Some(InertiaDefect::TriangleInequality { moments: m, short_by: -slack / largest });
    }
    None
}

/// The physical tensor nearest to `tensor` in the Frobenius norm (see the module documentation);
/// for `mass = 0`, the zero tensor.
pub fn nearest_physical(mass: f64, tensor: DMat3) -> Balanced {
    let (moments, axes) = symmetric_eigen(tensor);
    let after = if mass == 0.0 { DVec3::ZERO } else { project_on_triangle_cone(moments) };
    let balanced = axes * DMat3::from_diagonal(after) * axes.transpose();
    // symmetric to the last bit
    let balanced = 0.5 * (balanced + balanced.transpose());
    let norm = |a: DMat3| a.to_cols_array().iter().map(|x| x * x).sum::<f64>().sqrt();
    let before_norm = norm(tensor);
    let relative_change = if before_norm > 0.0 { norm(balanced - tensor) / before_norm } else { 0.0 };
    Balanced { tensor: balanced, before: moments.to_array(), after: after.to_array(), relative_change }
}

/// Euclidean projection of `λ` onto `{λᵢ + λⱼ ≥ λₖ}`: the nearest of the projections onto the
/// spans of every set of active constraints that is feasible (the projection lies on one face of
/// the cone, and is the nearest feasible point among those candidates).
pub fn project_on_triangle_cone(lambda: DVec3) -> DVec3 {
    let normals = [DVec3::new(1.0, 1.0, -1.0), DVec3::new(1.0, -1.0, 1.0), DVec3::new(-1.0, 1.0, 1.0)];
    let feasible = |x: DVec3| normals.iter().all(|n| n.dot(x) >= -1e-12 * x.abs().max_element());
    if feasible(lambda) {
        return lambda;
    }
    // |A| = 3: the apex
    let mut best = DVec3::ZERO;
    let mut best_distance = lambda.length_squared();
    let mut consider = |x: DVec3| {
        let d = (x - lambda).length_squared();
        if d < best_distance && feasible(x) {
            best = x;
            best_distance = d;
        }
    };
    // |A| = 1: x = λ − (n·λ / |n|²) n
    for n in normals {
        consider(lambda - n * (n.dot(lambda) / 3.0));
    }
    // |A| = 2: x = λ − Nᵀ G⁻¹ N λ with G = [[3, −1], [−1, 3]], G⁻¹ = [[3, 1], [1, 3]] / 8
    for (a, b) in [(0, 1), (0, 2), (1, 2)] {
        let (na, nb) = (normals[a], normals[b]);
        let (ra, rb) = (na.dot(lambda), nb.dot(lambda));
        let (ya, yb) = ((3.0 * ra + rb) / 8.0, (ra + 3.0 * rb) / 8.0);
        consider(lambda - na * ya - nb * yb);
    }
    best
}
