//! Rigid bodies: mass properties, state and the loads acting on them.
//!
//! Frames: the *body frame* of a [`RigidBody`] has its origin at the centre of mass and its axes along
//! the principal axes, so that `I_body` is diagonal. When a scene gives a full inertia tensor the
//! user's axes differ from the principal ones by [`MassProperties::user_from_body`]; the accessors
//! ending in `_user` speak of the user's axes, as files do.

pub mod dynamics;
pub mod mass;
pub mod shape;
pub mod solid;

pub use mass::{MassError, MassProperties};
pub use shape::{CompoundPart, CompoundShape, ConvexPiece, ConvexShape, Material, MeshShape, Shape, ShapeProblem};

use crate::math::{DMat3, DQuat, DVec3};

/// The state of a free rigid body (the unknowns of the Newton–Euler ODE).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyState {
    /// Position of the centre of mass, world frame (m).
    pub position: DVec3,
    /// Unit quaternion `world_from_body` (body principal axes → world).
    pub orientation: DQuat,
    /// Velocity of the centre of mass, world frame (m/s).
    pub velocity: DVec3,
    /// Angular velocity, body frame (rad/s).
    pub omega_body: DVec3,
}

impl BodyState {
    /// A body at rest at the origin with the identity orientation.
    pub const REST: Self =
        Self { position: DVec3::ZERO, orientation: DQuat::IDENTITY, velocity: DVec3::ZERO, omega_body: DVec3::ZERO };

    /// Angular velocity in the world frame, `ω_world = R ω_body` (rad/s).
    #[inline]
    pub fn omega_world(&self) -> DVec3 {
        self.orientation * self.omega_body
    }

    /// Whether every component is finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.position.is_finite()
            && self.orientation.is_finite()
            && self.velocity.is_finite()
            && self.omega_body.is_finite()
    }
}

/// A force applied at a point fixed in the body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointForce {
    /// Point of application relative to the centre of mass, body frame (m).
    pub point_body: DVec3,
    /// The force (N), in the frame named by `frame`.
    pub force: DVec3,
    /// Frame of `force`: world (fixed direction in space) or body (turns with the body).
    pub frame: Frame,
}

/// Which frame a vector is expressed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Frame {
    World,
    Body,
}

/// The external loads on a body besides gravity, all constant in their own frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Loads {
    /// Force at the centre of mass, world frame (N).
    pub force_world: DVec3,
    /// Force at the centre of mass, body frame (N).
    pub force_body: DVec3,
    /// Torque, world frame (N·m).
    pub torque_world: DVec3,
    /// Torque, body frame (N·m).
    pub torque_body: DVec3,
    /// Forces applied at points of the body.
    pub point_forces: Vec<PointForce>,
    /// Linear damping coefficient `c` (1/s): adds the force `−c m v`.
    pub linear_damping: f64,
    /// Angular damping coefficient `c` (1/s): adds the torque `−c I_body ω_body`.
    pub angular_damping: f64,
}

impl Loads {
    /// Whether the loads depend on the orientation (and the rotation matrix must be formed).
    #[inline]
    pub fn needs_rotation(&self) -> bool {
        self.force_body != DVec3::ZERO || self.torque_world != DVec3::ZERO || !self.point_forces.is_empty()
    }

    /// Whether there is no load at all besides gravity.
    #[inline]
    pub fn is_empty(&self) -> bool {
        *self == Loads::default()
    }
}

/// A rigid body: its name, mass properties, state and loads.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBody {
    /// Unique name (from the scene file).
    pub name: String,
    /// Mass and principal moments.
    pub mass: MassProperties,
    /// Current state.
    pub state: BodyState,
    /// External loads besides gravity.
    pub loads: Loads,
    /// A fixed body never moves and is not integrated.
    pub fixed: bool,
    /// Its shape, if any (user's body axes, centred on the centre of mass).
    pub shape: Option<Shape>,
    /// Contact material.
    pub material: Material,
    /// Factor on the world's gravity for this body (any finite value, default 1): its gravitational
    /// acceleration is `gravity_scale · g` ([`RigidBody::gravity`]).
    pub gravity_scale: f64,
}

impl RigidBody {
    /// A free body at rest at the origin with no loads.
    pub fn new(name: impl Into<String>, mass: MassProperties) -> Self {
        Self {
            name: name.into(),
            mass,
            state: BodyState::REST,
            loads: Loads::default(),
            fixed: false,
            shape: None,
            material: Material::default(),
            gravity_scale: 1.0,
        }
    }

    /// The body's gravitational acceleration, `gravity_scale · g`, world frame (m/s²), from the
    /// world's gravity `gravity_world` (m/s², world frame). Every stage that applies gravity to a
    /// body goes through here (integration, contacts, potential energy).
    #[inline]
    pub fn gravity(&self, gravity_world: DVec3) -> DVec3 {
        self.gravity_scale * gravity_world
    }

    /// Orientation `world_from_user`: the rotation of the axes the user gave (as written in files).
    #[inline]
    pub fn orientation_user(&self) -> DQuat {
        self.state.orientation * self.mass.user_from_body.conjugate()
    }

    /// Sets the orientation from `world_from_user` (as read from files).
    #[inline]
    pub fn set_orientation_user(&mut self, world_from_user: DQuat) {
        self.state.orientation = (world_from_user * self.mass.user_from_body).normalize();
    }

    /// Sets the angular velocity from the world frame (rad/s).
    #[inline]
    pub fn set_omega_world(&mut self, omega_world: DVec3) {
        self.state.omega_body = self.state.orientation.conjugate() * omega_world;
    }

    /// Sets the angular velocity from the user's body axes (rad/s).
    #[inline]
    pub fn set_omega_user(&mut self, omega_user: DVec3) {
        self.state.omega_body = self.mass.user_from_body.conjugate() * omega_user;
    }

    /// Angular momentum about the centre of mass, body frame, `L_body = I_body ω_body` (kg·m²/s).
    #[inline]
    pub fn angular_momentum_body(&self) -> DVec3 {
        self.mass.inertia_body * self.state.omega_body
    }

    /// Total angular momentum about the world origin, world frame:
    /// `L = x × m v + R I_body ω_body` (kg·m²/s).
    #[inline]
    pub fn angular_momentum_world(&self) -> DVec3 {
        let s = &self.state;
        s.position.cross(self.mass.mass * s.velocity) + s.orientation * self.angular_momentum_body()
    }

    /// Kinetic energy `½ m |v|² + ½ ω_bodyᵀ I_body ω_body` (J).
    #[inline]
    pub fn kinetic_energy(&self) -> f64 {
        let s = &self.state;
        0.5 * self.mass.mass * s.velocity.length_squared()
            + 0.5 * s.omega_body.dot(self.mass.inertia_body * s.omega_body)
    }

    /// Gravitational potential energy `−m g_body · x` (J), zero at the world origin, with the body's
    /// own acceleration `g_body = gravity_scale · gravity` from the world's `gravity` (m/s², world frame).
    #[inline]
    pub fn potential_energy(&self, gravity: DVec3) -> f64 {
        -self.mass.mass * self.gravity(gravity).dot(self.state.position)
    }

    /// The inertia tensor in the world frame, `I_world = R I_body Rᵀ` (1.2) (kg·m²).
    #[inline]
    pub fn inertia_world(&self) -> DMat3 {
        crate::math::inertia_world(DMat3::from_quat(self.state.orientation), self.mass.inertia_body)
    }
}

#[cfg(test)]
mod tests;
