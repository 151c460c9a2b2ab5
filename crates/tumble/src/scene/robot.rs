//! `[[robot]]` entries → validated [`Robot`]s: the URDF read (its errors keep the URDF's
//! file:line:column), the base placed, the initial state and the control set by joint name.
//!
//! Every joint name is checked against the model; an unknown one is an error that lists the valid
//! names (and the nearest one). Values are checked like a body's: finite, in range, of the joint's
//! length (`nq` for `q`, `nv` for `v` and `torque`).
//!
//! `lock`: `q` is read against the full model (a locked joint's entry is the value it is held at),
//! then the model is reduced ([`reduced_model`]) and everything else (`v`, `torque`, `damping`,
//! `pd`, the state, the outputs) speaks the reduced layout; naming a locked joint there is an error.
//! `package_paths`: directories (relative to the scene) where `package://NAME/` is looked for after
//! the URDF's parent directories ([`UrdfOptions::package_paths`]).
//!
//! Link inertias: a positive-definite tensor that only violates the triangle inequality (a camera's
//! or a sensor's box written with one moment too large) loads with a warning naming the link and the
//! defect ([`UrdfOptions::keep_triangle_violations`]): the mass matrix stays positive definite. A
//! tensor that is not positive definite is an error whose hint names `balance_inertia = true` and
//! `lock`; a massless moving subtree is an error whose hint names `lock`.

use super::error::{names_hint, nearest, num, nums, SceneError, Source};
use super::schema::{CtrlDoc, DampingDoc, JointTable, JointValue, Loc, RobotDoc, Table};
use super::{MAX_ANGULAR_SPEED, MAX_POSITION, QUAT_SILENT_TOLERANCE, QUAT_WARN_TOLERANCE};
use crate::math::{DMat3, DQuat, DVec3};
use crate::multibody::mjcf::{load_mjcf_leaving_out, ContactFilter, LeaveOut, Mjcf, MjcfOptions, Transmission};
use crate::multibody::spatial::Xform;
use crate::multibody::{
    kept_coordinates, load_urdf, reduced_model, Control, FrameOrigin, JointKind, LockError, Massless, ModelError,
    MultibodyModel, TendonDrive, UrdfErrorKind, UrdfOptions,
};
use crate::world::Robot;
use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// The base kinds, as written in files.
const BASES: [&str; 2] = ["fixed", "floating"];

/// Name → (field path, span) of what took it.
pub(crate) type Taken = HashMap<String, (String, Option<Range<usize>>)>;

/// Reads every `[[robot]]`; `taken` holds the bodies' names and receives the robots'. Returns the
/// robots and, for each, the MJCF file's contact filter (`None` for a URDF robot).
pub(crate) fn read_robots(
    src: &Source,
    entries: &[Loc<Table<RobotDoc>>],
    taken: &mut Taken,
    gravity: DVec3,
    warnings: &mut Vec<String>,
) -> Result<(Vec<Robot>, Vec<Option<ContactFilter>>), SceneError> {
    let mut robots = Vec::with_capacity(entries.len());
    let mut filters = Vec::with_capacity(entries.len());
    for (i, entry) in entries.iter().enumerate() {
        let path = format!("robot[{i}]");
        let mut reader =
            RobotReader { src, path: &path, span: entry.span.as_ref(), warnings, locked: Vec::new(), filter: None };
        robots.push(reader.read(&entry.value, taken, gravity)?);
        filters.push(reader.filter.take());
    }
    Ok((robots, filters))
}

struct RobotReader<'r, 'a> {
    src: &'r Source<'a>,
    path: &'r str,
    span: Option<&'r Range<usize>>,
    warnings: &'r mut Vec<String>,
    /// The joints of `lock` (for the errors of `v`, `torque`, `damping` and `pd` that name one).
    locked: Vec<String>,
    /// The MJCF file's contact filter.
    filter: Option<ContactFilter>,
}

impl RobotReader<'_, '_> {
    fn at(&self, key: &str) -> String {
        format!("{}.{}", self.path, key)
    }

    fn err<T>(&self, key: &str, loc: &Loc<T>, problem: impl Into<String>) -> SceneError {
        self.src.error(loc.span.as_ref(), self.at(key), problem)
    }

