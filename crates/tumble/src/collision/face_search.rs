//! The face of a convex polyhedron most nearly facing a direction, by a walk instead of a scan.
//!
//! A hull against a plane (a robot's mesh foot on the floor) makes its contact points on the face
//! whose outward normal is closest to the direction into the plane: `f* = argmax_f n_f · d`
//! (parry's `local_support_feature` scans every face for it: 1 340 faces for a 672-vertex foot, at
//! every step). The face normals are points of the unit sphere, so each is a vertex of their own
//! convex hull `N`, and `n_f · d` is a linear function on `N`: its maximum over the vertices is
//! reached by steepest ascent along `N`'s edges, since on a convex polytope a vertex no neighbour of
//! which is higher is the highest (the argument of the simplex method). The walk starts from the
//! face of the previous step, so a foot at rest finds its face in one look at its neighbours.
//!
//! `N`'s adjacency is made once, at load. Normals that the hull algorithm merges (closer than its
//! tolerance) are left out of the walk; they differ from a kept neighbour by round-off, so the face
//! found has `n · d` within round-off of the scan's (the unit test checks 1e-9 on meshes and point
//! clouds; ties between faces may be broken differently).

use parry3d_f64::shape::{ConvexPolyhedron, PackedFeatureId, PolygonalFeature};
use parry3d_f64::transformation::try_convex_hull;
use std::collections::HashMap;

use crate::math::DVec3;

/// The neighbours of each face of a convex polyhedron on the hull of its face normals.
#[derive(Debug, Clone)]
pub struct FaceGraph {
    /// `neighbours[start[f]..start[f + 1]]`: the faces next to face `f` (CSR).
    start: Vec<u32>,
    neighbours: Vec<u32>,
    /// The faces that are vertices of the normals' hull (a walk starts only on one).
    on_hull: Vec<bool>,
}

impl FaceGraph {
    /// The graph of `poly`'s faces, or `None` when it has fewer than 4 faces or the normals' hull
    /// cannot be made (the scan is then used).
    pub fn new(poly: &ConvexPolyhedron) -> Option<Self> {
        let faces = poly.faces();
        if faces.len() < 4 {
            return None;
        }
        let normals: Vec<DVec3> = faces.iter().map(|f| f.normal).collect();
        let (vertices, triangles) = try_convex_hull(&normals).ok()?;
        // the hull's vertices are copies of input normals: back to face indices by their bits
        let key = |v: DVec3| (v.x.to_bits(), v.y.to_bits(), v.z.to_bits());
        let index: HashMap<_, u32> = normals.iter().enumerate().map(|(f, &n)| (key(n), f as u32)).collect();
        let face_of: Vec<u32> = vertices.iter().map(|&v| index.get(&key(v)).copied()).collect::<Option<_>>()?;
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); faces.len()];
        for t in &triangles {
            for k in 0..3 {
                let (a, b) = (face_of[t[k] as usize], face_of[t[(k + 1) % 3] as usize]);
                if !lists[a as usize].contains(&b) {
                    lists[a as usize].push(b);
                }
                if !lists[b as usize].contains(&a) {
                    lists[b as usize].push(a);
                }
            }
        }
        let mut on_hull = vec![false; faces.len()];
        for &f in &face_of {
            on_hull[f as usize] = true;
        }
        let mut start = Vec::with_capacity(faces.len() + 1);
        let mut neighbours = Vec::new();
        for list in &lists {
            start.push(neighbours.len() as u32);
            neighbours.extend_from_slice(list);
        }
        start.push(neighbours.len() as u32);
        Some(Self { start, neighbours, on_hull })
    }

    /// The face `f` of `poly` (whose graph this is) maximising `n_f · dir` (`dir` in `poly`'s frame),
    /// walking from face `from` (any index; the face found last time is the best start).
    pub fn support_face(&self, poly: &ConvexPolyhedron, dir: DVec3, from: u32) -> u32 {
        let faces = poly.faces();
        let mut f = if (from as usize) < faces.len() && self.on_hull[from as usize] {
            from
        } else {
            self.on_hull.iter().position(|&h| h).unwrap_or(0) as u32
        };
        let mut best = faces[f as usize].normal.dot(dir);
        loop {
            let (a, b) = (self.start[f as usize] as usize, self.start[f as usize + 1] as usize);
            let mut next = f;
            for &g in &self.neighbours[a..b] {
                let value = faces[g as usize].normal.dot(dir);
                if value > best {
                    best = value;
                    next = g;
                }
            }
            if next == f {
                return f;
            }
            f = next;
        }
    }
}

