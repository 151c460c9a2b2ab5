//! Robots in the world: URDF trees integrated beside the free bodies.
//!
//! A [`Robot`] owns its [`MultibodyModel`] (placed in the world: a fixed base's pose is folded into
//! the placements of the joints that hang from the world), its [`Control`], its state in a
//! [`Simulator`], and a second [`Workspace`] that always holds the forward kinematics of the current
//! state, so that the trajectory writer and the invariants read link poses, energy and momentum
//! without recomputing them (and through `&World`).
//!
//! **Integrators.** A tree is stepped with the method closest to the world's integrator:
//!
//! | world `integrator`              | robots                                                    |
//! |---------------------------------|-----------------------------------------------------------|
//! | `euler`                         | explicit Euler                                            |
//! | `semi_implicit_euler`           | semi-implicit Euler (`v` first, then `q ⊕ v dt`)          |
//! | `rk4`                           | classical RK4                                             |
//! | `dopri5`, `splitting`, `splitting4` | RK4 at the world's `dt` (no adaptive or split form for trees) |
//!
//! **Limits.** A robot made by a scene holds its URDF joint position limits (`joint_limits`, see
//! [`crate::multibody::limits`]) and clamps its commanded joint forces to the URDF efforts
//! (`effort_limits`, [`Control::set_effort_limits`]); it counts, per joint, the steps in which each
//! happened ([`Robot::limit_activity`], [`Robot::effort_clamps`]) for the run report.
//!
//! **Divergence.** After each step every `q` and `v` entry of every robot must be finite and at most
//! [`MAX_STATE_MAGNITUDE`](super::MAX_STATE_MAGNITUDE) in magnitude; otherwise the step is undone (for
//! the bodies and for every robot) and the error names the robot, the joint, the step and the time.
//!
//! Nothing here allocates per step.

use super::{Diverged, World, MAX_STATE_MAGNITUDE};
use crate::integrate::Integrator;
use crate::math::{quat_to_wxyz, DMat3, DQuat, DVec3};
use crate::multibody::fk::{forward_kinematics, frame_x_world};
use crate::multibody::spatial::{Force, Motion, Xform};
use crate::multibody::{Control, Frame, LengthError, Method, MultibodyModel, Simulator, Workspace};

/// An MJCF actuator as a robot's control holds it. Its control `u` changes its force by `k u`
/// (gain `k`; the bias terms are in the control, which `u` does not change): on a joint with gear
/// `g` the joint force by `g k u` (held in [`Control::tau`]), on a fixed tendon the tendon force
/// `f₀` of its [`TendonDrive`](crate::multibody::TendonDrive) by `k u`.
#[derive(Debug, Clone, PartialEq)]
pub struct ActuatorDrive {
    pub name: String,
    pub target: DriveTarget,
    /// `g`.
    pub gear: f64,
    /// `k` (N or N·m per unit of control, before the gear).
    pub force_per_ctrl: f64,
    /// `ctrlrange` when the control is limited.
    pub ctrl_range: Option<(f64, f64)>,
    /// The control that `control` holds (the scene's `ctrl`, 0 unless given).
    pub ctrl: f64,
}

/// What an [`ActuatorDrive`] acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DriveTarget {
    /// A one-coordinate joint: its velocity coordinate.
    Joint { v_index: usize },
    /// A fixed tendon: the index of its drive in [`Control::tendons`].
    Tendon { drive: usize },
}

/// Why controls cannot be turned into joint forces ([`Robot::ctrl_torque`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CtrlError {
    #[error(transparent)]
    Length(#[from] LengthError),
    /// The force of an actuator on a tendon is clamped to its `forcerange` after the control is
    /// added: no joint force independent of the state gives it.
    #[error(
        "actuator `{0}` acts on a tendon with a forcerange: its force is clamped after the control is added, so \
         it has no equivalent joint force; set its control in the world (`set_ctrl`) instead"
    )]
    ClampedTendon(String),
}

impl ActuatorDrive {
    /// `u` clamped to the `ctrlrange`.
    pub fn clamped(&self, u: f64) -> f64 {
        match self.ctrl_range {
            Some((lo, hi)) => u.clamp(lo, hi),
            None => u,
        }
    }
}