    fn read(&mut self, doc: &RobotDoc, taken: &mut Taken, gravity: DVec3) -> Result<Robot, SceneError> {
        let name = self.name(doc, taken)?;
        let mjcf = self.mjcf(doc)?;
        let floating = match (&mjcf, &doc.base) {
            (Some(m), _) => m.model.bodies.first().is_some_and(|b| b.joint.kind == JointKind::Floating),
            (None, None) => false,
            (None, Some(l)) if l.value == "fixed" => false,
            (None, Some(l)) if l.value == "floating" => true,
            (None, Some(l)) => {
                let e = self
                    .err("base", l, "unknown base (expected \"fixed\" or \"floating\")")
                    .got(format!("\"{}\"", l.value));
                return Err(match nearest(&l.value, &BASES) {
                    Some(best) => e.hint(format!("did you mean `{best}`?")),
                    None => e,
                });
            }
        };
        let mut model = match &mjcf {
            Some(m) => m.model.clone(),
            None => self.model(doc, floating)?,
        };
        model.gravity = gravity;
        let position = self.position(doc)?;
        let orientation = self.orientation(doc)?;
        let mut q = model.neutral_configuration();
        let mut v0 = vec![0.0; model.nv()];
        if let Some(m) = &mjcf {
            // MuJoCo's qpos0: a free root where the file puts its body, hinges and slides at `ref`
            // (`q = 0`); `position` and `orientation` move a free root, or place a fixed one
            let (qpos, qvel) = match self.key(doc, m)? {
                Some(key) => {
                    if key.time != 0.0 {
                        let span = doc.keyframe.as_ref().and_then(|l| l.span.as_ref());
                        let text = format!(
                            "{}: <key time=\"{}\">: the run starts at t = 0 (the key's time is not used)",
                            key.at,
                            num(key.time)
                        );
                        self.warnings.push(self.src.warning(span, &self.at("keyframe"), &text));
                    }
                    (key.qpos.clone(), key.qvel.clone())
                }
                None => (m.layout.qpos0(), vec![0.0; model.nv()]),
            };
            (q, v0) = m.layout.state_from_mujoco(&qpos, &qvel).map_err(|e| self.mjcf_err(doc, e))?;
            if floating {
                if doc.position.is_some() {
                    q[0..3].copy_from_slice(&position.to_array());
                }
                if doc.orientation.is_some() {
                    q[3..7].copy_from_slice(&[orientation.w, orientation.x, orientation.y, orientation.z]);
                }
            } else {
                place_fixed_base(&mut model, DMat3::from_quat(orientation), position);
            }
        } else if floating {
            // the base pose is the free-flyer's coordinates
            q[0..3].copy_from_slice(&position.to_array());
            q[3..7].copy_from_slice(&[orientation.w, orientation.x, orientation.y, orientation.z]);
        } else {
            place_fixed_base(&mut model, DMat3::from_quat(orientation), position);
        }
        let base_pose_given = doc.position.is_some() || doc.orientation.is_some();
        if let Some(table) = &doc.q {
            for (joint, value) in &table.value.0 {
                let j = self.joint(&model, "q", joint, value.span.as_ref().or(table.span.as_ref()))?;
                let kind = model.bodies[j].joint.kind;
                if floating && j == 0 && base_pose_given {
                    return Err(self
                        .err(&format!("q.{joint}"), value, "the base pose is already given by `position`/`orientation`")
                        .hint("give the floating base's pose either way, not both"));
                }
                let values = self.values("q", joint, value, kind.nq(), kind)?;
                let qi = model.bodies[j].joint.q_index;
                q[qi..qi + kind.nq()].copy_from_slice(&values);
            }
        }
        // `q` names joints of the full model: a locked joint's entry is the value it is held at
        if let Some(lock) = &doc.lock {
            (model, q) = self.lock(lock, &model, &q)?;
        }
        // (a keyframe's velocities are an MJCF robot's, which `lock` is refused for)
        let mut v = if doc.lock.is_some() { vec![0.0; model.nv()] } else { v0 };
        if let Some(table) = &doc.v {
            for (joint, value) in &table.value.0 {
                let j = self.joint(&model, "v", joint, value.span.as_ref().or(table.span.as_ref()))?;
                let kind = model.bodies[j].joint.kind;
                let values = self.values("v", joint, value, kind.nv(), kind)?;
                if values.iter().any(|x| x.abs() > MAX_ANGULAR_SPEED) {
                    return Err(self
                        .err(&format!("v.{joint}"), value, format!("exceeds the limit of {MAX_ANGULAR_SPEED:e}"))
                        .got(nums(&values)));
                }
                let vi = model.bodies[j].joint.v_index;
                v[vi..vi + kind.nv()].copy_from_slice(&values);
            }
        }
        let mut control = self.control(doc, &model)?;
        let joint_limits = doc.joint_limits.as_ref().is_none_or(|b| b.value);
        if doc.effort_limits.as_ref().is_none_or(|b| b.value) {
            control.set_effort_limits(&model);
        }
        let drives = match &mjcf {
            Some(m) => self.actuators(doc, m, &model, &mut control)?,
            None => {
                if let Some(c) = &doc.ctrl {
                    return Err(self
                        .err("ctrl", c, "drives the actuators of an MJCF file: this robot has none")
                        .hint("a URDF robot is driven by `torque` and `[robot.pd]`"));
                }
                Vec::new()
            }
        };
        if joint_limits {
            self.warn_outside_limits(doc, &model, &q);
        }
        let mut robot =
            Robot::new(name, model, control, q, v).map_err(|e| self.src.error(self.span, self.path, e.to_string()))?;
        robot.set_joint_limits(joint_limits);
        robot.material = self.material(doc)?;
        robot.actuators = drives;
        Ok(robot)
    }

    /// `friction` (≥ 0) and `restitution` ([0, 1]) of every link.
    fn material(&self, doc: &RobotDoc) -> Result<crate::body::Material, SceneError> {
        let ranged = |key: &str, loc: &Option<Loc<f64>>, ok: fn(f64) -> bool, problem: &str| match loc {
            Some(l) if !l.value.is_finite() || !ok(l.value) => Err(self.err(key, l, problem).got(l.value.to_string())),
            _ => Ok(loc.as_ref().map(|l| l.value)),
        };
        Ok(crate::body::Material {
            friction: ranged("friction", &doc.friction, |f| f >= 0.0, "must be finite and ≥ 0")?,
            restitution: ranged("restitution", &doc.restitution, |e| (0.0..=1.0).contains(&e), "must be in [0, 1]")?,
        })
    }

    /// A warning for each joint, and each fixed tendon, that starts outside its position limits: the
    /// limit then stops it from moving further out and lets it come back, without pushing it in.
    fn warn_outside_limits(&mut self, doc: &RobotDoc, model: &MultibodyModel, q: &[f64]) {
        for b in &model.bodies {
            let j = &b.joint;
            let Some((lower, upper)) = j.limits.position else { continue };
            if !matches!(j.kind, JointKind::Revolute { .. } | JointKind::Prismatic { .. }) {
                continue;
            }
            let value = q[j.q_index];
            let side = if value < lower {
                "below its lower limit"
            } else if value > upper {
                "above its upper limit"
            } else {
                continue;
            };
            let unit = if matches!(j.kind, JointKind::Prismatic { .. }) { "m" } else { "rad" };
            let given = doc.q.as_ref().and_then(|t| t.value.0.iter().find(|(name, _)| *name == j.name));
            let (span, key) = match given {
                Some((_, loc)) => (loc.span.as_ref(), self.at(&format!("q.{}", j.name))),
                None => (self.span, self.path.to_string()),
            };
            let robot = doc.name.as_ref().map_or("", |n| n.value.as_str());
            let text = format!(
                "robot `{robot}`: joint `{}` starts at q = {} {unit}, {side} [{}, {}]: the limit stops it from moving further out \
                 and lets it come back (it is not pushed in); `joint_limits = false` ignores the limits",
                j.name,
                num(value),
                num(lower),
                num(upper)
            );
            self.warnings.push(self.src.warning(span, &key, &text));
        }
        // a fixed tendon's limit is held alike: one that starts outside its range stays out
        for t in &model.tendons {
            let Some((lower, upper)) = t.range else { continue };
            let length = t.length(q);
            let side = if length < lower {
                "below its lower limit"
            } else if length > upper {
                "above its upper limit"
            } else {
                continue;
            };
            let robot = doc.name.as_ref().map_or("", |n| n.value.as_str());
            let text = format!(
                "robot `{robot}`: tendon `{}` starts at length {}, {side} [{}, {}]: the limit stops it from moving further out \
                 and lets it come back (it is not pushed in); `joint_limits = false` ignores the limits",
                t.name,
                num(length),
                num(lower),
                num(upper)
            );
            self.warnings.push(self.src.warning(self.span, self.path, &text));
        }
    }

