//! The walk over an MJCF document: what is refused up front, the compiler, options and assets;
//! then the body tree ([`super::tree`]) and its assembly on the builder ([`super::assemble`]).

use super::attrs::{all_zero, View};
use super::defaults::Defaults;
use super::pose::Pose;
use super::xml::El;
use super::{Compiler, LeaveOut, Mjcf, MjcfError, MjcfErrorKind, MjcfIntegrator, MjcfOption, MjcfOptions};
use crate::math::{DQuat, DVec3};
use crate::multibody::fluid::Medium;
use crate::multibody::joint::JointDynamics;
use crate::multibody::model::GeometryShape;
use crate::multibody::spatial::RigidInertia;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

/// The soft-contact and solver parameters that tumble's contact model does not use: reported once each.
pub(super) const SOFT: &[&str] = &[
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
pub(super) const VISUAL: &[&str] = &["site", "camera", "light"];

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Kind {
    Hinge,
    Slide,
    Ball,
    Free,
}

pub(super) struct JointRec<'a> {
    pub(super) el: &'a El,
    pub(super) name: String,
    pub(super) kind: Kind,
    /// Anchor in the body frame (m).
    pub(super) anchor: DVec3,
    /// Unit axis in the body frame.
    pub(super) axis: DVec3,
    /// MuJoCo's `ref` (rad or m): `q = qpos − ref`.
    pub(super) reference: f64,
    /// Limits in MuJoCo's `qpos` (rad or m).
    pub(super) range: Option<(f64, f64)>,
    pub(super) dynamics: JointDynamics,
    /// `springref` in MuJoCo's `qpos`.
    pub(super) springref: f64,
}

pub(super) struct BodyRec<'a> {
    pub(super) name: String,
    /// Index of the parent in the list (`None`: the world).
    pub(super) parent: Option<usize>,
    /// The body frame in the parent body's frame.
    pub(super) in_parent: Pose,
    pub(super) joints: Vec<JointRec<'a>>,
    /// Spatial inertia in the body frame.
    pub(super) inertia: RigidInertia,
    /// MuJoCo's principal axes of that inertia (`body_from_inertial`), where MuJoCo takes them as
    /// given (`diaginertia`, a single primitive geom); `None`: from an eigen-solver.
    pub(super) principal_rot: Option<DQuat>,
    pub(super) geoms: Vec<GeomRec<'a>>,
}

pub(super) struct GeomRec<'a> {
    pub(super) el: &'a El,
    /// Counted in the body's inertia (its group is in `inertiagrouprange`).
    pub(super) counts: bool,
    /// `mass` if given, else `density` times the volume.
    pub(super) mass: Option<f64>,
    pub(super) density: f64,
    /// A mesh geom's `inertia` mode (`legacy`, `exact`, …).
    pub(super) mesh_inertia: Option<String>,
    pub(super) shape: GeometryShape,
    /// The geom frame in the body frame.
    pub(super) in_body: Pose,
    pub(super) contype: u32,
    pub(super) conaffinity: u32,
    pub(super) friction: Option<f64>,
    pub(super) line: u32,
}

pub(super) struct Reader<'a> {
    pub(super) defaults: &'a Defaults,
    pub(super) compiler: Compiler,
    /// mesh asset name → (file as written, resolved path, scale, `inertia` mode)
    pub(super) meshes: HashMap<String, (String, PathBuf, DVec3, String)>,
    pub(super) hfields: HashSet<String>,
    pub(super) bodies: Vec<BodyRec<'a>>,
    pub(super) world_geoms: Vec<GeomRec<'a>>,
    pub(super) options: MjcfOptions,
    pub(super) warned: Vec<String>,
    pub(super) warnings: Vec<String>,
    pub(super) joint_names: HashMap<String, u32>,
    pub(super) body_names: HashMap<String, u32>,
}

