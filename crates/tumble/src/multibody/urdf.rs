//! URDF robots → [`MultibodyModel`], with errors that name the file, line, column and element.
//!
//! Reference: the URDF XML specification (ROS wiki, `urdf/XML/link`, `urdf/XML/joint`); frame
//! conventions in `docs/multibody.md`.
//!
//! - A joint's `<origin xyz rpy>` places the joint frame (the child link's frame at `q = 0`) in the
//!   parent link's frame, `R(rpy) = Rz(y) Ry(p) Rx(r)`; `<axis>` is in the joint frame (normalised).
//! - `<inertial><origin>` places the centre of mass and the axes of `<inertia>` in the link frame.
//! - `fixed` joints are merged: the child's inertia is added to the body it is fixed to and the
//!   child stays a named frame.
//! - Joint order: depth-first from the root link, children in the order their joints appear in the
//!   file ([`ChildOrder::File`], the default) or sorted by joint name ([`ChildOrder::JointName`], the
//!   order Pinocchio's reader produces). Iterative: a chain of 10⁵ links does not grow the call stack.
//! - With `floating`, a `floating` joint named `root_joint` connects the world to the root link.
//! - `<collision>` and `<visual>` elements are recorded in `model.geometries` (box, cylinder, sphere,
//!   mesh with `scale`, each at its `<origin>` in the link frame; `geometry_placement` puts it on the
//!   body it moves with); a geometry that cannot be used is left out with a warning naming its line.
//!   `<mesh filename>` is also listed by `model.meshes()`, resolved by [`resolve_mesh_in`]
//!   (`package://` in the URDF's parent directories, then in [`UrdfOptions::package_paths`];
//!   `file://`, relative and absolute paths) but not read here; what cannot be resolved, or leaves
//!   its directory, gives a warning (with the paths tried).
//!
//! Rejected: malformed XML and DTDs (roxmltree), duplicate names, unknown joint types, a joint
//! naming a missing link, a link with two parent joints, no root or several roots, cycles, zero or
//! non-finite axes, revolute/prismatic joints without `<limit>` or with `lower > upper`, masses that
//! are negative or not finite, inertias that are not physical ([`super::balance`]: a negative
//! principal moment, the triangle inequality violated, a tensor without mass) unless
//! [`UrdfOptions::balance_inertia`] replaces them by the nearest physical one (one warning per
//! link) or, for a positive-definite tensor that only violates the triangle inequality,
//! [`UrdfOptions::keep_triangle_violations`] keeps it (one warning per link), and movable joints
//! whose subtree has no mass unless [`Massless::Fuse`] holds them (one warning per joint). A mimic naming no joint is a warning (mimic joints are independent joints).
//!
//! Warnings, loading continuing: unknown top-level tags (once per tag), an attribute or element
//! inside `<link>` or `<joint>` that the specification does not define (`urdf_vocabulary`, once
//! per element and name), a link whose radius of gyration is more than [`GYRATION_FACTOR`] times
//! the half-diagonal of its primitive collision geometry's bounding box.
//!
//! Cases that real robots use are accepted: `mass = 0` with an all-zero tensor is a massless link
//! (a frame, like `ee_link` of UR5 or `panda_link8`), `mass > 0` with an all-zero tensor is a point
//! mass (like Talos's `rgbd_optical_frame`), a tensor with one zero moment is a thin rod, and a
//! `<robot>` with no links and no joints is an empty model (with a warning).

use super::balance::{inertia_defect, nearest_physical};
use super::joint::{JointKind, JointLimits};
use super::model::{
    placed_inertia, FrameOrigin, GeometryRole, GeometryShape, LinkGeometry, ModelBuilder, ModelError, MultibodyModel,
};
use super::spatial::{rpy_rotation, RigidInertia, Xform};
use crate::body::mass::symmetric_eigen;
use crate::math::{skew, DMat3, DVec3};
use roxmltree::{Document, Node};
use std::collections::{HashMap, HashSet};
use std::path::{Component, Path, PathBuf};

/// Files larger than this are refused before reading (bytes).
pub const MAX_URDF_BYTES: u64 = 64 << 20;

/// A link whose radius of gyration exceeds this many times the half-diagonal of its collision
/// geometry's bounding box gets a warning. Mass that lies inside a box of half-diagonal `h` has
/// its centre of mass inside it too, so each particle is within `2h` of it and `λ_max ≤ Σ mᵢ |pᵢ − c|²
/// ≤ m (2h)²`: the radius of gyration is at most `2h` (a uniform cube's is `0.47 h`, a thin spherical
/// shell's `0.47 h`, a hoop's `0.71 h`). 10 leaves room for collision geometry smaller than the part
/// and still catches unit mistakes (g·mm² read as kg·m² is a factor 10⁹ on the moment, 3·10⁴ on the
/// radius).
pub const GYRATION_FACTOR: f64 = 10.0;

/// An error in a URDF file, with its position.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}:{line}:{column}: <{element}>: {kind}")]
pub struct UrdfError {
    /// The file (as given).
    pub file: String,
    /// 1-based line (0 when the file could not be read).
    pub line: u32,
    /// 1-based column.
    pub column: u32,
    /// The element concerned, e.g. `joint name="elbow"`.
    pub element: String,
    /// What is wrong (boxed: errors stay small on the happy path).
    pub kind: Box<UrdfErrorKind>,
}

