//! MuJoCo's joint coordinates and tumble's, and the maps between them (both ways).
//!
//! Both number the joints alike (bodies depth-first in file order, a body's joints in order), so a
//! joint's `qpos`/`qvel` slots are tumble's `q`/`v` slots. What differs, checked against
//! `mj_kinematics` and finite differences of `mj_integratePos`:
//!
//! | joint | MuJoCo `qpos` | MuJoCo `qvel` | tumble `q` | tumble `v` |
//! |-------|---------------|---------------|------------|------------|
//! | hinge, slide | angle or displacement | its rate | `qpos − ref` | the same rate |
//! | ball  | quaternion `w x y z` (child in parent) | `ω` in the child frame | the same | the same |
//! | free  | body origin (world), quaternion `w x y z` (body → world) | `ẋ` of the body origin in the **world** frame, then `ω` in the **body** frame | the same | `Rᵀ ẋ` (body frame), then `ω` (body frame) |
//!
//! With `v_tumble = T v_mujoco` (`T = diag(Rᵀ, 1)` on each free joint, the identity elsewhere):
//!
//! - generalised forces `τ_mujoco = Tᵀ τ_tumble` (the power `τᵀ v` is the same);
//! - the mass matrix `M_mujoco = Tᵀ M_tumble T`;
//! - accelerations `q̈_tumble = T q̈_mujoco + c`, with `c = Ṫ v_mujoco = −ω × (Rᵀ ẋ)` on a free joint's
//!   linear slots (`d/dt Rᵀ = −ω̃ Rᵀ`, `ω` in the body frame);
//! - the bias forces `b_mujoco = Tᵀ (b_tumble + M_tumble c)` (from `M q̈ + b = τ` in both).

use crate::math::{DMat3, DVec3};
use crate::multibody::joint::quat_wxyz;
use crate::multibody::model::MultibodyModel;
use crate::multibody::workspace::{check_len, LengthError};
use nalgebra::DMatrix;

/// One joint as MJCF gave it.
#[derive(Debug, Clone, PartialEq)]
pub struct LayoutJoint {
    pub name: String,
    /// A free joint (`T = diag(Rᵀ, 1)`).
    pub free: bool,
    /// MuJoCo's `ref` of a hinge or slide (rad or m): `q = qpos − ref`; zero for the others.
    pub reference: f64,
    /// A free joint's initial pose (the body's `pos`/`quat` in the world): its `qpos0`.
    pub free_pose0: Option<super::Pose>,
}

/// The layout of a model read from MJCF.
#[derive(Debug, Clone, PartialEq)]
pub struct MujocoLayout {
    pub joints: Vec<LayoutJoint>,
    /// Per joint: `(q_index, v_index, nq)` (the same in both).
    slots: Vec<(usize, usize, usize)>,
    nq: usize,
    nv: usize,
}

impl MujocoLayout {
    /// The layout of `model`, whose body `i` is moved by `joints[i]`.
    pub fn new(model: &MultibodyModel, joints: Vec<LayoutJoint>) -> Self {
        let slots = model.bodies.iter().map(|b| (b.joint.q_index, b.joint.v_index, b.joint.kind.nq())).collect();
        MujocoLayout { joints, slots, nq: model.nq(), nv: model.nv() }
    }

    /// MuJoCo's `qpos0`: `ref` for hinges and slides, the identity for balls, the body's pose for
    /// free joints.
    pub fn qpos0(&self) -> Vec<f64> {
        let mut qpos = vec![0.0; self.nq];
        for (j, &(qi, _, nq)) in self.joints.iter().zip(&self.slots) {
            match (nq, &j.free_pose0) {
                (7, Some(p)) => {
                    qpos[qi..qi + 3].copy_from_slice(&p.pos.to_array());
                    qpos[qi + 3..qi + 7].copy_from_slice(&[p.rot.w, p.rot.x, p.rot.y, p.rot.z]);
                }
                (4, _) | (7, None) => qpos[qi + nq - 4] = 1.0,
                _ => qpos[qi] = j.reference,
            }
        }
        qpos
    }

    /// The free joints: `(q_index, v_index)` and the rotation `R` (body → world) of their `qpos`.
    fn free<'q>(&'q self, q: &'q [f64]) -> impl Iterator<Item = (usize, DMat3)> + 'q {
        self.joints
            .iter()
            .zip(&self.slots)
            .filter(|(j, _)| j.free)
            .map(move |(_, &(qi, vi, _))| (vi, DMat3::from_quat(quat_wxyz(&q[qi + 3..qi + 7]))))
    }

    fn check(&self, q: &[f64], v: Option<&[f64]>) -> Result<(), LengthError> {
        check_len("q", q.len(), self.nq)?;
        if let Some(v) = v {
            check_len("v", v.len(), self.nv)?;
        }
        Ok(())
    }

    /// `(q, v)` of tumble from MuJoCo's `(qpos, qvel)`.
    pub fn state_from_mujoco(&self, qpos: &[f64], qvel: &[f64]) -> Result<(Vec<f64>, Vec<f64>), LengthError> {
        self.check(qpos, Some(qvel))?;
        let mut q = qpos.to_vec();
        for (j, &(qi, _, nq)) in self.joints.iter().zip(&self.slots) {
            if nq == 1 {
                q[qi] -= j.reference;
            }
        }
        let mut v = qvel.to_vec();
        for (vi, r) in self.free(qpos) {
            // v_body = Rᵀ ẋ_world
            let lin = r.transpose() * DVec3::from_slice(&qvel[vi..vi + 3]);
            v[vi..vi + 3].copy_from_slice(&lin.to_array());
        }
        Ok((q, v))
    }

