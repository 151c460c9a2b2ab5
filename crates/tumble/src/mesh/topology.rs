//! A triangle soup → a closed, consistently and outward oriented [`TriMesh`], or the reason why not.
//!
//! The volume integrals of [`integrals`](super::integrals) turn integrals over the solid into sums
//! over its surface (the divergence theorem), which holds when the triangles form a closed,
//! oriented surface: every edge `a → b` of a triangle must be matched by an edge `b → a` of
//! another. So the checks are, in order:
//!
//! 1. coordinates finite, indices in range;
//! 2. vertices *welded*: corners with bit-identical coordinates (`-0.0` = `0.0`) are one vertex,
//!    as an STL file writes every corner of every facet;
//! 3. triangles with two equal corners are skipped with a warning (they enclose nothing: their
//!    cross product is exactly zero); triangles of zero area with three distinct corners are kept
//!    (they close the surface around T-junctions) and counted in a warning;
//! 4. every undirected edge is used as often `a → b` as `b → a`. An edge used an odd number of times
//!    is *open* (the surface has a hole there); one used an even number of times but unevenly is
//!    *inconsistently oriented* (a flipped triangle). Both are errors naming how many edges and
//!    where one is. Edges shared by four or more triangles, evenly, are accepted with a warning
//!    (two solids touching along an edge);
//! 5. each shell (connected piece) that faces inward and is no cavity is flipped, with a warning
//!    (see [`shells`](super::shells)); then the volume must be clearly positive (`V > 1e-12 L³`,
//!    `L` the largest side of the bounding box).
//!
//! Cost: `O(n)`: hashing to weld, a counting sort of the `3n` directed edges by their smaller end.

use super::read::TriangleSoup;
use super::shells::orient_shells;
use super::MeshProblem;
use crate::math::DVec3;
use std::collections::HashMap;

/// A closed triangle mesh, consistently oriented with outward normals (corners counter-clockwise
/// seen from outside), vertices welded; coordinates in mesh axes (m). Built only by the checks.
#[derive(Debug, Clone, PartialEq)]
pub struct TriMesh {
    vertices: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
}

/// Things noticed in a mesh and accepted.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshWarning {
    /// `shells` shells faced inward (their signed volume, m³) and were no cavity: they were flipped.
    InsideOut { volume: f64, shells: usize },
    /// `shells` shells face inward within an outward shell's bounding box: taken as cavities (their
    /// signed volume, m³, is subtracted).
    Cavities { shells: usize, volume: f64 },
    /// Triangles with two or three equal corners (after welding) were skipped; `first` is the
    /// index of the first in the file's order.
    Degenerate { count: usize, first: usize },
    /// Triangles of zero area with three distinct corners were kept; `first` as above.
    ZeroArea { count: usize, first: usize },
    /// Edges shared by four or more triangles (evenly in both directions).
    NonManifold { edges: usize },
}

impl std::fmt::Display for MeshWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MeshWarning::InsideOut { volume, shells: 1 } => {
                write!(f, "the triangles face inward (signed volume {volume} m³): flipped them to face outward")
            }
            MeshWarning::InsideOut { volume, shells } => write!(
                f,
                "{shells} separate shells face inward (signed volume {volume} m³ in all): flipped them to face outward"
            ),
            MeshWarning::Cavities { shells, volume } => write!(
                f,
                "{shells} shells face inward within the bounding box of another: taken as cavities \
                 ({volume} m³); if they are separate parts, they are inside out"
            ),
            MeshWarning::Degenerate { count, first } => write!(
                f,
                "{count} degenerate triangles (two equal corners) skipped, the first is triangle {first}: \
                 they enclose no volume"
            ),
            MeshWarning::ZeroArea { count, first } => {
                write!(f, "{count} triangles of zero area (three corners on a line), the first is triangle {first}")
            }
            MeshWarning::NonManifold { edges } => write!(
                f,
                "{edges} edges are shared by four or more triangles (solids touching along an edge); \
                 the mass properties are those of the union"
            ),
        }
    }
}

impl TriMesh {
    /// Checks a triangle soup (see the module doc) and returns the closed, outward mesh and the warnings.
    pub fn from_soup(soup: TriangleSoup) -> Result<(TriMesh, Vec<MeshWarning>), MeshProblem> {
        Self::new(soup.vertices, soup.triangles)
    }