    fn name(&self, doc: &RobotDoc, taken: &mut Taken) -> Result<String, SceneError> {
        let name = match &doc.name {
            Some(n) if !n.value.trim().is_empty() && !n.value.contains('/') => n,
            Some(n) => {
                return Err(self
                    .err("name", n, "must be non-empty and without `/` (links are written `robot/link`)")
                    .got(format!("{:?}", n.value)))
            }
            None => {
                return Err(self
                    .src
                    .error(self.span, self.at("name"), "missing: every robot needs a unique name")
                    .hint("e.g. `name = \"arm\"`"))
            }
        };
        if let Some((first_path, first_span)) = taken.get(&name.value) {
            return Err(super::build::duplicate(self.src, self.path, name, first_path, first_span.as_ref()));
        }
        let prefix = format!("{}/", name.value);
        if let Some((body, (first_path, _))) = taken.iter().find(|(n, _)| n.starts_with(&prefix)) {
            return Err(self
                .err(
                    "name",
                    name,
                    format!("{first_path} is named `{body}`, which would collide with this robot's link rows"),
                )
                .got(format!("\"{}\"", name.value)));
        }
        taken.insert(name.value.clone(), (self.at("name"), name.span.clone()));
        Ok(name.value.clone())
    }

    /// `mjcf`: the MJCF file read (`None` for a URDF robot). The file decides the base (a free
    /// root body floats); the URDF-only keys are refused beside it.
    fn mjcf(&mut self, doc: &RobotDoc) -> Result<Option<Mjcf>, SceneError> {
        let Some(file) = &doc.mjcf else {
            for (key, span) in [
                ("leave_out", doc.leave_out.as_ref().map(|l| &l.span)),
                ("keyframe", doc.keyframe.as_ref().map(|l| &l.span)),
            ] {
                if let Some(span) = span {
                    return Err(self.src.error(span.as_ref(), self.at(key), "applies to an MJCF robot (`mjcf = ...`)"));
                }
            }
            return Ok(None);
        };
        if let Some(urdf) = &doc.urdf {
            return Err(self
                .err("urdf", urdf, "a robot is read from one file: both `urdf` and `mjcf` are given")
                .hint("keep one of them"));
        }
        // the URDF-only keys, where given: (key, its span, why)
        let refused = [
            (
                "base",
                doc.base.as_ref().map(|l| &l.span),
                "the MJCF file decides the base: a root body with a free joint floats, any other is fixed",
            ),
            (
                "balance_inertia",
                doc.balance_inertia.as_ref().map(|l| &l.span),
                "a URDF option: the MJCF reader takes the file's inertias as MuJoCo does",
            ),
            (
                "package_paths",
                doc.package_paths.as_ref().map(|l| &l.span),
                "a URDF option: an MJCF file finds its meshes by `meshdir`/`assetdir`",
            ),
            ("lock", doc.lock.as_ref().map(|l| &l.span), "not yet for an MJCF robot"),
        ];
        if let Some((key, Some(span), why)) = refused.into_iter().find(|(_, span, _)| span.is_some()) {
            return Err(self.src.error(span.as_ref(), self.at(key), format!("not used with `mjcf`: {why}")));
        }
        let scene_dir = Path::new(self.src.origin).parent().unwrap_or(Path::new(""));
        let path = scene_dir.join(&file.value);
        let mut leave_out = LeaveOut::default();
        for entry in doc.leave_out.iter().flat_map(|l| &l.value) {
            if entry.value == "world" {
                leave_out.world = true;
            } else {
                leave_out.bodies.push(entry.value.clone());
            }
        }
        let mjcf = load_mjcf_leaving_out(&path, MjcfOptions::default(), &leave_out).map_err(|e| {
            match (&doc.leave_out, e.to_string().contains("cannot leave out body")) {
                (Some(l), true) => self.err("leave_out", l, e.to_string()),
                _ => self.err("mjcf", file, e.to_string()),
            }
        })?;
        // (the reader's remarks name the MJCF file's own line and column)
        for w in &mjcf.model.warnings {
            self.warnings.push(self.src.warning(file.span.as_ref(), &self.at("mjcf"), w));
        }
        self.filter = Some(mjcf.filter.clone());
        Ok(Some(mjcf))
    }

