//! The immutable model of a kinematic tree: bodies, joints, inertias and joint placements.
//!
//! Bodies are numbered `0..n` so that a body's parent comes before it (`parent[i] < i`); a body
//! whose parent is `None` hangs from the world (the fixed base, or the floating joint of a
//! floating base). Body `i` is moved by joint `i`. Links attached by fixed joints are merged into
//! the body they are fixed to and kept as named [`Frame`]s.
//!
//! Coordinates: joint `i` owns `q[q_index .. q_index + nq]` and `v[v_index .. v_index + nv]`.

use super::joint::{JointDynamics, JointKind, JointLimits};
use super::spatial::{Motion, RigidInertia, Xform};
use super::workspace::{check_len, LengthError};
use crate::math::{DMat3, DVec3};

/// Why a model could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    #[error("joint '{joint}': its axis must be finite and non-zero (got {axis:?})")]
    BadAxis { joint: String, axis: [f64; 3] },
    #[error("joint '{joint}': its placement must be finite")]
    NonFinitePlacement { joint: String },
    #[error("body '{body}': its parent index {parent} is not an earlier body")]
    BadParent { body: String, parent: usize },
    #[error("joint '{joint}': {what}")]
    BadJointDynamics { joint: String, what: String },
    #[error("body '{body}': its inertia must be finite with mass ≥ 0")]
    BadInertia { body: String },
    #[error(
        "joint '{joint}' moves a subtree without mass (body '{body}' and its descendants): \
         the mass matrix would be singular (`tumble model` and `tumble dynamics` take `--massless fuse` to hold it at \
         q = 0)"
    )]
    MasslessSubtree { joint: String, body: String },
}

/// A joint of the tree.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// Unique name.
    pub name: String,
    /// Kind and axis.
    pub kind: JointKind,
    /// `X_T = jointframe_X_parent`: the joint frame (the child's frame at `q = 0`) placed in the
    /// parent body's frame.
    pub x_tree: Xform,
    /// First configuration coordinate.
    pub q_index: usize,
    /// First velocity coordinate.
    pub v_index: usize,
    /// Limits and damping (informational).
    pub limits: JointLimits,
    /// Armature, damping and spring, used by the dynamics (zero from URDF).
    pub dynamics: JointDynamics,
    /// The parent link's name as written in the source (the world for the root).
    pub parent_link: String,
}

/// A body of the tree (a link, with the links fixed to it merged in).
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// The link's name.
    pub name: String,
    /// Parent body; `None` for the world.
    pub parent: Option<usize>,
    /// The joint that moves this body.
    pub joint: Joint,
    /// Spatial inertia in this body's frame, including the links fixed to it.
    pub inertia: RigidInertia,
}

/// A named frame fixed to a body (every link of the source, merged or not), in depth-first order.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// The link's name.
    pub name: String,
    /// The body it is fixed to; `None` for the world (the fixed base and what is fixed to it).
    pub body: Option<usize>,
    /// `frame_X_body`: the frame's placement in the body's (or the world's) frame.
    pub x_from_body: Xform,
    /// How the frame is attached.
    pub origin: FrameOrigin,
    /// The link's own spatial inertia, in this frame's coordinates (what the source gave the link,
    /// before merging): the bodies' inertias are sums of these, so the links of a tree carry its whole
    /// mass once. Zero for a massless link (a tool frame).
    pub inertia: RigidInertia,
}

/// How a frame is attached to the tree.
#[derive(Debug, Clone, PartialEq)]
pub enum FrameOrigin {
    /// The root link of a fixed base (fixed to the world).
    Root,
    /// The frame of a body, moved by that body's joint.
    Body(usize),
    /// A link attached by a fixed joint, merged into the body it is fixed to.
    Fixed {
        /// The fixed joint's name.
        joint: String,
        /// The link on the other side of the fixed joint.
        parent_link: String,
    },
}

