//! Mesh files → a triangle soup: OBJ through `tobj`, STL (binary or ASCII) through `stl_io`.
//!
//! Sizes are checked before anything proportional to them is allocated: the file's length against
//! [`MeshLimits::max_file_bytes`] before it is read; a binary STL's triangle count against the
//! file's length (`84 + 50 n` bytes) and against [`MeshLimits::max_triangles`] before the triangles
//! are decoded; the faces of an OBJ and the facets of an ASCII STL are counted in a first pass over
//! the text before the parser runs. The OBJ pass also checks every face index, so that the parser
//! only ever sees indices it can follow, and gives the line of a bad one.
//!
//! Which STL: a file whose length is exactly `84 + 50 n`, with `n` the count in its header, is
//! binary (even if its header starts with `solid`, as some exporters write); otherwise a file
//! starting with `solid` is ASCII; anything else is a binary STL whose size does not match.

use super::{MeshError, MeshProblem};
use crate::math::DVec3;
use std::io::{Cursor, Read};
use std::path::Path;

/// The largest triangle count any mesh may have: vertex indices are `u32` and a triangle soup has
/// three vertices per triangle.
pub const HARD_MAX_TRIANGLES: u64 = (u32::MAX / 3) as u64;

/// Caps on what a mesh file may cost, checked before allocating (reliability R05).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshLimits {
    /// Largest file read (bytes); default 1 GiB.
    pub max_file_bytes: u64,
    /// Largest number of triangles; default 10⁷ (a binary STL of 500 MB). At most [`HARD_MAX_TRIANGLES`].
    pub max_triangles: u64,
}

impl Default for MeshLimits {
    fn default() -> Self {
        Self { max_file_bytes: 1 << 30, max_triangles: 10_000_000 }
    }
}

impl MeshLimits {
    fn triangle_cap(&self) -> u64 {
        self.max_triangles.min(HARD_MAX_TRIANGLES)
    }
}

/// A mesh file's format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ.
    Obj,
    /// Binary STL.
    StlBinary,
    /// ASCII STL.
    StlAscii,
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Format::Obj => "OBJ",
            Format::StlBinary => "binary STL",
            Format::StlAscii => "ASCII STL",
        })
    }
}

/// Triangles as read, before welding and checks: corners index `vertices` (m, mesh axes).
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleSoup {
    /// The file's format.
    pub format: Format,
    /// Vertex coordinates, mesh axes (m); finite.
    pub vertices: Vec<DVec3>,
    /// Corner indices into `vertices`, in the file's order (counter-clockwise seen from outside
    /// when the file is oriented as STL and OBJ intend).
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleSoup {
    /// The soup with every coordinate multiplied by `scale` (per axis).
    pub fn scaled(mut self, scale: [f64; 3]) -> Self {
        let s = DVec3::from_array(scale);
        if s != DVec3::ONE {
            self.vertices.iter_mut().for_each(|v| *v *= s);
        }
        self
    }
}

/// Reads a mesh file; the format comes from the extension (`.obj`, `.stl`, any case).
pub fn read_file(path: &Path, limits: &MeshLimits) -> Result<TriangleSoup, MeshError> {
    let file = path.display().to_string();
    let fail = |p: MeshProblem| MeshError::new(&file, p);
    let ext = path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase()).unwrap_or_default();
    let is_stl = match ext.as_str() {
        "stl" => true,
        "obj" => false,
        "" => return Err(fail(MeshProblem::UnknownFormat("no extension".into()))),
        _ => return Err(fail(MeshProblem::UnknownFormat(format!(".{ext}")))),
    };
    let meta = std::fs::metadata(path).map_err(|e| fail(MeshProblem::Io(e.to_string())))?;
    if meta.is_dir() {
        return Err(fail(MeshProblem::Io("is a directory".into())));
    }
    if meta.len() > limits.max_file_bytes {
        return Err(fail(MeshProblem::FileTooLarge { bytes: meta.len(), limit: limits.max_file_bytes }));
    }
    let mut bytes = Vec::new();
    // `take` guards against a file that grows between the metadata and the read
    std::fs::File::open(path)
        .and_then(|f| f.take(limits.max_file_bytes + 1).read_to_end(&mut bytes))
        .map_err(|e| fail(MeshProblem::Io(e.to_string())))?;
    if bytes.len() as u64 > limits.max_file_bytes {
        return Err(fail(MeshProblem::FileTooLarge { bytes: bytes.len() as u64, limit: limits.max_file_bytes }));
    }
    let soup = if is_stl { read_stl(bytes, limits) } else { read_obj(&bytes, limits) };
    soup.map_err(fail)
}

