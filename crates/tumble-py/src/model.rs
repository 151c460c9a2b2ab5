//! `tumble.Model`: a loaded scene (bodies, robots, settings) that never changes.
//!
//! It holds the world at `t = 0`; every `World` and every rollout row starts from a clone of it.
//! Frozen and `Sync`: one model may be shared by any number of threads. It pickles as its scene
//! text and origin (URDF files are read again where it is unpickled, relative to the origin).

use crate::bad;
use pyo3::prelude::*;
use pyo3::types::PyType;
use std::path::Path;
use tumble::scene::{self, Format};

/// The arguments of `Model._from_pickle`: scene text, format, origin.
type PickleArgs = (String, &'static str, String);

/// What a model knows about one robot.
pub struct RobotInfo {
    pub name: String,
    pub nq: usize,
    pub nv: usize,
    /// The scene's constant joint forces (nv): `set_torque` and rollout controls add to them.
    pub base_tau: Vec<f64>,
    pub link_names: Vec<String>,
}

/// An immutable scene: bodies, robots and settings.
///
/// Build it with `Model.from_file`, `Model.from_str` or `Model.from_urdf`; start simulations with
/// `World(model)` or `tumble.rollout(model, ...)`. Shareable between threads; picklable.
#[pyclass(module = "tumble", frozen)]
pub struct Model {
    pub world: tumble::World,
    pub robots: Vec<RobotInfo>,
    pub body_names: Vec<String>,
    text: String,
    format: &'static str,
    origin: String,
    warnings: Vec<String>,
}

fn parse_format(format: &str) -> PyResult<Format> {
    match format.to_ascii_lowercase().as_str() {
        "toml" => Ok(Format::Toml),
        "json" => Ok(Format::Json),
        other => Err(bad(format!("format: expected \"toml\" or \"json\", got {other:?}"))),
    }
}

fn format_name(format: Format) -> &'static str {
    match format {
        Format::Toml => "toml",
        Format::Json => "json",
    }
}

impl Model {
    fn build(text: String, format: Format, origin: String) -> PyResult<Self> {
        let scene = scene::from_str(&text, &origin, format).map_err(|e| bad(e.to_string()))?;
        Ok(Self::from_scene(scene, text, format, origin))
    }

    /// `origin`: where pickling says the text came from (URDF paths are relative to its directory).
    fn from_scene(scene: scene::Scene, text: String, format: Format, origin: String) -> Self {
        let world = scene.world;
        let robots = world
            .robots
            .iter()
            .map(|r| RobotInfo {
                name: r.name.clone(),
                nq: r.q().len(),
                nv: r.v().len(),
                base_tau: r.control.tau.clone(),
                link_names: r.link_names().to_vec(),
            })
            .collect();
        let body_names = world.free_bodies().map(|b| b.name.clone()).collect();
        Self { world, robots, body_names, text, format: format_name(format), origin, warnings: scene.warnings }
    }

    /// The robot named `robot` (a name or an index), or the only robot when `None`.
    pub fn robot_index(&self, robot: Option<&Bound<'_, PyAny>>) -> PyResult<usize> {
        let names = || self.robots.iter().map(|r| format!("`{}`", r.name)).collect::<Vec<_>>().join(", ");
        let Some(robot) = robot else {
            return match self.robots.len() {
                1 => Ok(0),
                0 => Err(bad("the model has no robot")),
                _ => Err(bad(format!("the model has several robots ({}): pass robot=NAME", names()))),
            };
        };
        if let Ok(i) = robot.extract::<usize>() {
            return if i < self.robots.len() {
                Ok(i)
            } else {
                Err(bad(format!("robot index {i} out of range: the model has {} robot(s)", self.robots.len())))
            };
        }
        let name: String = robot.extract().map_err(|_| bad("robot: expected a robot name (str) or index (int)"))?;
        self.robots
            .iter()
            .position(|r| r.name == name)
            .ok_or_else(|| bad(format!("no robot named `{name}` (robots: {})", names())))
    }

    /// Number of robot velocity coordinates, the width of a rollout's control.
    pub fn nu(&self) -> usize {
        self.robots.iter().map(|r| r.nv).sum()
    }
}

#[pymethods]
impl Model {
    /// Loads a scene file (`.toml` or `.json`); URDF paths are relative to the file.
    #[staticmethod]
    fn from_file(path: std::path::PathBuf) -> PyResult<Self> {
        // the loader checks the size, the encoding and the format, and names the file as given
        let scene = scene::load(&path).map_err(|e| bad(e.to_string()))?;
        let text = std::fs::read_to_string(&path).map_err(|e| bad(format!("{}: cannot read: {e}", path.display())))?;
        let format = Format::from_path(&path).unwrap_or(Format::Toml);
        let origin = std::path::absolute(&path).unwrap_or(path).display().to_string();
        Ok(Self::from_scene(scene, text, format, origin))
    }

