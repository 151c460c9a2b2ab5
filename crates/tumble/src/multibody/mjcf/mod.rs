//! MJCF (MuJoCo's XML) models → [`MultibodyModel`], through the same [`ModelBuilder`] as URDF.
//!
//! References: MuJoCo documentation, "XML Reference" and "Modeling" (frames, defaults, the
//! compiler's inertia from geoms); `docs/mjcf.md` maps each MuJoCo concept to tumble's.
//!
//! Read: `<compiler>` (`angle`, `eulerseq`, `autolimits`, `inertiafromgeom`, `inertiagrouprange`,
//! `meshdir`/`assetdir`, `settotalmass`, `coordinate="local"`), `<include>`, `<default>` classes
//! with `class`/`childclass`, `<option>` (`timestep`, `gravity`, `integrator`, `<flag gravity>`),
//! `<worldbody>` with `<body>`, `<frame>`, `<inertial>`, `<joint>`/`<freejoint>`, `<geom>`,
//! `<asset><mesh>`, `<actuator>` (recorded), `<contact><exclude>` (recorded).
//!
//! Each MJCF body becomes one tumble body per joint (a body with two hinges becomes two bodies, the
//! first without mass, as MuJoCo composes a body's joints in order); the tumble body's frame is
//! the joint's: at the joint's `pos`, with the MJCF body's axes, so the MJCF body frame is a named
//! [`Frame`](super::Frame) of it. A body without joints is merged into its parent, as URDF's fixed
//! links. Joint coordinates follow MuJoCo's order (bodies depth-first in file order, joints in
//! order within a body), so `q` lines up with `qpos` ([`layout`]): hinge and slide `q = qpos − ref`;
//! free joints `q = qpos`, `v` with the linear velocity in the body frame where MuJoCo's is in the
//! world frame.
//!
//! Refused with `file:line:col: <element attr>: not supported (…)`: what changes the dynamics and
//! is not read (equality constraints, tendons that act, fluid forces, `mocap`, `gravcomp`,
//! heightfields, plugins, composites, flex, …); `solref`, `solimp`, `margin` and the other soft-
//! contact parameters are reported once as not used. Visual elements are skipped.

mod assemble;
mod attrs;
mod build;
mod defaults;
pub mod filter;
mod keyframe;
pub mod layout;
mod mesh_inertia;
mod pose;
mod tendon;
mod tree;
mod xml;

use super::model::{ModelError, MultibodyModel};
use crate::math::DVec3;
use std::path::{Path, PathBuf};

pub use filter::ContactFilter;
pub use layout::MujocoLayout;
pub use xml::{MAX_ELEMENT_DEPTH, MAX_INCLUDE_DEPTH, MAX_MJCF_BYTES};

/// An error in an MJCF file, with its position.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}:{line}:{column}: <{element}>: {kind}")]
pub struct MjcfError {
    /// The file (as given, or the included file).
    pub file: String,
    /// 1-based line (0 when the file could not be read).
    pub line: u32,
    /// 1-based column.
    pub column: u32,
    /// The element and attribute concerned, e.g. `joint frictionloss`, `geom name="foot"`.
    pub element: String,
    /// What is wrong.
    pub kind: Box<MjcfErrorKind>,
}

impl MjcfError {
    fn at(pos: &xml::Pos, element: String, kind: MjcfErrorKind) -> Self {
        MjcfError { file: pos.file.to_string(), line: pos.line, column: pos.column, element, kind: Box::new(kind) }
    }

    /// True for an input that tumble cannot represent yet (rather than a malformed one).
    pub fn is_unsupported(&self) -> bool {
        matches!(*self.kind, MjcfErrorKind::Unsupported(_))
    }
}

/// What is wrong in an MJCF file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MjcfErrorKind {
    #[error("cannot read the file: {0}")]
    Io(String),
    #[error("malformed XML: {0}")]
    Xml(String),
    #[error("missing attribute '{0}'")]
    MissingAttribute(&'static str),
    #[error("'{value}': expected {expected}")]
    BadValue { value: String, expected: String },
    #[error("not supported ({0})")]
    Unsupported(String),
    #[error("{0}")]
    Invalid(String),
    #[error("{0}")]
    Model(ModelError),
}

