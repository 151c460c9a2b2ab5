//! What a robot's link looks like in the replay: its URDF `<visual>` geometry, else its
//! `<collision>` geometry ([`LinkGeometry`], read by the URDF loader), each element a part placed at
//! its `<origin>` in the link frame.
//!
//! - **Which elements.** A link's `<visual>` elements if every one of them can be drawn, else its
//!   `<collision>` elements if every one of them can, else nothing (the caller draws the inertia box
//!   or the marker). A link is never drawn half from one role and half from another.
//! - **Primitives** map one to one: `<box>` to `box {half_extents}`, `<sphere>` to `sphere`,
//!   `<cylinder>` (about its frame's z, as the page's) to `cylinder {radius, half_height}`.
//! - **Meshes** (STL, OBJ; [`tumble::mesh::read::read_file`]) are scaled by their `scale` (a mirrored
//!   scale, with an odd number of negative factors, has its triangles' corners swapped so that they
//!   still face out) and drawn as a `mesh` part, its vertices in the geometry frame. A mesh that cannot
//!   be read (a format that is not read, such as COLLADA `.dae`; a missing file; a URI that did not
//!   resolve) makes its link fall back, and is named in one warning per robot ([`LinkGeometries`]).
//! - **Page size.** Corners that coincide are welded (an STL repeats every corner of every
//!   triangle), coordinates are rounded to [`VERTEX_GRID`], and a mesh of more triangles than its
//!   share of [`ROBOT_TRIANGLES`] (at most [`MESH_TRIANGLES`]) is decimated by vertex clustering
//!   (Rossignac and Borrel 1993): its vertices are snapped to a grid of cubic cells, those in one
//!   cell merged to their mean, and the triangles that collapse dropped, the cell grown until the
//!   triangles fit. A mesh keeps its silhouette within about one cell.

use super::numbers;
use std::collections::{HashMap, HashSet};
use std::path::PathBuf;
use std::rc::Rc;
use tumble::math::{quat_to_wxyz, DQuat, DVec3};
use tumble::mesh::read::{read_file, MeshLimits};
use tumble::multibody::model::{GeometryRole, GeometryShape, LinkGeometry, MultibodyModel};

/// Triangles drawn for all the meshes of one robot, about (each mesh gets an equal share).
pub const ROBOT_TRIANGLES: usize = 40_000;
/// Triangles drawn for one mesh, at most.
pub const MESH_TRIANGLES: usize = 4_000;
/// A mesh's share is never below this many triangles.
const MIN_MESH_TRIANGLES: usize = 300;
/// Vertex coordinates are rounded to this grid (m): far below what a screen shows.
pub const VERTEX_GRID: f64 = 1e-5;

/// One drawable element of a link, in the link frame.
#[derive(Debug, Clone)]
struct Part {
    /// The geometry frame's origin in the link frame (m) and `link_from_geometry`.
    position: DVec3,
    orientation: DQuat,
    shape: PartShape,
}

#[derive(Debug, Clone)]
enum PartShape {
    /// A primitive's `geometry` object.
    Primitive(String),
    /// A mesh as read (file axes) and its scale.
    Mesh { soup: Rc<MeshSoup>, scale: DVec3 },
}

/// A mesh file's triangles, as read.
#[derive(Debug)]
struct MeshSoup {
    vertices: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
}

/// How a link is drawn from its URDF geometry.
#[derive(Debug, Clone)]
pub struct LinkDrawing {
    /// The role its parts come from.
    pub role: GeometryRole,
    parts: Vec<Part>,
}

/// The links of one robot drawn from their URDF geometry; the meshes that could not be read.
#[derive(Debug, Default)]
pub struct LinkGeometries {
    /// Each mesh file read once (a file several links name, or left and right by a mirrored scale).
    cache: HashMap<PathBuf, Result<Rc<MeshSoup>, String>>,
    /// Each mesh element that could not be read: why, its line in the URDF, and
    /// `uri (link 'name', <visual> line N)`.
    pub unreadable: Vec<(String, u32, String)>,
}