/// What is wrong in a URDF file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum UrdfErrorKind {
    #[error("cannot read the file: {0}")]
    Io(String),
    #[error("the file is {size} bytes, more than the limit of {limit}")]
    TooLarge { size: u64, limit: u64 },
    #[error("malformed XML: {0}")]
    Xml(String),
    #[error("the root element must be <robot>, found <{0}>")]
    NotRobot(String),
    #[error("missing attribute '{0}'")]
    MissingAttribute(&'static str),
    #[error("missing element <{0}>")]
    MissingElement(&'static str),
    #[error("attribute '{attribute}': expected {expected}, got '{value}'")]
    BadNumber { attribute: &'static str, value: String, expected: &'static str },
    #[error("duplicate {what} name '{name}' (first at line {first_line})")]
    Duplicate { what: &'static str, name: String, first_line: u32 },
    #[error("unknown joint type '{0}'; valid types: revolute, continuous, prismatic, fixed, floating")]
    UnknownJointType(String),
    #[error("joint type '{0}' is not supported (valid: revolute, continuous, prismatic, fixed, floating)")]
    UnsupportedJointType(String),
    #[error("joint '{joint}' names {role} link '{link}', which does not exist")]
    MissingLink { joint: String, role: &'static str, link: String },
    #[error("link '{link}' is the child of two joints: '{first}' and '{second}'")]
    TwoParents { link: String, first: String, second: String },
    #[error("no root link (every link is some joint's child)")]
    NoRoot,
    #[error("several root links: {0:?} (a robot has exactly one link that is no joint's child)")]
    SeveralRoots(Vec<String>),
    #[error("kinematic cycle: {0}")]
    Cycle(String),
    #[error("the robot has no links")]
    NoLinks,
    #[error("axis {axis:?}: {why}")]
    BadAxis { axis: [f64; 3], why: &'static str },
    #[error("a {0} joint needs a <limit> element")]
    MissingLimit(String),
    #[error("limit: {0}")]
    BadLimit(String),
    #[error("mass must be finite and ≥ 0, and > 0 when an inertia tensor is given (got {0})")]
    BadMass(f64),
    #[error(
        "inertia of link '{link}': {reason}; `--balance-inertia` (in a scene, `balance_inertia = true`) \
         replaces it by the nearest physical inertia"
    )]
    BadInertia { link: String, reason: String },
    #[error("mimic joint '{joint}' refers to '{target}': {why}")]
    BadMimic { joint: String, target: String, why: &'static str },
    #[error("{0}")]
    Model(ModelError),
}

/// Options of [`load_urdf`] and [`parse_urdf`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct UrdfOptions<'a> {
    /// Connect the root link to the world by a floating joint (a free-flyer base).
    pub floating: bool,
    /// The order of a link's children in the depth-first joint numbering.
    pub order: ChildOrder,
    /// Replace a link inertia that is not physical by the nearest physical one
    /// ([`balance::nearest_physical`](super::balance::nearest_physical)), with one warning per link;
    /// without it such a link is an error.
    pub balance_inertia: bool,
    /// Keep, with one warning per link, an inertia whose only defect is the triangle inequality and
    /// whose tensor is positive definite (every principal moment above round-off): no rigid body has
    /// such moments, but the link's spatial inertia is positive definite, so the mass matrix is and
    /// the dynamics stay consistent. Without it (and without `balance_inertia`) such a link is an
    /// error; a tensor that is not positive definite is an error either way.
    pub keep_triangle_violations: bool,
    /// What to do with a movable joint whose subtree has no mass.
    pub massless: Massless,
    /// Directories that hold packages: `package://NAME/REST` is looked for as `DIR/NAME/REST` in
    /// each, after the URDF's parent directories (see [`resolve_mesh_in`]).
    pub package_paths: &'a [PathBuf],
}

/// What to do with a movable joint whose subtree has no mass (its row of the mass matrix is zero).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Massless {
    /// An error naming the joint (the default).
    #[default]
    Error,
    /// The joint is made fixed at `q = 0`, with one warning per joint: the subtree has no mass, so
    /// the other joints' dynamics are unchanged; only its own motion is lost.
    Fuse,
    /// The model is built as it is (its mass matrix singular in those rows), for a model whose
    /// massless joints [`reduced_model`](super::reduce::reduced_model) then locks: the reduced model
    /// is checked.
    Allow,
}

/// The order in which the depth-first numbering visits a link's children.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ChildOrder {
    /// The order in which their joints appear in the file (the default).
    #[default]
    File,
    /// Sorted by joint name (byte order). This is the order Pinocchio's URDF reader produces (it
    /// keeps joints in a map sorted by name), so `q` and `v` then line up with Pinocchio's.
    JointName,
}

/// Reads and parses a URDF file.
pub fn load_urdf(path: &Path, options: UrdfOptions<'_>) -> Result<MultibodyModel, UrdfError> {
    let file = path.display().to_string();
    let whole_file =
        |kind| UrdfError { file: file.clone(), line: 0, column: 0, element: "robot".into(), kind: Box::new(kind) };
    let meta = std::fs::metadata(path).map_err(|e| whole_file(UrdfErrorKind::Io(e.to_string())))?;
    if meta.len() > MAX_URDF_BYTES {
        return Err(whole_file(UrdfErrorKind::TooLarge { size: meta.len(), limit: MAX_URDF_BYTES }));
    }
    let text = std::fs::read_to_string(path).map_err(|e| whole_file(UrdfErrorKind::Io(e.to_string())))?;
    parse_urdf(&text, &file, options)
}

/// Parses URDF text; `file` names it in errors.
pub fn parse_urdf(text: &str, file: &str, options: UrdfOptions<'_>) -> Result<MultibodyModel, UrdfError> {
    let doc = Document::parse(text).map_err(|e| {
        let pos = e.pos();
        UrdfError {
            file: file.into(),
            line: pos.row,
            column: pos.col,
            element: "xml".into(),
            kind: Box::new(UrdfErrorKind::Xml(e.to_string())),
        }
    })?;
    Parser { doc: &doc, file, options }.robot()
}

