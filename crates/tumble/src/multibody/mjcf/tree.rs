//! The body tree of an MJCF document: `<body>`, `<frame>`, `<joint>`/`<freejoint>`, `<inertial>`,
//! `<geom>`, each read through its default class, and MuJoCo's inertia from geoms.

use super::attrs::{all_zero, View};
use super::build::{unsupported, vec3, BodyRec, GeomRec, JointRec, Kind, Reader, VISUAL};
use super::mesh_inertia::mesh_mass_properties;
use super::pose::{orientation, pose, z_to_quat, Pose, ORIENTATIONS};
use super::xml::El;
use super::{MjcfError, MjcfErrorKind};
use crate::math::{DMat3, DQuat, DVec3};
use crate::multibody::joint::JointDynamics;
use crate::multibody::model::{placed_inertia, GeometryShape};
use crate::multibody::spatial::RigidInertia;
use std::collections::HashMap;

impl<'a> Reader<'a> {
    /// The children of a body (or the world, `body = None`), inside `frame` (their placement in the
    /// body frame), with the enclosing `childclass`.
    pub(super) fn children(
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
        let name = unique_name(&mut self.body_names, el, "body", id as usize)?;
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
            principal_rot: None,
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
        let (inertia, principal_rot) = if from_geoms {
            (self.inertia_from_geoms(index)?, self.single_geom_axes(index))
        } else {
            match inertial {
                Some((inertia, axes)) => (inertia, axes),
                None => (RigidInertia::ZERO, None),
            }
        };
        self.bodies[index].inertia = inertia;
        self.bodies[index].principal_rot = principal_rot;
        Ok(())
    }

    fn joint_name(&mut self, el: &El) -> Result<String, MjcfError> {
        let id = self.joint_names.len();
        unique_name(&mut self.joint_names, el, "joint", id)
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
        // dry joint friction, F ≥ 0; `drop_frictionloss` reads the model as if F = 0 (MuJoCo's
        // `<flag frictionloss="disable">`), with a warning per joint that had one
        let mut friction_loss = v.nonneg("frictionloss", 0.0)?;
        if self.options.drop_frictionloss && friction_loss != 0.0 {
            self.warnings.push(format!(
                "{}:{}:{}: <joint frictionloss>: joint '{}': frictionloss {} dropped (drop_frictionloss)",
                el.pos.file,
                el.pos.line,
                el.pos.column,
                el.attr("name").map(|a| a.value.as_str()).unwrap_or(""),
                friction_loss
            ));
            friction_loss = 0.0;
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
            friction_loss,
        };
        if dynamics.stiffness != 0.0 && matches!(kind, Kind::Ball | Kind::Free) {
            return Err(v.err("stiffness", unsupported("springs on ball and free joints")));
        }
        Ok(JointRec { el, name, kind, anchor, axis: axis / n, reference, range, dynamics, springref })
    }

    /// The `<inertial>`'s spatial inertia in the body frame and, with `diaginertia`, its principal
    /// axes (`body_from_principal`; `fullinertia` leaves them to an eigen-solver).
    fn inertial(&mut self, el: &'a El) -> Result<(RigidInertia, Option<DQuat>), MjcfError> {
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
        let axes = v.vec("diaginertia", 3)?.map(|_| rot);
        Ok((placed_inertia(mass, vec3(&pos), DMat3::from_quat(rot), tensor), axes))
    }

