//! Shapes built from other geometry: the convex hull of points, and compounds of several shapes.
//!
//! Both keep the body's convention: the shape sits on the centre of mass, in the user's body axes.
//! Where the centre of mass lies in the coordinates the user wrote (`center_of_mass_given`) is kept
//! for messages and `tumble check`.
//!
//! Mass properties per unit density:
//! - **convex**: the hull's triangles go through the mesh integrals of [`crate::mesh`] (exact for a
//!   polyhedron);
//! - **compound**: the sum of the parts, each moved by the parallel-axis theorem,
//!   `I = Σᵢ (Rᵢ Iᵢ Rᵢᵀ + Vᵢ (|dᵢ|² 𝟙 − dᵢ dᵢᵀ))`, `dᵢ = pᵢ − c`, `c = Σ Vᵢ pᵢ / Σ Vᵢ`
//!   (parts that overlap count their common volume twice).

use super::mass::MassProperties;
use super::shape::Shape;
use crate::math::{DMat3, DQuat, DVec3};
use crate::mesh::{MeshProblem, TriMesh};

/// Points within this fraction of their extent from one plane are coplanar: their hull has no volume.
pub const FLAT_TOLERANCE: f64 = 1e-9;

/// Why a convex or compound shape was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShapeProblem {
    #[error("a convex hull needs at least 4 points (got {count})")]
    TooFewPoints { count: usize },
    #[error("point {index} is not finite (got {point:?})")]
    NonFinitePoint { index: usize, point: [f64; 3] },
    #[error(
        "the points are coplanar (all within {distance:e} m of one plane, extent {extent:e} m): \
         their hull encloses no volume"
    )]
    Flat { distance: f64, extent: f64 },
    #[error("the convex hull could not be built: {0}")]
    Hull(String),
    #[error("a compound needs at least one part")]
    NoParts,
    #[error("part {index}: a {kind} cannot be part of a compound (parts: sphere, box, capsule, cylinder, convex)")]
    NotAPart { index: usize, kind: &'static str },
    #[error("part {index}: position and orientation must be finite, the orientation a unit quaternion")]
    BadPose { index: usize },
    #[error("its mass properties are unusable: {0}")]
    Mass(MeshProblem),
}

/// The convex hull of a set of points, with its mass properties per unit density.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvexShape {
    /// The hull: closed, outward triangles; vertices relative to the centre of mass, body axes (m).
    pub hull: TriMesh,
    /// How many points were given (some may lie inside the hull).
    pub points_given: usize,
    /// The centre of mass in the coordinates the points were written in (m).
    pub center_of_mass_given: DVec3,
    /// Volume (m³).
    pub volume: f64,
    /// Inertia tensor about the centre of mass per unit density, body axes (m⁵).
    pub inertia_per_density: DMat3,
    /// Its eigenvalues, ascending (m⁵).
    pub principal_per_density: DVec3,
}

impl ConvexShape {
    /// The convex hull of `points` (m): at least 4 finite points, not all in one plane.
    pub fn new(points: &[DVec3]) -> Result<Self, ShapeProblem> {
        if let Some((index, p)) = points.iter().enumerate().find(|(_, p)| !p.is_finite()) {
            return Err(ShapeProblem::NonFinitePoint { index, point: p.to_array() });
        }
        if points.len() < 4 {
            return Err(ShapeProblem::TooFewPoints { count: points.len() });
        }
        check_not_flat(points)?;
        let (vertices, triangles) = crate::collision::convex_hull(points)
            .ok_or_else(|| ShapeProblem::Hull("parry's hull of these points failed".into()))?;
        let (hull, _warnings) = TriMesh::new(vertices, triangles).map_err(|e| match e {
            MeshProblem::NoVolume { volume, extent } => {
                ShapeProblem::Flat { distance: volume / (extent * extent), extent }
            }
            other => ShapeProblem::Hull(other.to_string()),
        })?;
        let p = hull.mass_properties(1.0).map_err(ShapeProblem::Mass)?;
        p.body_mass().map_err(ShapeProblem::Mass)?;
        Ok(Self {
            hull: hull.map_vertices(|v| v - p.center_of_mass),
            points_given: points.len(),
            center_of_mass_given: p.center_of_mass,
            volume: p.volume,
            inertia_per_density: p.inertia,
            principal_per_density: p.principal_moments,
        })
    }
}