    /// `keyframe`: the MJCF file's key of that name (or index), `None` when not given.
    fn key<'m>(&self, doc: &RobotDoc, m: &'m Mjcf) -> Result<Option<&'m crate::multibody::mjcf::MjcfKey>, SceneError> {
        let Some(name) = &doc.keyframe else { return Ok(None) };
        if let Some(l) = doc.leave_out.as_ref().filter(|l| l.value.iter().any(|e| e.value != "world")) {
            return Err(self
                .err(
                    "keyframe",
                    name,
                    "a key's qpos is the whole file's: it cannot start a robot that leaves out free bodies",
                )
                .hint(format!(
                    "give the state by `q` and `v`, or leave out only \"world\" (leave_out at {})",
                    self.at("leave_out")
                ))
                .got(format!("{:?}", l.value.iter().map(|e| e.value.as_str()).collect::<Vec<_>>())));
        }
        m.keyframe(&name.value).map(Some).map_err(|why| {
            let file = doc.mjcf.as_ref().map_or("", |f| f.value.as_str());
            self.err("keyframe", name, format!("{file}: {why}")).got(format!("\"{}\"", name.value))
        })
    }

    fn mjcf_err(&self, doc: &RobotDoc, e: impl std::fmt::Display) -> SceneError {
        let span = doc.mjcf.as_ref().and_then(|l| l.span.as_ref()).or(self.span);
        self.src.error(span, self.at("mjcf"), e.to_string())
    }

    /// The MJCF actuators under constant controls (`ctrl`, clamped to each `ctrlrange`), as the
    /// joint forces they give: for an actuator on joint `j` with gear `g`, gain `k`, bias
    /// `(b₀, b₁, b₂)`, MuJoCo's force is `f = k u + b₀ + b₁ l + b₂ l̇` with the length `l = g qpos =
    /// g (q + ref)` and `l̇ = g v`, and the joint takes `τ = g f`; so a constant `g (k u + b₀ + b₁ g
    /// ref)`, a stiffness `−g² b₁` and a damping `−g² b₂` (a `position` actuator is a PD to `u`, a
    /// `velocity` one a damper to `u`, a `motor` a constant force). A symmetric `forcerange` is
    /// the joint's effort limit `|g| f_max` when the actuator is the only force commanded on it.
    fn actuators(
        &self,
        doc: &RobotDoc,
        m: &Mjcf,
        model: &MultibodyModel,
        control: &mut Control,
    ) -> Result<Vec<crate::world::ActuatorDrive>, SceneError> {
        let mut ctrl = match self.key(doc, m)? {
            Some(key) => key.ctrl.clone(),
            None => vec![0.0; m.actuators.len()],
        };
        let names: Vec<&str> = m.actuators.iter().map(|a| a.name.as_str()).collect();
        if let Some(c) = &doc.ctrl {
            match &c.value {
                CtrlDoc::All(x) => {
                    if !x.is_finite() {
                        return Err(self.err("ctrl", c, "must be finite").got(x.to_string()));
                    }
                    ctrl.fill(*x);
                }
                CtrlDoc::Actuators(JointTable(entries)) => {
                    for (name, x) in entries {
                        let key = format!("ctrl.{name}");
                        let Some(k) = names.iter().position(|n| n == name) else {
                            let e = self.err(
                                &key,
                                x,
                                format!(
                                    "names no actuator of `{}`",
                                    doc.mjcf.as_ref().map_or("", |f| f.value.as_str())
                                ),
                            );
                            let list = names.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ");
                            return Err(match nearest(name, &names) {
                                Some(best) => e.hint(format!("did you mean `{best}`? (actuators: {list})")),
                                None => e.hint(if names.is_empty() {
                                    "the file has no actuator".to_string()
                                } else {
                                    format!("actuators: {list}")
                                }),
                            });
                        };
                        if !x.value.is_finite() {
                            return Err(self.err(&key, x, "must be finite").got(x.value.to_string()));
                        }
                        ctrl[k] = x.value;
                    }
                }
            }
        }
        let commanded: Vec<bool> =
            (0..model.nv()).map(|i| control.tau[i] != 0.0 || control.kp[i] != 0.0 || control.kd[i] != 0.0).collect();
        let mut driven = vec![0usize; model.nv()];
        for a in &m.actuators {
            let Transmission::Joint(joint_name) = &a.target else { continue };
            let j = model.joint_index(joint_name).ok_or_else(|| {
                self.mjcf_err(doc, format!("actuator `{}`: joint `{}` is not in the model", a.name, joint_name))
            })?;
            let joint = &model.bodies[j].joint;
            if joint.kind.nv() != 1 {
                return Err(self.mjcf_err(
                    doc,
                    format!(
                        "actuator `{}`: drives the {} joint `{}`; tumble drives hinges and slides only",
                        a.name,
                        joint.kind.name(),
                        joint_name
                    ),
                ));
            }
            driven[joint.v_index] += 1;
        }
        let mut drives = Vec::with_capacity(m.actuators.len());
        for (a, &u) in m.actuators.iter().zip(&ctrl) {
            let g = a.gear;
            let [b0, b1, b2] = a.bias;
            if b1 > 0.0 || b2 > 0.0 {
                return Err(self.mjcf_err(
                    doc,
                    format!(
                        "actuator `{}`: a bias that pushes away from its set point (b₁ = {}, b₂ = {}) is not supported",
                        a.name,
                        num(b1),
                        num(b2)
                    ),
                ));
            }
            let joint_name = match &a.target {
                Transmission::Joint(name) => name,
                Transmission::Tendon(k) => {
                    // f = k u + b₀ + b₁ g L + b₂ g L̇ along the tendon, clamped to its forcerange
                    let tendon = &model.tendons[*k];
                    if let Some(t) = tendon.terms.iter().find(|t| commanded[t.v_index]) {
                        return Err(self
                            .mjcf_err(
                                doc,
                                format!(
                                    "actuator `{}` drives tendon `{}` of joint `{}`, which `torque` or `[robot.pd]` drives too",
                                    a.name, tendon.name, model.bodies[t.body].joint.name
                                ),
                            )
                            .hint("drive a joint by its actuator (`ctrl`) or by the scene's `torque`/`pd`, not both"));
                    }
                    let drive = crate::world::ActuatorDrive {
                        name: a.name.clone(),
                        target: crate::world::DriveTarget::Tendon { drive: control.tendons.len() },
                        gear: g,
                        force_per_ctrl: a.gain,
                        ctrl_range: a.ctrl_range,
                        ctrl: u,
                    };
                    control.tendons.push(TendonDrive {
                        tendon: *k,
                        gear: g,
                        force: a.gain * drive.clamped(u) + b0,
                        bias_length: b1,
                        bias_rate: b2,
                        force_range: a.force_range,
                    });
                    drives.push(drive);
                    continue;
                }
            };
            let j = model.joint_index(joint_name).expect("checked above");
            let vi = model.bodies[j].joint.v_index;
            let drive = crate::world::ActuatorDrive {
                name: a.name.clone(),
                target: crate::world::DriveTarget::Joint { v_index: vi },
                gear: g,
                force_per_ctrl: a.gain,
                ctrl_range: a.ctrl_range,
                ctrl: u,
            };
            let u = drive.clamped(u);
            drives.push(drive);
            let reference = m.layout.joints.iter().find(|lj| &lj.name == joint_name).map_or(0.0, |lj| lj.reference);
            let (stiffness, damping) = (-g * g * b1, -g * g * b2);
            if commanded[vi] {
                return Err(self
                    .mjcf_err(
                        doc,
                        format!(
                            "actuator `{}` drives joint `{}`, which `torque` or `[robot.pd]` drives too",
                            a.name, joint_name
                        ),
                    )
                    .hint("drive a joint by its actuator (`ctrl`) or by the scene's `torque`/`pd`, not both"));
            }
            control.tau[vi] += g * (a.gain * u + b0 + b1 * g * reference);
            control.kp[vi] += stiffness;
            control.kd[vi] += damping;
            if let Some((lo, hi)) = a.force_range {
                if driven[vi] != 1 || lo != -hi {
                    return Err(self.mjcf_err(doc, format!(
                        "actuator `{}`: forcerange [{}, {}] is supported only symmetric and for a joint's only actuator",
                        a.name, num(lo), num(hi)
                    )));
                }
                control.effort[vi] = control.effort[vi].min(g.abs() * hi);
            }
        }
        Ok(drives)
    }

    fn model(&mut self, doc: &RobotDoc, floating: bool) -> Result<MultibodyModel, SceneError> {
        let Some(urdf) = &doc.urdf else {
            return Err(self
                .src
                .error(self.span, self.at("urdf"), "missing: a robot needs its URDF (or MJCF) file")
                .hint("e.g. `urdf = \"robots/arm.urdf\"` (relative to the scene file)"));
        };
        let scene_dir = Path::new(self.src.origin).parent().unwrap_or(Path::new(""));
        let path = scene_dir.join(&urdf.value);
        let balance_inertia = doc.balance_inertia.as_ref().is_some_and(|b| b.value);
        // with `lock`, massless joints are allowed until the model is reduced (then checked)
        let massless = if doc.lock.is_some() { Massless::Allow } else { Massless::Error };
        let package_paths = self.package_paths(doc, scene_dir)?;
        let options = UrdfOptions {
            floating,
            balance_inertia,
            // a positive-definite tensor that violates only the triangle inequality: a warning
            keep_triangle_violations: true,
            massless,
            package_paths: &package_paths,
            ..UrdfOptions::default()
        };
        let model = load_urdf(&path, options).map_err(|e| {
            let error = self.err("urdf", urdf, e.to_string());
            match &*e.kind {
                UrdfErrorKind::Model(ModelError::MasslessSubtree { .. }) => {
                    // every joint that moves no mass, from the model built without the check
                    let allowed = UrdfOptions { massless: Massless::Allow, ..options };
                    let joints = load_urdf(&path, allowed).map(|m| quoted(&m.massless_joints())).unwrap_or_default();
                    error.hint(format!(
                        "a joint that moves no mass cannot be simulated: hold them with `lock = [{joints}]`"
                    ))
                }
                UrdfErrorKind::BadInertia { .. } => error.hint(
                    "`balance_inertia = true` replaces it by the nearest physical inertia (reported per link); if \
                     the link need not move (a sensor, an antenna), `lock = [\"joint\"]` beside it holds the joint \
                     that moves it",
                ),
                _ => error,
            }
        })?;
        for w in &model.warnings {
            let text = format!("{}: {w}", path.display());
            self.warnings.push(self.src.warning(urdf.span.as_ref(), &self.at("urdf"), &text));
        }
        Ok(model)
    }

    /// `package_paths`: directories relative to the scene file, each an existing directory.
    fn package_paths(&self, doc: &RobotDoc, scene_dir: &Path) -> Result<Vec<PathBuf>, SceneError> {
        let Some(list) = &doc.package_paths else { return Ok(Vec::new()) };
        let mut dirs = Vec::with_capacity(list.value.len());
        for entry in &list.value {
            let dir = scene_dir.join(&entry.value);
            if !dir.is_dir() {
                let span = entry.span.as_ref().or(list.span.as_ref());
                return Err(self
                    .src
                    .error(span, self.at("package_paths"), format!("`{}` is not a directory", dir.display()))
                    .got(format!("\"{}\"", entry.value))
                    .hint(
                        "each entry is a directory (relative to the scene file) that holds packages: \
                           `package://NAME/…` is looked for in `DIR/NAME/…`",
                    ));
            }
            dirs.push(dir);
        }
        Ok(dirs)
    }

    /// `lock`: each named joint held at its value in `q` (full layout); returns the reduced model
    /// and its `q`.
    fn lock(
        &mut self,
        lock: &Loc<Vec<Loc<String>>>,
        model: &MultibodyModel,
        q: &[f64],
    ) -> Result<(MultibodyModel, Vec<f64>), SceneError> {
        let mut names: Vec<&str> = Vec::with_capacity(lock.value.len());
        for entry in &lock.value {
            let joint = entry.value.as_str();
            let span = entry.span.as_ref().or(lock.span.as_ref());
            let error = |problem: String| self.src.error(span, self.at("lock"), problem);
            let Some(j) = model.joint_index(joint) else {
                let movable: Vec<&str> = model.bodies.iter().map(|b| b.joint.name.as_str()).collect();
                let list = movable.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ");
                let fixed =
                    model.frames.iter().any(|f| matches!(&f.origin, FrameOrigin::Fixed { joint: j, .. } if j == joint));
                return Err(if fixed {
                    error(format!("joint `{joint}` is fixed already: there is nothing to lock"))
                } else {
                    let e = error(format!("unknown joint `{joint}` (the URDF has no movable joint of that name)"));
                    match nearest(joint, &movable) {
                        Some(best) => e.hint(format!("did you mean `{best}`? (movable joints: {list})")),
                        None => e.hint(format!("movable joints: {list}")),
                    }
                });
            };
            if model.bodies[j].joint.kind == JointKind::Floating {
                return Err(error(format!("joint `{joint}` is the floating base: it cannot be locked"))
                    .hint("`base = \"fixed\"` holds the base at `position` and `orientation`"));
            }
            if names.contains(&joint) {
                return Err(error(format!("joint `{joint}` is locked twice")));
            }
            names.push(joint);
        }
        let reduced = reduced_model(model, &names, q).map_err(|e| {
            let error = self.src.error(lock.span.as_ref(), self.at("lock"), e.to_string());
            match &e {
                LockError::Massless { joints } => {
                    let all: Vec<&str> = names.iter().copied().chain(joints.iter().map(String::as_str)).collect();
                    error.hint(format!(
                        "a joint that moves no mass cannot be simulated: lock them too, `lock = [{}]`",
                        quoted(&all)
                    ))
                }
                _ => error,
            }
        })?;
        let (q_map, _) = kept_coordinates(model, &reduced);
        let q_reduced = q_map.iter().map(|&k| q[k]).collect();
        self.locked = names.iter().map(|n| n.to_string()).collect();
        Ok((reduced, q_reduced))
    }

    fn position(&self, doc: &RobotDoc) -> Result<DVec3, SceneError> {
        let Some(l) = &doc.position else { return Ok(DVec3::ZERO) };
        if l.value.iter().any(|x| !x.is_finite()) {
            return Err(self.err("position", l, "must be finite").got(nums(&l.value)));
        }
        let p = DVec3::from_array(l.value);
        if p.length() > MAX_POSITION {
            return Err(self
                .err("position", l, format!("magnitude {:e} m exceeds the limit of {MAX_POSITION:e} m", p.length()))
                .got(nums(&l.value)));
        }
        Ok(p)
    }

    fn orientation(&mut self, doc: &RobotDoc) -> Result<DQuat, SceneError> {
        let Some(l) = &doc.orientation else { return Ok(DQuat::IDENTITY) };
        let unit = self.unit_quaternion("orientation", l, &l.value)?;
        Ok(DQuat::from_xyzw(unit[1], unit[2], unit[3], unit[0]))
    }

    /// `[w, x, y, z]` normalised, under the scene's quaternion rules.
    fn unit_quaternion<T>(&mut self, key: &str, l: &Loc<T>, wxyz: &[f64]) -> Result<[f64; 4], SceneError> {
        if wxyz.iter().any(|c| !c.is_finite()) {
            return Err(self.err(key, l, "must be finite (a quaternion [w, x, y, z])").got(nums(wxyz)));
        }
        let norm = wxyz.iter().map(|c| c * c).sum::<f64>().sqrt();
        if norm == 0.0 {
            return Err(self
                .err(key, l, "must be a unit quaternion [w, x, y, z], not zero")
                .got(nums(wxyz))
                .hint("the identity (no rotation) is [1, 0, 0, 0]"));
        }
        let unit = [wxyz[0] / norm, wxyz[1] / norm, wxyz[2] / norm, wxyz[3] / norm];
        let deviation = (norm - 1.0).abs();
        if deviation > QUAT_WARN_TOLERANCE {
            return Err(self
                .err(key, l, format!("must be a unit quaternion [w, x, y, z] (|q| = {norm})"))
                .got(nums(wxyz))
                .hint(format!("normalised it is {}; write that if it is what you meant", nums(&unit))));
        }
        if deviation > QUAT_SILENT_TOLERANCE {
            let text = format!("not a unit quaternion (|q| = {norm}); normalised to {}", nums(&unit));
            self.warnings.push(self.src.warning(l.span.as_ref(), &self.at(key), &text));
        }
        Ok(unit)
    }

    /// The body moved by the joint named `joint`; `what` is the table (`q`, `v`, `damping`, ...).
    fn joint(
        &self,
        model: &MultibodyModel,
        what: &str,
        joint: &str,
        span: Option<&Range<usize>>,
    ) -> Result<usize, SceneError> {
        if let Some(j) = model.joint_index(joint) {
            return Ok(j);
        }
        let movable: Vec<&str> = model.bodies.iter().map(|b| b.joint.name.as_str()).collect();
        let list = movable.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ");
        if self.locked.iter().any(|l| l == joint) {
            return Err(self
                .src
                .error(
                    span,
                    self.at(&format!("{what}.{joint}")),
                    format!("joint `{joint}` is locked: it has no coordinates"),
                )
                .hint("a locked joint is held at its value in `q`; remove it from `lock` to move it"));
        }
        let fixed = model.frames.iter().any(|f| matches!(&f.origin, FrameOrigin::Fixed { joint: j, .. } if j == joint));
        let problem = if fixed {
            format!("joint `{joint}` is fixed: it has no coordinates")
        } else {
            format!("unknown joint `{joint}` (the URDF has no movable joint of that name)")
        };
        let e = self.src.error(span, self.at(&format!("{what}.{joint}")), problem);
        Err(match nearest(joint, &movable) {
            Some(best) if !fixed => e.hint(format!("did you mean `{best}`? (movable joints: {list})")),
            _ => e.hint(format!("movable joints: {list}")),
        })
    }

    /// A joint's `n` finite values; quaternions (`q` of spherical and floating joints) normalised.
    fn values(
        &mut self,
        what: &str,
        joint: &str,
        value: &Loc<JointValue>,
        n: usize,
        kind: JointKind,
    ) -> Result<Vec<f64>, SceneError> {
        let key = format!("{what}.{joint}");
        let x = &value.value.0;
        if x.len() != n {
            let expected = match (what, kind) {
                ("q", JointKind::Floating) => "7 numbers [x, y, z, qw, qx, qy, qz]".to_string(),
                ("q", JointKind::Spherical) => "4 numbers, a quaternion [w, x, y, z]".to_string(),
                (_, JointKind::Floating) => "6 numbers [vx, vy, vz, wx, wy, wz] (base frame)".to_string(),
                (_, JointKind::Spherical) => "3 numbers (child frame)".to_string(),
                _ => "one number".to_string(),
            };
            return Err(self.err(&key, value, format!("a {} joint takes {expected}", kind.name())).got(format!(
                "{} number{}: {}",
                x.len(),
                if x.len() == 1 { "" } else { "s" },
                nums(x)
            )));
        }
        if x.iter().any(|c| !c.is_finite()) {
            return Err(self.err(&key, value, "must be finite").got(nums(x)));
        }
        let mut out = x.clone();
        if what == "q" {
            let start = match kind {
                JointKind::Spherical => Some(0),
                JointKind::Floating => Some(3),
                _ => None,
            };
            if let Some(s) = start {
                if kind == JointKind::Floating && DVec3::new(x[0], x[1], x[2]).length() > MAX_POSITION {
                    return Err(self.err(&key, value, format!("position exceeds {MAX_POSITION:e} m")).got(nums(x)));
                }
                let unit = self.unit_quaternion(&key, value, &x[s..s + 4])?;
                out[s..s + 4].copy_from_slice(&unit);
            }
        }
        Ok(out)
    }

    /// A one-coordinate joint for damping and PD; spherical and floating joints are refused.
    fn scalar_joint(
        &self,
        model: &MultibodyModel,
        what: &str,
        joint: &str,
        span: Option<&Range<usize>>,
    ) -> Result<usize, SceneError> {
        let j = self.joint(model, what, joint, span)?;
        let kind = model.bodies[j].joint.kind;
        if kind.nv() != 1 {
            return Err(self.src.error(
                span,
                self.at(&format!("{what}.{joint}")),
                format!("{what} applies to one-coordinate joints; `{joint}` is {}", kind.name()),
            ));
        }
        Ok(j)
    }

    fn nonneg(&self, key: &str, l: &Loc<f64>, unit: &str) -> Result<f64, SceneError> {
        if l.value.is_finite() && l.value >= 0.0 {
            Ok(l.value)
        } else {
            Err(self.err(key, l, format!("must be finite and ≥ 0 ({unit})")).got(num(l.value)))
        }
    }

    fn control(&self, doc: &RobotDoc, model: &MultibodyModel) -> Result<Control, SceneError> {
        let mut control = Control::passive(model);
        let damping_unit = "N·m·s/rad or N·s/m";
        if let Some(d) = &doc.damping {
            match &d.value {
                DampingDoc::All(c) => {
                    let c = self.nonneg("damping", &Loc { value: *c, span: d.span.clone() }, damping_unit)?;
                    for b in model.bodies.iter().filter(|b| b.joint.kind.nv() == 1) {
                        control.damping[b.joint.v_index] = c;
                    }
                }
                DampingDoc::Urdf => {
                    for b in model.bodies.iter().filter(|b| b.joint.kind.nv() == 1) {
                        control.damping[b.joint.v_index] = b.joint.limits.damping;
                    }
                }
                DampingDoc::Joints(JointTable(entries)) => {
                    for (joint, c) in entries {
                        let j = self.scalar_joint(model, "damping", joint, c.span.as_ref().or(d.span.as_ref()))?;
                        let c = self.nonneg(&format!("damping.{joint}"), c, damping_unit)?;
                        control.damping[model.bodies[j].joint.v_index] = c;
                    }
                }
                DampingDoc::Other(s) => {
                    return Err(self
                        .err("damping", d, "expected a number, \"urdf\" or a table of joint names")
                        .got(format!("\"{s}\"")))
                }
            }
        }
        if let Some(table) = &doc.torque {
            for (joint, value) in &table.value.0 {
                let j = self.joint(model, "torque", joint, value.span.as_ref().or(table.span.as_ref()))?;
                let joint_ref = &model.bodies[j].joint;
                let key = format!("torque.{joint}");
                let x = &value.value.0;
                let n = joint_ref.kind.nv();
                if x.len() != n {
                    return Err(self
                        .err(&key, value, format!("a {} joint takes {n} number(s)", joint_ref.kind.name()))
                        .got(nums(x)));
                }
                if x.iter().any(|c| !c.is_finite()) {
                    return Err(self.err(&key, value, "must be finite").got(nums(x)));
                }
                control.tau[joint_ref.v_index..joint_ref.v_index + n].copy_from_slice(x);
            }
        }
        if let Some(table) = &doc.pd {
            for (joint, pd) in &table.value.0 {
                let span = pd.span.as_ref().or(table.span.as_ref());
                let j = self.scalar_joint(model, "pd", joint, span)?;
                let joint_ref = &model.bodies[j].joint;
                let key = |k: &str| format!("pd.{joint}.{k}");
                let Some(target) = &pd.value.target else {
                    return Err(self
                        .src
                        .error(span, self.at(&format!("pd.{joint}")), "missing `target` (rad or m)")
                        .hint("e.g. `{ target = 0.5, kp = 100.0, kd = 10.0 }`"));
                };
                if !target.value.is_finite() {
                    return Err(self.err(&key("target"), target, "must be finite").got(num(target.value)));
                }
                let Some(kp) = &pd.value.kp else {
                    return Err(self.src.error(span, self.at(&format!("pd.{joint}")), "missing `kp` (N·m/rad or N/m)"));
                };
                control.q_target[joint_ref.q_index] = target.value;
                control.kp[joint_ref.v_index] = self.nonneg(&key("kp"), kp, "N·m/rad or N/m")?;
                if let Some(kd) = &pd.value.kd {
                    control.kd[joint_ref.v_index] = self.nonneg(&key("kd"), kd, "N·m·s/rad or N·s/m")?;
                }
                if let Some(tv) = &pd.value.target_velocity {
                    if !tv.value.is_finite() {
                        return Err(self.err(&key("target_velocity"), tv, "must be finite").got(num(tv.value)));
                    }
                    control.v_target[joint_ref.v_index] = tv.value;
                }
                let wave = (&pd.value.amplitude, &pd.value.frequency, &pd.value.phase);
                if let (None, None, None) = wave {
                    continue;
                }
                let Some(amplitude) = wave.0 else {
                    return Err(self
                        .src
                        .error(
                            span,
                            self.at(&format!("pd.{joint}")),
                            "`frequency` and `phase` need an `amplitude` (rad or m)",
                        )
                        .hint("e.g. `{ target = 0.5, kp = 100.0, kd = 10.0, amplitude = 0.2, frequency = 2.0 }`"));
                };
                if !amplitude.value.is_finite() {
                    return Err(self.err(&key("amplitude"), amplitude, "must be finite").got(num(amplitude.value)));
                }
                let Some(frequency) = wave.1 else {
                    return Err(self.src.error(
                        span,
                        self.at(&format!("pd.{joint}")),
                        "`amplitude` needs a `frequency` (Hz)",
                    ));
                };
                if !(frequency.value.is_finite() && frequency.value > 0.0) {
                    return Err(self
                        .err(&key("frequency"), frequency, "must be finite and > 0 (Hz)")
                        .got(num(frequency.value)));
                }
                let phase = match wave.2 {
                    Some(p) if !p.value.is_finite() => {
                        return Err(self.err(&key("phase"), p, "must be finite (rad)").got(num(p.value)))
                    }
                    Some(p) => p.value,
                    None => 0.0,
                };
                control.waves.push(crate::multibody::PdWave {
                    q_index: joint_ref.q_index,
                    centre: target.value,
                    amplitude: amplitude.value,
                    frequency: frequency.value,
                    phase,
                });
            }
        }
        control.follow_waves(0.0);
        Ok(control)
    }
}