/// A mesh named by a link's `<visual>` or `<collision>` geometry (recorded, not read: the dynamics
/// needs no mesh).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshRef {
    /// The link whose geometry names it.
    pub link: String,
    /// The URI as written (`package://…`, a relative or absolute path, `file://…`).
    pub uri: String,
    /// The file it resolves to, or `None` (with a warning) when it cannot be resolved or leaves the
    /// directory it is resolved against.
    pub path: Option<std::path::PathBuf>,
    /// 1-based line of the `<visual>` or `<collision>` element that names it.
    pub line: u32,
}

/// Whether a link's geometry is for contact (`<collision>`) or for drawing (`<visual>`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GeometryRole {
    Collision,
    Visual,
}

/// The shape of a link's geometry, in the geometry's own frame (SI units).
#[derive(Debug, Clone, PartialEq)]
pub enum GeometryShape {
    /// `<box size>`: a box of these half extents about the geometry frame's origin (m).
    Box { half_extents: DVec3 },
    /// `<cylinder radius length>`: a cylinder about the geometry frame's z axis, centred (m).
    Cylinder { radius: f64, half_length: f64 },
    /// `<sphere radius>` (m).
    Sphere { radius: f64 },
    /// `<mesh filename scale>`: the file it resolves to (`None`: not resolved, with a warning)
    /// and the scale per axis of the geometry frame (non-zero; a negative factor mirrors).
    Mesh { uri: String, path: Option<std::path::PathBuf>, scale: DVec3 },
    /// A cylinder of this radius and half length about the frame's z axis, capped by hemispheres
    /// (MJCF `capsule`; m).
    Capsule { radius: f64, half_length: f64 },
    /// An ellipsoid of these semi-axes along the frame's axes (MJCF `ellipsoid`; m).
    Ellipsoid { radii: DVec3 },
    /// The half space below the frame's xy plane, normal +z (MJCF `plane`; fixed to the world).
    Plane,
}

impl GeometryShape {
    /// Volume (m³) and the principal moments of inertia per unit mass about the shape's centre, in
    /// its frame (m²), of a solid of uniform density; `None` for a mesh (not read here) and a
    /// plane (no volume).
    ///
    /// The formulas MuJoCo uses for its primitives (`mjCGeom::SetInertia`): a sphere
    /// `⅖ r²`; a box of half extents `a, b, c`, `(b² + c²)/3, …`; a cylinder of length `h = 2 l`,
    /// `(3 r² + h²)/12, …, r²/2`; an ellipsoid `(b² + c²)/5, …`; a capsule as its cylinder plus two
    /// half balls at its ends, `m_c (3 r² + h²)/12 + m_s (⅖ r² + h (3 r + 2 h)/8)` about x and y,
    /// `m_c r²/2 + ⅖ m_s r²` about z (`m_c`, `m_s` the masses of the cylinder and of the ball).
    pub fn unit_mass_properties(&self) -> Option<(f64, DVec3)> {
        use std::f64::consts::PI;
        match *self {
            GeometryShape::Sphere { radius: r } => Some((4.0 / 3.0 * PI * r.powi(3), DVec3::splat(0.4 * r * r))),
            GeometryShape::Box { half_extents: e } => {
                let (a, b, c) = (e.x * e.x, e.y * e.y, e.z * e.z);
                Some((8.0 * e.x * e.y * e.z, DVec3::new(b + c, a + c, a + b) / 3.0))
            }
            GeometryShape::Cylinder { radius: r, half_length } => {
                let h = 2.0 * half_length;
                let side = (3.0 * r * r + h * h) / 12.0;
                Some((PI * r * r * h, DVec3::new(side, side, 0.5 * r * r)))
            }
            GeometryShape::Ellipsoid { radii: e } => {
                let (a, b, c) = (e.x * e.x, e.y * e.y, e.z * e.z);
                Some((4.0 / 3.0 * PI * e.x * e.y * e.z, DVec3::new(b + c, a + c, a + b) / 5.0))
            }
            GeometryShape::Capsule { radius: r, half_length } => {
                let h = 2.0 * half_length;
                let v_ball = 4.0 / 3.0 * PI * r.powi(3);
                let v_cyl = PI * r * r * h;
                let volume = v_ball + v_cyl;
                // per unit mass: the ball's and the cylinder's shares of it
                let (m_s, m_c) = (v_ball / volume, v_cyl / volume);
                let side = m_c * (3.0 * r * r + h * h) / 12.0 + m_s * (0.4 * r * r + h * (3.0 * r + 2.0 * h) / 8.0);
                Some((volume, DVec3::new(side, side, (0.5 * m_c + 0.4 * m_s) * r * r)))
            }
            GeometryShape::Mesh { .. } | GeometryShape::Plane => None,
        }
    }
}

