//! The walk over an MJCF document: compiler, defaults, options, assets, the body tree, actuators;
//! then the tree handed to the [`ModelBuilder`] body by body.

use super::attrs::{all_zero, View};
use super::defaults::Defaults;
use super::layout::{LayoutJoint, MujocoLayout};
use super::pose::{orientation, pose, z_to_quat, Pose, ORIENTATIONS};
use super::xml::El;
use super::{
    Compiler, Mjcf, MjcfActuator, MjcfBody, MjcfError, MjcfErrorKind, MjcfIntegrator, MjcfOption, MjcfOptions,
};
use crate::math::{DMat3, DVec3};
use crate::multibody::joint::{JointDynamics, JointKind, JointLimits};
use crate::multibody::model::{placed_inertia, FrameOrigin, GeometryRole, GeometryShape, LinkGeometry, ModelBuilder};
use crate::multibody::spatial::{RigidInertia, Xform};
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

/// The soft-contact and solver parameters that tumble's contact model does not use: reported once each.
const SOFT: &[&str] = &[
    "solref",
    "solimp",
    "margin",
    "gap",
    "solmix",
    "priority",
    "condim",
    "solreflimit",
    "solimplimit",
    "solreffriction",
    "solimpfriction",
];

/// Elements that only draw or measure: skipped wherever they appear.
const VISUAL: &[&str] = &["site", "camera", "light"];

#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Hinge,
    Slide,
    Ball,
    Free,
}

struct JointRec<'a> {
    el: &'a El,
    name: String,
    kind: Kind,
    /// Anchor in the body frame (m).
    anchor: DVec3,
    /// Unit axis in the body frame.
    axis: DVec3,
    /// MuJoCo's `ref` (rad or m): `q = qpos − ref`.
    reference: f64,
    /// Limits in MuJoCo's `qpos` (rad or m).
    range: Option<(f64, f64)>,
    dynamics: JointDynamics,
    /// `springref` in MuJoCo's `qpos`.
    springref: f64,
}

struct BodyRec<'a> {
    name: String,
    /// Index of the parent in the list (`None`: the world).
    parent: Option<usize>,
    /// The body frame in the parent body's frame.
    in_parent: Pose,
    joints: Vec<JointRec<'a>>,
    /// Spatial inertia in the body frame.
    inertia: RigidInertia,
    geoms: Vec<GeomRec<'a>>,
}

struct GeomRec<'a> {
    el: &'a El,
    /// Counted in the body's inertia (its group is in `inertiagrouprange`).
    counts: bool,
    /// `mass` if given, else `density` times the volume.
    mass: Option<f64>,
    density: f64,
    shape: GeometryShape,
    /// The geom frame in the body frame.
    in_body: Pose,
    contype: u32,
    conaffinity: u32,
    friction: Option<f64>,
    line: u32,
}

struct Reader<'a> {
    defaults: &'a Defaults,
    compiler: Compiler,
    /// mesh asset name → (file as written, resolved path, scale)
    meshes: HashMap<String, (String, PathBuf, DVec3)>,
    hfields: HashSet<String>,
    bodies: Vec<BodyRec<'a>>,
    world_geoms: Vec<GeomRec<'a>>,
    options: MjcfOptions,
    warned: Vec<String>,
    warnings: Vec<String>,
    joint_names: HashMap<String, u32>,
    body_names: HashMap<String, u32>,
}

pub fn build(root: &El, dir: &Path, options: MjcfOptions) -> Result<Mjcf, MjcfError> {
    for el in &root.children {
        match el.tag.as_str() {
            "compiler" | "option" | "size" | "visual" | "statistic" | "default" | "custom" | "asset" | "worldbody"
            | "contact" | "equality" | "tendon" | "actuator" | "sensor" | "keyframe" => {}
            "extension" | "deformable" if el.children.is_empty() => {}
            "extension" => return Err(el.error(unsupported("plugins"))),
            "deformable" => return Err(el.error(unsupported("flex and skin deformables"))),
            other => return Err(el.error(MjcfErrorKind::Invalid(format!("unknown element <{other}> in <mujoco>")))),
        }
    }
    // what the tree cannot represent, before anything else: the first loop closure names the model's
    for el in root.children.iter().filter(|e| e.tag == "equality") {
        if let Some(first) = el.children.first() {
            return Err(first.error(unsupported(
                "an <equality> constraint: closed kinematic loops and coupled joints are not built yet",
            )));
        }
    }
    let defaults = Defaults::read(root)?;
    let compiler = read_compiler(root, dir)?;
    let mut tendon_warnings = Vec::new();
    for el in root.children.iter().filter(|e| e.tag == "tendon") {
        for t in &el.children {
            inert_tendon(t, &defaults, &compiler, &mut tendon_warnings)?;
        }
    }
    let mut reader = Reader {
        defaults: &defaults,
        compiler,
        meshes: HashMap::new(),
        hfields: HashSet::new(),
        bodies: Vec::new(),
        world_geoms: Vec::new(),
        options,
        warned: Vec::new(),
        warnings: Vec::new(),
        joint_names: HashMap::new(),
        body_names: HashMap::new(),
    };
    reader.warnings.extend(tendon_warnings);
    let option = reader.option(root)?;
    for el in root.children.iter().filter(|e| e.tag == "asset") {
        reader.assets(el)?;
    }
    for wb in root.children.iter().filter(|e| e.tag == "worldbody") {
        reader.children(wb, None, Pose::IDENTITY, None)?;
    }
    let excludes = reader.contact(root)?;
    let model_name = root.attr("model").map(|a| a.value.clone()).unwrap_or_else(|| "MuJoCo Model".into());
    reader.scale_total_mass(root)?;
    let (model, layout, bodies) = reader.assemble(&model_name, root, option.gravity)?;
    let actuators = reader_actuators(&reader, root, &model)?;
    let mut model = model;
    if !actuators.is_empty() {
        model.warnings.push(format!(
            "{} actuators read and recorded; tumble does not apply MJCF actuators yet (the dynamics here are those \
             of zero actuator force)",
            actuators.len()
        ));
    }
    Ok(Mjcf { model, option, layout, actuators, excludes, bodies })
}

