//! Time integration of a tree: `q̇ = G(q) v`, `v̇ = ABA(q, v, τ(q, v))`.
//!
//! The joint forces come from a [`Control`]: a constant force per velocity coordinate, joint
//! damping, and PD targets, `τ = clamp(τ_const + k_p (q* − q) + k_d (v* − v), ±τ_max) − c v` (PD and
//! damping on one-coordinate joints only; spherical and floating joints take `τ_const`). The
//! commanded part is clamped to the joint's effort limit `τ_max` where one is set
//! ([`Control::effort`]); damping is a passive force and is not clamped. The model's own joint
//! damping and springs ([`super::passive`], MuJoCo's `qfrc_passive`) are added after the clamp.
//!
//! Joint position limits ([`JointLimitSolver`], enabled by [`Simulator::set_joint_limits`]) act in
//! two phases around the integrator: an inelastic, speculative impulse at the start of the step and
//! a constraint force over the step applied at its end (see [`super::limits`]). The joints' dry
//! friction ([`JointDynamics::friction_loss`](super::joint::JointDynamics)) is solved with the
//! limits in that end phase, a bounded force `|τ| ≤ F` over the step, whether limits are enforced
//! or not.
//!
//! Integrators: `rk4` (classical, 4th order; `q` moves through ℝ^nq and quaternions are renormalised
//! at the end of each step, which keeps the order) and `semi_implicit_euler`
//! (`v ← v + dt v̇(q, v)`, then `q ← q ⊕ v dt` on the manifold) and explicit `euler` (both from the
//! old state). All scratch vectors live in the
//! [`Simulator`], so a step does not allocate.

use super::aba::{aba, AbaError};
use super::joint::JointKind;
use super::limits::{JointLimitSolver, Phase};
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
    /// Effort limits `τ_max > 0` (N·m or N) clamping the commanded force `τ_const + PD` of each
    /// velocity coordinate to `[−τ_max, τ_max]`; `f64::INFINITY` for none (length nv).
    pub effort: Vec<f64>,
    /// Periodic position targets: each sets `q*` of its coordinate at the start of every step
    /// ([`Control::follow_waves`]); empty for constant targets.
    pub waves: Vec<PdWave>,
    /// Forces along fixed tendons (MJCF actuators on tendons), each acting on all the tendon's
    /// joints; empty for a URDF robot.
    pub tendons: Vec<TendonDrive>,
}

/// A force along a fixed tendon of the model ([`super::tendon`]), an MJCF actuator with a tendon
/// transmission: with gear `g`, the actuator's length is `g L` and its force
///
/// ```text
/// f = f₀ + b₁ g L + b₂ g L̇        clamped to [f_lo, f_hi] when limited
/// τ += g J_tᵀ f                     (τ_i += g c_i f on each joint of the tendon)
/// ```
///
/// `f₀ = k u + b₀` holds the control `u` (gain `k`) and the constant bias.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TendonDrive {
    /// Index into [`MultibodyModel::tendons`].
    pub tendon: usize,
    /// `g`.
    pub gear: f64,
    /// `f₀` (N).
    pub force: f64,
    /// `b₁` (N/m): MuJoCo's `biasprm[1]` (`−kp` for a `position` actuator).
    pub bias_length: f64,
    /// `b₂` (N·s/m): `biasprm[2]` (`−kv`).
    pub bias_rate: f64,
    /// `forcerange` when the force is limited.
    pub force_range: Option<(f64, f64)>,
}

impl TendonDrive {
    /// `f(q, v)` before the clamp, and after it.
    #[inline]
    pub fn force(&self, model: &MultibodyModel, q: &[f64], v: &[f64]) -> (f64, f64) {
        let t = &model.tendons[self.tendon];
        let f = self.force + self.bias_length * self.gear * t.length(q) + self.bias_rate * self.gear * t.rate(v);
        let applied = match self.force_range {
            Some((lo, hi)) => f.max(lo).min(hi),
            None => f,
        };
        (f, applied)
    }
}

