//! Triangle meshes: reading OBJ and STL files, checking that they bound a solid, and the exact mass
//! properties of the solid they bound.
//!
//! - [`read`](mod@read): a file (`.obj`, `.stl` binary or ASCII) → a triangle soup, with its size
//!   checked before anything is allocated ([`MeshLimits`]).
//! - [`topology`]: the soup → a [`TriMesh`] whose vertices are welded, and the checks that make the
//!   volume integrals meaningful: finite coordinates, a closed surface, a consistent orientation,
//!   outward normals (an inside-out mesh is flipped with a warning), degenerate triangles.
//! - [`shells`]: which way each connected piece faces: a cavity, or a part to flip.
//! - [`integrals`]: volume, centre of mass and inertia tensor of the solid, exact to round-off.
//!
//! Frames and units: *mesh axes* are the axes the file is written in; coordinates are read as
//! metres (multiply by a scale to convert). The inertia is about the centre of mass, in mesh axes.
//!
//! References:
//! - B. Mirtich, "Fast and accurate computation of polyhedral mass properties", *Journal of Graphics
//!   Tools* 1(2), 1996: volume integrals over a closed polyhedron reduced by the divergence theorem.
//! - F. Tonon, "Explicit exact formulas for the 3-D tetrahedron inertia tensor in terms of its vertex
//!   coordinates", *Journal of Mathematics and Statistics* 1(1), 2004: the signed-tetrahedron form
//!   used here (equivalent to Mirtich's, with fewer terms).
//! - D. Eberly, "Polyhedral mass properties (revisited)", Geometric Tools, 2002.

pub mod integrals;
pub mod read;
pub mod shells;
pub mod topology;

pub use integrals::MeshMassProperties;
pub use read::{Format, MeshLimits, TriangleSoup};
pub use topology::{MeshWarning, TriMesh};

use crate::body::MassError;
use std::path::Path;

/// Why a mesh was rejected: the file (as given, or `<mesh>` for one built in memory) and the problem.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: {problem}")]
pub struct MeshError {
    /// The file as given.
    pub file: String,
    /// What is wrong with it.
    pub problem: MeshProblem,
}

/// What is wrong with a mesh. Every variant names the quantities a user needs to find the fault.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshProblem {
    #[error("cannot read: {0}")]
    Io(String),
    #[error("cannot tell the mesh format from the file name (got {0}); mesh files end in .obj or .stl")]
    UnknownFormat(String),
    #[error("the file is empty")]
    Empty,
    #[error("file too large: {bytes} bytes, the limit is {limit} bytes (MeshLimits::max_file_bytes)")]
    FileTooLarge { bytes: u64, limit: u64 },
    #[error("too many triangles: {count}, the limit is {limit} (see MeshLimits / --max-triangles)")]
    TooManyTriangles { count: u64, limit: u64 },
    #[error(
        "binary STL size does not match its triangle count: the header says {count} triangles, \
         which take 84 + 50 × {count} = {expected} bytes, but the file has {actual} bytes ({})",
        if actual < expected { "truncated" } else { "extra bytes at the end" }
    )]
    StlSizeMismatch { count: u64, expected: u64, actual: u64 },
    #[error("binary STL shorter than its 84-byte header ({actual} bytes) and not an ASCII STL")]
    StlTooShort { actual: u64 },
    #[error("{format} parse error{}: {message}", line.map(|l| format!(" at line {l}")).unwrap_or_default())]
    Parse { format: Format, line: Option<usize>, message: String },
    #[error("no triangles in the file")]
    NoTriangles,
    #[error(
        "coordinate {value} of {} is not finite",
        match (line, facet) {
            (Some(l), _) => format!("the vertex at line {l}"),
            (None, Some(f)) => format!("facet {f}"),
            _ => format!("vertex {vertex}"),
        }
    )]
    NonFinite { vertex: usize, value: f64, line: Option<usize>, facet: Option<usize> },
    #[error("triangle {triangle} refers to vertex {index}, but there are {vertices} vertices")]
    IndexOutOfRange { triangle: usize, index: u64, vertices: usize },
    #[error(
        "the surface is not closed: {open_edges} open edges (used by one triangle only), \
         e.g. between {} and {}{}",
        fmt_point(example.0), fmt_point(example.1),
        if *inconsistent_edges > 0 {
            format!("; and {inconsistent_edges} edges where two triangles disagree on the orientation")
        } else {
            String::new()
        }
    )]
    NotClosed { open_edges: usize, inconsistent_edges: usize, example: ([f64; 3], [f64; 3]) },
    #[error(
        "the triangles are not consistently oriented: {inconsistent_edges} edges are traversed in the same \
         direction by the triangles on both sides (e.g. between {} and {}): some triangles are flipped",
        fmt_point(example.0), fmt_point(example.1)
    )]
    Inconsistent { inconsistent_edges: usize, example: ([f64; 3], [f64; 3]) },
    #[error("coordinates too large: the volume integrals overflow (bounding box {extent:e} m)")]
    Overflow { extent: f64 },
    #[error("the mesh encloses no volume (signed volume {volume:e} m³ for a bounding box of {extent:e} m)")]
    NoVolume { volume: f64, extent: f64 },
    #[error("scale must be finite and > 0 in every axis (got {0:?})")]
    BadScale([f64; 3]),
    #[error("density must be finite and > 0 kg/m³ (got {0})")]
    BadDensity(f64),
    #[error("its mass properties are unusable: {0}")]
    Mass(MassError),
}

fn fmt_point(p: [f64; 3]) -> String {
    format!("[{}, {}, {}]", p[0], p[1], p[2])
}

impl MeshError {
    pub(crate) fn new(file: &str, problem: MeshProblem) -> Self {
        Self { file: file.to_string(), problem }
    }
}

/// A mesh read from a file and checked: closed, consistently oriented, outward, and what was noticed.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedMesh {
    /// The checked mesh, in mesh axes (m, after scaling).
    pub mesh: TriMesh,
    /// The file's format.
    pub format: Format,
    /// Things noticed but accepted (inside-out flipped, degenerate triangles skipped, ...).
    pub warnings: Vec<MeshWarning>,
}

/// Reads, welds and checks a mesh file (`.obj`, `.stl`); coordinates are multiplied by `scale`
/// (per axis, finite and > 0) to give metres.
pub fn load(path: &Path, scale: [f64; 3], limits: &MeshLimits) -> Result<LoadedMesh, MeshError> {
    let file = path.display().to_string();
    if scale.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return Err(MeshError::new(&file, MeshProblem::BadScale(scale)));
    }
    let soup = read::read_file(path, limits)?;
    let format = soup.format;
    let (mesh, warnings) = TriMesh::from_soup(soup.scaled(scale)).map_err(|p| MeshError::new(&file, p))?;
    Ok(LoadedMesh { mesh, format, warnings })
}

/// Reads a mesh file and computes the mass properties of the solid it bounds, of uniform density
/// `density` (kg/m³). Returns them with the warnings.
pub fn mass_properties_of_file(
    path: &Path,
    scale: [f64; 3],
    density: f64,
    limits: &MeshLimits,
) -> Result<(MeshMassProperties, Vec<MeshWarning>), MeshError> {
    let file = path.display().to_string();
    if !(density.is_finite() && density > 0.0) {
        return Err(MeshError::new(&file, MeshProblem::BadDensity(density)));
    }
    let loaded = load(path, scale, limits)?;
    let props = loaded.mesh.mass_properties(density).map_err(|p| MeshError::new(&file, p))?;
    Ok((props, loaded.warnings))
}