/// A `<fixed>` tendon that exerts nothing (no limit, spring, damping, friction or armature; no
/// actuator may act on it, those are refused) is accepted with a warning; anything else is refused.
fn inert_tendon(t: &El, defaults: &Defaults, compiler: &Compiler, warnings: &mut Vec<String>) -> Result<(), MjcfError> {
    if t.tag != "fixed" {
        return Err(t.error(unsupported("spatial tendons")));
    }
    let class = t.attr("class").map(|a| a.value.clone()).unwrap_or_else(|| "main".into());
    if !defaults.has(&class) {
        return Err(t.attr_error("class", MjcfErrorKind::Invalid(format!("no default class '{class}'"))));
    }
    let mut v = View::new(t, Some((defaults, class)));
    // tendon defaults are stored under "tendon"; the element's tag is "fixed"
    v.set_default_tag("tendon");
    v.check_known(&[
        "name",
        "class",
        "group",
        "limited",
        "actuatorfrclimited",
        "range",
        "actuatorfrcrange",
        "solreflimit",
        "solimplimit",
        "solreffriction",
        "solimpfriction",
        "frictionloss",
        "springlength",
        "width",
        "material",
        "margin",
        "stiffness",
        "damping",
        "armature",
        "rgba",
        "user",
    ])?;
    let why = "a fixed tendon with a limit, spring, damping, friction or armature: tendons are not built yet";
    let limited = match v.keyword("limited", &["true", "false", "auto"])?.unwrap_or("auto") {
        "true" => true,
        "false" => false,
        _ => compiler.autolimits && v.get("range").is_some(),
    };
    if limited {
        return Err(v.err(if v.get("range").is_some() { "range" } else { "limited" }, unsupported(why)));
    }
    for attr in ["stiffness", "damping", "frictionloss", "armature"] {
        v.refuse_unless(attr, all_zero, why)?;
    }
    for j in &t.children {
        let jv = View::new(j, None);
        if j.tag != "joint" {
            return Err(j.error(MjcfErrorKind::Invalid(format!("unknown element <{}> in <fixed>", j.tag))));
        }
        jv.check_known(&["joint", "coef"])?;
    }
    warnings.push(format!(
        "{}:{}:{}: <fixed{}>: read and ignored: it has no limit, spring, damping or actuator, so it exerts no force",
        t.pos.file,
        t.pos.line,
        t.pos.column,
        t.attr("name").map(|a| format!(" name=\"{}\"", a.value)).unwrap_or_default()
    ));
    Ok(())
}

fn unsupported(why: &str) -> MjcfErrorKind {
    MjcfErrorKind::Unsupported(why.to_string())
}

fn vec3(v: &[f64]) -> DVec3 {
    DVec3::new(v[0], v[1], v[2])
}

fn read_compiler(root: &El, dir: &Path) -> Result<Compiler, MjcfError> {
    let mut c = Compiler::default();
    let (mut meshdir, mut assetdir) = (None, None);
    for el in root.children.iter().filter(|e| e.tag == "compiler") {
        let v = View::new(el, None);
        v.check_known(&[
            "autolimits",
            "boundmass",
            "boundinertia",
            "settotalmass",
            "balanceinertia",
            "strippath",
            "coordinate",
            "angle",
            "fitaabb",
            "eulerseq",
            "meshdir",
            "texturedir",
            "discardvisual",
            "usethread",
            "fusestatic",
            "inertiafromgeom",
            "inertiagrouprange",
            "saveinertial",
            "assetdir",
            "alignfree",
            "exactmeshinertia",
            "convexhull",
            "maxhullvert",
        ])?;
        if let Some(a) = v.keyword("angle", &["degree", "radian"])? {
            c.degree = a == "degree";
        }
        if let Some(s) = v.str("eulerseq") {
            let b = s.trim().as_bytes();
            if b.len() != 3 || !b.iter().all(|x| b"xyzXYZ".contains(x)) {
                return Err(v.err(
                    "eulerseq",
                    MjcfErrorKind::BadValue { value: s.into(), expected: "three of x y z X Y Z".into() },
                ));
            }
            c.eulerseq = [b[0], b[1], b[2]];
        }
        if let Some(b) = v.bool("autolimits")? {
            c.autolimits = b;
        }
        if let Some(k) = v.keyword("inertiafromgeom", &["true", "false", "auto"])? {
            c.inertia_from_geom = match k {
                "true" => Some(true),
                "false" => Some(false),
                _ => None,
            };
        }
        if let Some(r) = v.vec("inertiagrouprange", 2)? {
            c.inertia_groups = (r[0] as i64, r[1] as i64);
        }
        if v.get("settotalmass").is_some() {
            let m = v.f64("settotalmass", -1.0)?;
            c.total_mass = (m > 0.0).then_some(m);
        }
        v.refuse_unless("coordinate", |s| s == "local", "coordinate=\"global\" (MuJoCo itself no longer reads it)")?;
        v.refuse_unless("boundmass", all_zero, "boundmass: masses clamped from below")?;
        v.refuse_unless("boundinertia", all_zero, "boundinertia: inertias clamped from below")?;
        v.refuse_unless("balanceinertia", |s| s == "false", "balanceinertia")?;
        v.refuse_unless("discardvisual", |s| s == "false", "discardvisual")?;
        v.refuse_unless("alignfree", |s| s == "false", "alignfree: free joints aligned to the inertial frame")?;
        if let Some(d) = v.str("meshdir") {
            meshdir = Some(d.to_string());
        }
        if let Some(d) = v.str("assetdir") {
            assetdir = Some(d.to_string());
        }
    }
    c.meshdir = dir.join(meshdir.or(assetdir).unwrap_or_default());
    Ok(c)
}