/// Reads an STL file's bytes (binary or ASCII).
pub fn read_stl(mut bytes: Vec<u8>, limits: &MeshLimits) -> Result<TriangleSoup, MeshProblem> {
    let len = bytes.len() as u64;
    if len == 0 {
        return Err(MeshProblem::Empty);
    }
    let header_count = (len >= 84).then(|| u64::from(u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]])));
    let starts_solid = bytes.trim_ascii_start().starts_with(b"solid");
    match header_count {
        Some(count) if 84 + 50 * count == len => {
            if count > limits.triangle_cap() {
                return Err(MeshProblem::TooManyTriangles { count, limit: limits.triangle_cap() });
            }
            // the header is free text: one starting with "solid " would make the reader take it for ASCII
            bytes[..5].fill(0);
            read_stl_binary(&bytes, count as usize)
        }
        _ if starts_solid => read_stl_ascii(&bytes, limits),
        None => Err(MeshProblem::StlTooShort { actual: len }),
        Some(count) => Err(MeshProblem::StlSizeMismatch { count, expected: 84 + 50 * count, actual: len }),
    }
}

fn read_stl_binary(bytes: &[u8], count: usize) -> Result<TriangleSoup, MeshProblem> {
    if count == 0 {
        return Err(MeshProblem::NoTriangles);
    }
    let parse =
        |e: std::io::Error| MeshProblem::Parse { format: Format::StlBinary, line: None, message: e.to_string() };
    let mut cursor = Cursor::new(bytes);
    let reader = stl_io::create_stl_reader(&mut cursor).map_err(parse)?;
    // `count` is known to fit the file: 50 bytes per triangle are there to be read
    let mut vertices = Vec::with_capacity(3 * count);
    for (facet, triangle) in reader.enumerate() {
        let triangle = triangle.map_err(parse)?;
        for corner in triangle.vertices {
            let v = DVec3::new(f64::from(corner[0]), f64::from(corner[1]), f64::from(corner[2]));
            if let Some(value) = v.to_array().into_iter().find(|x| !x.is_finite()) {
                return Err(MeshProblem::NonFinite { vertex: vertices.len(), value, line: None, facet: Some(facet) });
            }
            vertices.push(v);
        }
    }
    Ok(soup_of_corners(Format::StlBinary, vertices))
}

fn read_stl_ascii(bytes: &[u8], limits: &MeshLimits) -> Result<TriangleSoup, MeshProblem> {
    let facets = bytes.split(|&b| b == b'\n').filter(|l| l.trim_ascii_start().starts_with(b"facet")).count() as u64;
    if facets > limits.triangle_cap() {
        return Err(MeshProblem::TooManyTriangles { count: facets, limit: limits.triangle_cap() });
    }
    if facets == 0 {
        return Err(MeshProblem::NoTriangles);
    }
    // the reader wants the first line to be `solid <name>` exactly; the name is not used
    let first_end = bytes.iter().position(|&b| b == b'\n').unwrap_or(bytes.len());
    let mut text = b"solid mesh\n".to_vec();
    text.extend_from_slice(bytes.get(first_end + 1..).unwrap_or(&[]));
    let mut cursor = Cursor::new(text);
    let mut vertices = Vec::with_capacity(3 * facets as usize);
    let reader = stl_io::create_stl_reader(&mut cursor).map_err(|e| ascii_error(e, 0))?;
    for (facet, triangle) in reader.enumerate() {
        let triangle = triangle.map_err(|e| ascii_error(e, facet))?;
        for corner in triangle.vertices {
            vertices.push(DVec3::new(f64::from(corner[0]), f64::from(corner[1]), f64::from(corner[2])));
        }
    }
    let read = vertices.len() as u64 / 3;
    if read != facets {
        return Err(MeshProblem::Parse {
            format: Format::StlAscii,
            line: None,
            message: format!(
                "{facets} facets in the file but {read} before the first `endsolid`: \
                 a file with several solids is not read"
            ),
        });
    }
    Ok(soup_of_corners(Format::StlAscii, vertices))
}

fn ascii_error(e: std::io::Error, facet: usize) -> MeshProblem {
    MeshProblem::Parse { format: Format::StlAscii, line: None, message: format!("{e} (in facet {facet})") }
}

/// Three corners per triangle, in order.
fn soup_of_corners(format: Format, vertices: Vec<DVec3>) -> TriangleSoup {
    let triangles = (0..vertices.len() as u32 / 3).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
    TriangleSoup { format, vertices, triangles }
}

