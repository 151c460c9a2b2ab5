//! Malformed meshes are reported, not guessed (reliability U16, R05): each fault gives its own
//! problem with the numbers a user needs, and no input panics.

mod mesh_common;

use mesh_common::*;
use proptest::prelude::*;
use std::path::PathBuf;
use tumble::math::DVec3;
use tumble::mesh::read::{read_obj, read_stl};
use tumble::mesh::{self, Format, MeshLimits, MeshProblem, MeshWarning, TriMesh};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/meshes").join(name)
}

fn problem(name: &str) -> MeshProblem {
    let e = mesh::load(&fixture(name), [1.0; 3], &MeshLimits::default()).unwrap_err();
    assert!(e.to_string().starts_with(&fixture(name).display().to_string()), "{e}");
    e.problem
}

fn cube_stl() -> Vec<u8> {
    std::fs::read(fixture("cube.stl")).unwrap()
}

#[test]
fn an_open_surface_names_how_many_edges_are_open() {
    let p = problem("open_box.obj");
    assert!(matches!(p, MeshProblem::NotClosed { open_edges: 4, inconsistent_edges: 0, .. }), "{p:?}");
    assert!(p.to_string().contains("4 open edges"), "{p}");
}

#[test]
fn a_flipped_triangle_is_an_inconsistent_orientation() {
    let p = problem("flipped_face.obj");
    assert!(matches!(p, MeshProblem::Inconsistent { inconsistent_edges: 3, .. }), "{p:?}");
}

#[test]
fn an_inside_out_file_is_flipped_with_a_warning() {
    let loaded = mesh::load(&fixture("inside_out.stl"), [1.0; 3], &MeshLimits::default()).unwrap();
    assert_eq!(loaded.format, Format::StlAscii);
    assert_eq!(loaded.warnings, vec![MeshWarning::InsideOut { volume: -1.0, shells: 1 }]);
    assert_eq!(loaded.mesh.mass_properties(1.0).unwrap().volume, 1.0);
}

#[test]
fn degenerate_triangles_are_skipped_with_a_warning() {
    let loaded = mesh::load(&fixture("degenerate.obj"), [1.0; 3], &MeshLimits::default()).unwrap();
    assert_eq!(loaded.warnings, vec![MeshWarning::Degenerate { count: 1, first: 12 }]);
    assert_eq!(loaded.mesh.triangles().len(), 12);
    // zero-area triangles with distinct corners close T-junctions: kept, and counted
    let (mut v, mut t) = box_parts(DVec3::ONE);
    // split the side triangle [0, 1, 5] at the midpoint m of its edge 0–1, which the bottom face
    // [0, 3, 1] does not share: the sliver [0, 1, m] closes the gap
    v.push(DVec3::new(0.0, -1.0, -1.0));
    let m = 8;
    let side = t.iter().position(|f| *f == [0, 1, 5]).unwrap();
    t[side] = [0, m, 5];
    t.push([m, 1, 5]);
    t.push([0, 1, m]);
    let sliver = t.len() - 1;
    let (mesh, warnings) = TriMesh::new(v, t).unwrap();
    assert_eq!(warnings, vec![MeshWarning::ZeroArea { count: 1, first: sliver }]);
    assert_eq!(mesh.mass_properties(1.0).unwrap().volume, 8.0);
}

#[test]
fn a_nan_coordinate_names_its_line_or_facet() {
    let p = problem("nan.obj");
    assert!(matches!(p, MeshProblem::NonFinite { line: Some(8), .. }), "{p:?}");
    let mut bytes = cube_stl();
    // facet 3, second corner, y: 84 + 3·50 + 12 (normal) + 12 (first corner) + 4
    bytes[84 + 150 + 28..84 + 150 + 32].copy_from_slice(&f32::NAN.to_le_bytes());
    let p = read_stl(bytes, &MeshLimits::default()).unwrap_err();
    assert!(matches!(p, MeshProblem::NonFinite { facet: Some(3), .. }), "{p:?}");
    let p =
        TriMesh::new(vec![DVec3::ZERO, DVec3::X, DVec3::new(0.0, f64::INFINITY, 0.0)], vec![[0, 1, 2]]).unwrap_err();
    assert!(matches!(p, MeshProblem::NonFinite { vertex: 2, .. }), "{p:?}");
}