/// A position target that swings about a centre, `q*(t) = q̄ + A sin(2π f t + φ)`, held over each
/// step at its value at the step's start (a zero-order hold, as a controller writes its command
/// once per step). The velocity target is not changed: the PD then reads
/// `τ = k_p (q*(t) − q) + k_d (v* − v)`, as a position actuator whose command is `q*(t)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PdWave {
    /// The position coordinate (index into `q`).
    pub q_index: usize,
    /// Centre `q̄` (rad or m).
    pub centre: f64,
    /// Amplitude `A` (rad or m).
    pub amplitude: f64,
    /// Frequency `f` (Hz).
    pub frequency: f64,
    /// Phase `φ` (rad).
    pub phase: f64,
}

impl PdWave {
    /// `q*(t)`.
    pub fn target(&self, t: f64) -> f64 {
        self.centre + self.amplitude * (std::f64::consts::TAU * self.frequency * t + self.phase).sin()
    }
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
            effort: vec![f64::INFINITY; nv],
            waves: Vec::new(),
            tendons: Vec::new(),
        }
    }

    /// Sets the position target of every [`PdWave`] to its value at time `t` (s).
    pub fn follow_waves(&mut self, t: f64) {
        for w in &self.waves {
            self.q_target[w.q_index] = w.target(t);
        }
    }

    /// Sets [`effort`](Self::effort) from the URDF: each one-coordinate joint whose `<limit effort>`
    /// is positive is clamped to it (an `effort` of 0, which some URDFs write for "unspecified",
    /// leaves the joint unclamped).
    pub fn set_effort_limits(&mut self, model: &MultibodyModel) {
        for body in &model.bodies {
            let j = &body.joint;
            if j.kind.nv() != 1 {
                continue;
            }
            self.effort[j.v_index] = match j.limits.effort {
                Some(e) if e > 0.0 && e.is_finite() => e,
                _ => f64::INFINITY,
            };
        }
    }

    /// `τ(q, v)` written into `tau` (lengths nq, nv, nv); `ws` serves the medium's drag (its
    /// placements, velocities and forces are overwritten when the model's medium is not void).
    pub fn joint_forces(
        &self,
        model: &MultibodyModel,
        ws: &mut Workspace,
        q: &[f64],
        v: &[f64],
        tau: &mut [f64],
    ) -> Result<(), LengthError> {
        self.check(model)?;
        check_len("q", q.len(), model.nq())?;
        check_len("v", v.len(), model.nv())?;
        check_len("tau", tau.len(), model.nv())?;
        self.forces(model, ws, q, v, tau, None);
        Ok(())
    }

    /// `τ(q, v)` (lengths checked by the caller); `clamped[k]` is set where the effort limit cut
    /// coordinate `k`'s commanded force.
    fn forces(
        &self,
        model: &MultibodyModel,
        ws: &mut Workspace,
        q: &[f64],
        v: &[f64],
        tau: &mut [f64],
        mut clamped: Option<&mut [bool]>,
    ) {
        tau.copy_from_slice(&self.tau);
        for body in &model.bodies {
            let j = &body.joint;
            if matches!(j.kind, JointKind::Spherical | JointKind::Floating) {
                continue;
            }
            let (qi, vi) = (j.q_index, j.v_index);
            let limit = self.effort[vi];
            if limit == f64::INFINITY {
                // τ += −c v + k_p (q* − q) + k_d (v* − v)
                tau[vi] += -self.damping[vi] * v[vi]
                    + self.kp[vi] * (self.q_target[qi] - q[qi])
                    + self.kd[vi] * (self.v_target[vi] - v[vi]);
                continue;
            }
            // commanded: τ_const + k_p (q* − q) + k_d (v* − v), clamped to ±τ_max
            let commanded =
                tau[vi] + self.kp[vi] * (self.q_target[qi] - q[qi]) + self.kd[vi] * (self.v_target[vi] - v[vi]);
            let applied = commanded.max(-limit).min(limit);
            if applied != commanded {
                if let Some(c) = clamped.as_deref_mut() {
                    c[vi] = true;
                }
            }
            // passive: −c v (not clamped)
            tau[vi] = applied - self.damping[vi] * v[vi];
        }
        // forces along tendons: τ += g J_tᵀ f, f clamped to its range
        for d in &self.tendons {
            let (commanded, applied) = d.force(model, q, v);
            let tendon = &model.tendons[d.tendon];
            if applied != commanded {
                if let Some(c) = clamped.as_deref_mut() {
                    tendon.terms.iter().for_each(|t| c[t.v_index] = true);
                }
            }
            tendon.add_force(d.gear * applied, tau);
        }
        // the joints' own damping and springs (the model's, zero from URDF): −d v − k (q − q_ref), and
        // the medium's drag (none unless the model has a medium)
        super::passive::add_unchecked(model, ws, q, v, tau);
    }

    fn check(&self, model: &MultibodyModel) -> Result<(), LengthError> {
        let nv = model.nv();
        check_len("control tau", self.tau.len(), nv)?;
        check_len("control damping", self.damping.len(), nv)?;
        check_len("control kp", self.kp.len(), nv)?;
        check_len("control kd", self.kd.len(), nv)?;
        check_len("control q_target", self.q_target.len(), model.nq())?;
        check_len("control v_target", self.v_target.len(), nv)?;
        check_len("control effort", self.effort.len(), nv)?;
        match self.tendons.iter().find(|d| d.tendon >= model.tendons.len()) {
            Some(d) => Err(LengthError { what: "control tendon index", got: d.tendon, expected: model.tendons.len() }),
            None => Ok(()),
        }
    }
}