/// `<compiler>` settings that the reader uses.
#[derive(Debug, Clone, PartialEq)]
pub struct Compiler {
    /// Angles in degrees (`angle="degree"`, MJCF's default).
    pub degree: bool,
    /// `eulerseq`, three of `xyzXYZ`.
    pub eulerseq: [u8; 3],
    /// `autolimits`: a `range` makes a joint limited.
    pub autolimits: bool,
    /// `inertiafromgeom`: `Some(true)` always, `Some(false)` never, `None` = auto (when a body has
    /// no `<inertial>`).
    pub inertia_from_geom: Option<bool>,
    /// `inertiagrouprange`: the geom groups that count for inertia.
    pub inertia_groups: (i64, i64),
    /// Where mesh files are looked for (`meshdir`, else `assetdir`, relative to the model's directory).
    pub meshdir: PathBuf,
    /// `settotalmass`: every mass and inertia scaled so that the total is this.
    pub total_mass: Option<f64>,
}

impl Default for Compiler {
    fn default() -> Self {
        Compiler {
            degree: true,
            eulerseq: *b"xyz",
            autolimits: true,
            inertia_from_geom: None,
            inertia_groups: (0, 5),
            meshdir: PathBuf::new(),
            total_mass: None,
        }
    }
}

/// MuJoCo's integrator, as `<option integrator>` names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MjcfIntegrator {
    /// `Euler`: semi-implicit Euler (MuJoCo's default).
    Euler,
    /// `RK4`.
    Rk4,
    /// `implicit`.
    Implicit,
    /// `implicitfast`.
    ImplicitFast,
}

impl MjcfIntegrator {
    /// tumble's nearest integrator: RK4 for RK4, semi-implicit Euler for the others (MuJoCo's
    /// implicit integrators treat damping implicitly; tumble's integrates it explicitly).
    pub fn tumble_name(&self) -> &'static str {
        match self {
            MjcfIntegrator::Rk4 => "rk4",
            _ => "semi_implicit_euler",
        }
    }
}

/// `<option>`: the simulation settings.
#[derive(Debug, Clone, PartialEq)]
pub struct MjcfOption {
    /// `timestep` (s), 0.002 by default.
    pub timestep: f64,
    /// `gravity` (m/s², world frame), `0 0 −9.81` by default (zero with `<flag gravity="disable">`).
    pub gravity: DVec3,
    pub integrator: MjcfIntegrator,
    /// `density` (kg/m³), `viscosity` (Pa·s) and `wind` (m/s, world frame) of the medium, zero by
    /// default: MuJoCo's inertia-box fluid model ([`crate::multibody::fluid`]), carried by the model.
    pub medium: crate::multibody::fluid::Medium,
}

/// An actuator as read (scenes drive it under a constant `ctrl`, `scene::robot`): force
/// `gear · (gain · ctrl + bias₀ + bias₁ l + bias₂ l̇)` on its joint or tendon (`l = gear · qpos`,
/// or `gear · L` for a tendon of length `L`), with MuJoCo's `motor`,
/// `position` (`gain = kp`, `bias = [0, −kp, −kv]`), `velocity` (`gain = kv`, `bias = [0, 0, −kv]`)
/// and `general` (fixed gain, affine or no bias).
#[derive(Debug, Clone, PartialEq)]
pub struct MjcfActuator {
    pub name: String,
    /// The element (`motor`, `position`, `velocity`, `general`).
    pub kind: String,
    /// What it drives: a joint or a fixed tendon.
    pub target: Transmission,
    pub gear: f64,
    pub gain: f64,
    pub bias: [f64; 3],
    /// `ctrlrange` when control is limited.
    pub ctrl_range: Option<(f64, f64)>,
    /// `forcerange` when force is limited.
    pub force_range: Option<(f64, f64)>,
}

/// An actuator's transmission: what its force acts on.
#[derive(Debug, Clone, PartialEq)]
pub enum Transmission {
    /// A hinge or slide joint (a tumble joint name): the joint takes `gear · f`.
    Joint(String),
    /// A fixed tendon (index into the model's `tendons`): each of its joints takes `gear · c_i · f`.
    Tendon(usize),
}

/// A model read from MJCF: the tree and what MJCF adds to it.
#[derive(Debug, Clone)]
pub struct Mjcf {
    /// The tree (its `gravity` from `<option>`); its `warnings` hold the reader's remarks.
    pub model: MultibodyModel,
    pub option: MjcfOption,
    /// MuJoCo's joint layout and the maps between its state and tumble's.
    pub layout: MujocoLayout,
    pub actuators: Vec<MjcfActuator>,
    /// `<contact><exclude body1 body2>` pairs (MJCF body names).
    pub excludes: Vec<(String, String)>,
    /// The MJCF bodies in MuJoCo's order (world first): name, the tumble body it moves with
    /// (`None`: the world) and its frame in that body's (`body_X_mjcfbody`), for `xpos`/`xquat`.
    pub bodies: Vec<MjcfBody>,
    /// The bodies with a free joint and no child bodies, in file order (MJCF names): each is a rigid
    /// body of its own, which [`LeaveOut`] can take out of the tree.
    pub free_bodies: Vec<String>,
    /// MuJoCo's contact filter of the model's geometries ([`filter`]), one entry per geometry.
    pub filter: ContactFilter,
    /// `<keyframe><key>` states, in file order (none read when free bodies are left out: their
    /// `qpos` is the whole file's).
    pub keyframes: Vec<MjcfKey>,
}