/// The spatial inertia of a part of mass `mass` (kg) whose centre of mass is at `com` (m) and whose
/// inertia about it is `tensor` (kg·m²) along axes rotated by `axes` (`frame_from_axes`), all in
/// the frame the result is expressed in: `Ī_c = R I Rᵀ`, then shifted to the frame's origin
/// (Featherstone (2008) (2.63)). URDF's `<inertial>` and MJCF's `<inertial>` and geoms use it.
pub fn placed_inertia(mass: f64, com: DVec3, axes: DMat3, tensor: DMat3) -> RigidInertia {
    RigidInertia::from_com(mass, com, axes * tensor * axes.transpose())
}

/// One `<collision>` or `<visual>` element of a link: its shape placed in the link frame.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkGeometry {
    /// The link (a frame of the model).
    pub link: String,
    /// The element's `name`, if it has one (MJCF geoms; URDF `<collision name>`).
    pub name: Option<String>,
    pub role: GeometryRole,
    /// `geometry_X_link`: the geometry frame's placement in the link frame (its `<origin>`).
    pub x_from_link: Xform,
    pub shape: GeometryShape,
    /// 1-based line of the `<collision>` or `<visual>` element.
    pub line: u32,
    /// Collision filter bits (MJCF `contype`, `conaffinity`; 1 and 1 from URDF): two geometries may
    /// touch when `(contype₁ & conaffinity₂) | (contype₂ & conaffinity₁) ≠ 0`.
    pub contype: u32,
    pub conaffinity: u32,
    /// Sliding friction coefficient given by the source (MJCF `friction[0]`), if any.
    pub friction: Option<f64>,
}

/// The immutable model: the tree, joints, inertias and gravity.
#[derive(Debug, Clone, PartialEq)]
pub struct MultibodyModel {
    /// The robot's name.
    pub name: String,
    /// Gravity in the world frame (m/s²), `[0, 0, −9.81]` by default.
    pub gravity: DVec3,
    /// Bodies, parents first.
    pub bodies: Vec<Body>,
    /// Named frames (all links).
    pub frames: Vec<Frame>,
    /// Total mass of the moving bodies and of what is fixed to the world (kg).
    pub total_mass: f64,
    /// Inertia fixed to the world (the fixed base and links fixed to it), world frame.
    pub world_inertia: RigidInertia,
    /// Non-fatal remarks from the source (unknown tags, normalised axes, unresolved meshes).
    pub warnings: Vec<String>,
    /// Every `<collision>` and `<visual>` geometry of the links, in file order.
    pub geometries: Vec<LinkGeometry>,
    /// The joints locked by [`reduced_model`](super::reduce::reduced_model) and the values (their
    /// `q`) they are held at, in the source model's order; empty for a model as read.
    pub locked: Vec<(String, Vec<f64>)>,
    /// Fixed tendons (MJCF `<tendon><fixed>`): linear couplings of joint positions whose springs,
    /// dampers, actuators and limits act on several joints at once ([`super::tendon`]); empty
    /// from URDF.
    pub tendons: Vec<super::tendon::FixedTendon>,
    /// The medium the bodies move in and their equivalent boxes (MJCF `<option density viscosity
    /// wind>`, [`super::fluid`]); a void medium (the default, and every URDF model) exerts no force.
    pub fluid: super::fluid::Fluid,
    nq: usize,
    nv: usize,
    /// Motion subspace columns, one per velocity coordinate (child frame).
    subspace: Vec<Motion>,
    /// The body each velocity coordinate belongs to.
    dof_body: Vec<usize>,
    /// `λ(k)`: the velocity coordinate before `k` on the path to the root, `usize::MAX` for none.
    dof_parent: Vec<usize>,
    /// Offset of each body's block in a packed array of `nv_j × nv_j` blocks.
    block_offset: Vec<usize>,
}