struct Parser<'a, 'input> {
    doc: &'a Document<'input>,
    file: &'a str,
    options: UrdfOptions<'a>,
}

/// A link as read.
struct Link<'a, 'input> {
    node: Node<'a, 'input>,
    name: &'a str,
    /// Spatial inertia in the link frame.
    inertia: RigidInertia,
}

/// A joint as read.
struct RawJoint<'a, 'input> {
    node: Node<'a, 'input>,
    name: &'a str,
    /// `None` for fixed joints.
    kind: Option<JointKind>,
    parent: usize,
    child: usize,
    /// `jointframe_X_parentlink`.
    x_origin: Xform,
    limits: JointLimits,
}

fn describe(node: Node) -> String {
    match node.attribute("name") {
        Some(name) => format!("{} name=\"{}\"", node.tag_name().name(), name),
        None => node.tag_name().name().to_string(),
    }
}

impl<'a, 'input> Parser<'a, 'input> {
    fn error(&self, node: Node, kind: UrdfErrorKind) -> UrdfError {
        let pos = self.doc.text_pos_at(node.range().start);
        UrdfError {
            file: self.file.into(),
            line: pos.row,
            column: pos.col,
            element: describe(node),
            kind: Box::new(kind),
        }
    }

    fn line(&self, node: Node) -> u32 {
        self.doc.text_pos_at(node.range().start).row
    }

    fn attr(&self, node: Node<'a, 'input>, name: &'static str) -> Result<&'a str, UrdfError> {
        node.attribute(name).ok_or_else(|| self.error(node, UrdfErrorKind::MissingAttribute(name)))
    }

    fn number(&self, node: Node, name: &'static str, default: Option<f64>) -> Result<f64, UrdfError> {
        match node.attribute(name) {
            None => default.ok_or_else(|| self.error(node, UrdfErrorKind::MissingAttribute(name))),
            Some(text) => match text.trim().parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(self.error(
                    node,
                    UrdfErrorKind::BadNumber { attribute: name, value: text.into(), expected: "a finite number" },
                )),
            },
        }
    }

    fn vec3(&self, node: Node, name: &'static str, default: DVec3) -> Result<DVec3, UrdfError> {
        let Some(text) = node.attribute(name) else { return Ok(default) };
        let bad = || {
            self.error(
                node,
                UrdfErrorKind::BadNumber { attribute: name, value: text.into(), expected: "three finite numbers" },
            )
        };
        let mut out = [0.0; 3];
        let mut parts = text.split_whitespace();
        for x in out.iter_mut() {
            *x = parts.next().and_then(|p| p.parse::<f64>().ok()).filter(|x| x.is_finite()).ok_or_else(bad)?;
        }
        if parts.next().is_some() {
            return Err(bad());
        }
        Ok(DVec3::from_array(out))
    }

    /// `<origin xyz rpy>` as the pair (rotation `parent_from_child`, translation), identity if absent.
    fn origin(&self, parent: Node) -> Result<(DMat3, DVec3), UrdfError> {
        match child(parent, "origin") {
            None => Ok((DMat3::IDENTITY, DVec3::ZERO)),
            Some(o) => Ok((rpy_rotation(self.vec3(o, "rpy", DVec3::ZERO)?), self.vec3(o, "xyz", DVec3::ZERO)?)),
        }
    }