/// What a contact solve changes in a tree's step ([`Simulator::step_with_contact`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactChange<'a> {
    /// Collisions only: the joint velocity change (nv) at the start of the step.
    Impulse(&'a [f64]),
    /// Resting contact held the tree: the contact's generalized force over the step (nv),
    /// `τ_c = Jᵀ Λ / dt`, which the integrator adds to the joint forces, and the configuration (nq)
    /// where the contact solver's substeps put the tree at the end of the step, which replaces the
    /// integrator's (it holds the overlap correction). The contact solver solved the joint limits
    /// with the contacts: the limits' own phases are skipped. `v`: the velocity at the end of the
    /// step (nv), `v₀ + dt (a₀ + M⁻¹ τ_c)` with `a₀` the contact solver's own evaluation of the
    /// dynamics at the start of the step — what semi-implicit and explicit Euler would compute
    /// with `τ_c`, so that they take it instead of evaluating the dynamics a second time (one
    /// dynamics pass per step); RK4 integrates with `τ_c`.
    Held { q: &'a [f64], tau: &'a [f64], v: &'a [f64] },
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
    /// Configuration (nq). Written from outside, it wants [`Self::restart_limit_floor`] after (the
    /// contact stage's limit rows otherwise keep the floors of the old `q`).
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
    /// Joint position limits, when enforced.
    limits: Option<JointLimitSolver>,
    /// Coordinates whose commanded force was clamped during the last step (nv).
    clamped: Vec<bool>,
    /// A contact's generalized force over the current step (nv), added to the joint forces while
    /// `contact_force` is set ([`ContactChange::Held`]).
    tau_contact: Vec<f64>,
    contact_force: bool,
}

impl Simulator {
    /// A simulator starting at `(q, v)` at `t = 0`: limits off, the joints' friction loss on.
    pub fn new(model: &MultibodyModel, q: Vec<f64>, v: Vec<f64>) -> Result<Self, LengthError> {
        check_len("q", q.len(), model.nq())?;
        check_len("v", v.len(), model.nv())?;
        let (nq, nv) = (model.nq(), model.nv());
        let mut ws = Workspace::new(model);
        // a model with friction loss gets its rows now (there is no switch for them)
        let limits = JointLimitSolver::new(model, &mut ws, false);
        Ok(Self {
            q,
            v,
            t: 0.0,
            ws,
            tau: vec![0.0; nv],
            k_q: std::array::from_fn(|_| vec![0.0; nq]),
            k_v: std::array::from_fn(|_| vec![0.0; nv]),
            q_stage: vec![0.0; nq],
            v_stage: vec![0.0; nv],
            limits,
            clamped: vec![false; nv],
            tau_contact: vec![0.0; nv],
            contact_force: false,
        })
    }

    /// Enforces (or not) the position limits of `model`'s revolute and prismatic joints. Off by
    /// default; with no limited joint it stays off. The joints' friction loss acts either way.
    pub fn set_joint_limits(&mut self, model: &MultibodyModel, on: bool) {
        self.limits = JointLimitSolver::new(model, &mut self.ws, on);
        self.restart_limit_floor();
    }

    /// The joint-limit and friction-loss solver, when limits are enforced or a joint has friction
    /// loss (which joints, how often they pushed; [`JointLimitSolver::has_limits`]).
    pub fn joint_limits(&self) -> Option<&JointLimitSolver> {
        self.limits.as_ref()
    }

    /// Restarts the limits' floors ([`JointLimitSolver::floor`]) at the current `q`: after `q` was
    /// set from outside, a joint outside its limit is taken as it is, not pushed in.
    pub fn restart_limit_floor(&mut self) {
        if let Some(limits) = self.limits.as_mut() {
            limits.restart_floor(&self.q);
        }
    }

    /// The joint-limit solver, mutable (to count the activity of limits solved elsewhere).
    pub fn joint_limits_mut(&mut self) -> Option<&mut JointLimitSolver> {
        self.limits.as_mut()
    }

    /// Per velocity coordinate: whether its commanded force was clamped to its effort limit during
    /// the last step (at any stage of it).
    pub fn clamped(&self) -> &[bool] {
        &self.clamped
    }

    /// The workspace (poses and velocities of the last evaluation).
    pub fn workspace(&mut self) -> &mut Workspace {
        &mut self.ws
    }

    /// Advances by `dt` seconds.
    pub fn step(&mut self, model: &MultibodyModel, control: &Control, method: Method, dt: f64) -> Result<(), AbaError> {
        self.step_with_contact(model, control, method, dt, None)
    }

    /// Advances by `dt` seconds with the outcome of a contact solve (see [`crate::contact::links`]):
    /// a collision's velocity change, added at the start of the step before the integrator; or the
    /// end state of a tree that resting contact held, which the contact solver's substeps
    /// integrated (the joint limits' end-of-step phases then act on it, with the position weight of
    /// semi-implicit Euler).
    pub fn step_with_contact(
        &mut self,
        model: &MultibodyModel,
        control: &Control,
        method: Method,
        dt: f64,
        contact: Option<ContactChange<'_>>,
    ) -> Result<(), AbaError> {
        control.check(model)?;
        // the simulator's own vectors were sized for a model: it must be this one
        check_len("q (simulator state)", self.q.len(), model.nq())?;
        check_len("v (simulator state)", self.v.len(), model.nv())?;
        check_len("q (the model the simulator was made for)", self.q_stage.len(), model.nq())?;
        check_len("v (the model the simulator was made for)", self.v_stage.len(), model.nv())?;
        self.clamped.fill(false);
        self.contact_force = false;
        match contact {
            None => {}
            Some(ContactChange::Impulse(dv)) => {
                check_len("contact velocity change", dv.len(), model.nv())?;
                for (v, d) in self.v.iter_mut().zip(dv) {
                    *v += d;
                }
            }
            Some(ContactChange::Held { q, tau, v }) => {
                check_len("contact end configuration", q.len(), model.nq())?;
                check_len("contact force", tau.len(), model.nv())?;
                check_len("contact end velocity", v.len(), model.nv())?;
                self.tau_contact.copy_from_slice(tau);
                self.contact_force = true;
            }
        }
        // a tree held by resting contact had its limits solved with its contacts
        let held = matches!(contact, Some(ContactChange::Held { .. }));
        if let Some(limits) = self.limits.as_mut().filter(|_| !held) {
            // phase 1: the speculative, inelastic impulse at (q₀, v₀)
            limits.begin_step(&self.q);
            limits.apply(model, &mut self.ws, Phase::Impact, dt, &mut self.q, &mut self.v);
            limits.begin_integration(&self.v);
        }
        match (method, contact) {
            (Method::SemiImplicitEuler | Method::Euler, Some(ContactChange::Held { v, .. })) => {
                // the contact solve evaluated the dynamics at (q₀, v₀): its end velocity is this
                // step's (the configuration is the substeps', below); the forces only for the
                // effort clamps' count
                control.forces(model, &mut self.ws, &self.q, &self.v, &mut self.tau, Some(&mut self.clamped));
                self.v.copy_from_slice(v);
            }
            (Method::Rk4, _) => self.rk4(model, control, dt)?,
            (Method::SemiImplicitEuler, _) => {
                // v ← v + dt v̇(q, v);  q ← q ⊕ v dt
                control.forces(model, &mut self.ws, &self.q, &self.v, &mut self.tau, Some(&mut self.clamped));
                self.add_contact_force();
                aba(model, &mut self.ws, &self.q, &self.v, &self.tau, &mut self.k_v[0])?;
                for (v, a) in self.v.iter_mut().zip(&self.k_v[0]) {
                    *v += dt * a;
                }
                self.q_stage.copy_from_slice(&self.q);
                model.integrate(&self.q_stage, &self.v, dt, &mut self.q)?;
            }
            (Method::Euler, _) => {
                // q ← q ⊕ v dt and v ← v + dt v̇(q, v), from the old (q, v)
                control.forces(model, &mut self.ws, &self.q, &self.v, &mut self.tau, Some(&mut self.clamped));
                self.add_contact_force();
                aba(model, &mut self.ws, &self.q, &self.v, &self.tau, &mut self.k_v[0])?;
                self.q_stage.copy_from_slice(&self.q);
                model.integrate(&self.q_stage, &self.v, dt, &mut self.q)?;
                for (v, a) in self.v.iter_mut().zip(&self.k_v[0]) {
                    *v += dt * a;
                }
            }
        }
        if let Some(ContactChange::Held { q, .. }) = contact {
            // resting contact moved the tree in its substeps: it ends where they put it
            self.q.copy_from_slice(q);
            normalize_quaternions(model, &mut self.q);
            self.contact_force = false;
        }
        if let Some(limits) = self.limits.as_mut().filter(|_| !held) {
            // phase 2: the constraint force over the step, limits and friction together,
            // Δq = c h Δv (c = ½ for RK4, 1 for semi-implicit Euler); explicit Euler's q cannot
            // move, its v meets phase 1's condition and its friction acts on v alone (then the
            // velocity condition of phase 1 at the end state removes what is left of the velocity
            // into the limit: RK4's acceleration is not exactly constant over the step)
            let end_friction = match method {
                Method::Rk4 => {
                    limits.apply(model, &mut self.ws, Phase::Force { c: 0.5 }, dt, &mut self.q, &mut self.v);
                    false
                }
                Method::SemiImplicitEuler => {
                    limits.apply(model, &mut self.ws, Phase::Force { c: 1.0 }, dt, &mut self.q, &mut self.v);
                    false
                }
                Method::Euler => true,
            };
            let phase = Phase::EndVelocity { friction: end_friction };
            limits.apply(model, &mut self.ws, phase, dt, &mut self.q, &mut self.v);
            limits.end_step();
        }
        if let Some(limits) = self.limits.as_mut() {
            // the contact stage's rows never let a limited quantity sink below where it has been
            limits.raise_floor(&self.q);
        }
        self.t += dt;
        Ok(())
    }

    /// `τ += τ_c` while a contact force acts over the step.
    #[inline]
    fn add_contact_force(&mut self) {
        if self.contact_force {
            for (t, c) in self.tau.iter_mut().zip(&self.tau_contact) {
                *t += c;
            }
        }
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
            control.forces(model, &mut self.ws, &self.q_stage, &self.v_stage, &mut self.tau, Some(&mut self.clamped));
            self.add_contact_force();
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
