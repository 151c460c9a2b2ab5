//! Scene files (TOML or JSON, `version = 1`) → [`World`], with precise errors.
//!
//! PLACEHOLDER API (being implemented): the signatures below are the contract between the scene
//! loader and the command-line tool.

use crate::world::World;
use std::path::Path;

/// A loaded, validated scene.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The world, ready to step.
    pub world: World,
    /// Where it came from: the file path as given, or `<built-in demo>`.
    pub origin: String,
}

/// Why a scene could not be loaded. `Display` gives the whole message, e.g.
/// `scenes/x.toml:12:8: body[2].mass: must be finite and > 0 (got -1)`, with a `hint:` line where useful.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct SceneError {
    pub message: String,
}

/// Loads a scene file (`.toml` or `.json`, by extension).
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    Err(SceneError { message: format!("{}: scene loading is not implemented yet", path.display()) })
}

/// The built-in demo scene (`scenes/demo.toml`).
pub fn demo() -> Scene {
    use crate::math::DVec3;
    use crate::{MassProperties, RigidBody, WorldConfig};
    let mp = MassProperties::from_principal(1.0, DVec3::new(1.0, 2.0, 3.0)).expect("valid");
    let mut flipper = RigidBody::new("flipper", mp);
    flipper.state.omega_body = DVec3::new(0.01, 5.0, 0.01);
    let mut stable = RigidBody::new("stable", mp);
    stable.state.position = DVec3::new(3.0, 0.0, 0.0);
    stable.state.omega_body = DVec3::new(0.01, 0.01, 5.0);
    let config = WorldConfig { gravity: DVec3::ZERO, duration: 30.0, sample_every: 10, ..Default::default() };
    Scene { world: World::new(config, vec![flipper, stable]), origin: "<built-in demo>".into() }
}

impl Scene {
    /// A human-readable account of what was understood (for `tumble check`).
    pub fn describe(&self) -> String {
        format!("{}: {} bodies", self.origin, self.world.bodies.len())
    }
}
