//! Articulated bodies: Featherstone's spatial algebra and recursive algorithms over a kinematic
//! tree, and robots read from URDF and MJCF.
//!
//! Reference: R. Featherstone, *Rigid Body Dynamics Algorithms*, Springer 2008 (chapter and table
//! numbers in each module). Spatial vectors are `[angular; linear]`.
//!
//! | module        | computes                                                   | cost            |
//! |---------------|------------------------------------------------------------|-----------------|
//! | [`spatial`]   | motion/force vectors, Plücker transforms, inertias, `crm`/`crf` | —          |
//! | [`joint`]     | joint kinds, `X_J(q)`, motion subspaces `S`, `q̇ = G(q) v`  | —               |
//! | [`model`]     | the immutable [`MultibodyModel`] and its builder           | —               |
//! | [`reduce`]    | locked joints: the reduced model (`buildReducedModel`)     | `O(n)` once     |
//! | [`workspace`] | the mutable [`Workspace`], allocated once                  | —               |
//! | [`urdf`]      | URDF → model, with file:line:column errors                 | `O(n)`          |
//! | [`mjcf`]      | MJCF (MuJoCo) → model, the same builder, refusing what it cannot read | `O(n)` |
//! | [`fk`]        | link poses and velocities                                  | `O(n)`          |
//! | [`rnea`](mod@rnea) | inverse dynamics `τ = M q̈ + C q̇ + g`, bias forces         | `O(n)`          |
//! | [`crba`](mod@crba) | the mass matrix `M(q)`                                     | `O(n d)`        |
//! | [`ltdl`]      | `M = Lᵀ D L` without fill-in, and solves                   | `O(n d²)`, `O(n d)` |
//! | [`aba`](mod@aba)   | forward dynamics `q̈ = M⁻¹ (τ − C q̇ − g)`                 | `O(n)`          |
//! | [`impulse_aba`] | `Δv = M⁻¹ J_cᵀ p` of an impulse at a link's point, its `K`, through ABA's `I^A` | `O(n)`, `K` `O(d)` |
//! | [`energy`]    | kinetic and potential energy, centre of mass               | `O(n)`          |
//! | [`jacobian`]  | the Jacobian of a frame                                    | `O(n d)`        |
//! | [`passive`]   | joint damping and springs, `τ = −d v − k (q − q_ref)`, and the fluid's force | `O(n)` |
//! | [`fluid`]     | MuJoCo's inertia-box fluid model: Stokes and quadratic drag, `τ = Σ J_bᵀ w_b` | `O(n)` |
//! | [`tendon`]    | fixed tendons `L = L₀ + Σ c q`: spring-dampers `τ = J_tᵀ f`   | `O(terms)`      |
//! | [`simulate`]  | RK4, semi-implicit and explicit Euler; torques, damping, PD | `O(n)` a stage |
//! | [`limits`]    | joint position limits: speculative impulse + constraint force | `O(n d)` when active |
//!
//! Model vs state: a [`MultibodyModel`] never changes; `q` and `v` are plain slices, and every
//! algorithm is a free function `f(&model, &mut workspace, q, v, ...)` that allocates nothing.
//! Traversals are loops over the parents-first body order, never recursion, so a chain of 10⁵
//! links cannot overflow the stack.

pub mod aba;
pub mod balance;
pub mod contact_point;
pub mod crba;
pub mod energy;
pub mod fk;
pub mod fluid;
pub mod impulse_aba;
pub mod jacobian;
pub mod joint;
pub mod limits;
pub mod link_shapes;
pub mod ltdl;
pub mod mjcf;
pub mod model;
pub mod passive;
pub mod reduce;
pub mod rnea;
pub mod simulate;
pub mod spatial;
pub mod tendon;
pub mod urdf;
mod urdf_vocabulary;
pub mod workspace;

pub use aba::{aba, AbaError};
pub use crba::{crba, CrbaError};
pub use energy::{armature_energy, center_of_mass, kinetic_energy, potential_energy};
pub use fk::{forward_kinematics, update_placements};
pub use fluid::{add_fluid_forces, Fluid, FluidBox, Medium};
pub use jacobian::frame_jacobian;
pub use joint::{JointDynamics, JointKind, JointLimits};
pub use limits::JointLimitSolver;
pub use ltdl::{ltdl_factor, ltdl_solve, FactorError};
pub use model::{
    placed_inertia, Body, Frame, FrameOrigin, GeometryRole, GeometryShape, Joint, LinkGeometry, MeshRef, ModelBuilder,
    ModelError, MultibodyModel,
};
pub use passive::{add_passive_forces, passive_forces, spring_energy};
pub use reduce::{kept_coordinates, reduced_model, LockError};
pub(crate) use rnea::bias_forces_placed;
pub use rnea::{bias_forces, rnea};
pub use simulate::{ContactChange, Control, Method, PdWave, Simulator, TendonDrive};
pub use spatial::{ArticulatedInertia, Force, Motion, RigidInertia, Xform};
pub use tendon::{FixedTendon, TendonTerm};
pub use urdf::{load_urdf, parse_urdf, ChildOrder, Massless, UrdfError, UrdfErrorKind, UrdfOptions};
pub use workspace::{LengthError, TooLarge, Workspace, MAX_DENSE_NV};