/// Refuses points that lie in one plane (or on one line, or at one place) to within
/// [`FLAT_TOLERANCE`] of their extent: the farthest point from the first, the farthest from the
/// line of those two, and the farthest from the plane of those three.
fn check_not_flat(points: &[DVec3]) -> Result<(), ShapeProblem> {
    let (lo, hi) = points.iter().fold((points[0], points[0]), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let extent = (hi - lo).max_element();
    let flat = |distance: f64| ShapeProblem::Flat { distance, extent };
    let a = points[0];
    let farthest = |f: &dyn Fn(DVec3) -> f64| points.iter().map(|&p| (f(p), p)).max_by(|x, y| x.0.total_cmp(&y.0));
    let (d_ab, b) = farthest(&|p| (p - a).length()).expect("at least 4 points");
    if d_ab <= FLAT_TOLERANCE * extent || extent == 0.0 {
        return Err(flat(d_ab));
    }
    let axis = (b - a) / d_ab;
    let (d_c, c) = farthest(&|p| (p - a).reject_from_normalized(axis).length()).expect("at least 4 points");
    if d_c <= FLAT_TOLERANCE * extent {
        return Err(flat(d_c));
    }
    let normal = (b - a).cross(c - a).normalize();
    let (d_plane, _) = farthest(&|p| (p - a).dot(normal).abs()).expect("at least 4 points");
    if d_plane <= FLAT_TOLERANCE * extent {
        return Err(flat(d_plane));
    }
    Ok(())
}

/// One part of a compound: a shape and where it sits in the body.
#[derive(Debug, Clone, PartialEq)]
pub struct CompoundPart {
    /// Its shape (sphere, box, capsule, cylinder or convex), about its own centre.
    pub shape: Shape,
    /// The centre of the part's shape (for a convex part, its centre of mass) relative to the body's
    /// centre of mass, body axes (m).
    pub position: DVec3,
    /// Unit quaternion `user_from_part`: the part's axes in the body axes.
    pub orientation: DQuat,
}

/// Several shapes rigidly joined in one body, with their mass properties per unit density.
#[derive(Debug, Clone, PartialEq)]
pub struct CompoundShape {
    /// The parts, placed relative to the centre of mass.
    pub parts: Vec<CompoundPart>,
    /// The centre of mass in the coordinates the parts were written in (m).
    pub center_of_mass_given: DVec3,
    /// Volume, the sum of the parts' (m³).
    pub volume: f64,
    /// Inertia tensor about the centre of mass per unit density, body axes (m⁵).
    pub inertia_per_density: DMat3,
    /// Its eigenvalues, ascending (m⁵).
    pub principal_per_density: DVec3,
}

impl CompoundShape {
    /// The compound of `parts`, placed in common coordinates (m); they are moved so that the
    /// centre of mass of the whole (uniform density) is the origin.
    pub fn new(mut parts: Vec<CompoundPart>) -> Result<Self, ShapeProblem> {
        if parts.is_empty() {
            return Err(ShapeProblem::NoParts);
        }
        let mut volumes = Vec::with_capacity(parts.len());
        for (index, part) in parts.iter().enumerate() {
            if matches!(part.shape, Shape::Plane | Shape::Mesh(_) | Shape::Compound(_)) {
                return Err(ShapeProblem::NotAPart { index, kind: part.shape.type_name() });
            }
            let unit = (part.orientation.length() - 1.0).abs() <= 1e-9;
            if !(part.position.is_finite() && part.orientation.is_finite() && unit) {
                return Err(ShapeProblem::BadPose { index });
            }
            let (volume, tensor) = part.shape.inertia_tensor(1.0).expect("every part has a volume");
            volumes.push((volume, tensor));
        }
        let volume: f64 = volumes.iter().map(|v| v.0).sum();
        let center = parts.iter().zip(&volumes).map(|(p, v)| v.0 * p.position).sum::<DVec3>() / volume;
        let mut inertia = DMat3::ZERO;
        for (part, &(v, tensor_part)) in parts.iter_mut().zip(&volumes) {
            part.position -= center;
            let user_from_part = DMat3::from_quat(part.orientation);
            // I += R I_part Rᵀ + V (|d|² 𝟙 − d dᵀ)
            let d = part.position;
            let shift = DMat3::from_diagonal(DVec3::splat(d.length_squared())) - outer(d, d);
            inertia += crate::math::change_frame(user_from_part, tensor_part) + v * shift;
        }
        let principal = MassProperties::from_tensor(volume, inertia)
            .map_err(|e| ShapeProblem::Mass(MeshProblem::Mass(e)))?
            .inertia_body;
        let mut sorted = principal.to_array();
        sorted.sort_by(f64::total_cmp);
        Ok(Self {
            parts,
            center_of_mass_given: center,
            volume,
            inertia_per_density: inertia,
            principal_per_density: DVec3::from_array(sorted),
        })
    }
}

/// `a bᵀ`.
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}