/// Reads an OBJ file's bytes: vertices (`v`) and faces (`f`, polygons split into fans); groups and
/// objects are merged into one mesh; texture coordinates, normals and materials are ignored.
pub fn read_obj(bytes: &[u8], limits: &MeshLimits) -> Result<TriangleSoup, MeshProblem> {
    if bytes.is_empty() {
        return Err(MeshProblem::Empty);
    }
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let line = 1 + bytes[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count();
        MeshProblem::Parse { format: Format::Obj, line: Some(line), message: "not valid UTF-8 text".into() }
    })?;
    let triangles = prescan_obj(text, limits)?;
    if triangles == 0 {
        return Err(MeshProblem::NoTriangles);
    }
    let options =
        tobj::LoadOptions { triangulate: true, ignore_points: true, ignore_lines: true, ..Default::default() };
    let (models, _materials) =
        tobj::load_obj_buf(&mut Cursor::new(text.as_bytes()), &options, |_| Err(tobj::LoadError::GenericFailure))
            .map_err(|e| MeshProblem::Parse { format: Format::Obj, line: None, message: e.to_string() })?;
    let mut soup = TriangleSoup {
        format: Format::Obj,
        vertices: Vec::with_capacity(3 * triangles as usize),
        triangles: Vec::with_capacity(triangles as usize),
    };
    for model in &models {
        let offset = soup.vertices.len() as u32;
        let mesh = &model.mesh;
        soup.vertices.extend(mesh.positions.chunks_exact(3).map(|p| DVec3::new(p[0], p[1], p[2])));
        soup.triangles.extend(mesh.indices.chunks_exact(3).map(|t| [t[0] + offset, t[1] + offset, t[2] + offset]));
    }
    if let Some((vertex, value)) = soup
        .vertices
        .iter()
        .enumerate()
        .find_map(|(i, v)| v.to_array().into_iter().find(|x| !x.is_finite()).map(|x| (i, x)))
    {
        return Err(MeshProblem::NonFinite { vertex, value, line: first_non_finite_vertex_line(text), facet: None });
    }
    Ok(soup)
}

/// Checks every face index of an OBJ text and counts the triangles the faces will make; the line
/// of a bad index is reported. A positive index must name an existing element (`v`, `vt` or `vn`,
/// by its position in the triple), a negative one an element already written above the face.
fn prescan_obj(text: &str, limits: &MeshLimits) -> Result<u64, MeshProblem> {
    const KINDS: [&str; 3] = ["v", "vt", "vn"];
    let mut total = [0_i64; 3];
    for line in text.lines() {
        if let Some(kind) = line.split_whitespace().next().and_then(|w| KINDS.iter().position(|k| *k == w)) {
            total[kind] += 1;
        }
    }
    let mut seen = [0_i64; 3];
    let mut triangles = 0_u64;
    for (k, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let first = words.next();
        if let Some(kind) = first.and_then(|w| KINDS.iter().position(|k| *k == w)) {
            seen[kind] += 1;
            continue;
        }
        if first != Some("f") {
            continue;
        }
        let mut corners = 0_u64;
        for word in words {
            corners += 1;
            for (j, part) in word.split('/').enumerate().filter(|(_, p)| !p.is_empty()) {
                let ok = j < 3
                    && part.parse::<i64>().is_ok_and(|i| {
                        (1..=total[j]).contains(&i) || (i < 0 && i.unsigned_abs() <= seen[j].unsigned_abs())
                    });
                if !ok {
                    let kind = KINDS.get(j).copied().unwrap_or("?");
                    return Err(MeshProblem::Parse {
                        format: Format::Obj,
                        line: Some(k + 1),
                        message: format!(
                            "face index `{part}` names no `{kind}` (the file has {} of them, {} above this line)",
                            total.get(j).copied().unwrap_or(0),
                            seen.get(j).copied().unwrap_or(0)
                        ),
                    });
                }
            }
        }
        triangles += corners.saturating_sub(2);
        if triangles > limits.triangle_cap() {
            return Err(MeshProblem::TooManyTriangles { count: triangles, limit: limits.triangle_cap() });
        }
    }
    Ok(triangles)
}

/// The line of the first `v` whose coordinates do not all read as finite numbers.
fn first_non_finite_vertex_line(text: &str) -> Option<usize> {
    text.lines().enumerate().find_map(|(k, line)| {
        let mut words = line.split_whitespace();
        (words.next() == Some("v") && words.take(3).any(|w| w.parse::<f64>().is_ok_and(|x| !x.is_finite())))
            .then_some(k + 1)
    })
}