/// `"a", "b"`: names as a TOML array's items.
fn quoted(names: &[&str]) -> String {
    names.iter().map(|n| format!("\"{n}\"")).collect::<Vec<_>>().join(", ")
}

/// The collision geometry of every robot whose `collision` is on (the default): its URDF
/// `<collision>` shapes, self-collision when asked, and its `no_collide` pairs. A link is named
/// `robot/link`; a body's `no_collide` may name one.
///
/// `no_collide` is checked even when the robot has no collision geometry: a name that is no link of
/// the URDF is an error (with the nearest link, or a list of them); a link without `<collision>`
/// touches nothing already, so naming it is a warning that the entry has no effect.
pub(crate) fn robot_collisions(
    src: &Source,
    entries: &[Loc<Table<RobotDoc>>],
    filters: &[Option<ContactFilter>],
    world: &mut crate::world::World,
    warnings: &mut Vec<String>,
) -> Result<(), SceneError> {
    for (i, entry) in entries.iter().enumerate() {
        let doc = &entry.value;
        let path = format!("robot[{i}]");
        if !doc.collision.as_ref().is_none_or(|b| b.value) {
            for (key, given) in
                [("self_collision", doc.self_collision.is_some()), ("no_collide", doc.no_collide.is_some())]
            {
                if given {
                    warnings.push(src.warning(
                        entry.span.as_ref(),
                        &format!("{path}.{key}"),
                        "has no effect: `collision = false` takes the robot out of all contact",
                    ));
                }
            }
            continue;
        }
        let (key, urdf) = match (&doc.urdf, &doc.mjcf) {
            (Some(f), _) => ("urdf", f),
            (None, Some(f)) => ("mjcf", f),
            (None, None) => continue,
        };
        let file = Path::new(src.origin).parent().unwrap_or(Path::new("")).join(&urdf.value);
        let shapes =
            crate::multibody::link_shapes::collision_shapes(&world.robots[i].model, &file.display().to_string())
                .map_err(|e| {
                    src.error(urdf.span.as_ref(), format!("{path}.{key}"), e.to_string()).hint(
                        "`collision = false` loads the robot without its collision geometry (it then touches nothing)",
                    )
                })?;
        // with no collision geometry there is nothing to add, but `no_collide`'s names are checked
        let ids = if shapes.is_empty() { Vec::new() } else { world.add_link_shapes(i, &shapes) };
        if !shapes.is_empty() && doc.self_collision.as_ref().is_some_and(|b| b.value) {
            // an MJCF file's own filter first (contype/conaffinity, parent and child, <exclude>):
            // the k-th collision geometry is the k-th shape
            if let Some(filter) = &filters[i] {
                let model = &world.robots[i].model;
                let geoms: Vec<usize> = (0..model.geometries.len())
                    .filter(|&g| model.geometries[g].role == crate::multibody::GeometryRole::Collision)
                    .collect();
                let links = &mut world.contact_stage().links.colliders;
                for a in 0..ids.len() {
                    for b in a + 1..ids.len() {
                        if !filter.may_collide(geoms[a], geoms[b]) {
                            links.exclude_links(ids[a], ids[b]);
                        }
                    }
                }
            }
            for (a, b) in world.enable_self_collision(i) {
                warnings.push(src.warning(
                    doc.self_collision.as_ref().and_then(|l| l.span.as_ref()),
                    &format!("{path}.self_collision"),
                    &format!("`{a}` and `{b}` touch in the initial pose: that pair never collides"),
                ));
            }
        }
        let Some(list) = &doc.no_collide else { continue };
        let robot_name = world.robots[i].name.clone();
        let links_named = |world: &crate::world::World, link: &str| -> Vec<usize> {
            let full = format!("{robot_name}/{link}");
            ids.iter().copied().filter(|&l| world.contacts().links.colliders.links()[l].name == full).collect()
        };
        let key = format!("{path}.no_collide");
        for group in &list.value {
            let named: Result<Vec<Vec<usize>>, SceneError> = group
                .iter()
                .map(|link| {
                    let found = links_named(world, link);
                    if !found.is_empty() {
                        return Ok(found);
                    }
                    let model = &world.robots[i].model;
                    if model.frame_index(link).is_some() {
                        // a link without `<collision>` touches nothing: the entry changes nothing
                        let text = format!(
                            "link `{link}` of robot `{robot_name}` has no collision geometry: it touches nothing, \
                             and this entry has no effect"
                        );
                        warnings.push(src.warning(list.span.as_ref(), &key, &text));
                        return Ok(Vec::new());
                    }
                    let names: Vec<&str> = model.frames.iter().map(|f| f.name.as_str()).collect();
                    let e = src
                        .error(list.span.as_ref(), key.clone(), format!("names no link of robot `{robot_name}`"))
                        .got(format!("\"{link}\""));
                    Err(match names_hint(link, "its links", &names) {
                        Some(hint) => e.hint(hint),
                        None => e,
                    })
                })
                .collect();
            let named = named?;
            let links = &mut world.contact_stage().links.colliders;
            match named.as_slice() {
                [one] => one.iter().for_each(|&l| links.disable(l)),
                [a, b] => {
                    for &l in a {
                        for &m in b {
                            links.exclude_links(l, m);
                        }
                    }
                }
                _ => {
                    return Err(src
                        .error(list.span.as_ref(), format!("{path}.no_collide"), "each entry is one or two link names")
                        .got(format!("{group:?}"))
                        .hint("e.g. `no_collide = [[\"base\", \"FL_UPPER_LEG\"], [\"camera\"]]`"))
                }
            }
        }
    }
    Ok(())
}