/// A robot of the world: model, control, state and workspaces.
#[derive(Debug, Clone)]
pub struct Robot {
    /// Unique among the world's bodies and robots.
    pub name: String,
    /// The tree, placed in the world frame (a fixed base's pose is in its root placements); its
    /// `gravity` follows the world's at every step.
    pub model: MultibodyModel,
    /// Joint torques: constant, damping, PD.
    pub control: Control,
    /// Whether the base is a free-flyer (`root_joint`).
    pub floating: bool,
    /// Friction and restitution of every link (`None`: the world's defaults).
    pub material: crate::body::Material,
    /// The MJCF actuators that drive it (empty for a URDF robot), their effect at the scene's
    /// controls already in `control` (`scene::robot`); [`Robot::ctrl_torque`] gives the change of
    /// other controls.
    pub actuators: Vec<ActuatorDrive>,
    /// State `(q, v)` and the integrator's scratch.
    sim: Simulator,
    /// Forward kinematics of the current state.
    view: Workspace,
    /// `(q, v)` before the current step (to undo it).
    q_before: Vec<f64>,
    v_before: Vec<f64>,
    t_before: f64,
    /// The frames (links) that move, in the model's frame order, and their names `robot/link`.
    moving_frames: Vec<usize>,
    link_names: Vec<String>,
    /// Kinetic and potential energy of the current state (J).
    kinetic: f64,
    potential: f64,
    /// Total momentum `[L about the world origin; p]` of the current state, world frame.
    momentum: Force,
    /// Per velocity coordinate: the steps in which its commanded force was clamped to its effort
    /// limit.
    clamp_steps: Vec<u64>,
}

/// A joint and a number of steps (effort clamps, limit activity), for the run report.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JointSteps {
    /// The joint's name.
    pub joint: String,
    /// Steps in which it happened.
    pub steps: u64,
}

/// The state of one link as written in a trajectory, all world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkState {
    /// Origin of the link frame (m).
    pub position: DVec3,
    /// `world_from_link` (unit quaternion).
    pub orientation: DQuat,
    /// Velocity of the link frame's origin (m/s).
    pub velocity: DVec3,
    /// Angular velocity (rad/s).
    pub angular_velocity: DVec3,
}

impl Robot {
    /// A robot at `(q, v)` (lengths nq and nv of `model`).
    pub fn new(
        name: impl Into<String>,
        model: MultibodyModel,
        control: Control,
        q: Vec<f64>,
        v: Vec<f64>,
    ) -> Result<Self, LengthError> {
        let name = name.into();
        let sim = Simulator::new(&model, q.clone(), v.clone())?;
        // a free root joint, whatever its name (`root_joint` from a URDF's `base = "floating"`, the
        // file's own name from MJCF)
        let floating = model.bodies.first().is_some_and(|b| b.parent.is_none())
            && matches!(model.bodies[0].joint.kind, crate::multibody::JointKind::Floating);
        let moving_frames: Vec<usize> =
            model.frames.iter().enumerate().filter(|(_, f)| f.body.is_some()).map(|(i, _)| i).collect();
        let link_names = moving_frames.iter().map(|&f| format!("{name}/{}", model.frames[f].name)).collect();
        let view = Workspace::new(&model);
        let mut robot = Self {
            name,
            control,
            floating,
            material: crate::body::Material::default(),
            actuators: Vec::new(),
            sim,
            view,
            q_before: q,
            v_before: v,
            t_before: 0.0,
            moving_frames,
            link_names,
            kinetic: 0.0,
            potential: 0.0,
            momentum: Force::ZERO,
            clamp_steps: vec![0; model.nv()],
            model,
        };
        robot.refresh();
        Ok(robot)
    }

    /// The change of joint forces (nv, added to `out`) when the actuators' controls are `ctrl`
    /// (one per actuator, in [`Robot::actuators`] order, each clamped to its `ctrlrange`) instead
    /// of those `control` holds: `Σ g k (u − u_held)` on each joint actuator's coordinate, and
    /// `g c_i k (u − u_held)` on each joint `i` of a tendon actuator's tendon. An actuator on a
    /// tendon with a `forcerange` has no such joint force ([`CtrlError::ClampedTendon`]).
    pub fn ctrl_torque(&self, ctrl: &[f64], out: &mut [f64]) -> Result<(), CtrlError> {
        crate::multibody::workspace::check_len("ctrl (one per actuator)", ctrl.len(), self.actuators.len())?;
        crate::multibody::workspace::check_len("joint forces (nv)", out.len(), self.model.nv())?;
        for a in &self.actuators {
            if let DriveTarget::Tendon { drive } = a.target {
                if self.control.tendons[drive].force_range.is_some() {
                    return Err(CtrlError::ClampedTendon(a.name.clone()));
                }
            }
        }
        for (a, &u) in self.actuators.iter().zip(ctrl) {
            let du = a.force_per_ctrl * (a.clamped(u) - a.clamped(a.ctrl));
            match a.target {
                DriveTarget::Joint { v_index } => out[v_index] += a.gear * du,
                DriveTarget::Tendon { drive } => {
                    let d = &self.control.tendons[drive];
                    self.model.tendons[d.tendon].add_force(d.gear * du, out);
                }
            }
        }
        Ok(())
    }