    /// Checks triangles given by corner indices into `vertices` (m, mesh axes); see the module doc.
    pub fn new(vertices: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Result<(TriMesh, Vec<MeshWarning>), MeshProblem> {
        if triangles.is_empty() {
            return Err(MeshProblem::NoTriangles);
        }
        if let Some((vertex, value)) = vertices
            .iter()
            .enumerate()
            .find_map(|(i, v)| v.to_array().into_iter().find(|x| !x.is_finite()).map(|x| (i, x)))
        {
            return Err(MeshProblem::NonFinite { vertex, value, line: None, facet: None });
        }
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= vertices.len()) {
                return Err(MeshProblem::IndexOutOfRange {
                    triangle: t,
                    index: index.into(),
                    vertices: vertices.len(),
                });
            }
        }
        let mut warnings = Vec::new();
        let mut mesh = weld(&vertices, &triangles, &mut warnings);
        if mesh.triangles.is_empty() {
            return Err(MeshProblem::NoVolume { volume: 0.0, extent: extent(&mesh.vertices) });
        }
        mesh.check_edges(&mut warnings)?;
        let reference = bounding_box_centre(&mesh.vertices);
        let volume = orient_shells(&mesh.vertices, &mut mesh.triangles, reference, &mut warnings);
        let size = extent(&mesh.vertices);
        if !volume.is_finite() {
            return Err(MeshProblem::Overflow { extent: size });
        }
        // after the shells are oriented, a solid has a clearly positive volume
        if volume <= 1e-12 * size.powi(3) {
            return Err(MeshProblem::NoVolume { volume, extent: size });
        }
        Ok((mesh, warnings))
    }

    /// Vertex coordinates, mesh axes (m).
    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices
    }

    /// Corner indices, counter-clockwise seen from outside.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The same solid with every vertex moved by `f` (e.g. a rigid motion); the topology is kept and
    /// not checked again, so `f` must not mirror or collapse the mesh.
    pub fn map_vertices(&self, f: impl Fn(DVec3) -> DVec3) -> TriMesh {
        TriMesh { vertices: self.vertices.iter().map(|&v| f(v)).collect(), triangles: self.triangles.clone() }
    }

    /// Edge check (step 4 of the module doc). Each directed edge `a → b` is filed under its smaller
    /// end (a counting sort: two sequential passes and one scatter, no comparison sort of all
    /// `3n` edges), as `(larger end << 1) | (a < b)`; then each vertex's few edges are sorted and
    /// grouped by the other end.
    fn check_edges(&self, warnings: &mut Vec<MeshWarning>) -> Result<(), MeshProblem> {
        let n = self.vertices.len();
        let mut start = vec![0_usize; n + 1];
        for t in &self.triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                start[a.min(b) as usize + 1] += 1;
            }
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut filled = start.clone();
        let mut edges = vec![0_u64; 3 * self.triangles.len()];
        for t in &self.triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let lo = a.min(b) as usize;
                edges[filled[lo]] = (u64::from(a.max(b)) << 1) | u64::from(a < b);
                filled[lo] += 1;
            }
        }
        let (mut open, mut inconsistent, mut non_manifold) = (0_usize, 0_usize, 0_usize);
        let (mut open_example, mut inconsistent_example) = (None, None);
        for lo in 0..n {
            let bucket = &mut edges[start[lo]..start[lo + 1]];
            bucket.sort_unstable();
            for group in bucket.chunk_by(|x, y| x >> 1 == y >> 1) {
                let forward = group.iter().filter(|&&e| e & 1 == 1).count();
                let backward = group.len() - forward;
                let edge = (lo, (group[0] >> 1) as usize);
                if forward == backward {
                    non_manifold += usize::from(group.len() > 2);
                } else if group.len() % 2 == 1 {
                    open += 1;
                    open_example.get_or_insert(edge);
                } else {
                    inconsistent += 1;
                    inconsistent_example.get_or_insert(edge);
                }
            }
        }
        let example = |(a, b): (usize, usize)| (self.vertices[a].to_array(), self.vertices[b].to_array());
        if let Some(edge) = open_example {
            return Err(MeshProblem::NotClosed {
                open_edges: open,
                inconsistent_edges: inconsistent,
                example: example(edge),
            });
        }
        if let Some(edge) = inconsistent_example {
            return Err(MeshProblem::Inconsistent { inconsistent_edges: inconsistent, example: example(edge) });
        }
        if non_manifold > 0 {
            warnings.push(MeshWarning::NonManifold { edges: non_manifold });
        }
        Ok(())
    }
}