#[test]
fn empty_files_are_reported() {
    assert_eq!(problem("empty.stl"), MeshProblem::Empty);
    assert_eq!(problem("empty.obj"), MeshProblem::Empty);
    assert_eq!(read_obj(b"# nothing but a comment\nv 0 0 0\n", &MeshLimits::default()), Err(MeshProblem::NoTriangles));
    let mut header = vec![0u8; 84];
    assert_eq!(read_stl(header.clone(), &MeshLimits::default()), Err(MeshProblem::NoTriangles));
    header.truncate(40);
    assert_eq!(read_stl(header, &MeshLimits::default()), Err(MeshProblem::StlTooShort { actual: 40 }));
}

#[test]
fn a_binary_stl_whose_count_does_not_match_its_size_is_rejected_before_allocating() {
    let p = problem("truncated.stl");
    assert_eq!(p, MeshProblem::StlSizeMismatch { count: 12, expected: 684, actual: 664 });
    assert!(p.to_string().contains("truncated"), "{p}");
    // a header claiming 4 billion triangles in a 134-byte file: refused from the sizes alone
    let mut bytes = cube_stl()[..134].to_vec();
    bytes[80..84].copy_from_slice(&u32::MAX.to_le_bytes());
    let p = read_stl(bytes, &MeshLimits::default()).unwrap_err();
    assert!(matches!(p, MeshProblem::StlSizeMismatch { count: 4_294_967_295, actual: 134, .. }), "{p:?}");
    let mut longer = cube_stl();
    longer.extend_from_slice(&[0; 7]);
    assert!(read_stl(longer, &MeshLimits::default()).unwrap_err().to_string().contains("extra bytes"));
}

#[test]
fn the_triangle_cap_is_checked_before_reading_the_triangles() {
    let limits = MeshLimits { max_triangles: 11, ..MeshLimits::default() };
    assert_eq!(read_stl(cube_stl(), &limits), Err(MeshProblem::TooManyTriangles { count: 12, limit: 11 }));
    let obj = std::fs::read(fixture("cube.obj")).unwrap();
    assert_eq!(read_obj(&obj, &limits), Err(MeshProblem::TooManyTriangles { count: 12, limit: 11 }));
    let ascii = std::fs::read(fixture("inside_out.stl")).unwrap();
    assert_eq!(read_stl(ascii, &limits), Err(MeshProblem::TooManyTriangles { count: 12, limit: 11 }));
    let limits = MeshLimits { max_file_bytes: 100, ..MeshLimits::default() };
    let e = mesh::load(&fixture("cube.stl"), [1.0; 3], &limits).unwrap_err();
    assert_eq!(e.problem, MeshProblem::FileTooLarge { bytes: 684, limit: 100 });
}

#[test]
fn a_binary_stl_with_a_solid_header_is_read_as_binary() {
    let loaded = mesh::load(&fixture("solid_header.stl"), [1.0; 3], &MeshLimits::default()).unwrap();
    assert_eq!(loaded.format, Format::StlBinary);
    assert_eq!(loaded.mesh.mass_properties(1.0).unwrap().volume, 1.0);
}

#[test]
fn obj_faces_are_checked_with_their_line() {
    let p = problem("bad_index.obj");
    assert!(matches!(p, MeshProblem::Parse { format: Format::Obj, line: Some(22), .. }), "{p:?}");
    for face in [
        "f 1 2 0",
        "f 1 2 -9",
        "f 1/99 2 3",
        "f 1 2 x",
        "f 1 2 3/1/1/1",
        "f 1 2 9223372036854775807",
        "f 1 2 -9223372036854775808",
    ] {
        let text = format!("v 0 0 0\nv 1 0 0\nv 0 1 0\n{face}\n");
        let p = read_obj(text.as_bytes(), &MeshLimits::default()).unwrap_err();
        assert!(matches!(p, MeshProblem::Parse { line: Some(4), .. }), "{face}: {p:?}");
    }
}

#[test]
fn obj_polygons_negative_indices_and_groups_make_one_welded_solid() {
    // a unit cube: quads, relative indices, two objects sharing the corners
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                o bottom_and_sides\nf -8 -5 -6 -7\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n\
                o top\nvn 0 0 1\nf 5//1 6//1 7//1 8//1\n";
    let soup = read_obj(text.as_bytes(), &MeshLimits::default()).unwrap();
    let (mesh, warnings) = TriMesh::from_soup(soup).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!((mesh.vertices().len(), mesh.triangles().len()), (8, 12));
    let p = mesh.mass_properties(1.0).unwrap();
    assert_eq!((p.volume, p.center_of_mass), (1.0, DVec3::splat(0.5)));
}