impl LinkGeometries {
    /// How link `link` of `model` is drawn: its visual elements if all can be drawn, else its
    /// collision elements if all can, else `None`. Meshes that cannot be read are remembered in
    /// [`unreadable`](Self::unreadable).
    pub fn drawing(&mut self, model: &MultibodyModel, link: &str) -> Option<LinkDrawing> {
        for role in [GeometryRole::Visual, GeometryRole::Collision] {
            let elements: Vec<&LinkGeometry> =
                model.geometries.iter().filter(|g| g.link == link && g.role == role).collect();
            if elements.is_empty() {
                continue;
            }
            let parts: Vec<Option<Part>> = elements.iter().map(|g| self.part(g)).collect();
            if parts.iter().all(Option::is_some) {
                return Some(LinkDrawing { role, parts: parts.into_iter().flatten().collect() });
            }
        }
        None
    }

    /// One element as a part, or `None` (remembered) when its mesh cannot be read.
    fn part(&mut self, g: &LinkGeometry) -> Option<Part> {
        let shape = match &g.shape {
            GeometryShape::Box { half_extents } => PartShape::Primitive(format!(
                "{{\"type\":\"box\",\"half_extents\":{}}}",
                numbers(&half_extents.to_array())
            )),
            GeometryShape::Sphere { radius } => {
                PartShape::Primitive(format!("{{\"type\":\"sphere\",\"radius\":{}}}", super::num(*radius)))
            }
            GeometryShape::Cylinder { radius, half_length } => PartShape::Primitive(format!(
                "{{\"type\":\"cylinder\",\"radius\":{},\"half_height\":{}}}",
                super::num(*radius),
                super::num(*half_length)
            )),
            GeometryShape::Capsule { radius, half_length } => PartShape::Primitive(format!(
                "{{\"type\":\"capsule\",\"radius\":{},\"half_height\":{}}}",
                super::num(*radius),
                super::num(*half_length)
            )),
            // the page has no ellipsoid: drawn as its bounding ball (drawing only)
            GeometryShape::Ellipsoid { radii } => {
                PartShape::Primitive(format!("{{\"type\":\"sphere\",\"radius\":{}}}", super::num(radii.max_element())))
            }
            GeometryShape::Plane => PartShape::Primitive("{\"type\":\"plane\"}".to_string()),
            GeometryShape::Mesh { uri, path, scale } => {
                let role = match g.role {
                    GeometryRole::Visual => "visual",
                    GeometryRole::Collision => "collision",
                };
                let read = match path {
                    None => Err("the URI did not resolve to a file".to_string()),
                    Some(path) => self.read(path),
                };
                match read {
                    Ok(soup) => PartShape::Mesh { soup, scale: *scale },
                    Err(why) => {
                        let entry = (why, g.line, format!("{uri} (link '{}', <{role}> line {})", g.link, g.line));
                        if !self.unreadable.contains(&entry) {
                            self.unreadable.push(entry);
                        }
                        return None;
                    }
                }
            }
        };
        // geometry_X_link: r is the geometry frame's origin in link coordinates
        let orientation = DQuat::from_mat3(&g.x_from_link.rotation_a_from_b()).normalize();
        Some(Part { position: g.x_from_link.r, orientation, shape })
    }

    fn read(&mut self, path: &std::path::Path) -> Result<Rc<MeshSoup>, String> {
        self.cache
            .entry(path.to_path_buf())
            .or_insert_with(|| {
                read_file(path, &MeshLimits::default())
                    .map(|s| Rc::new(MeshSoup { vertices: s.vertices, triangles: s.triangles }))
                    .map_err(|e| match path.extension().and_then(|e| e.to_str()) {
                        Some(ext) if ext.eq_ignore_ascii_case("dae") => {
                            "COLLADA (.dae) is not read: convert it to STL or OBJ".to_string()
                        }
                        _ if !path.exists() => format!("missing (the path tried: {})", path.display()),
                        _ => format!("{} ({})", e.problem, path.display()),
                    })
            })
            .clone()
    }
}