/// No parent (index sentinel in the per-dof arrays).
pub const NONE: usize = usize::MAX;

impl MultibodyModel {
    /// Number of configuration coordinates.
    #[inline]
    pub fn nq(&self) -> usize {
        self.nq
    }

    /// Number of velocity coordinates (degrees of freedom).
    #[inline]
    pub fn nv(&self) -> usize {
        self.nv
    }

    /// Number of bodies (= moving joints).
    #[inline]
    pub fn nbodies(&self) -> usize {
        self.bodies.len()
    }

    /// The motion subspace columns of body `i`'s joint (child frame).
    #[inline]
    pub fn subspace(&self, i: usize) -> &[Motion] {
        let j = &self.bodies[i].joint;
        &self.subspace[j.v_index..j.v_index + j.kind.nv()]
    }

    /// The motion subspace column of velocity coordinate `k`.
    #[inline]
    pub fn subspace_column(&self, k: usize) -> Motion {
        self.subspace[k]
    }

    /// The body that velocity coordinate `k` moves.
    #[inline]
    pub fn dof_body(&self, k: usize) -> usize {
        self.dof_body[k]
    }

    /// `λ(k)` of the LTDL factorisation: the previous velocity coordinate towards the root.
    #[inline]
    pub fn dof_parent(&self, k: usize) -> usize {
        self.dof_parent[k]
    }

    /// Offset of body `i`'s `nv_i × nv_i` block in packed per-joint storage.
    #[inline]
    pub(crate) fn block_offset(&self, i: usize) -> usize {
        self.block_offset[i]
    }

    /// Total length of the packed per-joint blocks.
    #[inline]
    pub(crate) fn block_len(&self) -> usize {
        *self.block_offset.last().unwrap_or(&0)
    }

    /// The neutral configuration (zero angles, identity quaternions).
    pub fn neutral_configuration(&self) -> Vec<f64> {
        let mut q = vec![0.0; self.nq];
        for b in &self.bodies {
            let j = &b.joint;
            j.kind.neutral(&mut q[j.q_index..j.q_index + j.kind.nq()]);
        }
        q
    }

    /// The joints whose subtree (their body and its descendants) has no mass, in body order: the
    /// rows of the mass matrix that are zero. Empty for a model built by [`ModelBuilder::build`].
    pub fn massless_joints(&self) -> Vec<&str> {
        let mut subtree_mass: Vec<f64> = self.bodies.iter().map(|b| b.inertia.mass).collect();
        // children before parents (parent[i] < i)
        for i in (0..self.bodies.len()).rev() {
            if let Some(p) = self.bodies[i].parent {
                subtree_mass[p] += subtree_mass[i];
            }
        }
        self.bodies.iter().zip(&subtree_mass).filter(|(_, &m)| m <= 0.0).map(|(b, _)| b.joint.name.as_str()).collect()
    }