    fn robot(&self) -> Result<MultibodyModel, UrdfError> {
        let options = self.options;
        let root = self.doc.root_element();
        if root.tag_name().name() != "robot" {
            return Err(self.error(root, UrdfErrorKind::NotRobot(root.tag_name().name().into())));
        }
        let robot_name = root.attribute("name").unwrap_or("robot");
        let mut warnings = Vec::new();
        let mut warned_tags: Vec<&str> = Vec::new();
        let mut links: Vec<Link> = Vec::new();
        let mut link_index: HashMap<&str, usize> = HashMap::new();
        let mut joint_nodes: Vec<Node> = Vec::new();
        let mut geometries: Vec<LinkGeometry> = Vec::new();
        // (element, name) pairs already warned about as unknown inside links and joints
        let mut unknown_seen = HashSet::new();
        for node in root.children().filter(|n| n.is_element()) {
            if matches!(node.tag_name().name(), "link" | "joint") && node.tag_name().namespace().is_none() {
                super::urdf_vocabulary::check(self.doc, self.file, node, &mut unknown_seen, &mut warnings);
            }
            match node.tag_name().name() {
                "link" => {
                    let name = self.attr(node, "name")?;
                    if let Some(&first) = link_index.get(name) {
                        let first_line = self.line(links[first].node);
                        return Err(
                            self.error(node, UrdfErrorKind::Duplicate { what: "link", name: name.into(), first_line })
                        );
                    }
                    let inertia = self.inertial(node, name, &mut warnings)?;
                    let first_geometry = geometries.len();
                    self.geometries(node, name, &mut geometries, &mut warnings);
                    self.check_gyration(node, name, &inertia, &geometries[first_geometry..], &mut warnings);
                    link_index.insert(name, links.len());
                    links.push(Link { node, name, inertia });
                }
                "joint" => joint_nodes.push(node),
                "material" => {}
                other => {
                    if !warned_tags.contains(&other) {
                        warned_tags.push(other);
                        let pos = self.doc.text_pos_at(node.range().start);
                        warnings.push(format!("{}:{}:{}: ignored <{}> elements", self.file, pos.row, pos.col, other));
                    }
                }
            }
        }
        if links.is_empty() {
            if root.children().any(|n| n.is_element() && n.tag_name().name() == "joint") {
                return Err(self.error(root, UrdfErrorKind::NoLinks));
            }
            // an empty <robot> (a xacro left unexpanded, e.g.): an empty model, with a warning
            let mut builder = ModelBuilder::new(robot_name);
            let pos = self.doc.text_pos_at(root.range().start);
            builder.warn(format!("{}:{}:{}: the robot has no links: an empty model", self.file, pos.row, pos.col));
            return builder.build().map_err(|e| self.error(root, UrdfErrorKind::Model(e)));
        }

        // joints, checked against the links
        let mut joints: Vec<RawJoint> = Vec::with_capacity(joint_nodes.len());
        let mut joint_index: HashMap<&str, usize> = HashMap::new();
        let mut parent_joint: Vec<Option<usize>> = vec![None; links.len()];
        for &node in &joint_nodes {
            let joint = self.joint(node, &link_index, &mut warnings)?;
            if let Some(&first) = joint_index.get(joint.name) {
                let first_line = self.line(joints[first].node);
                return Err(
                    self.error(node, UrdfErrorKind::Duplicate { what: "joint", name: joint.name.into(), first_line })
                );
            }
            if let Some(first) = parent_joint[joint.child] {
                return Err(self.error(
                    node,
                    UrdfErrorKind::TwoParents {
                        link: links[joint.child].name.into(),
                        first: joints[first].name.into(),
                        second: joint.name.into(),
                    },
                ));
            }
            parent_joint[joint.child] = Some(joints.len());
            joint_index.insert(joint.name, joints.len());
            joints.push(joint);
        }
        self.check_mimics(&joint_nodes, &joint_index, &mut warnings)?;

        // the root, and cycles
        let roots: Vec<usize> = (0..links.len()).filter(|&l| parent_joint[l].is_none()).collect();
        if roots.len() > 1 {
            let names = roots.iter().map(|&l| links[l].name.to_string()).collect();
            return Err(self.error(links[roots[1]].node, UrdfErrorKind::SeveralRoots(names)));
        }
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); links.len()];
        for (j, joint) in joints.iter().enumerate() {
            children[joint.parent].push(j);
        }
        if options.order == ChildOrder::JointName {
            for list in children.iter_mut() {
                list.sort_by(|&a, &b| joints[a].name.cmp(joints[b].name));
            }
        }
        let Some(&root_link) = roots.first() else {
            let (path, node) = cycle_from(0, &links, &joints, &parent_joint);
            return Err(self.error(node, UrdfErrorKind::Cycle(path)));
        };

        // the mass of each link's subtree (links in depth-first order, then summed children first)
        let mut subtree_mass: Vec<f64> = links.iter().map(|l| l.inertia.mass).collect();
        if options.massless == Massless::Fuse {
            let mut order = Vec::with_capacity(links.len());
            let mut stack = vec![root_link];
            while let Some(l) = stack.pop() {
                order.push(l);
                stack.extend(children[l].iter().map(|&j| joints[j].child).filter(|&c| c != root_link));
                if order.len() > links.len() {
                    break; // a cycle: reported below
                }
            }
            for &l in order.iter().rev() {
                if let Some(j) = parent_joint[l] {
                    subtree_mass[joints[j].parent] += subtree_mass[l];
                }
            }
        }

        // depth-first from the root, children in file order, with an explicit stack
        let mut builder = ModelBuilder::new(robot_name);
        // for each link: the body it belongs to (None: the world) and link_X_body
        let mut link_body: Vec<Option<(Option<usize>, Xform)>> = vec![None; links.len()];
        let root_body = if options.floating {
            let b = builder
                .add_body(
                    links[root_link].name,
                    None,
                    "root_joint",
                    JointKind::Floating,
                    Xform::IDENTITY,
                    links[root_link].inertia,
                )
                .map_err(|e| self.error(links[root_link].node, UrdfErrorKind::Model(e)))?;
            Some(b)
        } else {
            builder.add_fixed_link(
                links[root_link].name,
                None,
                Xform::IDENTITY,
                FrameOrigin::Root,
                links[root_link].inertia,
            );
            None
        };
        link_body[root_link] = Some((root_body, Xform::IDENTITY));
        let mut stack: Vec<usize> = children[root_link].iter().rev().copied().collect();
        while let Some(j) = stack.pop() {
            let joint = &joints[j];
            let Some((parent_body, parent_x_body)) = link_body[joint.parent] else { continue };
            // X_T relative to the parent's body: jointframe_X_body = jointframe_X_parentlink · parentlink_X_body
            let x_tree = joint.x_origin.compose(&parent_x_body);
            let child_link = &links[joint.child];
            let mut kind = joint.kind;
            if kind.is_some() && options.massless == Massless::Fuse && subtree_mass[joint.child] <= 0.0 {
                let pos = self.doc.text_pos_at(joint.node.range().start);
                warnings.push(format!(
                    "{}:{}:{}: joint '{}': its subtree (link '{}' and below) has no mass: fused (held at q = 0)",
                    self.file, pos.row, pos.col, joint.name, child_link.name
                ));
                kind = None;
            }
            match kind {
                None => {
                    // fixed: the child link is part of the parent's body
                    let origin = FrameOrigin::Fixed {
                        joint: joint.name.to_string(),
                        parent_link: links[joint.parent].name.to_string(),
                    };
                    builder.add_fixed_link(child_link.name, parent_body, x_tree, origin, child_link.inertia);
                    link_body[joint.child] = Some((parent_body, x_tree));
                }
                Some(kind) => {
                    let b = builder
                        .add_body(child_link.name, parent_body, joint.name, kind, x_tree, child_link.inertia)
                        .map_err(|e| self.error(joint.node, UrdfErrorKind::Model(e)))?;
                    builder.set_limits(b, joint.limits);
                    builder.set_parent_link(b, links[joint.parent].name);
                    link_body[joint.child] = Some((Some(b), Xform::IDENTITY));
                }
            }
            stack.extend(children[joint.child].iter().rev());
        }
        if let Some(unreached) = (0..links.len()).find(|&l| link_body[l].is_none()) {
            // every link has at most one parent and one link is the root: the others sit on cycles
            let (path, node) = cycle_from(unreached, &links, &joints, &parent_joint);
            return Err(self.error(node, UrdfErrorKind::Cycle(path)));
        }
        for w in warnings {
            builder.warn(w);
        }
        for g in geometries {
            builder.add_geometry(g);
        }
        let built =
            if options.massless == Massless::Allow { builder.build_allowing_massless() } else { builder.build() };
        built.map_err(|e| {
            let node = match &e {
                ModelError::MasslessSubtree { joint, .. } => {
                    joint_index.get(joint.as_str()).map(|&j| joints[j].node).unwrap_or(root)
                }
                _ => root,
            };
            self.error(node, UrdfErrorKind::Model(e))
        })
    }

    /// Records each `<visual>` and `<collision>` element of a link: its `<origin>` and `<geometry>`
    /// (box, cylinder, sphere, or mesh with its file resolved and its scale), and each mesh in
    /// `meshes` too. A geometry that cannot be used (a missing or non-positive size, an unknown
    /// shape, a bad `<origin>`) is left out with a warning naming its line: the dynamics needs none.
    fn geometries(&self, link: Node, name: &str, geometries: &mut Vec<LinkGeometry>, warnings: &mut Vec<String>) {
        for element in link.children().filter(|n| n.is_element()) {
            let role = match element.tag_name().name() {
                "collision" => GeometryRole::Collision,
                "visual" => GeometryRole::Visual,
                _ => continue,
            };
            let line = self.line(element);
            let tag = element.tag_name().name();
            let skip = |warnings: &mut Vec<String>, why: String| {
                warnings.push(format!("{}:{}: link '{}': <{}> left out: {}", self.file, line, name, tag, why));
            };
            let Some(geometry) = child(element, "geometry") else {
                skip(warnings, "no <geometry>".into());
                continue;
            };
            let Some(shape_node) = geometry.children().find(|n| n.is_element()) else {
                skip(warnings, "an empty <geometry>".into());
                continue;
            };
            let x_from_link = match self.origin(element) {
                Ok((rot, xyz)) => Xform::from_pose(rot, xyz),
                Err(e) => {
                    skip(warnings, format!("<origin>: {}", e.kind));
                    continue;
                }
            };
            let positive = |attribute: &'static str| -> Result<f64, String> {
                let text = shape_node.attribute(attribute).ok_or(format!("no '{attribute}' attribute"))?;
                match text.trim().parse::<f64>() {
                    Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
                    _ => Err(format!("{attribute} = \"{text}\": expected a positive length (m)")),
                }
            };
            let shape = match shape_node.tag_name().name() {
                "box" if shape_node.attribute("size").is_none() => Err("<box> without a size".to_string()),
                "box" => match self.vec3(shape_node, "size", DVec3::ZERO) {
                    Ok(size) if size.is_finite() && size.min_element() > 0.0 => {
                        Ok(GeometryShape::Box { half_extents: 0.5 * size })
                    }
                    Ok(size) => Err(format!("<box size> {:?}: expected three positive lengths (m)", size.to_array())),
                    Err(e) => Err(format!("<box size>: {}", e.kind)),
                },
                "cylinder" => positive("radius").and_then(|radius| {
                    positive("length").map(|length| GeometryShape::Cylinder { radius, half_length: 0.5 * length })
                }),
                "sphere" => positive("radius").map(|radius| GeometryShape::Sphere { radius }),
                "mesh" => match shape_node.attribute("filename") {
                    None => Err("<mesh> without a filename".to_string()),
                    Some(uri) => match self.vec3(shape_node, "scale", DVec3::ONE) {
                        // a negative factor mirrors the mesh (left and right parts share one file)
                        Ok(scale) if scale.is_finite() && scale.abs().min_element() > 0.0 => {
                            let mesh_line = self.line(shape_node);
                            let path = match resolve_mesh_in(Path::new(self.file), uri, self.options.package_paths) {
                                Ok(path) => Some(path),
                                Err(why) => {
                                    warnings.push(format!(
                                        "{}:{}: link '{}': mesh '{}' not resolved: {}",
                                        self.file, mesh_line, name, uri, why
                                    ));
                                    None
                                }
                            };
                            Ok(GeometryShape::Mesh { uri: uri.into(), path, scale })
                        }
                        Ok(scale) => {
                            Err(format!("<mesh scale> {:?}: expected three non-zero factors", scale.to_array()))
                        }
                        Err(e) => Err(format!("<mesh scale>: {}", e.kind)),
                    },
                },
                other => Err(format!("unknown geometry <{other}>")),
            };
            match shape {
                Ok(shape) => geometries.push(LinkGeometry {
                    link: name.into(),
                    name: element.attribute("name").map(str::to_string),
                    role,
                    x_from_link,
                    shape,
                    line,
                    contype: 1,
                    conaffinity: 1,
                    friction: None,
                }),
                Err(why) => skip(warnings, why),
            }
        }
    }

    /// A warning when the link's radius of gyration, `sqrt(λ_max / m)` with `λ_max` the largest
    /// principal moment about the centre of mass, exceeds [`GYRATION_FACTOR`] times the half-diagonal
    /// of the bounding box of its collision geometry (in the link frame): no body of that size turns
    /// so slowly, so the inertia is most likely in the wrong units (g·mm², or a tensor about another
    /// point). Only primitive geometry is measured: a link with no collision geometry, or whose
    /// collision geometry includes a mesh (meshes are not read here), is not checked.
    fn check_gyration(
        &self,
        link: Node,
        name: &str,
        inertia: &RigidInertia,
        geometries: &[LinkGeometry],
        warnings: &mut Vec<String>,
    ) {
        let collision: Vec<&LinkGeometry> = geometries.iter().filter(|g| g.role == GeometryRole::Collision).collect();
        if inertia.mass <= 0.0 || collision.is_empty() {
            return;
        }
        let (mut lo_link, mut hi_link) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for g in collision {
            // the half extents of the shape's own bounding box, in its frame
            let half = match &g.shape {
                GeometryShape::Box { half_extents } => *half_extents,
                GeometryShape::Sphere { radius } => DVec3::splat(*radius),
                GeometryShape::Cylinder { radius, half_length } => DVec3::new(*radius, *radius, *half_length),
                GeometryShape::Capsule { radius, half_length } => DVec3::new(*radius, *radius, *half_length + *radius),
                GeometryShape::Ellipsoid { radii } => *radii,
                GeometryShape::Mesh { .. } | GeometryShape::Plane => return,
            };
            for k in 0..8 {
                let sign = DVec3::new(
                    if k & 1 == 0 { -1.0 } else { 1.0 },
                    if k & 2 == 0 { -1.0 } else { 1.0 },
                    if k & 4 == 0 { -1.0 } else { 1.0 },
                );
                // geometry_X_link: a corner in geometry coordinates, expressed in the link frame
                let corner_link = g.x_from_link.inv_apply_point(sign * half);
                lo_link = lo_link.min(corner_link);
                hi_link = hi_link.max(corner_link);
            }
        }
        let half_diagonal = 0.5 * (hi_link - lo_link).length();
        // Ī_c = Ī_o − m c̃ c̃ᵀ (parallel-axis theorem, Featherstone 2.63)
        let c = skew(inertia.com());
        let inertia_com = inertia.i_o - inertia.mass * (c * c.transpose());
        let (moments, _) = symmetric_eigen(inertia_com);
        let radius = (moments.max_element().max(0.0) / inertia.mass).sqrt();
        if radius > GYRATION_FACTOR * half_diagonal {
            let at = child(link, "inertial").and_then(|i| child(i, "inertia")).unwrap_or(link);
            let pos = self.doc.text_pos_at(at.range().start);
            warnings.push(format!(
                "{}:{}:{}: link '{}': radius of gyration {:.3e} m (sqrt(largest principal moment / mass)) is more than \
                 {GYRATION_FACTOR} times the half-diagonal {:.3e} m of its collision geometry's bounding box: is the \
                 inertia in kg·m² and about the centre of mass?",
                self.file, pos.row, pos.col, name, radius, half_diagonal
            ));
        }
    }

    /// `<inertial>` of a link: its spatial inertia in the link frame (zero without `<inertial>`).
    fn inertial(
        &self,
        link: Node<'a, 'input>,
        name: &str,
        warnings: &mut Vec<String>,
    ) -> Result<RigidInertia, UrdfError> {
        let Some(inertial) = child(link, "inertial") else { return Ok(RigidInertia::ZERO) };
        let mass_node =
            child(inertial, "mass").ok_or_else(|| self.error(inertial, UrdfErrorKind::MissingElement("mass")))?;
        let mass = match mass_node.attribute("value").map(|t| t.trim().parse::<f64>()) {
            None => return Err(self.error(mass_node, UrdfErrorKind::MissingAttribute("value"))),
            Some(Ok(m)) if m.is_finite() && m >= 0.0 => m,
            Some(Ok(m)) => return Err(self.error(mass_node, UrdfErrorKind::BadMass(m))),
            Some(Err(_)) => return Err(self.error(mass_node, UrdfErrorKind::BadMass(f64::NAN))),
        };
        let (rot, com) = self.origin(inertial)?;
        let node =
            child(inertial, "inertia").ok_or_else(|| self.error(inertial, UrdfErrorKind::MissingElement("inertia")))?;
        let ixx = self.number(node, "ixx", None)?;
        let ixy = self.number(node, "ixy", Some(0.0))?;
        let ixz = self.number(node, "ixz", Some(0.0))?;
        let iyy = self.number(node, "iyy", None)?;
        let iyz = self.number(node, "iyz", Some(0.0))?;
        let izz = self.number(node, "izz", None)?;
        let mut tensor =
            DMat3::from_cols(DVec3::new(ixx, ixy, ixz), DVec3::new(ixy, iyy, iyz), DVec3::new(ixz, iyz, izz));
        if tensor == DMat3::ZERO {
            // mass 0 and no tensor: a massless link (a frame); mass > 0 and no tensor: a point mass
            return Ok(RigidInertia::from_com(mass, com, DMat3::ZERO));
        }
        // physical: the triangle inequality on the eigenvalues (which implies that they are ≥ 0)
        if let Some(defect) = inertia_defect(mass, tensor) {
            if self.options.keep_triangle_violations && !self.options.balance_inertia && defect.is_positive_definite() {
                let pos = self.doc.text_pos_at(node.range().start);
                warnings.push(format!(
                    "{}:{}:{}: link '{}': inertia kept as written: {}; its tensor is positive definite, so the \
                     dynamics stay consistent (`balance_inertia = true` replaces it by the nearest physical one)",
                    self.file, pos.row, pos.col, name, defect
                ));
                return Ok(placed_inertia(mass, com, rot, tensor));
            }
            if !self.options.balance_inertia {
                let at = if mass == 0.0 { mass_node } else { node };
                return Err(self.error(at, UrdfErrorKind::BadInertia { link: name.into(), reason: defect.to_string() }));
            }
            let balanced = nearest_physical(mass, tensor);
            let pos = self.doc.text_pos_at(node.range().start);
            warnings.push(format!(
                "{}:{}:{}: link '{}': inertia balanced: {}; replaced by the nearest physical tensor, principal \
                 moments {:?} kg·m² along the same axes (it changed by {:.3e} of its norm)",
                self.file, pos.row, pos.col, name, defect, balanced.after, balanced.relative_change
            ));
            tensor = balanced.tensor;
        }
        // I_c in the link axes: R I Rᵀ; then shifted to the link origin
        Ok(placed_inertia(mass, com, rot, tensor))
    }

    fn joint(
        &self,
        node: Node<'a, 'input>,
        link_index: &HashMap<&str, usize>,
        warnings: &mut Vec<String>,
    ) -> Result<RawJoint<'a, 'input>, UrdfError> {
        let name = self.attr(node, "name")?;
        let ty = self.attr(node, "type")?;
        let link_of = |role: &'static str| -> Result<usize, UrdfError> {
            let elem = child(node, role).ok_or_else(|| self.error(node, UrdfErrorKind::MissingElement(role)))?;
            let link = self.attr(elem, "link")?;
            link_index.get(link).copied().ok_or_else(|| {
                self.error(elem, UrdfErrorKind::MissingLink { joint: name.into(), role, link: link.into() })
            })
        };
        let parent = link_of("parent")?;
        let child_link = link_of("child")?;
        let (rot, xyz) = self.origin(node)?;
        let x_origin = Xform::from_pose(rot, xyz);
        let mut limits = JointLimits::default();
        if let Some(d) = child(node, "dynamics") {
            limits.damping = self.number(d, "damping", Some(0.0))?;
            limits.friction = self.number(d, "friction", Some(0.0))?;
        }
        let mut axis = || -> Result<DVec3, UrdfError> {
            let Some(a) = child(node, "axis") else { return Ok(DVec3::X) };
            let axis = self.vec3(a, "xyz", DVec3::X)?;
            let n = axis.length();
            if !(1e-6..=1e6).contains(&n) {
                let why = if n == 0.0 { "the zero vector has no direction" } else { "its norm is outside [1e-6, 1e6]" };
                return Err(self.error(a, UrdfErrorKind::BadAxis { axis: axis.to_array(), why }));
            }
            if (n - 1.0).abs() > 1e-9 {
                let pos = self.doc.text_pos_at(a.range().start);
                warnings.push(format!(
                    "{}:{}:{}: joint '{}': axis {:?} normalised (norm {})",
                    self.file,
                    pos.row,
                    pos.col,
                    name,
                    axis.to_array(),
                    n
                ));
            }
            Ok(axis / n)
        };
        let kind = match ty {
            "fixed" => None,
            "revolute" => Some(JointKind::Revolute { axis: axis()? }),
            "continuous" => Some(JointKind::Continuous { axis: axis()? }),
            "prismatic" => Some(JointKind::Prismatic { axis: axis()? }),
            "floating" => Some(JointKind::Floating),
            "planar" => return Err(self.error(node, UrdfErrorKind::UnsupportedJointType(ty.into()))),
            other => return Err(self.error(node, UrdfErrorKind::UnknownJointType(other.into()))),
        };
        match (ty, child(node, "limit")) {
            ("revolute" | "prismatic", None) => return Err(self.error(node, UrdfErrorKind::MissingLimit(ty.into()))),
            (_, Some(l)) => {
                let lower = self.number(l, "lower", Some(0.0))?;
                let upper = self.number(l, "upper", Some(0.0))?;
                if ty != "continuous" {
                    if lower > upper {
                        return Err(self.error(l, UrdfErrorKind::BadLimit(format!("lower {lower} > upper {upper}"))));
                    }
                    limits.position = Some((lower, upper));
                }
                for (attr, slot) in [("effort", &mut limits.effort), ("velocity", &mut limits.velocity)] {
                    if l.attribute(attr).is_some() {
                        let x = self.number(l, attr, None)?;
                        if x < 0.0 {
                            return Err(self.error(l, UrdfErrorKind::BadLimit(format!("{attr} {x} < 0"))));
                        }
                        *slot = Some(x);
                    }
                }
            }
            _ => {}
        }
        Ok(RawJoint { node, name, kind, parent, child: child_link, x_origin, limits })
    }

    /// A joint mimicking itself is an error. A mimic naming no joint is a warning: mimic joints are
    /// independent joints here, so the relation is never used (example-robot-data's
    /// `alex_psyonic_hands.urdf` has twelve such tags, the target names missing their `Left_` prefix).
    fn check_mimics(
        &self,
        joint_nodes: &[Node],
        joint_index: &HashMap<&str, usize>,
        warnings: &mut Vec<String>,
    ) -> Result<(), UrdfError> {
        for &node in joint_nodes {
            if let Some(m) = child(node, "mimic") {
                let name = node.attribute("name").unwrap_or("");
                let target = self.attr(m, "joint")?;
                if target == name {
                    let why = "a joint cannot mimic itself";
                    return Err(
                        self.error(m, UrdfErrorKind::BadMimic { joint: name.into(), target: target.into(), why })
                    );
                }
                if !joint_index.contains_key(target) {
                    let pos = self.doc.text_pos_at(m.range().start);
                    warnings.push(format!(
                        "{}:{}:{}: mimic joint '{}' refers to '{}': no joint has that name (ignored: mimic joints are \
                         independent joints)",
                        self.file, pos.row, pos.col, name, target
                    ));
                }
            }
        }
        Ok(())
    }
}