/// Slots of the cache of recently welded vertices (a power of two; 16 Ki × 32 bytes = 512 KiB).
const RECENT: usize = 1 << 14;

/// Welds bit-identical corners, keeps only used vertices (in order of first use), skips triangles
/// with equal corners and counts those of zero area (steps 2 and 3 of the module doc).
fn weld(vertices: &[DVec3], triangles: &[[u32; 3]], warnings: &mut Vec<MeshWarning>) -> TriMesh {
    // `+ 0.0` turns -0.0 into 0.0, so that the two weld
    let key = |v: DVec3| (v + DVec3::ZERO).to_array().map(f64::to_bits);
    // a closed mesh has about half as many vertices as triangles (Euler: V − E + F = 2, E = 3F/2)
    let expected = vertices.len().min(triangles.len() / 2 + 16);
    let mut index_of: HashMap<[u64; 3], u32, ahash::RandomState> =
        HashMap::with_capacity_and_hasher(expected, ahash::RandomState::new());
    let mut welded = Vec::with_capacity(expected);
    // files list neighbouring triangles near each other: a small direct-mapped cache of recent
    // vertices (in the processor's cache) answers most look-ups before the large table does;
    // all-ones bits are a NaN, which no checked coordinate is, so empty slots never match
    let mut recent = vec![([u64::MAX; 3], 0_u32); RECENT];
    let slot = |k: &[u64; 3]| {
        let h = (k[0] ^ k[1].rotate_left(21) ^ k[2].rotate_left(42)).wrapping_mul(0x9e37_79b9_7f4a_7c15);
        (h >> (64 - RECENT.trailing_zeros())) as usize
    };
    // the welded index of each input vertex, filled on first use
    let mut remap = vec![u32::MAX; vertices.len()];
    let mut out = Vec::with_capacity(triangles.len());
    let (mut degenerate, mut first_degenerate) = (0, None);
    let (mut zero_area, mut first_zero_area) = (0, None);
    for (t, tri) in triangles.iter().enumerate() {
        let corners = tri.map(|i| {
            let i = i as usize;
            if remap[i] == u32::MAX {
                let k = key(vertices[i]);
                let s = slot(&k);
                remap[i] = if recent[s].0 == k {
                    recent[s].1
                } else {
                    let id = *index_of.entry(k).or_insert_with(|| {
                        welded.push(vertices[i]);
                        (welded.len() - 1) as u32
                    });
                    recent[s] = (k, id);
                    id
                };
            }
            remap[i]
        });
        if corners[0] == corners[1] || corners[1] == corners[2] || corners[2] == corners[0] {
            degenerate += 1;
            first_degenerate.get_or_insert(t);
            continue;
        }
        let [a, b, c] = corners.map(|i| welded[i as usize]);
        if (b - a).cross(c - a) == DVec3::ZERO {
            zero_area += 1;
            first_zero_area.get_or_insert(t);
        }
        out.push(corners);
    }
    if let Some(first) = first_degenerate {
        warnings.push(MeshWarning::Degenerate { count: degenerate, first });
    }
    if let Some(first) = first_zero_area {
        warnings.push(MeshWarning::ZeroArea { count: zero_area, first });
    }
    TriMesh { vertices: welded, triangles: out }
}

/// The centre of the axis-aligned bounding box (m).
pub(crate) fn bounding_box_centre(vertices: &[DVec3]) -> DVec3 {
    let (lo, hi) = bounds(vertices);
    0.5 * (lo + hi)
}

/// The largest side of the axis-aligned bounding box (m).
fn extent(vertices: &[DVec3]) -> f64 {
    let (lo, hi) = bounds(vertices);
    (hi - lo).max_element().max(0.0)
}

fn bounds(vertices: &[DVec3]) -> (DVec3, DVec3) {
    vertices.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)))
}