    /// MuJoCo's `(qpos, qvel)` from tumble's `(q, v)`.
    pub fn state_to_mujoco(&self, q: &[f64], v: &[f64]) -> Result<(Vec<f64>, Vec<f64>), LengthError> {
        self.check(q, Some(v))?;
        let mut qpos = q.to_vec();
        for (j, &(qi, _, nq)) in self.joints.iter().zip(&self.slots) {
            if nq == 1 {
                qpos[qi] += j.reference;
            }
        }
        let mut qvel = v.to_vec();
        for (vi, r) in self.free(q) {
            // ẋ_world = R v_body
            let lin = r * DVec3::from_slice(&v[vi..vi + 3]);
            qvel[vi..vi + 3].copy_from_slice(&lin.to_array());
        }
        Ok((qpos, qvel))
    }

    /// `τ_mujoco = Tᵀ τ_tumble` (a free joint's force from the body frame to the world frame).
    pub fn force_to_mujoco(&self, q: &[f64], tau: &[f64]) -> Result<Vec<f64>, LengthError> {
        self.check(q, Some(tau))?;
        let mut out = tau.to_vec();
        for (vi, r) in self.free(q) {
            out[vi..vi + 3].copy_from_slice(&(r * DVec3::from_slice(&tau[vi..vi + 3])).to_array());
        }
        Ok(out)
    }

    /// `τ_tumble = T⁻ᵀ τ_mujoco`.
    pub fn force_from_mujoco(&self, q: &[f64], tau: &[f64]) -> Result<Vec<f64>, LengthError> {
        self.check(q, Some(tau))?;
        let mut out = tau.to_vec();
        for (vi, r) in self.free(q) {
            out[vi..vi + 3].copy_from_slice(&(r.transpose() * DVec3::from_slice(&tau[vi..vi + 3])).to_array());
        }
        Ok(out)
    }

    /// `M_mujoco = Tᵀ M_tumble T`.
    pub fn mass_matrix_to_mujoco(&self, q: &[f64], m: &DMatrix<f64>) -> Result<DMatrix<f64>, LengthError> {
        self.check(q, None)?;
        check_len("mass matrix rows", m.nrows(), self.nv)?;
        check_len("mass matrix columns", m.ncols(), self.nv)?;
        let mut t = DMatrix::<f64>::identity(self.nv, self.nv);
        for (vi, r) in self.free(q) {
            // v_tumble = Rᵀ ẋ: the block Rᵀ
            for a in 0..3 {
                for b in 0..3 {
                    t[(vi + a, vi + b)] = r.col(a)[b];
                }
            }
        }
        Ok(t.transpose() * m * t)
    }

    /// `c = Ṫ v_mujoco`: `−ω × v_body` on each free joint's linear slots, zero elsewhere (tumble's `v`).
    fn velocity_product(&self, q: &[f64], v: &[f64]) -> Vec<f64> {
        let mut c = vec![0.0; self.nv];
        for (vi, _) in self.free(q) {
            let (lin, omega) = (DVec3::from_slice(&v[vi..vi + 3]), DVec3::from_slice(&v[vi + 3..vi + 6]));
            c[vi..vi + 3].copy_from_slice(&(-omega.cross(lin)).to_array());
        }
        c
    }

    /// MuJoCo's `qacc` from tumble's `q̈` at `(q, v)` (tumble's): `q̈_mujoco = T⁻¹ (q̈_tumble − c)`.
    pub fn acceleration_to_mujoco(&self, q: &[f64], v: &[f64], qdd: &[f64]) -> Result<Vec<f64>, LengthError> {
        self.check(q, Some(v))?;
        check_len("qdd", qdd.len(), self.nv)?;
        let c = self.velocity_product(q, v);
        let mut out: Vec<f64> = qdd.iter().zip(&c).map(|(a, c)| a - c).collect();
        for (vi, r) in self.free(q) {
            let lin = r * DVec3::from_slice(&out[vi..vi + 3]);
            out[vi..vi + 3].copy_from_slice(&lin.to_array());
        }
        Ok(out)
    }

    /// tumble's `q̈` from MuJoCo's `qacc` at `(q, v)` (tumble's): `q̈_tumble = T q̈_mujoco + c`.
    pub fn acceleration_from_mujoco(&self, q: &[f64], v: &[f64], qacc: &[f64]) -> Result<Vec<f64>, LengthError> {
        self.check(q, Some(v))?;
        check_len("qacc", qacc.len(), self.nv)?;
        let c = self.velocity_product(q, v);
        let mut out = qacc.to_vec();
        for (vi, r) in self.free(q) {
            out[vi..vi + 3].copy_from_slice(&(r.transpose() * DVec3::from_slice(&qacc[vi..vi + 3])).to_array());
        }
        for (o, c) in out.iter_mut().zip(&c) {
            *o += c;
        }
        Ok(out)
    }

    /// MuJoCo's `qfrc_bias` from tumble's bias `b` and mass matrix `M` at `(q, v)` (tumble's):
    /// `b_mujoco = Tᵀ (b + M c)`.
    pub fn bias_to_mujoco(
        &self,
        q: &[f64],
        v: &[f64],
        bias: &[f64],
        m: &DMatrix<f64>,
    ) -> Result<Vec<f64>, LengthError> {
        self.check(q, Some(v))?;
        check_len("bias", bias.len(), self.nv)?;
        let c = nalgebra::DVector::from_vec(self.velocity_product(q, v));
        let mc = m * c;
        let total: Vec<f64> = bias.iter().zip(mc.iter()).map(|(b, x)| b + x).collect();
        self.force_to_mujoco(q, &total)
    }
}
