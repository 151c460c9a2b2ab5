//! # tumble — rigid-body dynamics as the textbooks derive it
//!
//! - [`math`]: frames, rotations, the cross-product matrix (`skew`), quaternion exponential map.
//! - [`body`]: rigid bodies, mass properties, the Newton–Euler equations (body and world forms).
//! - [`integrate`]: explicit and semi-implicit Euler, RK4, Dormand–Prince 5(4), and the symplectic
//!   Lie–Poisson splittings of 2nd and 4th order.
//! - [`collision`]: collision geometry (parry3d-f64): shapes, broad and narrow phase, contact points.
//! - [`contact`]: collisions by integrating through the impact (Mirtich, Stronge), resting contact.
//! - [`world`]: the world and its step.
//! - [`scene`]: scene files (TOML/JSON) → [`world::World`], with precise errors.
//! - [`trajectory`]: CSV and JSON Lines trajectories, the run summary.
//! - [`mesh`]: OBJ/STL meshes, their checks and the exact mass properties of the solids they bound.
//! - [`multibody`]: articulated bodies (spatial algebra, RNEA, CRBA, ABA, URDF).
//! - [`analytic`]: exact solutions used as references (torque-free tops, Jacobi elliptic functions).
//!
//! Conventions: SI units, `f64`, world z up, quaternions `world_from_body` written `[w, x, y, z]` in
//! files, angular velocity in the world frame unless a name ends in `_body`.
// `unsafe` is allowed in two places only: the AVX lanes of the batched step and of the contact
// solver, and their run-time dispatch (`integrate::lanes`, `integrate::batch`, `contact::batch`),
// where the CPU's AVX2 (AVX-512F for the eight lanes of the batched step) is detected before use
#![deny(unsafe_code)]

pub mod analytic;
pub mod body;
pub mod collision;
pub mod contact;
pub mod integrate;
pub mod math;
pub mod mesh;
pub mod multibody;
pub mod profile;
pub mod scene;
pub mod trajectory;
pub mod world;

pub use body::{BodyState, MassProperties, RigidBody};
pub use integrate::Integrator;
pub use world::{World, WorldConfig};

// the README's example is compiled and run as a doctest
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