    /// The index of the body whose joint is named `name`.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.joint.name == name)
    }

    /// The index of the frame named `name`.
    pub fn frame_index(&self, name: &str) -> Option<usize> {
        self.frames.iter().position(|f| f.name == name)
    }

    /// The meshes named by the links' geometry, in file order (from [`geometries`](Self::geometries)).
    pub fn meshes(&self) -> Vec<MeshRef> {
        self.geometries
            .iter()
            .filter_map(|g| match &g.shape {
                GeometryShape::Mesh { uri, path, .. } => {
                    Some(MeshRef { link: g.link.clone(), uri: uri.clone(), path: path.clone(), line: g.line })
                }
                _ => None,
            })
            .collect()
    }

    /// Where a link geometry sits: the body it is fixed to (`None`: the world) and
    /// `geometry_X_body = geometry_X_link · link_X_body`. `None` if its link is not a frame.
    pub fn geometry_placement(&self, geometry: &LinkGeometry) -> Option<(Option<usize>, Xform)> {
        let frame = &self.frames[self.frame_index(&geometry.link)?];
        Some((frame.body, geometry.x_from_link.compose(&frame.x_from_body)))
    }

    /// `q̇ = G(q) v` for the whole tree, written into `qd` (lengths nq, nv, nq).
    pub fn coordinate_rate(&self, q: &[f64], v: &[f64], qd: &mut [f64]) -> Result<(), LengthError> {
        check_len("q", q.len(), self.nq)?;
        check_len("v", v.len(), self.nv)?;
        check_len("qd", qd.len(), self.nq)?;
        for b in &self.bodies {
            let j = &b.joint;
            let (qi, vi, nq) = (j.q_index, j.v_index, j.kind.nq());
            j.kind.coordinate_rate(&q[qi..qi + nq], &v[vi..vi + j.kind.nv()], &mut qd[qi..qi + nq]);
        }
        Ok(())
    }

    /// `q ⊕ v dt` for the whole tree, written into `q_next` (see [`JointKind`]'s integration: additive
    /// for one-coordinate joints, the exponential map for rotations).
    pub fn integrate(&self, q: &[f64], v: &[f64], dt: f64, q_next: &mut [f64]) -> Result<(), LengthError> {
        check_len("q", q.len(), self.nq)?;
        check_len("v", v.len(), self.nv)?;
        check_len("q_next", q_next.len(), self.nq)?;
        for b in &self.bodies {
            let j = &b.joint;
            let (qi, vi, nq) = (j.q_index, j.v_index, j.kind.nq());
            j.kind.integrate(&q[qi..qi + nq], &v[vi..vi + j.kind.nv()], dt, &mut q_next[qi..qi + nq]);
        }
        Ok(())
    }
}

/// Builds a [`MultibodyModel`] body by body (parents first).
#[derive(Debug, Clone, Default)]
pub struct ModelBuilder {
    name: String,
    bodies: Vec<Body>,
    frames: Vec<Frame>,
    world_inertia: RigidInertia,
    warnings: Vec<String>,
    geometries: Vec<LinkGeometry>,
    nq: usize,
    nv: usize,
}

impl ModelBuilder {
    /// An empty tree named `name`.
    pub fn new(name: impl Into<String>) -> Self {
        Self { name: name.into(), ..Self::default() }
    }

    /// Adds a body moved by a joint of `kind` placed at `x_tree = jointframe_X_parent` in its parent
    /// (`None`: the world), with spatial inertia `inertia` in its own frame. Returns its index.
    ///
    /// Axes must be finite and non-zero; they are normalised.
    pub fn add_body(
        &mut self,
        name: impl Into<String>,
        parent: Option<usize>,
        joint_name: impl Into<String>,
        kind: JointKind,
        x_tree: Xform,
        inertia: RigidInertia,
    ) -> Result<usize, ModelError> {
        let name = name.into();
        let joint_name = joint_name.into();
        if let Some(p) = parent {
            if p >= self.bodies.len() {
                return Err(ModelError::BadParent { body: name, parent: p });
            }
        }
        let kind = normalise_axis(kind, &joint_name)?;
        if !(x_tree.e.is_finite() && x_tree.r.is_finite()) {
            return Err(ModelError::NonFinitePlacement { joint: joint_name });
        }
        if !(inertia.mass >= 0.0 && inertia.mass.is_finite() && inertia.h.is_finite() && inertia.i_o.is_finite()) {
            return Err(ModelError::BadInertia { body: name });
        }
        let parent_link = match parent {
            Some(p) => self.bodies[p].name.clone(),
            None => "world".to_string(),
        };
        let joint = Joint {
            name: joint_name,
            kind,
            x_tree,
            q_index: self.nq,
            v_index: self.nv,
            limits: JointLimits::default(),
            dynamics: JointDynamics::default(),
            parent_link,
        };
        self.nq += kind.nq();
        self.nv += kind.nv();
        let index = self.bodies.len();
        self.frames.push(Frame {
            name: name.clone(),
            body: Some(index),
            x_from_body: Xform::IDENTITY,
            origin: FrameOrigin::Body(index),
            inertia,
        });
        self.bodies.push(Body { name, parent, joint, inertia });
        Ok(index)
    }

