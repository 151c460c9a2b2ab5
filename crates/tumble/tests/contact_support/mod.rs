//! Shared builders for the contact tests: bodies with shapes, a ground plane, a world.
#![allow(dead_code)]

use tumble::body::{Material, Shape};
use tumble::math::{DQuat, DVec3};
use tumble::{MassProperties, RigidBody, World, WorldConfig};

/// A free solid sphere of radius `r` (m) and mass `m` (kg) at `position` (m, world).
pub fn sphere(name: &str, r: f64, m: f64, position: DVec3) -> RigidBody {
    let shape = Shape::Sphere { radius: r };
    let (m1, i1) = shape.mass_properties(1.0).unwrap();
    let mut b = RigidBody::new(name, MassProperties::from_principal(m, i1 * (m / m1)).unwrap());
    b.shape = Some(shape);
    b.state.position = position;
    b
}

/// A free solid box of half extents `h` (m) and mass `m` (kg) at `position` (m, world).
pub fn cuboid(name: &str, h: DVec3, m: f64, position: DVec3) -> RigidBody {
    let shape = Shape::Box { half_extents: h };
    let (m1, i1) = shape.mass_properties(1.0).unwrap();
    let mut b = RigidBody::new(name, MassProperties::from_principal(m, i1 * (m / m1)).unwrap());
    b.shape = Some(shape);
    b.state.position = position;
    b
}

/// A fixed plane through `position` with normal `orientation · z`.
pub fn ground(orientation: DQuat) -> RigidBody {
    let mut b = RigidBody::new("ground", MassProperties::from_principal(1.0, DVec3::ONE).unwrap());
    b.fixed = true;
    b.shape = Some(Shape::Plane);
    b.state.orientation = orientation;
    b
}

/// Sets a body's friction and restitution.
pub fn material(mut b: RigidBody, friction: f64, restitution: f64) -> RigidBody {
    b.material = Material { friction: Some(friction), restitution: Some(restitution) };
    b
}

/// A world with `dt` (s), gravity (m/s²) and the given bodies.
pub fn world(dt: f64, gravity: DVec3, bodies: Vec<RigidBody>) -> World {
    let config = WorldConfig { dt, gravity, integrator: tumble::Integrator::Rk4, ..WorldConfig::default() };
    World::new(config, bodies)
}