    /// MuJoCo's inertial axes when a body's inertia comes from one geom of mass above `mjEPS`
    /// (`mjCBody::InertiaFromGeom` copies that geom's frame; a primitive's frame is principal). `None`
    /// for several geoms or a mesh: its principal axes come from an eigen-solver.
    fn single_geom_axes(&self, index: usize) -> Option<DQuat> {
        let mut counted = self.bodies[index].geoms.iter().filter(|g| {
            let volume = g.shape.unit_mass_properties().map(|(volume, _)| volume);
            let mass = g.mass.or(volume.map(|vol| g.density * vol));
            g.counts && mass.is_none_or(|m| m > 1e-14)
        });
        let g = counted.next()?;
        if counted.next().is_some() || matches!(g.shape, GeometryShape::Mesh { .. }) {
            return None;
        }
        Some(g.in_body.rot)
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
        // the inertia-box fluid model is read (the medium in <option>); the ellipsoid model is not
        v.refuse_unless(
            "fluidshape",
            |s| s == "none",
            "fluidshape=\"ellipsoid\": MuJoCo's ellipsoid fluid model (the inertia-box model, fluidshape=\"none\", is read)",
        )?;
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
        // MuJoCo's geom orientation, which is its inertial frame when it is a body's only geom
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
            // MuJoCo turns z to `from − to` (mjuu_z2quat), not to `to − from`: the same axis, but
            // the geom turned otherwise about it (a box's or an ellipsoid's sides, and the inertial
            // axes MuJoCo copies from a body's single geom)
            in_frame = Pose { rot: z_to_quat(-d / len), pos: 0.5 * (a + b) };
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
        let mut mesh_inertia = None;
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
                // with `fromto`, MuJoCo takes the first size for both sides across the axis
                // (`size = (s₀, s₀, |to − from| / 2)`; checked with MuJoCo's `geom_size`)
                let e = match half_length {
                    Some(h) => {
                        let across = positive(0, "the first half size")?;
                        DVec3::new(across, across, h)
                    }
                    None => DVec3::new(
                        positive(0, "the first half size")?,
                        positive(1, "the second half size")?,
                        positive(2, "the third half size")?,
                    ),
                };
                if ty == "box" {
                    GeometryShape::Box { half_extents: e }
                } else {
                    GeometryShape::Ellipsoid { radii: e }
                }
            }
            _ => {
                let Some(name) = v.str("mesh") else { return Err(el.error(MjcfErrorKind::MissingAttribute("mesh"))) };
                let Some((file, path, scale, mode)) = self.meshes.get(name) else {
                    return Err(v.err("mesh", MjcfErrorKind::Invalid(format!("no mesh asset named '{name}'"))));
                };
                mesh_inertia = Some(mode.clone());
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
            mesh_inertia,
            shape,
            in_body,
            contype: contype as u32,
            conaffinity: conaffinity as u32,
            friction,
            line: el.pos.line,
        };
        Ok(Some(rec))
    }

    /// MuJoCo's inertia from geoms: each counted geom's mass (`mass`, or `density` × volume) and
    /// principal moments about its centre (`GeometryShape::unit_mass_properties`) placed in the body
    /// frame and summed (the parallel-axis rule is `RigidInertia`'s addition).
    fn inertia_from_geoms(&self, index: usize) -> Result<RigidInertia, MjcfError> {
        let mut total = RigidInertia::ZERO;
        for g in self.bodies[index].geoms.iter().filter(|g| g.counts) {
            if let GeometryShape::Mesh { path: Some(path), scale, uri } = &g.shape {
                let mode = g.mesh_inertia.as_deref().unwrap_or("legacy");
                if !matches!(mode, "legacy" | "exact") {
                    return Err(g.el.error(unsupported(&format!(
                        "the inertia of a mesh with inertia=\"{mode}\" (legacy and exact are computed)"
                    ))));
                }
                let (volume, com, unit) = mesh_mass_properties(path, *scale, mode == "legacy").map_err(|why| {
                    g.el.error(MjcfErrorKind::Invalid(format!("mesh '{uri}' ({}): {why}", path.display())))
                })?;
                let mass = g.mass.unwrap_or(g.density * volume);
                if !(mass >= 0.0 && mass.is_finite()) {
                    return Err(g.el.error(MjcfErrorKind::Invalid(format!("a geom mass of {mass}"))));
                }
                // the mesh's centre of mass and tensor in the geom frame, then in the body frame
                let rot = DMat3::from_quat(g.in_body.rot);
                let density = mass / volume;
                total += placed_inertia(mass, g.in_body.pos + rot * com, rot, density * unit);
                continue;
            }
            let Some((volume, unit)) = g.shape.unit_mass_properties() else {
                return Err(g.el.error(unsupported("the inertia of this geom")));
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
}

/// `el`'s `name` (else `{kind}{id}`, MuJoCo's unnamed elements), registered in `names` with its
/// line; a name already there is an error naming the first one's line.
fn unique_name(names: &mut HashMap<String, u32>, el: &El, kind: &str, id: usize) -> Result<String, MjcfError> {
    let name = match el.attr("name") {
        Some(a) => a.value.clone(),
        None => format!("{kind}{id}"),
    };
    if let Some(first) = names.insert(name.clone(), el.pos.line) {
        return Err(el.attr_error(
            "name",
            MjcfErrorKind::Invalid(format!("repeated {kind} name '{name}' (first at line {first})")),
        ));
    }
    Ok(name)
}
