//! Shapes a body may have: for mass properties now, for collisions later.
//!
//! Every shape is centred on the body's origin in the user's body axes; axes of capsules and
//! cylinders are body z; a plane's normal is body +z (planes are for fixed bodies only).

use crate::math::DVec3;

/// A primitive shape, dimensions in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// A ball of radius `radius`.
    Sphere { radius: f64 },
    /// A box with half extents along the body axes.
    Box { half_extents: DVec3 },
    /// A cylinder of radius `radius` and half height `half_height` capped by hemispheres, axis body z.
    Capsule { radius: f64, half_height: f64 },
    /// A cylinder of radius `radius` and half height `half_height`, axis body z.
    Cylinder { radius: f64, half_height: f64 },
    /// The half space below the body's xy plane (normal body +z); fixed bodies only.
    Plane,
}

impl Shape {
    /// The shape's name as written in scene files.
    pub fn type_name(&self) -> &'static str {
        match self {
            Shape::Sphere { .. } => "sphere",
            Shape::Box { .. } => "box",
            Shape::Capsule { .. } => "capsule",
            Shape::Cylinder { .. } => "cylinder",
            Shape::Plane => "plane",
        }
    }

    /// Mass (kg) and principal moments about the centre (kg·m², body axes) of the solid shape of
    /// density `rho` (kg/m³); `None` for a plane, which has no finite volume.
    pub fn mass_properties(&self, rho: f64) -> Option<(f64, DVec3)> {
        use super::mass::{solid_box, solid_capsule, solid_cylinder, solid_sphere};
        match *self {
            Shape::Sphere { radius } => Some(solid_sphere(rho, radius)),
            Shape::Box { half_extents } => Some(solid_box(rho, half_extents)),
            Shape::Capsule { radius, half_height } => Some(solid_capsule(rho, radius, half_height)),
            Shape::Cylinder { radius, half_height } => Some(solid_cylinder(rho, radius, half_height)),
            Shape::Plane => None,
        }
    }
}

/// Contact material of a body (used by the contact solver).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Material {
    /// Coefficient of restitution in [0, 1]; `None`: the world's default.
    pub restitution: Option<f64>,
    /// Coulomb friction coefficient ≥ 0; `None`: the world's default.
    pub friction: Option<f64>,
}