/// Face `fid` of `poly` as parry's polygonal feature (its first four vertices, as parry's
/// `local_support_feature` writes it).
pub fn face_feature(poly: &ConvexPolyhedron, fid: u32, out: &mut PolygonalFeature) {
    let face = &poly.faces()[fid as usize];
    let first = face.first_vertex_or_edge as usize;
    let count = (face.num_vertices_or_edges as usize).min(4);
    let (vertices, edges) = (poly.vertices_adj_to_face(), poly.edges_adj_to_face());
    for i in 0..count {
        let (vid, eid) = (vertices[first + i], edges[first + i]);
        out.vertices[i] = poly.points()[vid as usize];
        out.vids[i] = PackedFeatureId::vertex(vid);
        out.eids[i] = PackedFeatureId::edge(eid);
    }
    out.fid = PackedFeatureId::face(fid);
    out.num_vertices = count;
}

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d_f64::shape::PolygonalFeatureMap;

    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    fn random_unit(seed: &mut u64) -> DVec3 {
        loop {
            let v = DVec3::new(2.0 * lcg(seed) - 1.0, 2.0 * lcg(seed) - 1.0, 2.0 * lcg(seed) - 1.0);
            if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }

    /// Hulls of many faces: points on a sphere, on a flattened ellipsoid (near-parallel faces), in a
    /// box with rounded corners, and a few points.
    fn hulls() -> Vec<ConvexPolyhedron> {
        let mut seed = 7;
        let mut clouds: Vec<Vec<DVec3>> = Vec::new();
        clouds.push((0..600).map(|_| random_unit(&mut seed)).collect());
        clouds.push((0..400).map(|_| random_unit(&mut seed) * DVec3::new(0.03, 0.01, 0.002)).collect());
        clouds.push(
            (0..500)
                .map(|_| (random_unit(&mut seed) * 0.2).clamp(DVec3::splat(-0.15), DVec3::splat(0.15)) * 3.0)
                .collect(),
        );
        clouds.push((0..9).map(|_| random_unit(&mut seed)).collect());
        clouds.iter().map(|c| ConvexPolyhedron::from_convex_hull(c).expect("a hull")).collect()
    }

    /// The walk finds a face as well aligned as the scan's, from any start, for random directions.
    #[test]
    fn the_walk_finds_the_scans_face() {
        let mut seed = 11;
        for poly in hulls() {
            let graph = FaceGraph::new(&poly).expect("a graph");
            let faces = poly.faces().len() as u32;
            for k in 0..2000 {
                let dir = random_unit(&mut seed);
                let mut scan = PolygonalFeature::default();
                poly.local_support_feature(dir, &mut scan);
                let best = poly.faces()[scan.fid.unpack().unwrap_face() as usize].normal.dot(dir);
                let from = (k * 7919) % faces;
                let found = graph.support_face(&poly, dir, from);
                let value = poly.faces()[found as usize].normal.dot(dir);
                assert!(value >= best - 1e-9, "{faces} faces: walk {value} against scan {best}");
            }
        }
    }

    /// The feature of a face is parry's, field by field.
    #[test]
    fn a_face_feature_is_parrys() {
        let mut seed = 3;
        for poly in hulls() {
            for _ in 0..200 {
                let dir = random_unit(&mut seed);
                let mut scan = PolygonalFeature::default();
                poly.local_support_feature(dir, &mut scan);
                let mut ours = PolygonalFeature::default();
                face_feature(&poly, scan.fid.unpack().unwrap_face(), &mut ours);
                assert_eq!(ours.num_vertices, scan.num_vertices);
                assert_eq!(ours.fid, scan.fid);
                for i in 0..ours.num_vertices {
                    assert_eq!(
                        (ours.vertices[i], ours.vids[i], ours.eids[i]),
                        (scan.vertices[i], scan.vids[i], scan.eids[i])
                    );
                }
            }
        }
    }
}