    /// Sets the actuators' controls (one per actuator, each clamped to its `ctrlrange`): a tendon
    /// actuator's force `f₀` takes its control now (and holds it); the change of the joint
    /// actuators' forces from the controls `control` holds is added to `out` (nv), as
    /// [`Robot::ctrl_torque`] gives it, for the caller to apply.
    pub fn set_ctrl(&mut self, ctrl: &[f64], out: &mut [f64]) -> Result<(), LengthError> {
        crate::multibody::workspace::check_len("ctrl (one per actuator)", ctrl.len(), self.actuators.len())?;
        crate::multibody::workspace::check_len("joint forces (nv)", out.len(), self.model.nv())?;
        for (a, &u) in self.actuators.iter_mut().zip(ctrl) {
            let du = a.force_per_ctrl * (a.clamped(u) - a.clamped(a.ctrl));
            match a.target {
                DriveTarget::Joint { v_index } => out[v_index] += a.gear * du,
                DriveTarget::Tendon { drive } => {
                    self.control.tendons[drive].force += du;
                    a.ctrl = u;
                }
            }
        }
        Ok(())
    }

    /// Enforces (or not) the URDF position limits of the revolute and prismatic joints (off for a
    /// robot made by [`Robot::new`]; scenes turn them on unless `joint_limits = false`).
    pub fn set_joint_limits(&mut self, on: bool) {
        self.sim.set_joint_limits(&self.model, on);
    }

    /// Whether joint position limits are enforced (and the robot has some).
    pub fn joint_limits_enforced(&self) -> bool {
        self.sim.joint_limits().is_some_and(|s| s.has_limits())
    }

    /// The joints whose commanded force was clamped to their effort limit, with the number of
    /// steps it happened in (joints never clamped are left out).
    pub fn effort_clamps(&self) -> Vec<JointSteps> {
        self.per_joint(|vi| self.clamp_steps[vi])
    }

    /// The joints whose position limit pushed, with the number of steps it did.
    pub fn limit_activity(&self) -> Vec<JointSteps> {
        let Some(solver) = self.sim.joint_limits() else { return Vec::new() };
        let counts: Vec<(usize, u64)> = solver.limited_dofs().zip(solver.active_steps().iter().copied()).collect();
        self.per_joint(|vi| counts.iter().find(|(k, _)| *k == vi).map_or(0, |(_, n)| *n))
    }

    /// The limited fixed tendons (when limits are enforced), each with its name and the number of
    /// steps its limit pushed in (the joints' are [`limit_activity`](Self::limit_activity)).
    pub fn tendon_limit_activity(&self) -> Vec<(&str, u64)> {
        let Some(solver) = self.sim.joint_limits() else { return Vec::new() };
        solver
            .limited_tendons()
            .zip(solver.tendon_active_steps().iter().copied())
            .map(|(t, n)| (self.model.tendons[t].name.as_str(), n))
            .collect()
    }

    fn per_joint(&self, steps_of: impl Fn(usize) -> u64) -> Vec<JointSteps> {
        self.model
            .bodies
            .iter()
            .filter(|b| b.joint.kind.nv() == 1)
            .map(|b| JointSteps { joint: b.joint.name.clone(), steps: steps_of(b.joint.v_index) })
            .filter(|c| c.steps > 0)
            .collect()
    }