    /// Sets the limits of the joint of body `index`.
    pub fn set_limits(&mut self, index: usize, limits: JointLimits) {
        if let Some(b) = self.bodies.get_mut(index) {
            b.joint.limits = limits;
        }
    }

    /// Sets the armature, damping, spring and friction loss of the joint of body `index`: each
    /// coefficient finite and ≥ 0, a spring only on a one-coordinate joint.
    pub fn set_dynamics(&mut self, index: usize, dynamics: JointDynamics) -> Result<(), ModelError> {
        let Some(b) = self.bodies.get_mut(index) else { return Ok(()) };
        let bad = |what: String| ModelError::BadJointDynamics { joint: b.joint.name.clone(), what };
        for (name, x) in [
            ("armature", dynamics.armature),
            ("damping", dynamics.damping),
            ("stiffness", dynamics.stiffness),
            ("friction_loss", dynamics.friction_loss),
        ] {
            if !(x.is_finite() && x >= 0.0) {
                return Err(bad(format!("{name} must be finite and ≥ 0 (got {x})")));
            }
        }
        if !dynamics.spring_ref.is_finite() {
            return Err(bad(format!("the spring's reference must be finite (got {})", dynamics.spring_ref)));
        }
        if dynamics.stiffness != 0.0 && b.joint.kind.nv() != 1 {
            return Err(bad(format!("a spring needs a one-coordinate joint (this one is {})", b.joint.kind.name())));
        }
        b.joint.dynamics = dynamics;
        Ok(())
    }

    /// Adds inertia (in the body's frame) to body `index`, or to the world for `None`.
    pub fn add_inertia(&mut self, index: Option<usize>, inertia: RigidInertia) {
        match index.and_then(|i| self.bodies.get_mut(i)) {
            Some(b) => b.inertia += inertia,
            None => self.world_inertia += inertia,
        }
    }

    /// Places the frame of body `index` (the one [`add_body`](Self::add_body) named after it) at
    /// `frame_X_body` instead of on the body's joint frame: for a source whose link frame is not
    /// where the joint moves it about (an MJCF joint with a `pos`).
    pub fn place_body_frame(&mut self, index: usize, x_from_body: Xform) {
        if let Some(f) = self.frames.iter_mut().find(|f| f.origin == FrameOrigin::Body(index)) {
            f.x_from_body = x_from_body;
        }
    }

    /// Adds a link fixed to `body` (`None`: the world) at `link_X_body`, with its own inertia
    /// `inertia_link` (link frame): the inertia joins the body's, the link stays a named frame.
    pub fn add_fixed_link(
        &mut self,
        name: impl Into<String>,
        body: Option<usize>,
        x_from_body: Xform,
        origin: FrameOrigin,
        inertia_link: RigidInertia,
    ) {
        // I_body += link_X_body* I_link body_X_link
        self.add_inertia(body, inertia_link.transform_to_a(&x_from_body));
        self.add_frame(name, body, x_from_body, origin, inertia_link);
    }

    /// Adds a named frame fixed to `body` (`None`: the world) at `frame_X_body`, for a link whose own
    /// inertia is `inertia` (in the frame's coordinates; it is not added to the body: see
    /// [`add_inertia`](Self::add_inertia)).
    pub fn add_frame(
        &mut self,
        name: impl Into<String>,
        body: Option<usize>,
        x_from_body: Xform,
        origin: FrameOrigin,
        inertia: RigidInertia,
    ) {
        self.frames.push(Frame { name: name.into(), body, x_from_body, origin, inertia });
    }

