//! Convex geometry made once, at load: convex hulls of points and convex decompositions of meshes.
//!
//! **Convex decomposition** (a moving concave mesh): parry's V-HACD (K. Mamou, "Volumetric
//! Hierarchical Approximate Convex Decomposition", *Game Engine Gems 3*, 2016). The solid is
//! voxelised, cut recursively by planes until each piece's concavity is small, and each piece is
//! replaced by the exact convex hull of the mesh's surface inside its voxels (triangles that cross
//! pieces are clipped to the voxels), so a piece's faces are the mesh's own faces where it has them.
//! Parameters ([`decomposition_parameters`]): a voxel grid of [`VHACD_RESOLUTION`]³ over the
//! bounding box; concavity at most [`VHACD_CONCAVITY`] (parry's measure, relative to the size of
//! the mesh); at most [`VHACD_MAX_PIECES`] pieces, which bounds the narrow-phase work of a pair;
//! the rest parry's defaults (planes sampled every 4 voxels, approximate hulls while searching,
//! flood fill from outside). Measured on the 2 304-triangle torus of the tests: 11 pieces whose
//! volumes add to 4.7 % more than the torus, in 0.2–0.6 s (release build, shared machine; figures in
//! `docs/meshes.md`); the cost grows with the resolution (≈ 2.3 s at 128³), little with the
//! triangle count (0.5 s for 36 864 triangles).

use crate::body::ConvexPiece;
use crate::math::DVec3;
use crate::mesh::TriMesh;
use parry3d_f64::shape::SharedShape;
use parry3d_f64::transformation::vhacd::{VHACDParameters, VHACD};

/// Voxels along the longest side of the bounding box in a convex decomposition.
pub const VHACD_RESOLUTION: u32 = 64;
/// Largest concavity of a piece (parry's measure; its default in 3D).
pub const VHACD_CONCAVITY: f64 = 0.01;
/// Most pieces in a convex decomposition.
pub const VHACD_MAX_PIECES: u32 = 32;

/// The V-HACD parameters tumble decomposes with (see the module doc).
pub fn decomposition_parameters() -> VHACDParameters {
    VHACDParameters {
        resolution: VHACD_RESOLUTION,
        concavity: VHACD_CONCAVITY,
        max_convex_hulls: VHACD_MAX_PIECES,
        ..VHACDParameters::default()
    }
}

/// The convex hull of `points` (m): its vertices and outward triangles, or `None` when parry cannot
/// build it (fewer than 4 points, or all in a plane).
pub fn convex_hull(points: &[DVec3]) -> Option<(Vec<DVec3>, Vec<[u32; 3]>)> {
    parry3d_f64::transformation::try_convex_hull(points).ok()
}

/// The convex hull of a mesh's vertices as a parry shape (a checked mesh encloses a volume, so the
/// hull exists; a degenerate one falls back to the bounding ball).
pub(crate) fn mesh_hull(mesh: &TriMesh) -> SharedShape {
    SharedShape::convex_hull(mesh.vertices()).unwrap_or_else(|| {
        let radius = mesh.vertices().iter().map(|v| v.length()).fold(0.0, f64::max);
        SharedShape::ball(radius)
    })
}

/// How much larger a mesh's convex hull is than the mesh (`V_hull / V_mesh − 1`): about 0 for a convex
/// part; a concave part's hull fills its hollows.
pub fn mesh_hull_excess(mesh: &TriMesh, mesh_volume: f64) -> f64 {
    let hull_volume = mesh_hull(mesh).mass_properties(1.0).mass();
    hull_volume / mesh_volume - 1.0
}

/// The convex pieces of a closed mesh (body axes, m) by V-HACD with [`decomposition_parameters`];
/// pieces whose hull is degenerate are left out (so the result may be empty).
pub fn convex_decomposition(mesh: &TriMesh) -> Vec<ConvexPiece> {
    let decomposition = VHACD::decompose(&decomposition_parameters(), mesh.vertices(), mesh.triangles(), true);
    decomposition
        .compute_exact_convex_hulls(mesh.vertices(), mesh.triangles())
        .into_iter()
        .filter(|(vertices, triangles)| vertices.len() >= 4 && !triangles.is_empty())
        .map(|(vertices, triangles)| ConvexPiece { vertices, triangles })
        .collect()
}

/// A piece as a parry convex polyhedron.
pub(crate) fn piece_shape(piece: &ConvexPiece) -> Option<SharedShape> {
    SharedShape::convex_mesh(piece.vertices.clone(), &piece.triangles)
}
