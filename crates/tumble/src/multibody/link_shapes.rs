//! The collision shapes of a robot's links: each `<collision>` geometry of the URDF
//! ([`LinkGeometry`]) as a [`Shape`] placed in the frame of the body it moves with.
//!
//! Primitives map one to one (a URDF cylinder's axis is its frame's z, as tumble's). A mesh (STL or
//! OBJ, with its `scale`, mirrored or not) is read and collides as its convex hull, as a moving mesh
//! body does without a decomposition; the hull is centred on its centre of mass, which the shape's
//! position accounts for. A geometry fixed to the world (the fixed base and what is
//! fixed to it) has `body = None`.
//!
//! Errors name the URDF, the line of the `<collision>` element and the link: a mesh that could not
//! be resolved, a file that is missing or unreadable (with the path tried), a format that is not
//! read (COLLADA `.dae` among others: convert it to STL or OBJ), a hull that is flat.

use super::model::{GeometryRole, GeometryShape, MultibodyModel};
use crate::body::{ConvexShape, Shape};
use crate::math::{DQuat, DVec3};
use crate::mesh::read::{read_file, MeshLimits};
use std::sync::Arc;

/// One collision shape of a link, in the frame of the body it moves with.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkShape {
    /// The URDF link.
    pub link: String,
    /// The body it moves with (`None`: fixed to the world).
    pub body: Option<usize>,
    pub shape: Shape,
    /// The shape's frame in the body frame: its origin (m) and `body_from_shape` rotation.
    pub position_body: DVec3,
    pub orientation_body: DQuat,
    /// 1-based line of the `<collision>` element.
    pub line: u32,
}

/// Why a link's collision geometry cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}:{line}: link '{link}': <collision>: {problem}")]
pub struct LinkShapeError {
    /// The URDF file.
    pub file: String,
    /// Line of the `<collision>` element.
    pub line: u32,
    pub link: String,
    pub problem: String,
}

/// The collision shapes of every link of `model` read from `urdf_file` (named in errors), in the
/// file's order.
pub fn collision_shapes(model: &MultibodyModel, urdf_file: &str) -> Result<Vec<LinkShape>, LinkShapeError> {
    let mut shapes = Vec::new();
    for g in model.geometries.iter().filter(|g| g.role == GeometryRole::Collision) {
        let fail =
            |problem: String| LinkShapeError { file: urdf_file.into(), line: g.line, link: g.link.clone(), problem };
        let (body, x) = model.geometry_placement(g).ok_or_else(|| fail("the link is not in the model".into()))?;
        // the shape's own origin in the geometry frame: a hull is centred on its centre of mass
        let mut origin_geometry = DVec3::ZERO;
        let shape = match &g.shape {
            GeometryShape::Box { half_extents } => Shape::Box { half_extents: *half_extents },
            GeometryShape::Sphere { radius } => Shape::Sphere { radius: *radius },
            GeometryShape::Cylinder { radius, half_length } => {
                Shape::Cylinder { radius: *radius, half_height: *half_length }
            }
            GeometryShape::Capsule { radius, half_length } => {
                Shape::Capsule { radius: *radius, half_height: *half_length }
            }
            GeometryShape::Plane if body.is_none() => Shape::Plane,
            GeometryShape::Plane => return Err(fail("a plane must be fixed to the world".into())),
            GeometryShape::Ellipsoid { .. } => {
                return Err(fail("an ellipsoid does not collide yet (only its inertia is used)".into()))
            }
            GeometryShape::Mesh { uri, path, scale } => {
                let path = path.as_ref().ok_or_else(|| fail(unresolved(model, uri)))?;
                let soup = read_file(path, &MeshLimits::default())
                    .map_err(|e| fail(format!("mesh '{uri}': {} (the path tried: {})", e.problem, path.display())))?;
                let points: Vec<DVec3> = soup.vertices.iter().map(|v| *v * *scale).collect();
                let hull = ConvexShape::new(&points)
                    .map_err(|e| fail(format!("mesh '{uri}': its convex hull: {e} ({})", path.display())))?;
                origin_geometry = hull.center_of_mass_given;
                Shape::Convex(Arc::new(hull))
            }
        };
        // geometry_X_body: the shape's origin in body coordinates and the rotation body_from_shape
        let position_body = x.inv_apply_point(origin_geometry);
        let orientation_body = DQuat::from_mat3(&x.rotation_a_from_b()).normalize();
        shapes.push(LinkShape { link: g.link.clone(), body, shape, position_body, orientation_body, line: g.line });
    }
    Ok(shapes)
}

/// "mesh '…' could not be resolved", with the reason the URDF reader gave in its warning (the paths
/// tried, or why none could be).
fn unresolved(model: &MultibodyModel, uri: &str) -> String {
    let marker = format!("mesh '{uri}' not resolved: ");
    match model.warnings.iter().find_map(|w| w.split_once(&marker).map(|(_, why)| why)) {
        Some(why) => format!("mesh '{uri}' could not be resolved: {why}"),
        None => format!("mesh '{uri}' could not be resolved"),
    }
}
