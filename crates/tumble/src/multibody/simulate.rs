//! Time integration of a tree: `q̇ = G(q) v`, `v̇ = ABA(q, v, τ(q, v))`.
//!
//! The joint forces come from a [`Control`]: a constant force per velocity coordinate, joint
//! damping, and PD targets, `τ = τ_const − c v + k_p (q* − q) + k_d (v* − v)` (PD and damping on
//! one-coordinate joints only; spherical and floating joints take `τ_const`).
//!
//! Integrators: `rk4` (classical, 4th order; `q` moves through ℝ^nq and quaternions are renormalised
//! at the end of each step, which keeps the order) and `semi_implicit_euler`
//! (`v ← v + dt v̇(q, v)`, then `q ← q ⊕ v dt` on the manifold) and explicit `euler` (both from the
//! old state). All scratch vectors live in the
//! [`Simulator`], so a step does not allocate.

use super::aba::{aba, AbaError};
use super::joint::JointKind;
use super::model::{Joint, MultibodyModel};
use super::workspace::{check_len, LengthError, Workspace};

/// Joint forces as a function of the state. Vectors are indexed by velocity coordinate (length nv)
/// except `q_target` (length nq, only its one-coordinate entries are used).
#[derive(Debug, Clone, PartialEq)]
pub struct Control {
    /// Constant joint forces (N·m or N; for a floating base `[f; n]` in the base frame).
    pub tau: Vec<f64>,
    /// Viscous damping coefficients `c ≥ 0` (N·m·s/rad or N·s/m).
    pub damping: Vec<f64>,
    /// Proportional gains `k_p ≥ 0` (N·m/rad or N/m); 0 disables.
    pub kp: Vec<f64>,
    /// Derivative gains `k_d ≥ 0` (N·m·s/rad or N·s/m).
    pub kd: Vec<f64>,
    /// Position targets `q*` (length nq).
    pub q_target: Vec<f64>,
    /// Velocity targets `v*` (length nv).
    pub v_target: Vec<f64>,
}

impl Control {
    /// No force at all (a passive tree).
    pub fn passive(model: &MultibodyModel) -> Self {
        let nv = model.nv();
        Self {
            tau: vec![0.0; nv],
            damping: vec![0.0; nv],
            kp: vec![0.0; nv],
            kd: vec![0.0; nv],
            q_target: model.neutral_configuration(),
            v_target: vec![0.0; nv],
        }
    }

    /// `τ(q, v)` written into `tau` (lengths nq, nv, nv).
    pub fn joint_forces(
        &self,
        model: &MultibodyModel,
        q: &[f64],
        v: &[f64],
        tau: &mut [f64],
    ) -> Result<(), LengthError> {
        self.check(model)?;
        check_len("q", q.len(), model.nq())?;
        check_len("v", v.len(), model.nv())?;
        check_len("tau", tau.len(), model.nv())?;
        tau.copy_from_slice(&self.tau);
        for body in &model.bodies {
            let j = &body.joint;
            if matches!(j.kind, JointKind::Spherical | JointKind::Floating) {
                continue;
            }
            let (qi, vi) = (j.q_index, j.v_index);
            // τ += −c v + k_p (q* − q) + k_d (v* − v)
            tau[vi] += -self.damping[vi] * v[vi]
                + self.kp[vi] * (self.q_target[qi] - q[qi])
                + self.kd[vi] * (self.v_target[vi] - v[vi]);
        }
        Ok(())
    }

    fn check(&self, model: &MultibodyModel) -> Result<(), LengthError> {
        let nv = model.nv();
        check_len("control tau", self.tau.len(), nv)?;
        check_len("control damping", self.damping.len(), nv)?;
        check_len("control kp", self.kp.len(), nv)?;
        check_len("control kd", self.kd.len(), nv)?;
        check_len("control q_target", self.q_target.len(), model.nq())?;
        check_len("control v_target", self.v_target.len(), nv)
    }
}

/// How a [`Simulator`] steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    Rk4,
    SemiImplicitEuler,
    /// Explicit (forward) Euler: `q ← q ⊕ v dt`, `v ← v + dt v̇(q, v)`, both from the state at the
    /// start of the step (first order; it gains energy on oscillations).
    Euler,
}

/// The state `(q, v)` of a tree, its model's workspace and the integrator's scratch.
#[derive(Debug, Clone)]
pub struct Simulator {
    /// Configuration (nq).
    pub q: Vec<f64>,
    /// Velocity (nv).
    pub v: Vec<f64>,
    /// Simulated time (s).
    pub t: f64,
    ws: Workspace,
    tau: Vec<f64>,
    k_q: [Vec<f64>; 4],
    k_v: [Vec<f64>; 4],
    q_stage: Vec<f64>,
    v_stage: Vec<f64>,
}

impl Simulator {
    /// A simulator starting at `(q, v)` at `t = 0`.
    pub fn new(model: &MultibodyModel, q: Vec<f64>, v: Vec<f64>) -> Result<Self, LengthError> {
        check_len("q", q.len(), model.nq())?;
        check_len("v", v.len(), model.nv())?;
        let (nq, nv) = (model.nq(), model.nv());
        Ok(Self {
            q,
            v,
            t: 0.0,
            ws: Workspace::new(model),
            tau: vec![0.0; nv],
            k_q: std::array::from_fn(|_| vec![0.0; nq]),
            k_v: std::array::from_fn(|_| vec![0.0; nv]),
            q_stage: vec![0.0; nq],
            v_stage: vec![0.0; nv],
        })
    }