    /// What the contact stage reads: model, forward kinematics of the current state, state, control
    /// and material.
    pub fn contact_view(&self) -> crate::contact::links::RobotView<'_> {
        crate::contact::links::RobotView {
            model: &self.model,
            ws: &self.view,
            q: &self.sim.q,
            v: &self.sim.v,
            control: &self.control,
            material: self.material,
            limits: self.sim.joint_limits(),
        }
    }

    /// Configuration (nq): see `docs/multibody.md` for each joint's coordinates.
    pub fn q(&self) -> &[f64] {
        &self.sim.q
    }

    /// Velocity (nv).
    pub fn v(&self) -> &[f64] {
        &self.sim.v
    }

    /// Kinetic plus potential energy (J): gravity's (zero at the world origin) and the joint springs'.
    pub fn energy(&self) -> f64 {
        self.kinetic + self.potential
    }

    /// Kinetic energy (J).
    pub fn kinetic_energy(&self) -> f64 {
        self.kinetic
    }

    /// Total linear momentum of the links, world frame (kg·m/s).
    pub fn linear_momentum(&self) -> DVec3 {
        self.momentum.lin
    }

    /// Total angular momentum of the links about the world origin, world frame (kg·m²/s).
    pub fn angular_momentum(&self) -> DVec3 {
        self.momentum.ang
    }

    /// The names written in trajectories, `robot/link`, one per moving link.
    pub fn link_names(&self) -> &[String] {
        &self.link_names
    }

    /// The frame of moving link `k` (index into [`link_names`](Self::link_names)): its placement, its
    /// body, and the link's own inertia in the link frame ([`Frame::inertia`]), the mass that a
    /// trajectory row of the link carries.
    pub fn link_frame(&self, k: usize) -> &Frame {
        &self.model.frames[self.moving_frames[k]]
    }

    /// The state of moving link `k` (index into [`link_names`](Self::link_names)).
    pub fn link_state(&self, k: usize) -> LinkState {
        let f = self.moving_frames[k];
        let frame = &self.model.frames[f];
        let body = frame.body.unwrap_or(0);
        // frame_X_0 and the frame's velocity in its own coordinates, frame_X_body v_body
        let x: Xform = frame_x_world(&self.model, &self.view, f);
        let v_frame: Motion = frame.x_from_body.apply_motion(self.view.v[body]);
        let world_from_frame: DMat3 = x.rotation_a_from_b();
        LinkState {
            position: x.r,
            orientation: DQuat::from_mat3(&world_from_frame).normalize(),
            velocity: world_from_frame * v_frame.lin,
            angular_velocity: world_from_frame * v_frame.ang,
        }
    }

    /// The orientation of link `k` as written in files, `[w, x, y, z]`.
    pub fn link_orientation_wxyz(&self, k: usize) -> [f64; 4] {
        quat_to_wxyz(self.link_state(k).orientation)
    }

    /// Sets the state `(q, v)` (lengths nq and nv, already checked by the caller: finite, unit
    /// quaternions), renormalising the quaternions of spherical and floating joints, and recomputes
    /// the link poses, energy and momentum.
    pub fn set_state(&mut self, q: &[f64], v: &[f64]) {
        self.sim.q.copy_from_slice(q);
        self.sim.v.copy_from_slice(v);
        crate::multibody::simulate::normalize_quaternions(&self.model, &mut self.sim.q);
        self.sim.restart_limit_floor();
        self.refresh();
    }

    /// Recomputes the forward kinematics, energy and momentum of the current state.
    fn refresh(&mut self) {
        let (model, ws) = (&self.model, &mut self.view);
        if forward_kinematics(model, ws, &self.sim.q, &self.sim.v).is_err() {
            return; // lengths are fixed at construction
        }
        let mut kinetic = 0.0;
        let mut potential = 0.0;
        let mut momentum = Force::ZERO;
        for (i, b) in model.bodies.iter().enumerate() {
            // T = ½ vᵢᵀ Iᵢ vᵢ;  V = −mᵢ g · cᵢ;  h = Σ 0_X_iᵀ* (Iᵢ vᵢ)
            let h_body = b.inertia.mul_motion(ws.v[i]);
            kinetic += 0.5 * ws.v[i].dot(h_body);
            let c_world = ws.x_world[i].inv_apply_point(b.inertia.com());
            potential -= b.inertia.mass * model.gravity.dot(c_world);
            momentum += ws.x_world[i].inv_apply_force(h_body);
        }
        // the joints' armature (MJCF `armature`, a rotor's reflected inertia), ½ Σ a v², so that
        // T = ½ vᵀ M v with the M the dynamics use (zero for a URDF robot)
        kinetic += crate::multibody::armature_energy(model, &self.sim.v);
        // and the joints' springs (MJCF `stiffness`), ½ k (q − q_ref)²: with them a passive robot's
        // mechanical energy only falls (zero for a URDF robot, which has no joint springs)
        potential += crate::multibody::spring_energy(model, &self.sim.q).unwrap_or(0.0);
        self.kinetic = kinetic;
        self.potential = potential;
        self.momentum = momentum;
    }

    /// One step of `dt` seconds, without the bookkeeping of the new state ([`Self::refresh`], the
    /// caller's); on a non-finite or absurd state, the state is restored and the problem described
    /// (`joint `elbow`: v is not finite`).
    /// `contact`: what the step's contacts changed ([`crate::contact::links::LinkStage::robot_change`]).
    fn step(
        &mut self,
        method: Method,
        dt: f64,
        gravity: DVec3,
        contact: Option<crate::multibody::ContactChange<'_>>,
    ) -> Result<(), String> {
        self.model.gravity = gravity;
        self.q_before.copy_from_slice(&self.sim.q);
        self.v_before.copy_from_slice(&self.sim.v);
        self.t_before = self.sim.t;
        if let Err(e) = self.sim.step_with_contact(&self.model, &self.control, method, dt, contact) {
            self.undo();
            return Err(format!("the dynamics failed: {e}"));
        }
        if let Some(problem) = self.check() {
            self.undo();
            return Err(problem);
        }
        for (count, &clamped) in self.clamp_steps.iter_mut().zip(self.sim.clamped()) {
            *count += u64::from(clamped);
        }
        Ok(())
    }

    fn undo(&mut self) {
        self.sim.q.copy_from_slice(&self.q_before);
        self.sim.v.copy_from_slice(&self.v_before);
        self.sim.t = self.t_before;
        self.sim.restart_limit_floor();
        self.refresh();
    }

    /// Names the first joint whose `q` or `v` is non-finite or beyond [`MAX_STATE_MAGNITUDE`].
    fn check(&self) -> Option<String> {
        let sane = |x: &f64| x.abs() <= MAX_STATE_MAGNITUDE; // false for NaN
        if self.sim.q.iter().all(sane) && self.sim.v.iter().all(sane) {
            return None;
        }
        for b in &self.model.bodies {
            let j = &b.joint;
            let q = &self.sim.q[j.q_index..j.q_index + j.kind.nq()];
            let v = &self.sim.v[j.v_index..j.v_index + j.kind.nv()];
            for (what, values) in [("q", q), ("v", v)] {
                if let Some(x) = values.iter().find(|x| !sane(x)) {
                    let problem = if x.is_finite() {
                        format!("|{what}| = {:e} exceeds {MAX_STATE_MAGNITUDE:e}", x.abs())
                    } else {
                        format!("{what} is not finite")
                    };
                    return Some(format!("joint `{}`: {problem}", j.name));
                }
            }
        }
        None
    }
}