/// The first child element named `tag`.
fn child<'a, 'input>(node: Node<'a, 'input>, tag: &str) -> Option<Node<'a, 'input>> {
    node.children().find(|n| n.is_element() && n.tag_name().name() == tag)
}

/// Follows parent joints from `start` until a link repeats and prints the cycle
/// `a -(j1)-> b -(j2)-> a` (parent to child); also returns a joint node on it.
fn cycle_from<'a, 'input>(
    start: usize,
    links: &[Link<'a, 'input>],
    joints: &[RawJoint<'a, 'input>],
    parent_joint: &[Option<usize>],
) -> (String, Node<'a, 'input>) {
    let mut seen = vec![false; links.len()];
    let mut l = start;
    // walk up until a link repeats: that link is on the cycle
    while !seen[l] {
        seen[l] = true;
        match parent_joint[l] {
            Some(j) => l = joints[j].parent,
            None => return (format!("{} has no parent", links[l].name), links[l].node),
        }
    }
    let on_cycle = l;
    let mut path = vec![links[on_cycle].name.to_string()];
    let mut node = links[on_cycle].node;
    while let Some(j) = parent_joint[l] {
        node = joints[j].node;
        let p = joints[j].parent;
        path.push(format!("({})", joints[j].name));
        path.push(links[p].name.to_string());
        l = p;
        if l == on_cycle {
            break;
        }
    }
    // the walk went child → parent: print it parent → child
    path.reverse();
    (path.join(" → "), node)
}