/// The triangles each mesh of `drawings` may keep: an equal share of [`ROBOT_TRIANGLES`], between
/// [`MIN_MESH_TRIANGLES`] and [`MESH_TRIANGLES`].
pub fn mesh_budget<'a>(drawings: impl Iterator<Item = &'a LinkDrawing>) -> usize {
    let meshes = drawings.flat_map(|d| &d.parts).filter(|p| matches!(p.shape, PartShape::Mesh { .. })).count();
    (ROBOT_TRIANGLES / meshes.max(1)).clamp(MIN_MESH_TRIANGLES, MESH_TRIANGLES)
}

impl LinkDrawing {
    /// The page's part objects (comma-separated), meshes decimated to `budget` triangles each.
    pub fn parts_json(&self, budget: usize) -> String {
        let parts: Vec<String> = self
            .parts
            .iter()
            .map(|part| {
                let geometry = match &part.shape {
                    PartShape::Primitive(g) => g.clone(),
                    PartShape::Mesh { soup, scale } => {
                        let (vertices, triangles) = page_mesh(soup, *scale, budget);
                        super::triangles("mesh", &vertices, &triangles)
                    }
                };
                format!(
                    "{{\"geometry\":{geometry},\"position\":{},\"orientation\":{}}}",
                    numbers(&part.position.to_array()),
                    numbers(&quat_to_wxyz(part.orientation))
                )
            })
            .collect();
        parts.join(",")
    }
}

/// A mesh for the page: scaled (corners swapped when the scale mirrors), welded, rounded to
/// [`VERTEX_GRID`], and decimated by vertex clustering to at most `budget` triangles.
fn page_mesh(soup: &MeshSoup, scale: DVec3, budget: usize) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let points: Vec<DVec3> = soup.vertices.iter().map(|v| *v * scale).collect();
    let mirrored = scale.x * scale.y * scale.z < 0.0;
    let triangles: Vec<[u32; 3]> =
        soup.triangles.iter().map(|t| if mirrored { [t[0], t[2], t[1]] } else { *t }).collect();
    let mut clustered = cluster(&points, &triangles, VERTEX_GRID);
    if clustered.1.len() > budget {
        let (lo, hi) =
            points.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        // start at 256 cells across the largest extent, and grow the cell until the mesh fits
        let mut cell = ((hi - lo).max_element() / 256.0).max(VERTEX_GRID);
        while clustered.1.len() > budget {
            clustered = cluster(&points, &triangles, cell);
            cell *= 1.25;
        }
    }
    clustered
}

/// Vertex clustering: the points in one cubic cell of side `cell` (m) become one vertex, their mean
/// rounded to [`VERTEX_GRID`]; triangles with two corners in one cell are dropped, and so is a
/// triangle whose corners another already has.
fn cluster(points: &[DVec3], triangles: &[[u32; 3]], cell: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut index_of_cell: HashMap<[i64; 3], u32> = HashMap::new();
    let mut sums: Vec<(DVec3, f64)> = Vec::new();
    let mut new_index = vec![u32::MAX; points.len()];
    let mut cell_of = |i: usize| -> u32 {
        if new_index[i] == u32::MAX {
            let key = (points[i] / cell).floor().to_array().map(|c| c as i64);
            let next = sums.len() as u32;
            let k = *index_of_cell.entry(key).or_insert(next);
            if k == next {
                sums.push((DVec3::ZERO, 0.0));
            }
            sums[k as usize].0 += points[i];
            sums[k as usize].1 += 1.0;
            new_index[i] = k;
        }
        new_index[i]
    };
    let mut kept = Vec::new();
    let mut seen = HashSet::new();
    for t in triangles {
        let c = t.map(|i| cell_of(i as usize));
        if c[0] == c[1] || c[1] == c[2] || c[0] == c[2] {
            continue;
        }
        let mut key = c;
        key.sort_unstable();
        if seen.insert(key) {
            kept.push(c);
        }
    }
    // only the vertices that a kept triangle uses, renumbered in order of use
    let mut used = vec![u32::MAX; sums.len()];
    let mut vertices = Vec::new();
    for t in &mut kept {
        for c in t.iter_mut() {
            if used[*c as usize] == u32::MAX {
                used[*c as usize] = vertices.len() as u32;
                let (sum, n) = sums[*c as usize];
                vertices.push((sum / n / VERTEX_GRID).round() * VERTEX_GRID);
            }
            *c = used[*c as usize];
        }
    }
    (vertices, kept)
}