/// The world's robots as the contact stage reads them (it is handed them by [`World::step`]).
impl crate::contact::links::RobotViews for Vec<Robot> {
    fn count(&self) -> usize {
        self.len()
    }

    fn view(&self, robot: usize) -> crate::contact::links::RobotView<'_> {
        self[robot].contact_view()
    }
}

/// The tree method used for a world integrator (see the module's table).
pub fn robot_method(integrator: Integrator) -> Method {
    match integrator {
        Integrator::Euler => Method::Euler,
        Integrator::SemiImplicitEuler => Method::SemiImplicitEuler,
        Integrator::Rk4 | Integrator::Dopri5 | Integrator::Splitting | Integrator::Splitting4 => Method::Rk4,
    }
}

impl World {
    /// Steps every robot by `dt`; on divergence, restores the robots stepped so far and returns the
    /// error (the caller restores the bodies).
    pub(super) fn step_robots(&mut self) -> Result<(), Diverged> {
        let method = robot_method(self.config.integrator);
        let (dt, gravity) = (self.config.dt, self.config.gravity);
        for (r, k) in self.contact.links.limits_pushed() {
            if let Some(limits) = self.robots[r].sim.joint_limits_mut() {
                limits.note_active(k);
            }
        }
        for r in 0..self.robots.len() {
            let contact = self.contact.links.robot_change(r);
            let held = matches!(contact, Some(crate::multibody::ContactChange::Held { .. }));
            let energy_before = self.robots[r].energy();
            let mut clock = super::Clock::start(self.profile.is_some());
            let stepped = self.robots[r].step(method, dt, gravity, contact);
            let dynamics = clock.lap();
            if stepped.is_ok() {
                self.robots[r].refresh();
            }
            if let Some(p) = &mut self.profile {
                p.robot_dynamics += dynamics;
                p.robot_bookkeeping += clock.lap();
            }
            if let Err(quantity) = stepped {
                for earlier in &mut self.robots[..r] {
                    earlier.undo();
                }
                return Err(Diverged {
                    body: self.robots[r].name.clone(),
                    quantity,
                    step: self.steps + 1,
                    time: (self.steps + 1) as f64 * dt,
                });
            }
            if held {
                self.contact.links.book_resting(r, energy_before, self.robots[r].energy());
            }
        }
        Ok(())
    }

