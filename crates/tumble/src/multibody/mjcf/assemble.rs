//! The tree read from MJCF handed to the [`ModelBuilder`]: tumble bodies, frames, geometry and
//! the MuJoCo layout; the actuators and contact exclusions recorded.

use super::attrs::{all_zero, View};
use super::build::{unsupported, GeomRec, Kind, Reader};
use super::filter::{pair_may_collide, ContactFilter, GeomFilter};
use super::layout::{LayoutJoint, MujocoLayout};
use super::pose::Pose;
use super::xml::El;
use super::{LeaveOut, MjcfActuator, MjcfBody, MjcfError, MjcfErrorKind, MjcfOption, Transmission};
use crate::math::{DMat3, DVec3};
use crate::multibody::fluid::{principal_axes, Fluid, FluidBox};
use crate::multibody::joint::{JointDynamics, JointKind, JointLimits};
use crate::multibody::model::{FrameOrigin, GeometryRole, LinkGeometry, ModelBuilder};
use crate::multibody::spatial::{outer, RigidInertia, Xform};

impl<'a> Reader<'a> {
    /// `<contact>`: `<exclude>` pairs recorded; `<pair>` refused.
    pub(super) fn contact(&self, root: &'a El) -> Result<Vec<(String, String)>, MjcfError> {
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
    pub(super) fn scale_total_mass(&mut self, root: &El) -> Result<(), MjcfError> {
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

    /// The bodies with a free joint and no child bodies (MJCF names, file order).
    pub(super) fn free_bodies(&self) -> Vec<String> {
        (0..self.bodies.len())
            .filter(|&i| self.bodies[i].joints.iter().any(|j| j.kind == Kind::Free))
            .filter(|&i| !self.bodies.iter().any(|b| b.parent == Some(i)))
            .map(|i| self.bodies[i].name.clone())
            .collect()
    }

    /// The equivalent box of each MJCF body with mass (MuJoCo's `body_mass`, `body_ipos`,
    /// `body_iquat`, `body_inertia`), fixed to the tumble body it sits on; `placed` as
    /// [`assemble`](Self::assemble) made it (the world first). The principal axes are MuJoCo's
    /// where it takes them as given, else an eigen-solver's.
    fn fluid_boxes(&self, placed: &[MjcfBody]) -> Vec<FluidBox> {
        let mut boxes = Vec::new();
        for (b, at) in self.bodies.iter().zip(&placed[1..]) {
            let Some(body) = at.body else { continue };
            let i = &b.inertia;
            let com = i.com();
            // Ī_c = Ī_o − m (|c|² 1 − c cᵀ)
            let shift = DMat3::from_diagonal(DVec3::splat(com.length_squared())) - outer(com, com);
            let inertia_com = i.i_o - i.mass * shift;
            let (moments, axes) = match b.principal_rot {
                Some(rot) => {
                    let r = DMat3::from_quat(rot);
                    let principal = r.transpose() * inertia_com * r;
                    (DVec3::new(principal.x_axis.x, principal.y_axis.y, principal.z_axis.z), r)
                }
                None => principal_axes(inertia_com),
            };
            // in the tumble body's frame: the MJCF body frame sits at pose_in_body
            let body_from_mjcf = DMat3::from_quat(at.pose_in_body.rot);
            let com_body = at.pose_in_body.pos + body_from_mjcf * com;
            if let Some(fb) = FluidBox::new(body, i.mass, com_body, body_from_mjcf * axes, moments) {
                boxes.push(fb);
            }
        }
        boxes
    }

    /// The tree handed to the builder: per MJCF body one tumble body per joint, the geometry and
    /// the frames; the layout of MuJoCo's coordinates; where each MJCF body sits. What
    /// `leave_out` names is not built (its names are checked by the caller).
    pub(super) fn assemble(
        &mut self,
        name: &str,
        root: &El,
        option: &MjcfOption,
        leave_out: &LeaveOut,
        excludes: &[(String, String)],
    ) -> Result<(crate::multibody::MultibodyModel, MujocoLayout, Vec<MjcfBody>, ContactFilter), MjcfError> {
        let mut builder = ModelBuilder::new(name);
        builder.add_frame("world", None, Xform::IDENTITY, FrameOrigin::Root, RigidInertia::ZERO);
        let mut placed: Vec<MjcfBody> =
            vec![MjcfBody { name: "world".into(), body: None, pose_in_body: Pose::IDENTITY }];
        let mut layout = Vec::new();
        for b in &self.bodies {
            if leave_out.bodies.contains(&b.name) {
                // childless: no later body refers to its entry
                placed.push(MjcfBody { name: b.name.clone(), body: None, pose_in_body: Pose::IDENTITY });
                continue;
            }
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
        // geometry: each geom in its body's frame (the link is the MJCF body's frame), with MuJoCo's
        // contact filter; what is left out goes: the world's (the worldbody's and that of bodies
        // welded to it), left-out bodies'
        let world_geoms = std::mem::take(&mut self.world_geoms);
        let bodies = &self.bodies;
        // a left-out body is a weld body of its own, not the world
        let weld = |k: usize| match leave_out.bodies.contains(&bodies[k].name) {
            true => Some(usize::MAX - k),
            false => placed[k + 1].body,
        };
        let mut weld_parent: Vec<Option<usize>> = Vec::with_capacity(bodies.len());
        for b in bodies {
            let wp = match b.parent {
                None => None,
                Some(p) if b.joints.is_empty() => weld_parent[p],
                Some(p) => weld(p),
            };
            weld_parent.push(wp);
        }
        let filter_of = |g: &GeomRec, body: Option<usize>| GeomFilter {
            body: body.map_or("world".to_string(), |k| bodies[k].name.clone()),
            weld: body.and_then(weld),
            weld_parent: body.and_then(|k| weld_parent[k]),
            contype: g.contype,
            conaffinity: g.conaffinity,
        };
        // (geom, its body, its filter, kept)
        let all: Vec<(&GeomRec, Option<usize>, GeomFilter, bool)> = world_geoms
            .iter()
            .map(|g| (g, None, filter_of(g, None), !leave_out.world))
            .chain((0..bodies.len()).flat_map(|k| {
                let kept = !leave_out.bodies.contains(&bodies[k].name) && !(leave_out.world && weld(k).is_none());
                bodies[k].geoms.iter().map(move |g| (g, Some(k), filter_of(g, Some(k)), kept))
            }))
            .collect();
        // in a file that is its own world, a geom that can collide with none of the file's is no
        // collision shape
        let collides = |g: &GeomRec| g.contype | g.conaffinity != 0;
        let alive: Vec<bool> = (0..all.len())
            .map(|a| {
                collides(all[a].0)
                    && (!leave_out.world
                        || (0..all.len())
                            .any(|b| b != a && collides(all[b].0) && pair_may_collide(&all[a].2, &all[b].2, excludes)))
            })
            .collect();
        let mut filter = ContactFilter { geoms: Vec::new(), excludes: excludes.to_vec() };
        for ((g, body, f, kept), alive) in all.into_iter().zip(alive) {
            if !kept {
                continue;
            }
            let role = if alive { GeometryRole::Collision } else { GeometryRole::Visual };
            builder.add_geometry(LinkGeometry {
                link: body.map_or("world".to_string(), |k| bodies[k].name.clone()),
                name: g.el.attr("name").map(|a| a.value.clone()),
                role,
                x_from_link: g.in_body.xform(),
                shape: g.shape.clone(),
                line: g.line,
                contype: g.contype,
                conaffinity: g.conaffinity,
                friction: g.friction,
            });
            filter.geoms.push(f);
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
        model.gravity = option.gravity;
        if !option.medium.is_void() {
            model.fluid = Fluid { medium: option.medium, boxes: self.fluid_boxes(&placed) };
        }
        let layout = MujocoLayout::new(&model, layout);
        placed.retain(|b| !leave_out.bodies.contains(&b.name));
        Ok((model, layout, placed, filter))
    }
}

/// `<actuator>`: `motor`, `position`, `velocity` and `general` on joints and fixed tendons, recorded.
pub(super) fn reader_actuators(
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
            for t in ["site", "body", "jointinparent", "cranksite"] {
                if v.get(t).is_some() {
                    return Err(v.err(t, unsupported("actuators on anything but a joint or a fixed tendon")));
                }
            }
            let target = match (v.str("joint"), v.str("tendon")) {
                (Some(_), Some(_)) => {
                    return Err(v.err("tendon", MjcfErrorKind::Invalid("both a joint and a tendon".into())))
                }
                (None, None) => return Err(a.error(MjcfErrorKind::MissingAttribute("joint"))),
                (Some(joint), None) => {
                    if model.joint_index(joint).is_none() {
                        return Err(v.err("joint", MjcfErrorKind::Invalid(format!("no joint named '{joint}'"))));
                    }
                    Transmission::Joint(joint.to_string())
                }
                (None, Some(tendon)) => match model.tendons.iter().position(|t| t.name == tendon) {
                    Some(k) => Transmission::Tendon(k),
                    None => return Err(v.err("tendon", MjcfErrorKind::Invalid(format!("no tendon named '{tendon}'")))),
                },
            };
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
                target,
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