    /// The workspace (poses and velocities of the last evaluation).
    pub fn workspace(&mut self) -> &mut Workspace {
        &mut self.ws
    }

    /// Advances by `dt` seconds.
    pub fn step(&mut self, model: &MultibodyModel, control: &Control, method: Method, dt: f64) -> Result<(), AbaError> {
        control.check(model)?;
        // the simulator's own vectors were sized for a model: it must be this one
        check_len("q (simulator state)", self.q.len(), model.nq())?;
        check_len("v (simulator state)", self.v.len(), model.nv())?;
        check_len("q (the model the simulator was made for)", self.q_stage.len(), model.nq())?;
        check_len("v (the model the simulator was made for)", self.v_stage.len(), model.nv())?;
        match method {
            Method::Rk4 => self.rk4(model, control, dt)?,
            Method::SemiImplicitEuler => {
                // v ← v + dt v̇(q, v);  q ← q ⊕ v dt
                control.joint_forces(model, &self.q, &self.v, &mut self.tau)?;
                aba(model, &mut self.ws, &self.q, &self.v, &self.tau, &mut self.k_v[0])?;
                for (v, a) in self.v.iter_mut().zip(&self.k_v[0]) {
                    *v += dt * a;
                }
                self.q_stage.copy_from_slice(&self.q);
                model.integrate(&self.q_stage, &self.v, dt, &mut self.q)?;
            }
            Method::Euler => {
                // q ← q ⊕ v dt and v ← v + dt v̇(q, v), from the old (q, v)
                control.joint_forces(model, &self.q, &self.v, &mut self.tau)?;
                aba(model, &mut self.ws, &self.q, &self.v, &self.tau, &mut self.k_v[0])?;
                self.q_stage.copy_from_slice(&self.q);
                model.integrate(&self.q_stage, &self.v, dt, &mut self.q)?;
                for (v, a) in self.v.iter_mut().zip(&self.k_v[0]) {
                    *v += dt * a;
                }
            }
        }
        self.t += dt;
        Ok(())
    }

    fn rk4(&mut self, model: &MultibodyModel, control: &Control, dt: f64) -> Result<(), AbaError> {
        const C: [f64; 4] = [0.0, 0.5, 0.5, 1.0];
        for (s, c) in C.iter().enumerate() {
            // stage s at (q + C_s dt k_{s−1}, v + C_s dt k_{s−1})
            if s == 0 {
                self.q_stage.copy_from_slice(&self.q);
                self.v_stage.copy_from_slice(&self.v);
            } else {
                let h = c * dt;
                for ((stage, y), k) in self.q_stage.iter_mut().zip(&self.q).zip(&self.k_q[s - 1]) {
                    *stage = y + h * k;
                }
                for ((stage, y), k) in self.v_stage.iter_mut().zip(&self.v).zip(&self.k_v[s - 1]) {
                    *stage = y + h * k;
                }
            }
            model.coordinate_rate(&self.q_stage, &self.v_stage, &mut self.k_q[s])?;
            control.joint_forces(model, &self.q_stage, &self.v_stage, &mut self.tau)?;
            aba(model, &mut self.ws, &self.q_stage, &self.v_stage, &self.tau, &mut self.k_v[s])?;
        }
        // y ← y + dt/6 (k1 + 2 k2 + 2 k3 + k4)
        for i in 0..self.q.len() {
            self.q[i] += dt / 6.0 * (self.k_q[0][i] + 2.0 * self.k_q[1][i] + 2.0 * self.k_q[2][i] + self.k_q[3][i]);
        }
        for i in 0..self.v.len() {
            self.v[i] += dt / 6.0 * (self.k_v[0][i] + 2.0 * self.k_v[1][i] + 2.0 * self.k_v[2][i] + self.k_v[3][i]);
        }
        normalize_quaternions(model, &mut self.q);
        Ok(())
    }
}

/// The joints that carry a unit quaternion in `q` (spherical and floating), each with the index of
/// its quaternion's first component `[w, x, y, z]`.
pub fn quaternion_slots(model: &MultibodyModel) -> impl Iterator<Item = (&Joint, usize)> {
    model.bodies.iter().filter_map(|body| {
        let j = &body.joint;
        match j.kind {
            JointKind::Spherical => Some((j, j.q_index)),
            JointKind::Floating => Some((j, j.q_index + 3)),
            _ => None,
        }
    })
}

/// Projects the quaternions of spherical and floating joints back onto the unit sphere.
pub fn normalize_quaternions(model: &MultibodyModel, q: &mut [f64]) {
    for (_, start) in quaternion_slots(model) {
        let quat = &mut q[start..start + 4];
        let n = quat.iter().map(|x| x * x).sum::<f64>().sqrt();
        if n > 0.0 && n.is_finite() {
            quat.iter_mut().for_each(|x| *x /= n);
        }
    }
}