pub(super) fn build(root: &El, dir: &Path, options: MjcfOptions) -> Result<Mjcf, MjcfError> {
    build_leaving_out(root, dir, options, &LeaveOut::default())
}

pub(super) fn build_leaving_out(
    root: &El,
    dir: &Path,
    options: MjcfOptions,
    leave_out: &LeaveOut,
) -> Result<Mjcf, MjcfError> {
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
    let free_bodies = reader.free_bodies();
    if let Some(name) = leave_out.bodies.iter().find(|n| !free_bodies.contains(n)) {
        let list = free_bodies.iter().map(|n| format!("'{n}'")).collect::<Vec<_>>().join(", ");
        return Err(root.error(MjcfErrorKind::Invalid(format!(
            "cannot leave out body '{name}': only bodies with a free joint and no child bodies can be ({})",
            if list.is_empty() { "the file has none".to_string() } else { list }
        ))));
    }
    let (model, layout, bodies, filter) = reader.assemble(&model_name, root, &option, leave_out, &excludes)?;
    let mut model = model;
    model.tendons = super::tendon::read_tendons(&mut reader, root, &model, &layout)?;
    // what reading the tendons noticed (the soft parameters), after the tree's remarks
    model.warnings.append(&mut reader.warnings);
    let actuators = super::assemble::reader_actuators(&reader, root, &model)?;
    if !actuators.is_empty() {
        model.warnings.push(format!(
            "{} actuators read: a scene's `[[robot]] mjcf` drives them by `ctrl`; the model alone (`tumble model`, \
             `tumble dynamics`) has the dynamics of zero actuator force",
            actuators.len()
        ));
    }
    // a key's qpos is the whole file's: none are read when free bodies are left out
    let keyframes = if leave_out.bodies.is_empty() {
        super::keyframe::read_keyframes(root, &model, &layout, actuators.len())?
    } else {
        Vec::new()
    };
    Ok(Mjcf { model, option, layout, actuators, excludes, bodies, free_bodies, filter, keyframes })
}

pub(super) fn unsupported(why: &str) -> MjcfErrorKind {
    MjcfErrorKind::Unsupported(why.to_string())
}

pub(super) fn vec3(v: &[f64]) -> DVec3 {
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
        v.refuse_unless("exactmeshinertia", |s| s == "false", "exactmeshinertia (give each mesh inertia=\"exact\")")?;
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
    pub(super) fn view(&self, el: &'a El, childclass: Option<&str>) -> Result<View<'a>, MjcfError> {
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
    pub(super) fn soft(&mut self, v: &View) {
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
        let mut o = MjcfOption {
            timestep: 0.002,
            gravity: DVec3::new(0.0, 0.0, -9.81),
            integrator: MjcfIntegrator::Euler,
            medium: Medium::default(),
        };
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
            // the medium of the inertia-box fluid model (crate::multibody::fluid)
            if let Some(w) = v.vec("wind", 3)? {
                o.medium.wind = vec3(&w);
            }
            for (name, value) in [("density", &mut o.medium.density), ("viscosity", &mut o.medium.viscosity)] {
                *value = v.f64(name, *value)?;
                if !(*value >= 0.0 && value.is_finite()) {
                    return Err(
                        v.err(name, MjcfErrorKind::Invalid(format!("the medium's {name} must be finite and ≥ 0")))
                    );
                }
            }
            if !o.medium.wind.is_finite() {
                return Err(v.err("wind", MjcfErrorKind::Invalid("the wind must be finite".into())));
            }
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
                    let mode = v.keyword("inertia", &["legacy", "exact", "convex", "shell"])?.unwrap_or("legacy");
                    self.meshes.insert(name, (file.to_string(), path, scale, mode.to_string()));
                }
                "model" => return Err(el.error(unsupported("<model> assets (attached sub-models)"))),
                other => return Err(el.error(MjcfErrorKind::Invalid(format!("unknown element <{other}> in <asset>")))),
            }
        }
        Ok(())
    }
}