impl<'a> Reader<'a> {
    fn view(&self, el: &'a El, childclass: Option<&str>) -> Result<View<'a>, MjcfError> {
        let class = match el.attr("class") {
            Some(a) => a.value.clone(),
            None => childclass.unwrap_or("main").to_string(),
        };
        if !self.defaults.has(&class) {
            return Err(el.attr_error("class", MjcfErrorKind::Invalid(format!("no default class '{class}'"))));
        }
        Ok(View::new(el, Some((self.defaults, class))))
    }

    /// One warning per soft-contact parameter name.
    fn soft(&mut self, v: &View) {
        for &name in SOFT {
            if let Some(a) = v.get(name) {
                let harmless = (name == "condim" && a.value.trim() == "3")
                    || (matches!(name, "margin" | "gap" | "priority") && all_zero(&a.value));
                if !harmless && !self.warned.iter().any(|w| w == name) {
                    self.warned.push(name.to_string());
                    self.warnings.push(format!(
                        "{}:{}:{}: <{} {}>: MuJoCo's soft-contact parameter is not used by tumble's contact model \
                         (reported once)",
                        a.pos.file, a.pos.line, a.pos.column, v.el.tag, name
                    ));
                }
            }
        }
    }

    fn option(&mut self, root: &'a El) -> Result<MjcfOption, MjcfError> {
        let mut o =
            MjcfOption { timestep: 0.002, gravity: DVec3::new(0.0, 0.0, -9.81), integrator: MjcfIntegrator::Euler };
        let mut gravity_on = true;
        for el in root.children.iter().filter(|e| e.tag == "option") {
            let v = View::new(el, None);
            v.check_known(&[
                "timestep",
                "apirate",
                "impratio",
                "tolerance",
                "ls_tolerance",
                "noslip_tolerance",
                "ccd_tolerance",
                "gravity",
                "wind",
                "magnetic",
                "density",
                "viscosity",
                "o_margin",
                "o_solref",
                "o_solimp",
                "o_friction",
                "integrator",
                "cone",
                "jacobian",
                "solver",
                "iterations",
                "ls_iterations",
                "noslip_iterations",
                "ccd_iterations",
                "sdf_iterations",
                "sdf_initpoints",
                "actuatorgroupdisable",
                "collision",
                "sleep_tolerance",
            ])?;
            o.timestep = v.f64("timestep", o.timestep)?;
            if !(o.timestep > 0.0) {
                return Err(v.err("timestep", MjcfErrorKind::Invalid("the time step must be > 0".into())));
            }
            if let Some(g) = v.vec("gravity", 3)? {
                o.gravity = vec3(&g);
            }
            if let Some(i) = v.keyword("integrator", &["Euler", "RK4", "implicit", "implicitfast"])? {
                o.integrator = match i {
                    "Euler" => MjcfIntegrator::Euler,
                    "RK4" => MjcfIntegrator::Rk4,
                    "implicit" => MjcfIntegrator::Implicit,
                    _ => MjcfIntegrator::ImplicitFast,
                };
            }
            v.refuse_unless("wind", all_zero, "wind: fluid forces are not modelled")?;
            v.refuse_unless("density", all_zero, "density of the medium: fluid forces are not modelled")?;
            v.refuse_unless("viscosity", all_zero, "viscosity of the medium: fluid forces are not modelled")?;
            v.refuse_unless("o_margin", all_zero, "o_margin: an override of contact margins")?;
            for child in &el.children {
                if child.tag != "flag" {
                    return Err(
                        child.error(MjcfErrorKind::Invalid(format!("unknown element <{}> in <option>", child.tag)))
                    );
                }
                let f = View::new(child, None);
                for a in &child.attrs {
                    let value = f.keyword(&a.name, &["enable", "disable"])?.unwrap_or("enable");
                    match a.name.as_str() {
                        "gravity" => gravity_on = value == "enable",
                        // numerics, diagnostics and actuators (not applied): no effect on the tree's dynamics here
                        "warmstart" | "energy" | "fwdinv" | "invdiscrete" | "sensor" | "midphase" | "nativeccd"
                        | "island" | "eulerdamp" | "autoreset" | "multiccd" | "refsafe" | "clampctrl" | "actuation"
                        | "filterparent" | "contact" | "equality" | "frictionloss" | "spring" | "damper"
                        | "passive" | "limit" | "constraint" | "override" | "sleep" => {
                            let default_on = !matches!(
                                a.name.as_str(),
                                "energy" | "fwdinv" | "invdiscrete" | "multiccd" | "override" | "island" | "sleep"
                            );
                            let changes = matches!(
                                a.name.as_str(),
                                "filterparent"
                                    | "contact"
                                    | "spring"
                                    | "damper"
                                    | "passive"
                                    | "limit"
                                    | "constraint"
                                    | "override"
                            );
                            if changes && (value == "enable") != default_on {
                                return Err(f.err(&a.name, unsupported("a <flag> that changes the dynamics")));
                            }
                        }
                        _ => return Err(f.err(&a.name, MjcfErrorKind::Invalid(format!("unknown flag '{}'", a.name)))),
                    }
                }
            }
        }
        if !gravity_on {
            o.gravity = DVec3::ZERO;
        }
        Ok(o)
    }

    fn assets(&mut self, asset: &'a El) -> Result<(), MjcfError> {
        for el in &asset.children {
            match el.tag.as_str() {
                "texture" | "material" | "skin" => {}
                "hfield" => {
                    if let Some(n) = el.attr("name") {
                        self.hfields.insert(n.value.clone());
                    }
                }
                "mesh" => {
                    let v = self.view(el, None)?;
                    v.check_known(&[
                        "name",
                        "class",
                        "content_type",
                        "file",
                        "vertex",
                        "normal",
                        "texcoord",
                        "face",
                        "refpos",
                        "refquat",
                        "scale",
                        "smoothnormal",
                        "maxhullvert",
                        "inertia",
                        "builtin",
                        "params",
                        "material",
                    ])?;
                    for attr in ["vertex", "face", "builtin"] {
                        if v.get(attr).is_some() {
                            return Err(v.err(attr, unsupported("meshes given in the XML: only mesh files are read")));
                        }
                    }
                    v.refuse_unless("refpos", all_zero, "refpos (deprecated)")?;
                    v.refuse_unless(
                        "refquat",
                        |s| s.split_whitespace().collect::<Vec<_>>() == ["1", "0", "0", "0"],
                        "refquat (deprecated)",
                    )?;
                    let Some(file) = v.str("file") else {
                        return Err(el.error(MjcfErrorKind::MissingAttribute("file")));
                    };
                    let scale = v.vec("scale", 3)?.map(|s| vec3(&s)).unwrap_or(DVec3::ONE);
                    let name = match v.str("name") {
                        Some(n) => n.to_string(),
                        // MuJoCo names an unnamed mesh after its file, without directory and extension
                        None => {
                            Path::new(file).file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_default()
                        }
                    };
                    let path = self.compiler.meshdir.join(file);
                    self.meshes.insert(name, (file.to_string(), path, scale));
                }
                "model" => return Err(el.error(unsupported("<model> assets (attached sub-models)"))),
                other => return Err(el.error(MjcfErrorKind::Invalid(format!("unknown element <{other}> in <asset>")))),
            }
        }
        Ok(())
    }

    /// The children of a body (or the world, `body = None`), inside `frame` (their placement in the
    /// body frame), with the enclosing `childclass`.
    fn children(
        &mut self,
        el: &'a El,
        body: Option<usize>,
        frame: Pose,
        childclass: Option<&str>,
    ) -> Result<(), MjcfError> {
        for child in &el.children {
            match child.tag.as_str() {
                "body" => self.body(child, body, frame, childclass)?,
                "frame" => {
                    let v = View::new(child, None);
                    v.check_known(&["name", "childclass", "pos", "quat", "axisangle", "euler", "xyaxes", "zaxis"])?;
                    let p = frame.then(&pose(&v, &self.compiler)?);
                    let cc = child.attr("childclass").map(|a| a.value.clone());
                    self.children(child, body, p, cc.as_deref().or(childclass))?;
                }
                "geom" => {
                    let g = self.geom(child, childclass, frame)?;
                    if let Some(g) = g {
                        match body {
                            Some(b) => self.bodies[b].geoms.push(g),
                            None => self.world_geom(g),
                        }
                    }
                }
                "inertial" | "joint" | "freejoint" if body.is_some() && el.tag == "body" => {}
                t if VISUAL.contains(&t) => {}
                "composite" | "flexcomp" => return Err(child.error(unsupported("composites and flex objects"))),
                "plugin" => return Err(child.error(unsupported("plugins"))),
                "attach" | "replicate" => return Err(child.error(unsupported("<attach> and <replicate>"))),
                "joint" | "freejoint" | "inertial" => {
                    return Err(
                        child.error(MjcfErrorKind::Invalid(format!("<{}> must be a child of a <body>", child.tag)))
                    )
                }
                other => {
                    return Err(
                        child.error(MjcfErrorKind::Invalid(format!("unknown element <{other}> in <{}>", el.tag)))
                    )
                }
            }
        }
        Ok(())
    }

    fn world_geom(&mut self, g: GeomRec<'a>) {
        self.world_geoms.push(g);
    }

    fn body(
        &mut self,
        el: &'a El,
        parent: Option<usize>,
        frame: Pose,
        childclass: Option<&str>,
    ) -> Result<(), MjcfError> {
        let v = View::new(el, None);
        v.check_known(&[
            "name",
            "childclass",
            "pos",
            "quat",
            "axisangle",
            "euler",
            "xyaxes",
            "zaxis",
            "mocap",
            "gravcomp",
            "user",
        ])?;
        v.refuse_unless("mocap", |s| s == "false", "mocap bodies")?;
        v.refuse_unless("gravcomp", all_zero, "gravity compensation (gravcomp)")?;
        let index = self.bodies.len();
        let id = index as u32 + 1;
        let name = match el.attr("name") {
            Some(a) => a.value.clone(),
            None => format!("body{id}"),
        };
        if let Some(first) = self.body_names.insert(name.clone(), el.pos.line) {
            return Err(el.attr_error(
                "name",
                MjcfErrorKind::Invalid(format!("repeated body name '{name}' (first at line {first})")),
            ));
        }
        let in_parent = frame.then(&pose(&v, &self.compiler)?);
        let cc_own = el.attr("childclass").map(|a| a.value.clone());
        let cc = cc_own.as_deref().or(childclass).map(str::to_string);
        if let Some(c) = &cc {
            if !self.defaults.has(c) {
                return Err(el.attr_error("childclass", MjcfErrorKind::Invalid(format!("no default class '{c}'"))));
            }
        }
        self.bodies.push(BodyRec {
            name,
            parent,
            in_parent,
            joints: Vec::new(),
            inertia: RigidInertia::ZERO,
            geoms: Vec::new(),
        });
        // joints in order, the explicit inertial
        let mut inertial = None;
        for child in &el.children {
            match child.tag.as_str() {
                "joint" => {
                    let j = self.joint(child, cc.as_deref())?;
                    self.bodies[index].joints.push(j);
                }
                "freejoint" => {
                    let fv = View::new(child, None);
                    fv.check_known(&["name", "group", "align"])?;
                    fv.refuse_unless(
                        "align",
                        |s| s == "false" || s == "auto",
                        "align: a free joint aligned to the inertial frame",
                    )?;
                    let j = JointRec {
                        el: child,
                        name: self.joint_name(child)?,
                        kind: Kind::Free,
                        anchor: DVec3::ZERO,
                        axis: DVec3::Z,
                        reference: 0.0,
                        range: None,
                        dynamics: JointDynamics::default(),
                        springref: 0.0,
                    };
                    self.bodies[index].joints.push(j);
                }
                "inertial" => {
                    if inertial.is_some() {
                        return Err(child.error(MjcfErrorKind::Invalid("a second <inertial>".into())));
                    }
                    inertial = Some(self.inertial(child)?);
                }
                _ => {}
            }
        }
        self.children(el, Some(index), Pose::IDENTITY, cc.as_deref())?;
        // free joints: alone in a body that hangs from the world
        let joints = &self.bodies[index].joints;
        if let Some(f) = joints.iter().find(|j| j.kind == Kind::Free) {
            if joints.len() > 1 {
                return Err(f
                    .el
                    .error(MjcfErrorKind::Invalid("a free joint must be the only joint of its body".into())));
            }
            if parent.is_some() {
                return Err(f.el.error(unsupported("a free joint in a body that is not a child of the world")));
            }
        }
        // the body's inertia: <inertial>, or from its geoms
        let from_geoms = match self.compiler.inertia_from_geom {
            Some(b) => b,
            None => inertial.is_none(),
        };
        self.bodies[index].inertia =
            if from_geoms { self.inertia_from_geoms(index)? } else { inertial.unwrap_or(RigidInertia::ZERO) };
        Ok(())
    }

    fn joint_name(&mut self, el: &El) -> Result<String, MjcfError> {
        let id = self.joint_names.len();
        let name = match el.attr("name") {
            Some(a) => a.value.clone(),
            None => format!("joint{id}"),
        };
        if let Some(first) = self.joint_names.insert(name.clone(), el.pos.line) {
            return Err(el.attr_error(
                "name",
                MjcfErrorKind::Invalid(format!("repeated joint name '{name}' (first at line {first})")),
            ));
        }
        Ok(name)
    }

    fn joint(&mut self, el: &'a El, childclass: Option<&str>) -> Result<JointRec<'a>, MjcfError> {
        let v = self.view(el, childclass)?;
        v.check_known(&[
            "name",
            "class",
            "type",
            "group",
            "pos",
            "axis",
            "springdamper",
            "limited",
            "actuatorfrclimited",
            "solreflimit",
            "solimplimit",
            "solreffriction",
            "solimpfriction",
            "stiffness",
            "range",
            "actuatorfrcrange",
            "actuatorgravcomp",
            "margin",
            "ref",
            "springref",
            "armature",
            "damping",
            "frictionloss",
            "user",
        ])?;
        self.soft(&v);
        let kind = match v.keyword("type", &["hinge", "slide", "ball", "free"])?.unwrap_or("hinge") {
            "hinge" => Kind::Hinge,
            "slide" => Kind::Slide,
            "ball" => Kind::Ball,
            _ => Kind::Free,
        };
        if !self.options.drop_frictionloss {
            v.refuse_unless(
                "frictionloss",
                all_zero,
                "frictionloss: dry joint friction is a constraint not built yet; `drop_frictionloss` reads the model \
                 without it",
            )?;
        } else if let Some(a) = v.get("frictionloss").filter(|a| !all_zero(&a.value)) {
            self.warnings.push(format!(
                "{}:{}:{}: <joint frictionloss>: joint '{}': frictionloss {} dropped (drop_frictionloss)",
                el.pos.file,
                el.pos.line,
                el.pos.column,
                el.attr("name").map(|a| a.value.as_str()).unwrap_or(""),
                a.value.trim()
            ));
        }
        v.refuse_unless("springdamper", all_zero, "springdamper")?;
        v.refuse_unless("actuatorgravcomp", |s| s == "false", "actuatorgravcomp")?;
        let name = self.joint_name(el)?;
        let anchor = v.vec("pos", 3)?.map(|p| vec3(&p)).unwrap_or(DVec3::ZERO);
        let axis = v.vec("axis", 3)?.map(|p| vec3(&p)).unwrap_or(DVec3::Z);
        let n = axis.length();
        if !(n > 1e-10) {
            return Err(v.err("axis", MjcfErrorKind::Invalid("a zero axis".into())));
        }
        let angular = kind == Kind::Hinge;
        let deg = |x: f64| if angular && self.compiler.degree { x.to_radians() } else { x };
        let reference = deg(v.f64("ref", 0.0)?);
        let springref = deg(v.f64("springref", 0.0)?);
        let range = v.vec("range", 2)?;
        let limited = match v.keyword("limited", &["true", "false", "auto"])?.unwrap_or("auto") {
            "true" => true,
            "false" => false,
            _ => self.compiler.autolimits && range.is_some(),
        };
        let range = match (limited, range) {
            (false, _) => None,
            (true, None) => {
                return Err(v.err("limited", MjcfErrorKind::Invalid("a limited joint needs a range".into())))
            }
            (true, Some(r)) => {
                let scale = |x: f64| if kind == Kind::Ball && self.compiler.degree { x.to_radians() } else { deg(x) };
                let (lo, hi) = (scale(r[0]), scale(r[1]));
                if lo > hi {
                    return Err(v.err("range", MjcfErrorKind::Invalid(format!("lower {} > upper {}", r[0], r[1]))));
                }
                Some((lo, hi))
            }
        };
        if range.is_some() && matches!(kind, Kind::Ball | Kind::Free) {
            return Err(v.err("range", unsupported("limits of ball and free joints")));
        }
        let dynamics = JointDynamics {
            armature: v.nonneg("armature", 0.0)?,
            damping: v.nonneg("damping", 0.0)?,
            stiffness: v.nonneg("stiffness", 0.0)?,
            spring_ref: 0.0,
        };
        if dynamics.stiffness != 0.0 && matches!(kind, Kind::Ball | Kind::Free) {
            return Err(v.err("stiffness", unsupported("springs on ball and free joints")));
        }
        Ok(JointRec { el, name, kind, anchor, axis: axis / n, reference, range, dynamics, springref })
    }

    fn inertial(&mut self, el: &'a El) -> Result<RigidInertia, MjcfError> {
        let v = View::new(el, None);
        v.check_known(&["pos", "quat", "axisangle", "euler", "xyaxes", "zaxis", "mass", "diaginertia", "fullinertia"])?;
        let Some(pos) = v.vec("pos", 3)? else { return Err(el.error(MjcfErrorKind::MissingAttribute("pos"))) };
        let Some(mass) = v.vec("mass", 1)? else { return Err(el.error(MjcfErrorKind::MissingAttribute("mass"))) };
        let mass = mass[0];
        if mass < 0.0 {
            return Err(v.err("mass", MjcfErrorKind::Invalid("a negative mass".into())));
        }
        let rot = orientation(&v, &self.compiler)?.unwrap_or_default();
        let tensor = match (v.vec("diaginertia", 3)?, v.vec("fullinertia", 6)?) {
            (Some(d), None) => DMat3::from_diagonal(vec3(&d)),
            (None, Some(f)) => {
                if ORIENTATIONS.iter().any(|o| v.get(o).is_some()) {
                    return Err(v.err("fullinertia", MjcfErrorKind::Invalid("fullinertia with an orientation".into())));
                }
                // ixx iyy izz ixy ixz iyz
                DMat3::from_cols(
                    DVec3::new(f[0], f[3], f[4]),
                    DVec3::new(f[3], f[1], f[5]),
                    DVec3::new(f[4], f[5], f[2]),
                )
            }
            (None, None) => return Err(el.error(MjcfErrorKind::MissingAttribute("diaginertia"))),
            (Some(_), Some(_)) => {
                return Err(v.err("fullinertia", MjcfErrorKind::Invalid("both diaginertia and fullinertia".into())))
            }
        };
        if let Some(defect) = crate::multibody::balance::inertia_defect(mass, tensor) {
            // MuJoCo refuses these too
            return Err(el.error(MjcfErrorKind::Invalid(format!("the inertia is not physical: {defect}"))));
        }
        Ok(placed_inertia(mass, vec3(&pos), DMat3::from_quat(rot), tensor))
    }

    fn geom(&mut self, el: &'a El, childclass: Option<&str>, frame: Pose) -> Result<Option<GeomRec<'a>>, MjcfError> {
        let v = self.view(el, childclass)?;
        v.check_known(&[
            "name",
            "class",
            "type",
            "contype",
            "conaffinity",
            "condim",
            "group",
            "priority",
            "size",
            "material",
            "rgba",
            "friction",
            "mass",
            "density",
            "shellinertia",
            "solmix",
            "solref",
            "solimp",
            "margin",
            "gap",
            "fromto",
            "pos",
            "quat",
            "axisangle",
            "euler",
            "xyaxes",
            "zaxis",
            "hfield",
            "mesh",
            "fitscale",
            "fluidshape",
            "fluidcoef",
            "user",
        ])?;
        self.soft(&v);
        v.refuse_unless("shellinertia", |s| s == "false", "shellinertia: the inertia of a shell")?;
        v.refuse_unless("fluidshape", |s| s == "none", "fluidshape: fluid forces are not modelled")?;
        let ty = v
            .keyword("type", &["plane", "hfield", "sphere", "capsule", "ellipsoid", "cylinder", "box", "mesh", "sdf"])?
            .unwrap_or(if v.get("mesh").is_some() { "mesh" } else { "sphere" });
        match ty {
            "hfield" => return Err(v.err("type", unsupported("heightfields"))),
            "sdf" => return Err(v.err("type", unsupported("signed-distance-field geoms"))),
            _ => {}
        }
        if ty != "mesh" && v.get("mesh").is_some() {
            return Err(v.err("mesh", unsupported("a primitive fitted to a mesh")));
        }
        let size = v.numbers("size")?.unwrap_or_default();
        if size.len() > 3 {
            return Err(v.err(
                "size",
                MjcfErrorKind::BadValue {
                    value: v.str("size").unwrap_or("").into(),
                    expected: "at most 3 numbers".into(),
                },
            ));
        }
        let s = |k: usize| size.get(k).copied().unwrap_or(0.0);
        let mut in_frame = pose(&v, &self.compiler)?;
        let mut half_length = None;
        if let Some(ft) = v.vec("fromto", 6)? {
            if !matches!(ty, "capsule" | "cylinder" | "box" | "ellipsoid") {
                return Err(v.err("fromto", MjcfErrorKind::Invalid(format!("fromto on a {ty}"))));
            }
            let (a, b) = (vec3(&ft[..3]), vec3(&ft[3..]));
            let d = b - a;
            let len = d.length();
            if !(len > 1e-10) {
                return Err(v.err("fromto", MjcfErrorKind::Invalid("its two points coincide".into())));
            }
            in_frame = Pose { rot: z_to_quat(d / len), pos: 0.5 * (a + b) };
            half_length = Some(0.5 * len);
        }
        let positive = |k: usize, what: &str| -> Result<f64, MjcfError> {
            let x = s(k);
            if x > 0.0 {
                Ok(x)
            } else {
                Err(v.err("size", MjcfErrorKind::Invalid(format!("{what} must be > 0 (size[{k}] = {x})"))))
            }
        };
        let shape = match ty {
            "plane" => GeometryShape::Plane,
            "sphere" => GeometryShape::Sphere { radius: positive(0, "the radius")? },
            "capsule" => GeometryShape::Capsule {
                radius: positive(0, "the radius")?,
                half_length: match half_length {
                    Some(h) => h,
                    None => positive(1, "the half length")?,
                },
            },
            "cylinder" => GeometryShape::Cylinder {
                radius: positive(0, "the radius")?,
                half_length: match half_length {
                    Some(h) => h,
                    None => positive(1, "the half length")?,
                },
            },
            "box" | "ellipsoid" => {
                let z = match half_length {
                    Some(h) => h,
                    None => positive(2, "the third half size")?,
                };
                let e = DVec3::new(positive(0, "the first half size")?, positive(1, "the second half size")?, z);
                if ty == "box" {
                    GeometryShape::Box { half_extents: e }
                } else {
                    GeometryShape::Ellipsoid { radii: e }
                }
            }
            _ => {
                let Some(name) = v.str("mesh") else { return Err(el.error(MjcfErrorKind::MissingAttribute("mesh"))) };
                let Some((file, path, scale)) = self.meshes.get(name) else {
                    return Err(v.err("mesh", MjcfErrorKind::Invalid(format!("no mesh asset named '{name}'"))));
                };
                GeometryShape::Mesh { uri: file.clone(), path: Some(path.clone()), scale: *scale }
            }
        };
        let contype = v.int("contype", 1)?;
        let conaffinity = v.int("conaffinity", 1)?;
        if !(0..=u32::MAX as i64).contains(&contype) || !(0..=u32::MAX as i64).contains(&conaffinity) {
            return Err(v.err("contype", MjcfErrorKind::Invalid("contype and conaffinity are 32-bit masks".into())));
        }
        let friction = v.numbers("friction")?.and_then(|f| f.first().copied());
        let group = v.int("group", 0)?;
        let in_body = frame.then(&in_frame);
        let (lo, hi) = self.compiler.inertia_groups;
        let counts = (lo..=hi).contains(&group) && !matches!(shape, GeometryShape::Plane);
        let mass = v.vec("mass", 1)?.map(|m| m[0]);
        let density = v.f64("density", 1000.0)?;
        let rec = GeomRec {
            el,
            counts,
            mass,
            density,
            shape,
            in_body,
            contype: contype as u32,
            conaffinity: conaffinity as u32,
            friction,
            line: el.pos.line,
        };
        Ok(Some(rec))
    }
}

impl<'a> Reader<'a> {
    /// MuJoCo's inertia from geoms: each counted geom's mass (`mass`, or `density` × volume) and
    /// principal moments about its centre (`GeometryShape::unit_mass_properties`) placed in the body
    /// frame and summed (the parallel-axis rule is `RigidInertia`'s addition).
    fn inertia_from_geoms(&self, index: usize) -> Result<RigidInertia, MjcfError> {
        let mut total = RigidInertia::ZERO;
        for g in self.bodies[index].geoms.iter().filter(|g| g.counts) {
            let Some((volume, unit)) = g.shape.unit_mass_properties() else {
                return Err(g.el.error(unsupported(
                    "the inertia of a mesh geom (give its body an <inertial>, or put the mesh in a group outside \
                     inertiagrouprange)",
                )));
            };
            let mass = match g.mass {
                Some(m) => m,
                None => g.density * volume,
            };
            if !(mass >= 0.0 && mass.is_finite()) {
                return Err(g.el.error(MjcfErrorKind::Invalid(format!("a geom mass of {mass}"))));
            }
            total +=
                placed_inertia(mass, g.in_body.pos, DMat3::from_quat(g.in_body.rot), DMat3::from_diagonal(mass * unit));
        }
        Ok(total)
    }

    /// `<contact>`: `<exclude>` pairs recorded; `<pair>` refused.
    fn contact(&self, root: &'a El) -> Result<Vec<(String, String)>, MjcfError> {
        let mut out = Vec::new();
        for el in root.children.iter().filter(|e| e.tag == "contact") {
            for c in &el.children {
                match c.tag.as_str() {
                    "exclude" => {
                        let v = View::new(c, None);
                        v.check_known(&["name", "body1", "body2"])?;
                        let body = |k: &'static str| -> Result<String, MjcfError> {
                            let n = v.str(k).ok_or_else(|| c.error(MjcfErrorKind::MissingAttribute(k)))?;
                            if !self.body_names.contains_key(n) && n != "world" {
                                return Err(v.err(k, MjcfErrorKind::Invalid(format!("no body named '{n}'"))));
                            }
                            Ok(n.to_string())
                        };
                        out.push((body("body1")?, body("body2")?));
                    }
                    "pair" => return Err(c.error(unsupported("explicit contact pairs"))),
                    other => {
                        return Err(c.error(MjcfErrorKind::Invalid(format!("unknown element <{other}> in <contact>"))))
                    }
                }
            }
        }
        Ok(out)
    }

    /// `<compiler settotalmass>`: every body's mass and inertia scaled by the same factor.
    fn scale_total_mass(&mut self, root: &El) -> Result<(), MjcfError> {
        let Some(target) = self.compiler.total_mass else { return Ok(()) };
        let total: f64 = self.bodies.iter().map(|b| b.inertia.mass).sum();
        if !(total > 0.0) {
            return Err(root.error(MjcfErrorKind::Invalid("settotalmass on a model without mass".into())));
        }
        let k = target / total;
        for b in &mut self.bodies {
            b.inertia = RigidInertia { mass: k * b.inertia.mass, h: k * b.inertia.h, i_o: k * b.inertia.i_o };
        }
        Ok(())
    }

    /// The tree handed to the builder: per MJCF body one tumble body per joint, the geometry and
    /// the frames; the layout of MuJoCo's coordinates; where each MJCF body sits.
    fn assemble(
        &mut self,
        name: &str,
        root: &El,
        gravity: DVec3,
    ) -> Result<(crate::multibody::MultibodyModel, MujocoLayout, Vec<MjcfBody>), MjcfError> {
        let mut builder = ModelBuilder::new(name);
        builder.add_frame("world", None, Xform::IDENTITY, FrameOrigin::Root, RigidInertia::ZERO);
        let mut placed: Vec<MjcfBody> =
            vec![MjcfBody { name: "world".into(), body: None, pose_in_body: Pose::IDENTITY }];
        let mut layout = Vec::new();
        for b in &self.bodies {
            let parent = match b.parent {
                Some(p) => &placed[p + 1],
                None => &placed[0],
            };
            // the body frame in the parent's tumble body: parent frame ∘ in_parent
            let frame_in_parent = parent.pose_in_body.then(&b.in_parent);
            let (body, pose_in_body) = if b.joints.is_empty() {
                let origin =
                    FrameOrigin::Fixed { joint: format!("{}(weld)", b.name), parent_link: parent.name.clone() };
                // link_X_body of the welded body; its inertia moves with it
                builder.add_fixed_link(&b.name, parent.body, frame_in_parent.xform(), origin, b.inertia);
                (parent.body, frame_in_parent)
            } else {
                let mut tumble_parent = parent.body;
                // the joint frame of the previous joint in this body, in the body frame
                let previous = frame_in_parent;
                let mut last_anchor = DVec3::ZERO;
                let n = b.joints.len();
                for (k, j) in b.joints.iter().enumerate() {
                    let last = k + 1 == n;
                    // X_T: the joint frame (at the anchor, body axes) in the previous tumble body
                    let x_tree = match j.kind {
                        Kind::Free => Pose::IDENTITY,
                        _ if k == 0 => previous.then(&Pose::translation(j.anchor)),
                        _ => Pose::translation(j.anchor - last_anchor),
                    };
                    let kind = match j.kind {
                        Kind::Hinge if j.range.is_some() => JointKind::Revolute { axis: j.axis },
                        Kind::Hinge => JointKind::Continuous { axis: j.axis },
                        Kind::Slide => JointKind::Prismatic { axis: j.axis },
                        Kind::Ball => JointKind::Spherical,
                        Kind::Free => JointKind::Floating,
                    };
                    // the mass sits on the last joint's body, in its frame: the body frame is at −anchor
                    let inertia = if last {
                        b.inertia.transform_to_a(&Pose::translation(-j.anchor).xform())
                    } else {
                        RigidInertia::ZERO
                    };
                    let body_name = if last { b.name.clone() } else { format!("{}/{}", b.name, j.name) };
                    let i = builder
                        .add_body(body_name, tumble_parent, &j.name, kind, x_tree.xform(), inertia)
                        .map_err(|e| j.el.error(MjcfErrorKind::Model(e)))?;
                    builder.set_parent_link(i, &parent.name);
                    let mut limits = JointLimits::default();
                    limits.position = j.range.map(|(lo, hi)| (lo - j.reference, hi - j.reference));
                    builder.set_limits(i, limits);
                    let dynamics = JointDynamics { spring_ref: j.springref - j.reference, ..j.dynamics };
                    builder.set_dynamics(i, dynamics).map_err(|e| j.el.error(MjcfErrorKind::Model(e)))?;
                    layout.push(LayoutJoint {
                        name: j.name.clone(),
                        free: j.kind == Kind::Free,
                        reference: if matches!(j.kind, Kind::Hinge | Kind::Slide) { j.reference } else { 0.0 },
                        free_pose0: (j.kind == Kind::Free).then_some(frame_in_parent),
                    });
                    tumble_parent = Some(i);
                    last_anchor = if j.kind == Kind::Free { DVec3::ZERO } else { j.anchor };
                }
                let i = tumble_parent.expect("a body with joints");
                let pose_in_body = Pose::translation(-last_anchor);
                builder.place_body_frame(i, pose_in_body.xform());
                (Some(i), pose_in_body)
            };
            placed.push(MjcfBody { name: b.name.clone(), body, pose_in_body });
        }
        // geometry: each geom in its body's frame (the link is the MJCF body's frame)
        let world_geoms = std::mem::take(&mut self.world_geoms);
        let link_geoms = world_geoms
            .iter()
            .map(|g| ("world".to_string(), g))
            .chain(self.bodies.iter().flat_map(|b| b.geoms.iter().map(move |g| (b.name.clone(), g))));
        for (link, g) in link_geoms {
            let role = if g.contype | g.conaffinity != 0 { GeometryRole::Collision } else { GeometryRole::Visual };
            builder.add_geometry(LinkGeometry {
                link,
                role,
                x_from_link: g.in_body.xform(),
                shape: g.shape.clone(),
                line: g.line,
                contype: g.contype,
                conaffinity: g.conaffinity,
                friction: g.friction,
            });
        }
        for w in self.warnings.drain(..) {
            builder.warn(w);
        }
        let mut model = builder.build().map_err(|e| {
            let at = match &e {
                crate::multibody::ModelError::MasslessSubtree { joint, .. } => self
                    .bodies
                    .iter()
                    .flat_map(|b| b.joints.iter())
                    .find(|j| &j.name == joint)
                    .map(|j| j.el)
                    .unwrap_or(root),
                _ => root,
            };
            at.error(MjcfErrorKind::Model(e))
        })?;
        model.gravity = gravity;
        let layout = MujocoLayout::new(&model, layout);
        Ok((model, layout, placed))
    }
}

/// `<actuator>`: `motor`, `position`, `velocity` and `general` on joints, recorded.
fn reader_actuators(
    reader: &Reader,
    root: &El,
    model: &crate::multibody::MultibodyModel,
) -> Result<Vec<MjcfActuator>, MjcfError> {
    let mut out = Vec::new();
    for el in root.children.iter().filter(|e| e.tag == "actuator") {
        for a in &el.children {
            let kind = a.tag.as_str();
            if !matches!(kind, "motor" | "position" | "velocity" | "general") {
                return Err(a.error(unsupported(&format!(
                    "<{kind}> actuators (motor, position, velocity and general are read)"
                ))));
            }
            let v = reader.view(a, None)?;
            v.check_known(&[
                "name",
                "class",
                "group",
                "ctrllimited",
                "forcelimited",
                "actlimited",
                "ctrlrange",
                "forcerange",
                "actrange",
                "lengthrange",
                "gear",
                "cranklength",
                "joint",
                "jointinparent",
                "tendon",
                "cranksite",
                "site",
                "refsite",
                "body",
                "dyntype",
                "gaintype",
                "biastype",
                "dynprm",
                "gainprm",
                "biasprm",
                "actearly",
                "actdim",
                "user",
                "kp",
                "kv",
                "dampratio",
                "timeconst",
                "inheritrange",
                "nsample",
                "interp",
                "delay",
            ])?;
            for t in ["tendon", "site", "body", "jointinparent", "cranksite"] {
                if v.get(t).is_some() {
                    return Err(v.err(t, unsupported("actuators on anything but a joint")));
                }
            }
            let Some(joint) = v.str("joint") else { return Err(a.error(MjcfErrorKind::MissingAttribute("joint"))) };
            if model.joint_index(joint).is_none() {
                return Err(v.err("joint", MjcfErrorKind::Invalid(format!("no joint named '{joint}'"))));
            }
            v.refuse_unless("dyntype", |s| s == "none", "actuator activation dynamics")?;
            v.refuse_unless("gaintype", |s| s == "fixed", "a gain that is not fixed")?;
            v.refuse_unless("biastype", |s| s == "none" || s == "affine", "a bias that is not affine")?;
            v.refuse_unless("dampratio", all_zero, "dampratio")?;
            v.refuse_unless("timeconst", all_zero, "timeconst: activation dynamics")?;
            v.refuse_unless("inheritrange", all_zero, "inheritrange")?;
            let gear = v.numbers("gear")?.unwrap_or_else(|| vec![1.0]);
            if gear.iter().skip(1).any(|&g| g != 0.0) {
                return Err(v.err("gear", unsupported("a gear with more than one component on a joint")));
            }
            let (gain, bias) = match kind {
                "motor" => (1.0, [0.0; 3]),
                "position" => {
                    let (kp, kv) = (v.f64("kp", 1.0)?, v.f64("kv", 0.0)?);
                    (kp, [0.0, -kp, -kv])
                }
                "velocity" => {
                    let kv = v.f64("kv", 1.0)?;
                    (kv, [0.0, 0.0, -kv])
                }
                _ => {
                    let g = v.numbers("gainprm")?.unwrap_or_else(|| vec![1.0]);
                    let b = v.numbers("biasprm")?.unwrap_or_default();
                    let affine = v.str("biastype") == Some("affine");
                    let bb = |k: usize| if affine { b.get(k).copied().unwrap_or(0.0) } else { 0.0 };
                    (g.first().copied().unwrap_or(1.0), [bb(0), bb(1), bb(2)])
                }
            };
            let limited = |flag: &str, range: &str| -> Result<Option<(f64, f64)>, MjcfError> {
                let r = v.vec(range, 2)?;
                let on = match v.keyword(flag, &["true", "false", "auto"])?.unwrap_or("auto") {
                    "true" => true,
                    "false" => false,
                    _ => reader.compiler.autolimits && r.is_some(),
                };
                Ok(if on { r.map(|r| (r[0], r[1])) } else { None })
            };
            out.push(MjcfActuator {
                name: v.str("name").map(str::to_string).unwrap_or_else(|| format!("actuator{}", out.len())),
                kind: kind.to_string(),
                joint: joint.to_string(),
                gear: gear.first().copied().unwrap_or(1.0),
                gain,
                bias,
                ctrl_range: limited("ctrllimited", "ctrlrange")?,
                force_range: limited("forcelimited", "forcerange")?,
            });
        }
    }
    Ok(out)
}