#[test]
fn ascii_stl_variants() {
    let cube = std::fs::read_to_string(fixture("inside_out.stl")).unwrap();
    // `solid` without a name, indented
    let unnamed = cube.replacen("solid fixture", "  solid", 1);
    assert!(read_stl(unnamed.into_bytes(), &MeshLimits::default()).is_ok());
    // a second solid would be silently dropped by the reader: refused
    let two = format!("{cube}{cube}");
    let p = read_stl(two.into_bytes(), &MeshLimits::default()).unwrap_err();
    assert!(p.to_string().contains("24 facets in the file but 12"), "{p}");
    let p = read_stl(cube.replacen("vertex", "vertx", 1).into_bytes(), &MeshLimits::default()).unwrap_err();
    assert!(matches!(p, MeshProblem::Parse { format: Format::StlAscii, .. }), "{p:?}");
    let p = read_stl(cube.replacen("vertex 1.0", "vertex nan", 1).into_bytes(), &MeshLimits::default()).unwrap_err();
    assert!(matches!(p, MeshProblem::Parse { .. }), "{p:?}");
}

#[test]
fn solids_touching_along_an_edge_are_accepted_with_a_warning() {
    let (mut v, mut t) = box_parts(DVec3::splat(0.5));
    let (v2, t2) = box_parts(DVec3::splat(0.5));
    // the second cube shares the edge x = 0.5, y = 0.5 of the first
    let n = v.len() as u32;
    v.extend(v2.into_iter().map(|p| p + DVec3::new(1.0, 1.0, 0.0)));
    t.extend(t2.into_iter().map(|f| f.map(|i| i + n)));
    let (mesh, warnings) = TriMesh::new(v, t).unwrap();
    assert_eq!(warnings, vec![MeshWarning::NonManifold { edges: 1 }]);
    assert_eq!(mesh.mass_properties(1.0).unwrap().volume, 2.0);
}

#[test]
fn a_flat_closed_surface_encloses_no_volume() {
    // a square sheet, both sides
    let v = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
    let t = vec![[0, 1, 2], [0, 2, 3], [0, 2, 1], [0, 3, 2]];
    assert!(matches!(TriMesh::new(v, t), Err(MeshProblem::NoVolume { .. })));
    let p = TriMesh::new(vec![DVec3::ZERO, DVec3::X], vec![[0, 1, 1]]).unwrap_err();
    assert!(matches!(p, MeshProblem::NoVolume { .. }), "{p:?}");
    assert!(matches!(TriMesh::new(vec![DVec3::ZERO], vec![[0, 0, 5]]), Err(MeshProblem::IndexOutOfRange { .. })));
}

#[test]
fn files_that_cannot_be_read_say_why() {
    let limits = MeshLimits::default();
    assert!(matches!(mesh::load(&fixture("missing.stl"), [1.0; 3], &limits).unwrap_err().problem, MeshProblem::Io(_)));
    assert!(matches!(mesh::load(&fixture("."), [1.0; 3], &limits).unwrap_err().problem, MeshProblem::UnknownFormat(_)));
    let e = mesh::load(&fixture("cube.ply"), [1.0; 3], &limits).unwrap_err();
    assert_eq!(e.problem, MeshProblem::UnknownFormat(".ply".into()));
    let e = mesh::load(&fixture("cube.obj"), [1.0, 0.0, 1.0], &limits).unwrap_err();
    assert_eq!(e.problem, MeshProblem::BadScale([1.0, 0.0, 1.0]));
    let p = mesh::mass_properties_of_file(&fixture("cube.obj"), [1.0; 3], f64::NAN, &limits).unwrap_err();
    assert!(matches!(p.problem, MeshProblem::BadDensity(_)));
    // a scale multiplies the coordinates: volume × sx sy sz
    let loaded = mesh::load(&fixture("cube.obj"), [2.0, 3.0, 0.5], &limits).unwrap();
    assert_eq!(loaded.mesh.mass_properties(1.0).unwrap().volume, 3.0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Any bytes: an error or a mesh, never a panic.
    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let _ = read_stl(bytes.clone(), &MeshLimits::default()).map(TriMesh::from_soup);
        let _ = read_obj(&bytes, &MeshLimits::default()).map(TriMesh::from_soup);
    }

    /// Valid files with a few bytes changed: an error or a mesh, never a panic.
    #[test]
    fn mutated_files_never_panic(
        which in 0usize..3,
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..6),
    ) {
        let name = ["cube.obj", "cube.stl", "inside_out.stl"][which];
        let mut bytes = std::fs::read(fixture(name)).unwrap();
        for (at, byte) in edits {
            let i = at.index(bytes.len());
            bytes[i] = byte;
        }
        let soup = if name.ends_with(".obj") { read_obj(&bytes, &MeshLimits::default()) } else { read_stl(bytes, &MeshLimits::default()) };
        if let Ok((mesh, _)) = soup.map(TriMesh::from_soup).and_then(|r| r) {
            let _ = mesh.mass_properties(1.0);
        }
    }
}