    /// Gives robot `robot`'s links their collision shapes (see
    /// [`crate::multibody::link_shapes::collision_shapes`]); its links then collide with the bodies and
    /// the other robots' links. Returns the indices of the new link colliders.
    pub fn add_link_shapes(&mut self, robot: usize, shapes: &[crate::multibody::link_shapes::LinkShape]) -> Vec<usize> {
        let name = &self.robots[robot].name;
        let links = &mut self.contact.links.colliders;
        shapes
            .iter()
            .map(|s| {
                links.push(crate::collision::links::LinkCollider::new(
                    robot,
                    s.body,
                    format!("{name}/{}", s.link),
                    &s.shape,
                    s.position_body,
                    s.orientation_body,
                ))
            })
            .collect()
    }

    /// Lets robot `robot`'s own links collide with each other, except parent and child, links fixed
    /// to each other (one body), and pairs that touch or overlap in the current pose. Returns those
    /// last pairs, `(robot/link, robot/link)`, which stay excluded.
    pub fn enable_self_collision(&mut self, robot: usize) -> Vec<(String, String)> {
        let model = &self.robots[robot].model;
        let links = &mut self.contact.links.colliders;
        links.set_self_collision(robot, true);
        let mine: Vec<usize> = (0..links.links().len()).filter(|&l| links.links()[l].robot == robot).collect();
        for (k, &l) in mine.iter().enumerate() {
            for &m in &mine[k + 1..] {
                let (a, b) = (links.links()[l].body, links.links()[m].body);
                let parent = |x: Option<usize>| x.and_then(|i| model.bodies[i].parent);
                if parent(a) == b || parent(b) == a {
                    links.exclude_links(l, m);
                }
            }
        }
        let views: Vec<_> = self.robots.iter().map(|r| r.contact_view().ws.clone()).collect();
        links.place(self.config.dt, 0.0, |r, b| {
            let x = views[r].x_world[b];
            crate::collision::links::BodyMotion {
                pose: parry3d_f64::math::Pose::from_parts(x.r, DQuat::from_mat3(&x.rotation_a_from_b()).normalize()),
                speed: 0.0,
                angular_speed: 0.0,
            }
        });
        let touching = links.touching_pairs(robot, 0.0);
        let mut names = Vec::new();
        for &(l, m) in &touching {
            if links.pair_allowed(l, m) {
                links.exclude_links(l, m);
                names.push((links.links()[l].name.clone(), links.links()[m].name.clone()));
            }
        }
        names
    }

    /// The link colliders named `robot/link`, if any.
    pub fn link_shapes_named(&self, name: &str) -> Option<Vec<usize>> {
        let links = self.contact.links.colliders.links();
        let found: Vec<usize> = (0..links.len()).filter(|&l| links[l].name == name).collect();
        (!found.is_empty()).then_some(found)
    }

    /// The index of the robot with this name.
    pub fn robot_index(&self, name: &str) -> Option<usize> {
        self.robots.iter().position(|r| r.name == name)
    }

    /// Energy of the robots, kinetic plus potential (gravity's and the joint springs') (J).
    pub fn robots_energy(&self) -> f64 {
        self.robots.iter().map(Robot::energy).sum()
    }

    /// Linear and angular momentum (about the world origin) of the floating-base robots, world frame.
    /// Fixed-base robots are left out: the world holds them, so their momentum is not conserved.
    pub fn robots_momentum(&self) -> (DVec3, DVec3) {
        self.robots
            .iter()
            .filter(|r| r.floating)
            .fold((DVec3::ZERO, DVec3::ZERO), |(p, l), r| (p + r.linear_momentum(), l + r.angular_momentum()))
    }

    /// Number of trajectory rows the robots add per sample (their moving links).
    pub fn robot_link_count(&self) -> usize {
        self.robots.iter().map(|r| r.link_names.len()).sum()
    }
}