/// Resolves a mesh URI of the URDF file `urdf` without touching the file system:
///
/// - `package://PKG/REST`: `REST` under the nearest directory named `PKG` that contains the URDF file
///   (how robot description packages are laid out, e.g. `example-robot-data/robots/…`);
/// - `file:///ABS` and absolute paths: as written;
/// - a relative path: relative to the URDF file's directory.
///
/// `..` components are applied lexically; a package path or a relative path that climbs out of the
/// directory it is resolved against is refused (reliability catalogue U17), as is any other scheme.
pub fn resolve_mesh(urdf: &Path, uri: &str) -> Result<PathBuf, String> {
    let urdf_dir = urdf.parent().unwrap_or(Path::new(""));
    if let Some(rest) = uri.strip_prefix("package://") {
        // `package:///name/…` (an empty host, as some robots write it) names the same package
        let rest = rest.trim_start_matches('/');
        let (package, relative) = rest.split_once('/').ok_or("no path after the package name")?;
        let root = urdf_dir.ancestors().find(|a| a.file_name().is_some_and(|n| n == package)).ok_or_else(|| {
            format!(
                "no directory named '{package}' contains {} (its parent directories were searched; a scene's \
                     `package_paths` lists more directories that hold packages)",
                urdf.display()
            )
        })?;
        return inside(root, relative);
    }
    if let Some(absolute) = uri.strip_prefix("file://") {
        return Ok(PathBuf::from(absolute));
    }
    if let Some((scheme, _)) = uri.split_once("://") {
        return Err(format!("unsupported scheme '{scheme}://'"));
    }
    if Path::new(uri).is_absolute() {
        return Ok(PathBuf::from(uri));
    }
    inside(urdf_dir, uri)
}