#[test]
fn coordinates_too_large_for_the_integrals_are_an_error_not_infinity() {
    // the volume overflows
    let (v, t) = box_parts(DVec3::splat(1e120));
    assert!(matches!(TriMesh::new(v, t), Err(MeshProblem::Overflow { .. })));
    // the volume does not, the inertia (or the mass) does
    let (v, t) = box_parts(DVec3::splat(1e100));
    let (mesh, _) = TriMesh::new(v, t).unwrap();
    assert!(matches!(mesh.mass_properties(1.0), Err(MeshProblem::Overflow { .. })));
    let (v, t) = box_parts(DVec3::splat(1e100));
    let (mesh, _) = TriMesh::new(v, t).unwrap();
    assert!(matches!(mesh.mass_properties(1e10), Err(MeshProblem::Overflow { .. })));
}

/// Two boxes as one mesh: the second of half extents `h2` at `offset`; each facing inward or not.
/// Returns the volume, the inertia's xx entry and the warnings.
fn two_boxes(h1: f64, h2: f64, offset: DVec3, inward: [bool; 2]) -> (f64, f64, Vec<MeshWarning>) {
    let face = |f: [u32; 3], inward: bool| if inward { [f[0], f[2], f[1]] } else { f };
    let (mut v, t1) = box_parts(DVec3::splat(h1));
    let mut t: Vec<[u32; 3]> = t1.into_iter().map(|f| face(f, inward[0])).collect();
    let (v2, t2) = box_parts(DVec3::splat(h2));
    v.extend(v2.into_iter().map(|p| p + offset));
    t.extend(t2.into_iter().map(|f| face(f.map(|i| i + 8), inward[1])));
    let (mesh, warnings) = TriMesh::new(v, t).unwrap();
    let p = mesh.mass_properties(1.0).unwrap();
    (p.volume, p.inertia.x_axis.x, warnings)
}

#[test]
fn an_inward_shell_inside_another_is_a_cavity() {
    // a hollow cube: side 2 outside, side 1 inside; I = m s²/6 outside minus inside
    let (volume, ixx, warnings) = two_boxes(1.0, 0.5, DVec3::ZERO, [false, true]);
    assert_eq!(warnings, vec![MeshWarning::Cavities { shells: 1, volume: -1.0 }]);
    assert_eq!(volume, 7.0);
    close("inertia", ixx, 8.0 * 4.0 / 6.0 - 1.0 / 6.0, 1e-15, 1.0);
}

#[test]
fn a_separate_inside_out_part_is_flipped_alone() {
    let away = DVec3::new(5.0, 0.0, 0.0);
    let (volume, ixx, warnings) = two_boxes(1.0, 0.5, away, [false, false]);
    assert!(warnings.is_empty());
    assert_eq!(volume, 9.0);
    let (v1, i1, warnings) = two_boxes(1.0, 0.5, away, [false, true]);
    assert_eq!(warnings, vec![MeshWarning::InsideOut { volume: -1.0, shells: 1 }]);
    assert_eq!((v1, i1), (volume, ixx));
    let (v2, i2, warnings) = two_boxes(1.0, 0.5, away, [true, true]);
    assert_eq!(warnings, vec![MeshWarning::InsideOut { volume: -9.0, shells: 2 }]);
    assert_eq!((v2, i2), (volume, ixx));
    assert!(warnings[0].to_string().contains("2 separate shells"));
}
