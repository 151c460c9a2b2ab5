//! Joints: their coordinates, their transform `X_J(q)` and their motion subspace `S`.
//!
//! Reference: Featherstone (2008), §4.4 and Table 4.1.
//!
//! A joint connects a predecessor (parent) frame to a successor (child) frame. The *joint frame*
//! is the child's frame at `q = 0`, placed in the parent by the fixed transform `X_T` (URDF's
//! `<origin>`); the joint then moves the child relative to the joint frame:
//! `child_X_parent = X_J(q) · X_T`.
//!
//! Every joint here has a motion subspace `S` that is constant in the child frame, so the joint's
//! velocity is `v_J = S q̇` and its velocity-product term `c_J = Ṡ q̇` is zero.
//!
//! | kind        | nq | nv | q                          | v (child frame)                       |
//! |-------------|----|----|----------------------------|---------------------------------------|
//! | revolute    | 1  | 1  | angle (rad)                | angle rate (rad/s)                    |
//! | continuous  | 1  | 1  | angle (rad)                | angle rate (rad/s)                    |
//! | prismatic   | 1  | 1  | displacement (m)           | rate (m/s)                            |
//! | spherical   | 4  | 3  | unit quaternion `[w,x,y,z]` `joint_from_child` | `ω` (rad/s)       |
//! | floating    | 7  | 6  | `[x, y, z, qw, qx, qy, qz]` | `[v; ω]`: linear then angular          |
//!
//! The floating joint's `q` is the position of the child's origin and the quaternion
//! `parent_from_child`; its `v` is the child origin's linear velocity and the angular velocity, both
//! in the child frame (the contract of `tumble model`).

use super::spatial::{axis_angle_rotation, Motion, Xform};
use crate::math::{DMat3, DQuat, DVec3};

/// The kind of a joint, with its axis (a unit vector in the joint frame) where it has one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointKind {
    /// Rotation about `axis` within limits.
    Revolute { axis: DVec3 },
    /// Rotation about `axis` without limits (one coordinate: the angle).
    Continuous { axis: DVec3 },
    /// Translation along `axis`.
    Prismatic { axis: DVec3 },
    /// Any rotation (unit quaternion).
    Spherical,
    /// Any rigid motion (a free-flyer base).
    Floating,
}

impl JointKind {
    /// Number of configuration coordinates.
    #[inline]
    pub fn nq(&self) -> usize {
        match self {
            JointKind::Revolute { .. } | JointKind::Continuous { .. } | JointKind::Prismatic { .. } => 1,
            JointKind::Spherical => 4,
            JointKind::Floating => 7,
        }
    }

    /// Number of velocity coordinates (degrees of freedom).
    #[inline]
    pub fn nv(&self) -> usize {
        match self {
            JointKind::Revolute { .. } | JointKind::Continuous { .. } | JointKind::Prismatic { .. } => 1,
            JointKind::Spherical => 3,
            JointKind::Floating => 6,
        }
    }