/// Resolves a mesh URI as [`resolve_mesh`] does, and looks for `package://NAME/REST` in the
/// directories `package_paths` too (as ROS's `ROS_PACKAGE_PATH` and Pinocchio's `package_dirs`:
/// `DIR/NAME/REST`), after the URDF's parent directories.
///
/// Without package paths nothing touches the file system (the path found by the URDF's parent
/// directories, as [`resolve_mesh`]). With them, the first candidate that is a file wins; when none
/// is, the error lists every path tried.
pub fn resolve_mesh_in(urdf: &Path, uri: &str, package_paths: &[PathBuf]) -> Result<PathBuf, String> {
    let Some(rest) = uri.strip_prefix("package://").filter(|_| !package_paths.is_empty()) else {
        return resolve_mesh(urdf, uri);
    };
    let rest = rest.trim_start_matches('/');
    let (package, relative) = rest.split_once('/').ok_or("no path after the package name")?;
    if matches!(package, "" | "." | "..") {
        return Err(format!("'{package}' is not a package name"));
    }
    let mut tried = Vec::new();
    // the URDF's parent directories first, then each package path
    match resolve_mesh(urdf, uri) {
        Ok(path) => tried.push(path),
        Err(why) if why.starts_with("no directory named") => {}
        Err(why) => return Err(why),
    }
    for dir in package_paths {
        tried.push(inside(&dir.join(package), relative)?);
    }
    if let Some(found) = tried.iter().find(|p| p.is_file()) {
        return Ok(found.clone());
    }
    let list = tried.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ");
    Err(format!("no such file; the paths tried: {list}"))
}

/// `root/relative` with `.` and `..` applied, refused if it leaves `root`.
fn inside(root: &Path, relative: &str) -> Result<PathBuf, String> {
    let mut parts: Vec<&std::ffi::OsStr> = Vec::new();
    for c in Path::new(relative).components() {
        match c {
            Component::Normal(p) => parts.push(p),
            Component::CurDir => {}
            Component::ParentDir => {
                if parts.pop().is_none() {
                    return Err(format!("'{relative}' leaves {}", root.display()));
                }
            }
            Component::RootDir | Component::Prefix(_) => return Err(format!("'{relative}' is not relative")),
        }
    }
    let mut path = root.to_path_buf();
    path.extend(parts);
    Ok(path)
}
