//! `tumble.World`: one simulation, the mutable state beside an immutable `Model`.
//!
//! `step(n)` releases the GIL for the whole of its `n` steps. A `World` is used by one thread at a
//! time (a second thread touching it while it steps gets "Already borrowed"): give each thread its
//! own, from the same shared `Model`.

use crate::arrays::{check_shape, f64_array, finite_vector, out_array, values};
use crate::model::Model;
use crate::{bad, DivergedError};
use numpy::{PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tumble::collision::links::Side;

/// One simulation of a model, at `t = 0` when created.
#[pyclass(module = "tumble")]
pub struct World {
    world: tumble::World,
    model: Py<Model>,
}

/// Sets robot `r`'s joint forces to the scene's plus `extra` (nv).
pub fn apply_torque(world: &mut tumble::World, base_tau: &[f64], r: usize, extra: &[f64]) {
    for ((tau, base), u) in world.robots[r].control.tau.iter_mut().zip(base_tau).zip(extra) {
        *tau = base + u;
    }
}

/// The message of a diverged step as a `DivergedError`.
pub fn diverged(e: tumble::world::StepError) -> PyErr {
    DivergedError::new_err(e.to_string())
}

impl World {
    fn robot(&self, robot: Option<&Bound<'_, PyAny>>) -> PyResult<usize> {
        self.model.get().robot_index(robot)
    }

    /// The engine's world, for batched calls (`step_worlds`).
    pub(crate) fn inner(&self) -> &tumble::World {
        &self.world
    }

    /// The engine's world, for batched calls (`step_worlds`).
    pub(crate) fn inner_mut(&mut self) -> &mut tumble::World {
        &mut self.world
    }

    /// Robot `robot` (name, index or the only one): its index and `nq`, after checking it has PD
    /// gains (with `kp`, `kd` the gains about to be set, when given).
    pub(crate) fn pd_robot(
        &self,
        robot: Option<&Bound<'_, PyAny>>,
        kp: Option<&[f64]>,
        kd: Option<&[f64]>,
    ) -> PyResult<(usize, usize)> {
        let r = self.robot(robot)?;
        let control = &self.world.robots[r].control;
        let has_gains =
            kp.unwrap_or(&control.kp).iter().any(|k| *k > 0.0) || kd.unwrap_or(&control.kd).iter().any(|k| *k > 0.0);
        if !has_gains {
            let name = &self.model.get().robots[r].name;
            return Err(bad(format!(
                "robot `{name}` has no PD gains: pass kp (and kd), or set them in the scene's [robot.pd]"
            )));
        }
        Ok((r, self.model.get().robots[r].nq))
    }
}

#[pymethods]
impl World {
    /// A new simulation of `model` at `t = 0`, in the scene's initial state.
    #[new]
    fn new(model: Bound<'_, Model>) -> Self {
        Self { world: model.get().world.clone(), model: model.unbind() }
    }

    /// The model this world simulates.
    #[getter]
    fn model(&self, py: Python<'_>) -> Py<Model> {
        self.model.clone_ref(py)
    }

    /// Advances `n` steps of `dt` (the GIL is released meanwhile). A step that diverges raises
    /// `DivergedError` and leaves the world at the last finite state (the steps before it are kept).
    #[pyo3(signature = (n = 1))]
    fn step(&mut self, py: Python<'_>, n: u64) -> PyResult<()> {
        let world = &mut self.world;
        py.detach(|| (0..n).try_for_each(|_| world.step())).map_err(diverged)
    }

    /// Simulated time (s), `steps · dt`.
    #[getter]
    fn time(&self) -> f64 {
        self.world.time()
    }

    /// Steps taken since the start.
    #[getter]
    fn steps(&self) -> u64 {
        self.world.steps()
    }

    /// The state, float64 of shape (nstate,): each moving body's `[x, y, z, qw, qx, qy, qz, vx, vy,
    /// vz, wx, wy, wz]` (world frame, the trajectory CSV row), then each robot's `q` then `v`.
    /// With `out` (a C-contiguous float64 array of that shape) it is written there and returned:
    /// nothing is allocated.
    #[pyo3(signature = (out = None))]
    fn state<'py>(&self, py: Python<'py>, out: Option<&Bound<'py, PyAny>>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let n = self.world.state_len();
        let array = match out {
            Some(out) => out_array(out, &[n])?,
            None => PyArrayDyn::<f64>::zeros(py, numpy::IxDyn(&[n]), false),
        };
        {
            let mut rw = array.try_readwrite().map_err(|e| bad(format!("out: {e}")))?;
            let slice = rw.as_slice_mut().map_err(|e| bad(format!("out: {e}")))?;
            self.world.write_state(slice).map_err(|e| bad(e.to_string()))?;
        }
        Ok(array)
    }

    /// Sets the state (the layout of `state()`). Checked as a whole before anything changes: shape
    /// (nstate,), dtype float64, every entry finite, every quaternion of unit norm (to 1e-6; it is
    /// then renormalised). Raises `TumbleError` naming the entry. Time, controls and the contact
    /// history are kept.
    fn set_state(&mut self, x: &Bound<'_, PyAny>) -> PyResult<()> {
        let a = f64_array(x, "x")?;
        check_shape("x", a.shape(), &[Some(self.world.state_len())], "(nstate,)")?;
        let ro = a.try_readonly().map_err(|e| bad(format!("x: {e}")))?;
        let v = values(&ro);
        self.world.set_state(&v).map_err(|e| bad(format!("x: {e}")))
    }

    /// Back to the model's initial state at `t = 0` (controls too).
    fn reset(&mut self) {
        self.world.clone_from(&self.model.get().world);
    }

    /// Kinetic plus gravitational potential energy of the moving bodies and robots (J).
    fn energy(&self) -> f64 {
        self.world.energy()
    }

    /// The potential energy stored at the end of the last step in the soft rows that hold the
    /// robots (their resting contacts, joint and tendon limits), each a spring of stiffness
    /// `m_n ω²` on its deflection (J): a passive robot's energy that cannot rise is `energy()`
    /// plus this.
    fn contact_elastic_energy(&self) -> f64 {
        self.world.contact_elastic_energy()
    }

    /// Total linear momentum of the moving bodies and floating-base robots, world frame (kg·m/s).
    fn linear_momentum<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.world.linear_momentum().to_array())
    }

    /// Total angular momentum about the world origin, world frame (kg·m²/s).
    fn angular_momentum<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.world.angular_momentum().to_array())
    }

    /// Joint forces of a robot (nv, N·m or N), added to the scene's constant ones from the next step
    /// on, until set again; the sum (with the PD) is clamped to the URDF efforts unless the scene says
    /// `effort_limits = false`. `robot`: name or index (default: the only robot).
    #[pyo3(signature = (robot, tau))]
    fn set_torque(&mut self, robot: &Bound<'_, PyAny>, tau: &Bound<'_, PyAny>) -> PyResult<()> {
        let r = self.robot(Some(robot))?;
        let model = self.model.get();
        let info = &model.robots[r];
        let tau = finite_vector(tau, "tau", info.nv, "(nv,) joint forces")?;
        apply_torque(&mut self.world, &info.base_tau, r, &tau);
        Ok(())
    }

    /// Controls of a robot's MJCF actuators, held until changed: `ctrl` (nu_actuators,) in the
    /// order of `Model.actuator_names`, each clamped to its `ctrlrange`. An actuator with gear `g`
    /// and gain `k` adds `g k u` to its joint's force (its bias acts at any `ctrl`); one on a fixed
    /// tendon sets the tendon's force `k u + bias` (clamped to its `forcerange`), which each joint
    /// `i` of the tendon takes times `g c_i`. Like `set_torque`, this replaces the joint forces that
    /// `set_torque` or an earlier `set_ctrl` gave.
    fn set_ctrl(&mut self, robot: &Bound<'_, PyAny>, ctrl: &Bound<'_, PyAny>) -> PyResult<()> {
        let r = self.robot(Some(robot))?;
        let model = self.model.get();
        let info = &model.robots[r];
        let n = self.world.robots[r].actuators.len();
        if n == 0 {
            return Err(crate::bad(format!(
                "robot `{}` has no MJCF actuator: drive it by set_torque or set_pd_target",
                info.name
            )));
        }
        let ctrl = finite_vector(ctrl, "ctrl", n, "(nu_actuators,) controls")?;
        let mut extra = vec![0.0; info.nv];
        self.world.robots[r].set_ctrl(&ctrl, &mut extra).map_err(|e| crate::bad(e.to_string()))?;
        apply_torque(&mut self.world, &info.base_tau, r, &extra);
        Ok(())
    }

    /// PD targets of a robot: `τ += kp (q* − q) + kd (v* − v)` on its one-coordinate joints.
    /// `q_target` (nq,); `kp`, `kd` (nv,) replace the scene's gains when given (a robot needs
    /// non-zero gains for the target to act); `v_target` (nv,) defaults to zero velocity.
    #[pyo3(signature = (robot, q_target, kp = None, kd = None, v_target = None))]
    fn set_pd_target(
        &mut self,
        robot: &Bound<'_, PyAny>,
        q_target: &Bound<'_, PyAny>,
        kp: Option<&Bound<'_, PyAny>>,
        kd: Option<&Bound<'_, PyAny>>,
        v_target: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let r = self.robot(Some(robot))?;
        let model = self.model.get();
        let (nq, nv) = (model.robots[r].nq, model.robots[r].nv);
        let q_target = finite_vector(q_target, "q_target", nq, "(nq,) joint positions")?;
        let gains = |g: Option<&Bound<'_, PyAny>>, name| -> PyResult<Option<Vec<f64>>> {
            let Some(g) = g else { return Ok(None) };
            let g = finite_vector(g, name, nv, "(nv,) gains")?;
            if let Some(i) = g.iter().position(|x| *x < 0.0) {
                return Err(bad(format!("{name}: entry {i} is negative (got {})", g[i])));
            }
            Ok(Some(g))
        };
        let kp = gains(kp, "kp")?;
        let kd = gains(kd, "kd")?;
        let v_target = v_target.map(|v| finite_vector(v, "v_target", nv, "(nv,) joint velocities")).transpose()?;
        self.pd_robot(Some(robot), kp.as_deref(), kd.as_deref())?;
        let control = &mut self.world.robots[r].control;
        control.q_target.copy_from_slice(&q_target);
        if let Some(kp) = kp {
            control.kp.copy_from_slice(&kp);
        }
        if let Some(kd) = kd {
            control.kd.copy_from_slice(&kd);
        }
        if let Some(v) = v_target {
            control.v_target.copy_from_slice(&v);
        }
        Ok(())
    }

    /// Poses and velocities of a robot's moving links (the order of `Model.link_names`), shape
    /// (nlink, 13): `[x, y, z, qw, qx, qy, qz, vx, vy, vz, wx, wy, wz]` of each link frame, world frame.
    #[pyo3(signature = (robot = None))]
    fn link_states<'py>(
        &self,
        py: Python<'py>,
        robot: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let r = self.robot(robot)?;
        let robot = &self.world.robots[r];
        let n = robot.link_names().len();
        let mut rows = Vec::with_capacity(n);
        for k in 0..n {
            let s = robot.link_state(k);
            let mut row = Vec::with_capacity(13);
            row.extend(s.position.to_array());
            row.extend(robot.link_orientation_wxyz(k));
            row.extend(s.velocity.to_array());
            row.extend(s.angular_velocity.to_array());
            rows.push(row);
        }
        if rows.is_empty() {
            return Ok(PyArray2::zeros(py, [0, 13], false));
        }
        PyArray2::from_vec2(py, &rows).map_err(|e| bad(e.to_string()))
    }

    /// The active contacts of the last step (those that carried an impulse, or whose surfaces
    /// overlapped), a list of dicts: `a`, `b` (body names), `point` (m), `normal` (unit, from `a`
    /// towards `b`), both world frame, `depth` (m, > 0 when the shapes overlap) and `force` (N, on
    /// `b`: the contact's whole impulse over the step, collision included, divided by `dt`) — the
    /// lines of `tumble run --contacts`: the bodies' contacts, then the robot links' (a link named
    /// `robot/link`; `b` is always a link).
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let inv_dt = 1.0 / self.world.config.dt;
        let stage = self.world.contacts();
        let bodies = stage.active().map(|(c, p)| {
            let (a, b) = (&self.world.bodies[c.a].name, &self.world.bodies[c.b].name);
            (a, b, c.point_world, c.normal_world, c.gap, p)
        });
        let link_colliders = stage.links.colliders.links();
        let side = |s: Side| match s {
            Side::Body(i) => &self.world.bodies[i].name,
            Side::Link(l) => &link_colliders[l].name,
        };
        let links = stage.links.active().map(|(c, p)| (side(c.a), side(c.b), c.point_world, c.normal_world, c.gap, p));
        let mut out = Vec::new();
        for (a, b, point, normal, gap, p) in bodies.chain(links) {
            let d = PyDict::new(py);
            d.set_item("a", a)?;
            d.set_item("b", b)?;
            d.set_item("point", PyArray1::from_slice(py, &point.to_array()))?;
            d.set_item("normal", PyArray1::from_slice(py, &normal.to_array()))?;
            d.set_item("depth", -gap)?;
            d.set_item("force", PyArray1::from_slice(py, &(p * inv_dt).to_array()))?;
            out.push(d);
        }
        Ok(out)
    }

    /// Collisions resolved since the start.
    fn collisions(&self) -> u64 {
        self.world.contact_collisions()
    }

    /// Free bodies asleep now: islands at rest on a fixed body (`[world] sleep`); they wake when
    /// touched, or when `set_state` or a force changes one of them.
    fn asleep(&self) -> usize {
        self.world.contacts().sleep().count()
    }

    fn __repr__(&self) -> String {
        format!("World(t={}, steps={}, nstate={})", self.world.time(), self.world.steps(), self.world.state_len())
    }
}

/// Checks every row of `x0` (B, nstate) as `World.set_state` would, naming the row.
pub fn check_rows(world: &mut tumble::World, x0: &[f64], s: usize) -> PyResult<()> {
    for (b, row) in x0.chunks_exact(s.max(1)).enumerate() {
        world.set_state(row).map_err(|e| bad(format!("x0[{b}]: {e}")))?;
    }
    Ok(())
}
