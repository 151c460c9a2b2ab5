//! Shapes a body may have: for its mass properties and its collisions.
//!
//! Every shape is centred on the body's origin in the user's body axes; axes of capsules and
//! cylinders are body z; a plane's normal is body +z (planes are for fixed bodies only); a mesh's
//! vertices, a convex hull's and a compound's parts are moved so that the centre of mass of the
//! solid is the origin, its axes are the ones the file wrote it in.

pub use super::solid::{CompoundPart, CompoundShape, ConvexShape, ShapeProblem};
use crate::math::{DMat3, DVec3};
use crate::mesh::{MeshProblem, TriMesh};
use std::sync::Arc;

/// A shape, dimensions in metres.
#[derive(Debug, Clone, PartialEq)]
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
    /// A closed triangle mesh read from a file (shared: copies of a body share one mesh).
    Mesh(Arc<MeshShape>),
    /// The convex hull of points.
    Convex(Arc<ConvexShape>),
    /// Several shapes, each with its pose in the body (`shapes = [...]` in files).
    Compound(Arc<CompoundShape>),
}

/// A solid bounded by a closed triangle mesh, and its mass properties per unit density.
///
/// Collisions (see `collision::parry_shape`): a fixed body collides as the triangles themselves; a
/// moving one as its convex decomposition when it has one ([`MeshShape::decomposition`]), else
/// as the convex hull of its vertices.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshShape {
    /// The file as written in the scene.
    pub file: String,
    /// The factor applied to the file's coordinates, per axis.
    pub scale: DVec3,
    /// The checked mesh (closed, outward), vertices relative to the centre of mass, body axes (m).
    pub mesh: TriMesh,
    /// The centre of mass in the file's coordinates after scaling (m): the point of the file that
    /// sits at the body's `position`.
    pub center_of_mass_file: DVec3,
    /// Volume (m³).
    pub volume: f64,
    /// Inertia tensor about the centre of mass per unit density, body axes (m⁵).
    pub inertia_per_density: DMat3,
    /// Its eigenvalues, ascending (m⁵).
    pub principal_per_density: DVec3,
    /// How much larger the convex hull of the vertices is than the solid, `V_hull / V − 1`.
    pub hull_excess: f64,
    /// Convex pieces covering the solid (body axes, m), which a moving body collides as: set for
    /// a concave mesh on a moving body (see [`MeshShape::decompose`]); `None`: the hull.
    pub decomposition: Option<Vec<ConvexPiece>>,
}

/// A convex polyhedron of a decomposition: its hull's vertices (m, body axes) and outward triangles.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvexPiece {
    pub vertices: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
}

impl MeshShape {
    /// The shape of a checked mesh (m, file axes after scaling): computes its mass properties and
    /// moves its vertices to the centre of mass.
    pub fn new(file: impl Into<String>, scale: DVec3, mesh: TriMesh) -> Result<Self, MeshProblem> {
        let p = mesh.mass_properties(1.0)?;
        p.body_mass()?;
        let centred = mesh.map_vertices(|v| v - p.center_of_mass);
        let hull_excess = crate::collision::mesh_hull_excess(&centred, p.volume);
        Ok(Self {
            file: file.into(),
            scale,
            mesh: centred,
            center_of_mass_file: p.center_of_mass,
            volume: p.volume,
            inertia_per_density: p.inertia,
            principal_per_density: p.principal_moments,
            hull_excess,
            decomposition: None,
        })
    }

    /// Computes the convex decomposition a moving body collides as (see
    /// `collision::convex_decomposition` for the method, its parameters and cost). A mesh whose
    /// decomposition comes out empty keeps its hull.
    pub fn decompose(&mut self) {
        let pieces = crate::collision::convex_decomposition(&self.mesh);
        self.decomposition = (!pieces.is_empty()).then_some(pieces);
    }
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
            Shape::Mesh(_) => "mesh",
            Shape::Convex(_) => "convex",
            Shape::Compound(_) => "compound",
        }
    }

    /// Mass (kg) and principal moments about the centre (kg·m², body axes) of the solid shape of
    /// density `rho` (kg/m³); `None` for a plane, which has no finite volume. A mesh's moments are
    /// about its principal axes, which need not be the body axes: see [`Shape::inertia_tensor`]
    /// (so are a convex hull's and a compound's).
    pub fn mass_properties(&self, rho: f64) -> Option<(f64, DVec3)> {
        use super::mass::{solid_box, solid_capsule, solid_cylinder, solid_sphere};
        match *self {
            Shape::Sphere { radius } => Some(solid_sphere(rho, radius)),
            Shape::Box { half_extents } => Some(solid_box(rho, half_extents)),
            Shape::Capsule { radius, half_height } => Some(solid_capsule(rho, radius, half_height)),
            Shape::Cylinder { radius, half_height } => Some(solid_cylinder(rho, radius, half_height)),
            Shape::Plane => None,
            Shape::Mesh(ref m) => Some((rho * m.volume, rho * m.principal_per_density)),
            Shape::Convex(ref c) => Some((rho * c.volume, rho * c.principal_per_density)),
            Shape::Compound(ref c) => Some((rho * c.volume, rho * c.principal_per_density)),
        }
    }

    /// Mass (kg) and inertia tensor about the centre of mass in body axes (kg·m²) of the solid
    /// shape of density `rho` (kg/m³); `None` for a plane. Diagonal for the primitive shapes.
    pub fn inertia_tensor(&self, rho: f64) -> Option<(f64, DMat3)> {
        match self {
            Shape::Mesh(m) => Some((rho * m.volume, rho * m.inertia_per_density)),
            Shape::Convex(c) => Some((rho * c.volume, rho * c.inertia_per_density)),
            Shape::Compound(c) => Some((rho * c.volume, rho * c.inertia_per_density)),
            _ => self.mass_properties(rho).map(|(mass, moments)| (mass, DMat3::from_diagonal(moments))),
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