    /// Names the link on the parent side of body `index`'s joint (by default the parent body's name).
    pub fn set_parent_link(&mut self, index: usize, parent_link: impl Into<String>) {
        if let Some(b) = self.bodies.get_mut(index) {
            b.joint.parent_link = parent_link.into();
        }
    }

    /// Records a link's collision or visual geometry.
    pub fn add_geometry(&mut self, geometry: LinkGeometry) {
        self.geometries.push(geometry);
    }

    /// Records a non-fatal remark.
    pub fn warn(&mut self, message: impl Into<String>) {
        self.warnings.push(message.into());
    }

    /// Checks that every moving subtree has mass and builds the model.
    pub fn build(self) -> Result<MultibodyModel, ModelError> {
        let n = self.bodies.len();
        // subtree masses, children before parents (parent[i] < i)
        let mut subtree_mass: Vec<f64> = self.bodies.iter().map(|b| b.inertia.mass).collect();
        for i in (0..n).rev() {
            if let Some(p) = self.bodies[i].parent {
                subtree_mass[p] += subtree_mass[i];
            }
        }
        for (i, b) in self.bodies.iter().enumerate() {
            if subtree_mass[i] <= 0.0 {
                return Err(ModelError::MasslessSubtree { joint: b.joint.name.clone(), body: b.name.clone() });
            }
        }
        self.build_allowing_massless()
    }

    /// Builds the model without checking that every moving subtree has mass: its mass matrix is
    /// singular where one has none. For a model that [`reduced_model`](super::reduce::reduced_model)
    /// then makes regular by locking those joints (the reduced model is checked).
    pub fn build_allowing_massless(self) -> Result<MultibodyModel, ModelError> {
        let n = self.bodies.len();
        let mut subspace = Vec::with_capacity(self.nv);
        let mut dof_body = Vec::with_capacity(self.nv);
        let mut dof_parent = Vec::with_capacity(self.nv);
        let mut block_offset = Vec::with_capacity(n + 1);
        let mut offset = 0;
        for (i, b) in self.bodies.iter().enumerate() {
            let nv = b.joint.kind.nv();
            // the last dof of the parent's joint precedes this joint's first dof
            let mut previous = match b.parent {
                Some(p) => self.bodies[p].joint.v_index + self.bodies[p].joint.kind.nv() - 1,
                None => NONE,
            };
            for (k, s) in b.joint.kind.motion_subspace().into_iter().enumerate() {
                subspace.push(s);
                dof_body.push(i);
                dof_parent.push(previous);
                previous = b.joint.v_index + k;
            }
            block_offset.push(offset);
            offset += nv * nv;
        }
        block_offset.push(offset);
        let total_mass = self.world_inertia.mass + self.bodies.iter().map(|b| b.inertia.mass).sum::<f64>();
        Ok(MultibodyModel {
            name: self.name,
            gravity: DVec3::new(0.0, 0.0, -9.81),
            bodies: self.bodies,
            frames: self.frames,
            total_mass,
            world_inertia: self.world_inertia,
            warnings: self.warnings,
            geometries: self.geometries,
            locked: Vec::new(),
            tendons: Vec::new(),
            fluid: super::fluid::Fluid::default(),
            nq: self.nq,
            nv: self.nv,
            subspace,
            dof_body,
            dof_parent,
            block_offset,
        })
    }
}

fn normalise_axis(kind: JointKind, joint: &str) -> Result<JointKind, ModelError> {
    let fix = |axis: DVec3| -> Result<DVec3, ModelError> {
        let n = axis.length();
        if !(n.is_finite() && n > 0.0) {
            return Err(ModelError::BadAxis { joint: joint.to_string(), axis: axis.to_array() });
        }
        Ok(axis / n)
    };
    Ok(match kind {
        JointKind::Revolute { axis } => JointKind::Revolute { axis: fix(axis)? },
        JointKind::Continuous { axis } => JointKind::Continuous { axis: fix(axis)? },
        JointKind::Prismatic { axis } => JointKind::Prismatic { axis: fix(axis)? },
        other => other,
    })
}