/// Places a fixed-base model at `world_from_base = (rotation, position)`: the joints that hang from
/// the world get `jointframe_X_world = jointframe_X_base · base_X_world`, the links fixed to the
/// world move with the base, and the inertia fixed to the world is expressed in the world frame.
pub(crate) fn place_fixed_base(model: &mut MultibodyModel, rotation: DMat3, position: DVec3) {
    if rotation == DMat3::IDENTITY && position == DVec3::ZERO {
        return;
    }
    let base_x_world = Xform::from_pose(rotation, position);
    for body in model.bodies.iter_mut().filter(|b| b.parent.is_none()) {
        body.joint.x_tree = body.joint.x_tree.compose(&base_x_world);
    }
    for frame in model.frames.iter_mut().filter(|f| f.body.is_none()) {
        frame.x_from_body = frame.x_from_body.compose(&base_x_world);
    }
    model.world_inertia = model.world_inertia.transform_to_a(&base_x_world);
}

/// The account of a robot printed by `tumble check`: base, mass, joints with their initial state and
/// control.
pub(crate) fn describe_robot(out: &mut String, robot: &Robot) {
    use std::fmt::Write as _;
    let m = &robot.model;
    let base = if robot.floating { "floating" } else { "fixed" };
    let _ = writeln!(
        out,
        "robot `{}`: {} base, {} joints, nq = {}, nv = {}, mass {} kg, {} moving links",
        robot.name,
        base,
        m.nbodies(),
        m.nq(),
        m.nv(),
        m.total_mass,
        robot.link_names().len()
    );
    let c = &robot.control;
    let limited = m.bodies.iter().filter(|b| b.joint.limits.position.is_some() && b.joint.kind.nv() == 1).count();
    let clamped = c.effort.iter().filter(|e| e.is_finite()).count();
    let _ = writeln!(
        out,
        "  joint limits: {}; effort limits: {}",
        if robot.joint_limits_enforced() {
            match m.tendons.iter().filter(|t| t.range.is_some()).count() {
                0 => format!("enforced on {limited} joints"),
                tendons => format!("enforced on {limited} joints and {tendons} tendons"),
            }
        } else {
            "off".to_string()
        },
        if clamped > 0 {
            format!("commanded forces clamped to the URDF effort on {clamped} joints")
        } else {
            "off".to_string()
        }
    );
    if !m.locked.is_empty() {
        let list: Vec<String> = m.locked.iter().map(|(name, q)| format!("{name} at {}", nums(q))).collect();
        let _ = writeln!(out, "  locked: {}", list.join(", "));
    }
    for b in &m.bodies {
        let j = &b.joint;
        let (qi, vi) = (j.q_index, j.v_index);
        let q = &robot.q()[qi..qi + j.kind.nq()];
        let v = &robot.v()[vi..vi + j.kind.nv()];
        let _ = write!(out, "  {} ({}): q = {}, v = {}", j.name, j.kind.name(), nums(q), nums(v));
        let tau = &c.tau[vi..vi + j.kind.nv()];
        if tau.iter().any(|x| *x != 0.0) {
            let _ = write!(out, ", torque {}", nums(tau));
        }
        if j.kind.nv() == 1 {
            if c.damping[vi] != 0.0 {
                let _ = write!(out, ", damping {}", num(c.damping[vi]));
            }
            if c.kp[vi] != 0.0 || c.kd[vi] != 0.0 {
                let _ = write!(
                    out,
                    ", PD target {} (kp {}, kd {}, target velocity {})",
                    num(c.q_target[qi]),
                    num(c.kp[vi]),
                    num(c.kd[vi]),
                    num(c.v_target[vi])
                );
                if let Some(w) = c.waves.iter().find(|w| w.q_index == qi) {
                    let _ = write!(
                        out,
                        ", swinging about {} by {} at {} Hz, phase {} rad",
                        num(w.centre),
                        num(w.amplitude),
                        num(w.frequency),
                        num(w.phase)
                    );
                }
            }
        }
        let _ = writeln!(out);
    }
}