/// The warning of a robot whose meshes could not all be read, or `None`: one line, the meshes
/// grouped by why, in the URDF's order.
pub fn warning(robot: &str, unreadable: &[(String, u32, String)]) -> Option<String> {
    if unreadable.is_empty() {
        return None;
    }
    let mut sorted: Vec<&(String, u32, String)> = unreadable.iter().collect();
    sorted.sort_by_key(|(_, line, _)| *line);
    let mut groups: Vec<(&str, Vec<&str>)> = Vec::new();
    for (why, _, what) in sorted {
        match groups.iter_mut().find(|(w, _)| w == why) {
            Some((_, items)) => items.push(what),
            None => groups.push((why, vec![what])),
        }
    }
    let groups: Vec<String> = groups.iter().map(|(why, items)| format!("{why}: {}", items.join(", "))).collect();
    Some(format!(
        "robot `{robot}`: {} not drawn, the links drawn from their <collision> geometry or else as their inertia \
         box; {}",
        if unreadable.len() == 1 { "1 mesh is" } else { "meshes are" },
        groups.join("; ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit square of two triangles, as an STL gives it: six corners, two of them twice.
    fn square() -> MeshSoup {
        let v = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::ZERO, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        MeshSoup { vertices: v.to_vec(), triangles: vec![[0, 1, 2], [3, 4, 5]] }
    }

    #[test]
    fn coincident_corners_are_welded() {
        let (vertices, triangles) = page_mesh(&square(), DVec3::ONE, 100);
        assert_eq!(vertices.len(), 4);
        assert_eq!(triangles, [[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn a_mirroring_scale_keeps_the_triangles_facing_out() {
        let normal = |v: &[DVec3], t: [u32; 3]| {
            let [a, b, c] = t.map(|i| v[i as usize]);
            (b - a).cross(c - a)
        };
        let (vertices, triangles) = page_mesh(&square(), DVec3::new(-2.0, 1.0, 1.0), 100);
        // the square is mirrored to x ≤ 0 and still faces +z
        assert!(vertices.iter().all(|v| v.x <= 0.0) && vertices.iter().any(|v| v.x == -2.0));
        assert!(triangles.iter().all(|t| normal(&vertices, *t).z > 0.0));
    }

    #[test]
    fn a_large_mesh_is_decimated_to_its_budget() {
        // a 100 × 100 grid of squares: 20,000 triangles
        let n = 100;
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                vertices.push(DVec3::new(i as f64, j as f64, ((i * j) as f64).sin()) / n as f64);
            }
        }
        let at = |i: u32, j: u32| i * (n + 1) + j;
        for i in 0..n {
            for j in 0..n {
                triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        let (v, t) = page_mesh(&MeshSoup { vertices, triangles }, DVec3::ONE, 2_000);
        assert!(t.len() <= 2_000 && t.len() > 500, "{} triangles", t.len());
        // the corners stay within a cell of the unit square
        let (lo, hi) = v.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        assert!(lo.x < 0.05 && lo.y < 0.05 && hi.x > 0.95 && hi.y > 0.95, "{lo} {hi}");
        assert!(t.iter().flatten().all(|&i| (i as usize) < v.len()));
    }
}