/// A `<keyframe><key>`: a state in MuJoCo's layout, complete (what the key does not give is
/// MuJoCo's default: `qpos0`, zero velocities and controls).
#[derive(Debug, Clone, PartialEq)]
pub struct MjcfKey {
    /// Its `name` (`None`: unnamed, chosen by its index).
    pub name: Option<String>,
    /// `time` (s).
    pub time: f64,
    /// `qpos` (nq; ball and free joints' quaternions normalised), `qvel` (nv), `ctrl` (one per
    /// actuator).
    pub qpos: Vec<f64>,
    pub qvel: Vec<f64>,
    pub ctrl: Vec<f64>,
    /// `file:line:col` of the element.
    pub at: String,
}

impl Mjcf {
    /// The key named `name`, or the unnamed one whose index it is; else an error that lists the
    /// keys.
    pub fn keyframe(&self, name: &str) -> Result<&MjcfKey, String> {
        if let Some(k) = self.keyframes.iter().find(|k| k.name.as_deref() == Some(name)) {
            return Ok(k);
        }
        if let Some(k) = name.parse::<usize>().ok().and_then(|i| self.keyframes.get(i)) {
            if k.name.is_none() {
                return Ok(k);
            }
        }
        let names: Vec<String> = self
            .keyframes
            .iter()
            .enumerate()
            .map(|(i, k)| k.name.as_ref().map_or(format!("{i} (unnamed)"), |n| format!("'{n}'")))
            .collect();
        Err(if names.is_empty() {
            format!("no keyframe '{name}': the file has no <keyframe><key>")
        } else {
            format!("no keyframe '{name}' (keys: {})", names.join(", "))
        })
    }
}

/// What [`load_mjcf_leaving_out`] leaves out of the tree (`[[robot]] leave_out`): the world's
/// geometry (the worldbody's geoms and those of bodies welded to it), and bodies with a free joint
/// and no child bodies, by name. `tumble run X.xml` makes them scene bodies beside the robot.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LeaveOut {
    /// The geometry fixed to the world.
    pub world: bool,
    /// Free bodies without child bodies (MJCF names; each must be one, else an error).
    pub bodies: Vec<String>,
}

/// An MJCF body: where its frame sits on the tree.
#[derive(Debug, Clone, PartialEq)]
pub struct MjcfBody {
    pub name: String,
    /// The tumble body it moves with (`None`: fixed to the world).
    pub body: Option<usize>,
    /// Its frame in that body's frame (or the world's).
    pub pose_in_body: pose::Pose,
}

/// Options of [`load_mjcf`] and [`parse_mjcf`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MjcfOptions {
    /// Read joints with `frictionloss` as if it were zero, with one warning per joint: the dynamics
    /// are then MuJoCo's with `<flag frictionloss="disable">` (without it, `frictionloss` is read
    /// into [`JointDynamics::friction_loss`](crate::multibody::JointDynamics)).
    pub drop_frictionloss: bool,
}

/// Reads an MJCF file (and what it includes).
pub fn load_mjcf(path: &Path, options: MjcfOptions) -> Result<Mjcf, MjcfError> {
    let root = xml::load(path)?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    build::build(&root, &dir, options)
}

/// Reads an MJCF file without what `leave_out` names (see [`LeaveOut`]): the model, its layout
/// (MuJoCo's coordinates of the joints kept), its bodies and geometry are those of the rest.
pub fn load_mjcf_leaving_out(path: &Path, options: MjcfOptions, leave_out: &LeaveOut) -> Result<Mjcf, MjcfError> {
    let root = xml::load(path)?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    build::build_leaving_out(&root, &dir, options, leave_out)
}

/// Parses MJCF text; `file` names it in errors, includes and meshes are looked for beside it.
pub fn parse_mjcf(text: &str, file: &str, options: MjcfOptions) -> Result<Mjcf, MjcfError> {
    let dir = Path::new(file).parent().map(Path::to_path_buf).unwrap_or_default();
    let root = xml::parse(text, file, &dir)?;
    build::build(&root, &dir, options)
}

pub use pose::Pose;