    /// The name used by `tumble model`.
    pub fn name(&self) -> &'static str {
        match self {
            JointKind::Revolute { .. } => "revolute",
            JointKind::Continuous { .. } => "continuous",
            JointKind::Prismatic { .. } => "prismatic",
            JointKind::Spherical => "spherical",
            JointKind::Floating => "floating",
        }
    }

    /// The columns of the motion subspace `S` (child frame), one per velocity coordinate.
    pub fn motion_subspace(&self) -> Vec<Motion> {
        let e = [DVec3::X, DVec3::Y, DVec3::Z];
        match *self {
            JointKind::Revolute { axis } | JointKind::Continuous { axis } => vec![Motion::new(axis, DVec3::ZERO)],
            JointKind::Prismatic { axis } => vec![Motion::new(DVec3::ZERO, axis)],
            JointKind::Spherical => e.iter().map(|&k| Motion::new(k, DVec3::ZERO)).collect(),
            // v = [linear; angular] (the contract), spatial vectors are [angular; linear]
            JointKind::Floating => e
                .iter()
                .map(|&k| Motion::new(DVec3::ZERO, k))
                .chain(e.iter().map(|&k| Motion::new(k, DVec3::ZERO)))
                .collect(),
        }
    }

    /// The joint transform `X_J(q) = child_X_jointframe` for the coordinates `q` (length [`nq`](Self::nq),
    /// checked by the callers).
    ///
    /// Quaternions are normalised here, so a `q` slightly off the unit sphere still gives a rotation.
    #[inline]
    pub(crate) fn transform(&self, q: &[f64]) -> Xform {
        match *self {
            // rotation by θ about k: joint_from_child = R(k, θ), E = Rᵀ
            JointKind::Revolute { axis } | JointKind::Continuous { axis } => {
                Xform { e: axis_angle_rotation(axis, q[0]).transpose(), r: DVec3::ZERO }
            }
            // translation by d k: the child's origin is at d k in the joint frame
            JointKind::Prismatic { axis } => Xform { e: DMat3::IDENTITY, r: axis * q[0] },
            JointKind::Spherical => Xform::from_pose(DMat3::from_quat(quat_wxyz(&q[0..4])), DVec3::ZERO),
            JointKind::Floating => {
                Xform::from_pose(DMat3::from_quat(quat_wxyz(&q[3..7])), DVec3::new(q[0], q[1], q[2]))
            }
        }
    }

    /// The neutral configuration (zero angles and displacements, identity rotations), written into `q`.
    pub(crate) fn neutral(&self, q: &mut [f64]) {
        q.fill(0.0);
        match self {
            JointKind::Spherical => q[0] = 1.0,
            JointKind::Floating => q[3] = 1.0,
            _ => {}
        }
    }

    /// The rate of the coordinates, `q̇ = G(q) v`, written into `qd` (length nq).
    ///
    /// One-coordinate joints: `q̇ = v`. Quaternions: `q̇ = ½ q ⊗ (0, ω)`. Floating position:
    /// `ẋ = R v_linear` (the linear velocity is in the child frame).
    pub(crate) fn coordinate_rate(&self, q: &[f64], v: &[f64], qd: &mut [f64]) {
        match self {
            JointKind::Spherical => {
                let r = quat_rate(quat_wxyz(&q[0..4]), DVec3::new(v[0], v[1], v[2]));
                qd[..4].copy_from_slice(&r);
            }
            JointKind::Floating => {
                let rot = quat_wxyz(&q[3..7]);
                let xd = rot * DVec3::new(v[0], v[1], v[2]);
                qd[..3].copy_from_slice(&xd.to_array());
                let r = quat_rate(rot, DVec3::new(v[3], v[4], v[5]));
                qd[3..7].copy_from_slice(&r);
            }
            _ => qd[0] = v[0],
        }
    }

    /// The configuration reached from `q` by moving with constant `v` for `dt` seconds (written
    /// into `q_next`): additive for one-coordinate joints, the exponential map for rotations
    /// (`R ← R exp(ω dt)`), and for the floating base the position moved by `R(q) v_linear dt`.
    pub(crate) fn integrate(&self, q: &[f64], v: &[f64], dt: f64, q_next: &mut [f64]) {
        match self {
            JointKind::Spherical => {
                let r = quat_wxyz(&q[0..4]) * crate::math::quat_exp(DVec3::new(v[0], v[1], v[2]) * dt);
                q_next[..4].copy_from_slice(&wxyz(r.normalize()));
            }
            JointKind::Floating => {
                let rot = quat_wxyz(&q[3..7]);
                let x = DVec3::new(q[0], q[1], q[2]) + rot * DVec3::new(v[0], v[1], v[2]) * dt;
                q_next[..3].copy_from_slice(&x.to_array());
                let r = rot * crate::math::quat_exp(DVec3::new(v[3], v[4], v[5]) * dt);
                q_next[3..7].copy_from_slice(&wxyz(r.normalize()));
            }
            _ => q_next[0] = q[0] + v[0] * dt,
        }
    }
}