    /// Parses a scene from text (`format` "toml" or "json"); URDF paths are relative to `base_dir`
    /// (default: the current directory).
    #[staticmethod]
    #[pyo3(signature = (text, format = "toml", base_dir = None))]
    fn from_str(text: String, format: &str, base_dir: Option<std::path::PathBuf>) -> PyResult<Self> {
        let format = parse_format(format)?;
        let base = match base_dir {
            Some(dir) => dir,
            None => std::env::current_dir().map_err(|e| bad(format!("cannot read the current directory: {e}")))?,
        };
        let origin = std::path::absolute(&base).unwrap_or(base).join("<string>").display().to_string();
        Self::build(text, format, origin)
    }

    /// A model of one robot read from a URDF file (its name: the file's stem), at the neutral
    /// configuration, with the default world (gravity −9.81 m/s² along z, `dt` = 1 ms, RK4) and the
    /// scene defaults: its joint position limits hold and its commanded forces are clamped to the
    /// URDF efforts.
    /// `floating`: a free-flying base (`q` starts `[x, y, z, qw, qx, qy, qz]`).
    #[staticmethod]
    #[pyo3(signature = (path, floating = false))]
    fn from_urdf(path: std::path::PathBuf, floating: bool) -> PyResult<Self> {
        if !path.is_file() {
            return Err(bad(format!("{}: cannot read the URDF file: no such file", path.display())));
        }
        let absolute = std::path::absolute(&path).unwrap_or(path.clone());
        let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "robot".into());
        let quote = |s: &str| serde_json_string(s);
        let text = format!(
            "version = 1\n\n[[robot]]\nname = {}\nurdf = {}\nbase = \"{}\"\n",
            quote(&stem),
            quote(&absolute.display().to_string()),
            if floating { "floating" } else { "fixed" }
        );
        let origin = absolute.parent().unwrap_or(Path::new("/")).join("<urdf>").display().to_string();
        Self::build(text, Format::Toml, origin)
    }

    /// A MuJoCo MJCF file as a whole world, as `tumble run X.xml` reads it: the file's `<option>`
    /// (`timestep` as `dt`, `gravity`, `integrator`), each plane of its worldbody a fixed plane,
    /// and the tree as one robot (its name: the `<mujoco model>`) at MuJoCo's `qpos0`, with its
    /// actuators at `ctrl = 0` (`World.set_ctrl` drives them).
    #[staticmethod]
    fn from_mjcf(path: std::path::PathBuf) -> PyResult<Self> {
        if !path.is_file() {
            return Err(bad(format!("{}: cannot read the MJCF file: no such file", path.display())));
        }
        let absolute = std::path::absolute(&path).unwrap_or(path.clone());
        let (text, _) = scene::mjcf_world_text(&absolute, None).map_err(|e| bad(e.to_string()))?;
        Self::build(text, Format::Json, absolute.display().to_string())
    }

    /// The names of a robot's MJCF actuators, in the order of `World.set_ctrl`'s `ctrl` (empty for
    /// a URDF robot).
    #[pyo3(signature = (robot = None))]
    fn actuator_names(&self, robot: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<String>> {
        let r = self.robot_index(robot)?;
        Ok(self.world.robots[r].actuators.iter().map(|a| a.name.clone()).collect())
    }

    /// The joint forces `(..., nv)` that the actuators' controls `ctrl` `(..., n_actuators)` add to a
    /// robot's (each control clamped to its `ctrlrange`; gear × gain × ctrl on its joint, and on
    /// each joint `i` of a fixed tendon gear × c_i × gain × ctrl): what `World.set_ctrl` applies,
    /// and for a one-robot model a rollout's `control` that drives the actuators by `ctrl` at every
    /// step. An actuator on a tendon with a `forcerange` is refused (its clamp comes after the
    /// control: drive it with `World.set_ctrl`).
    #[pyo3(signature = (ctrl, robot = None))]
    fn ctrl_torque<'py>(
        &self,
        py: Python<'py>,
        ctrl: &Bound<'py, PyAny>,
        robot: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, numpy::PyArrayDyn<f64>>> {
        use numpy::{PyArrayMethods, PyUntypedArrayMethods};
        let r = self.robot_index(robot)?;
        let target = &self.world.robots[r];
        let (n, nv) = (target.actuators.len(), self.robots[r].nv);
        if n == 0 {
            return Err(bad(format!("robot `{}` has no MJCF actuator", self.robots[r].name)));
        }
        let a = crate::arrays::f64_array(ctrl, "ctrl")?;
        let shape = a.shape().to_vec();
        // any leading axes, then one control per actuator
        let mut want = vec![None; shape.len().saturating_sub(1)];
        want.push(Some(n));
        crate::arrays::check_shape("ctrl", &shape, &want, "(..., n_actuators) controls")?;
        let ro = a.try_readonly().map_err(|e| bad(format!("ctrl: {e}")))?;
        let values = crate::arrays::values(&ro);
        crate::arrays::check_finite("ctrl", &values)?;
        let mut out = vec![0.0; values.len() / n * nv];
        for (u, tau) in values.chunks(n).zip(out.chunks_mut(nv)) {
            target.ctrl_torque(u, tau).map_err(|e| bad(e.to_string()))?;
        }
        let mut out_shape = shape[..shape.len() - 1].to_vec();
        out_shape.push(nv);
        numpy::PyArray1::from_vec(py, out).reshape(out_shape)
    }

    /// Rebuilds a model from `__reduce__`'s arguments.
    #[classmethod]
    fn _from_pickle(_cls: &Bound<'_, PyType>, text: String, format: &str, origin: String) -> PyResult<Self> {
        Self::build(text, parse_format(format)?, origin)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, PickleArgs)> {
        let m = slf.get();
        let rebuild = slf.get_type().getattr("_from_pickle")?;
        Ok((rebuild, (m.text.clone(), m.format, m.origin.clone())))
    }

    /// Length of the state vector: 13 per moving body, then `nq + nv` per robot.
    #[getter]
    fn nstate(&self) -> usize {
        self.world.state_len()
    }

    /// Width of a rollout's control: the robots' velocity coordinates, in robot order.
    #[getter(nu)]
    fn nu_py(&self) -> usize {
        self.nu()
    }

    /// The time step (s).
    #[getter]
    fn dt(&self) -> f64 {
        self.world.config.dt
    }

    /// The scene's `duration` (s).
    #[getter]
    fn duration(&self) -> f64 {
        self.world.config.duration
    }

    /// The integrator's name (`rk4`, `splitting`, ...).
    #[getter]
    fn integrator(&self) -> &'static str {
        self.world.config.integrator.name()
    }

    /// Names of the moving bodies, in state order.
    #[getter]
    fn body_names(&self) -> Vec<String> {
        self.body_names.clone()
    }

    /// Names of the robots, in state and control order.
    #[getter]
    fn robot_names(&self) -> Vec<String> {
        self.robots.iter().map(|r| r.name.clone()).collect()
    }

    /// Number of configuration coordinates of a robot (name or index; default: the only robot).
    #[pyo3(signature = (robot = None))]
    fn nq(&self, robot: Option<&Bound<'_, PyAny>>) -> PyResult<usize> {
        Ok(self.robots[self.robot_index(robot)?].nq)
    }

    /// Number of velocity coordinates of a robot (name or index; default: the only robot).
    #[pyo3(signature = (robot = None))]
    fn nv(&self, robot: Option<&Bound<'_, PyAny>>) -> PyResult<usize> {
        Ok(self.robots[self.robot_index(robot)?].nv)
    }

    /// The moving links of a robot, `robot/link`, in the order of `World.link_states`.
    #[pyo3(signature = (robot = None))]
    fn link_names(&self, robot: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<String>> {
        Ok(self.robots[self.robot_index(robot)?].link_names.clone())
    }

    /// A label per state entry: `body.x` ... `body.wz`, then `robot.q[i]`, `robot.v[i]`.
    #[getter]
    fn state_names(&self) -> Vec<String> {
        const FIELDS: [&str; 13] = ["x", "y", "z", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx", "wy", "wz"];
        let mut names = Vec::with_capacity(self.world.state_len());
        for b in &self.body_names {
            names.extend(FIELDS.iter().map(|f| format!("{b}.{f}")));
        }
        for r in &self.robots {
            names.extend((0..r.nq).map(|i| format!("{}.q[{i}]", r.name)));
            names.extend((0..r.nv).map(|i| format!("{}.v[{i}]", r.name)));
        }
        names
    }

    /// What the loader noticed but accepted (a quaternion normalised, ...).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// The scene text the model was built from.
    #[getter]
    fn text(&self) -> String {
        self.text.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "Model({} moving bodies, {} robots, nstate={}, dt={}, integrator={})",
            self.body_names.len(),
            self.robots.len(),
            self.world.state_len(),
            self.world.config.dt,
            self.integrator()
        )
    }
}

/// A TOML basic string: JSON's escaping is valid TOML for every character.
fn serde_json_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 || c == '\u{7f}' => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