/// A unit quaternion from `[w, x, y, z]`, normalised (the identity for a zero or non-finite input).
#[inline]
pub fn quat_wxyz(q: &[f64]) -> DQuat {
    let quat = DQuat::from_xyzw(q[1], q[2], q[3], q[0]);
    let n = quat.length();
    if n > 0.0 && n.is_finite() {
        quat / n
    } else {
        DQuat::IDENTITY
    }
}

#[inline]
fn wxyz(q: DQuat) -> [f64; 4] {
    [q.w, q.x, q.y, q.z]
}

/// `q̇ = ½ q ⊗ (0, ω)` as `[w, x, y, z]`.
#[inline]
fn quat_rate(q: DQuat, omega: DVec3) -> [f64; 4] {
    let r = q * DQuat::from_xyzw(omega.x, omega.y, omega.z, 0.0);
    [0.5 * r.w, 0.5 * r.x, 0.5 * r.y, 0.5 * r.z]
}

/// The joint's own passive dynamics, used by every algorithm (zero for a URDF joint):
///
/// - `armature` (kg·m² or kg) is added to the mass-matrix diagonal of each of the joint's velocity
///   coordinates, `M_kk += a` (a rotor's reflected inertia; MuJoCo's `armature`): CRBA adds it to
///   `M`, ABA to `D = Sᵀ I^A S`, RNEA adds `a q̈`, the kinetic energy `½ a v²`;
/// - `damping` `d ≥ 0` gives the passive force `−d v` on each of its velocity coordinates;
/// - `stiffness` `k ≥ 0` gives `−k (q − spring_ref)` (one-coordinate joints only), with
///   `spring_ref` in this model's coordinates (rad or m) and the potential `½ k (q − spring_ref)²`;
/// - `friction_loss` `F ≥ 0` is dry (Coulomb) friction on each of its velocity coordinates: a
///   generalized force in `[−F, F]` that opposes the motion and holds the joint still while the
///   other forces on it stay within `F` (MuJoCo's `frictionloss`).
///
/// The passive forces enter the joint forces `τ` ([`passive_forces`](super::passive::passive_forces)),
/// as MuJoCo's `qfrc_passive`. Friction loss is not a passive force but a constraint: a bounded
/// impulse `|λ| ≤ F h` per step of `h` ([`super::limits`], and [`crate::contact::links`] for a tree
/// held by resting contact), as MuJoCo's friction-loss rows.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointDynamics {
    /// Added to `M_kk` for each velocity coordinate `k` of the joint (kg·m² or kg).
    pub armature: f64,
    /// Viscous damping `d ≥ 0` (N·m·s/rad or N·s/m): force `−d v`.
    pub damping: f64,
    /// Spring stiffness `k ≥ 0` (N·m/rad or N/m): force `−k (q − spring_ref)`.
    pub stiffness: f64,
    /// The spring's rest position (rad or m), in this model's coordinates.
    pub spring_ref: f64,
    /// Dry friction `F ≥ 0` (N·m or N) on each velocity coordinate: a force in `[−F, F]`.
    pub friction_loss: f64,
}

impl JointDynamics {
    /// True when every coefficient is zero (a URDF joint).
    #[inline]
    pub fn is_zero(&self) -> bool {
        self.armature == 0.0 && self.damping == 0.0 && self.stiffness == 0.0 && self.friction_loss == 0.0
    }
}

/// Position limits and damping of a joint as read from URDF (not used by the dynamics algorithms).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointLimits {
    /// Lower and upper position limits (rad or m), when the joint has them.
    pub position: Option<(f64, f64)>,
    /// Effort limit (N·m or N).
    pub effort: Option<f64>,
    /// Velocity limit (rad/s or m/s).
    pub velocity: Option<f64>,
    /// Viscous damping coefficient (N·m·s/rad or N·s/m).
    pub damping: f64,
    /// Coulomb friction (N·m or N).
    pub friction: f64,
}
