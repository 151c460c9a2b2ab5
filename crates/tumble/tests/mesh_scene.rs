//! Mesh-shaped bodies in scenes: `shape = { type = "mesh", file = "...", scale = ... }`.

mod mesh_common;

use mesh_common::{close, max_abs};
use std::path::{Path, PathBuf};
use tumble::body::Shape;
use tumble::math::DVec3;
use tumble::mesh::{self, MeshLimits};
use tumble::scene;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/meshes").join(name)
}

/// A scene file `scene.toml` beside copies of the named fixtures, in a fresh directory.
fn scene_with(meshes: &[&str], text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    for name in meshes {
        std::fs::copy(fixture(name), dir.path().join(name)).unwrap();
    }
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

fn load_err(path: &Path) -> String {
    scene::load(path).unwrap_err().to_string()
}

#[test]
fn density_and_a_mesh_give_the_meshs_mass_properties() {
    let text =
        "version = 1\n[[body]]\nname = \"part\"\ndensity = 500.0\nshape = { type = \"mesh\", file = \"torus.obj\" }\n";
    let (_dir, path) = scene_with(&["torus.obj"], text);
    let loaded = scene::load(&path).unwrap();
    // a torus is concave: on a moving body it collides as convex pieces, which needs no warning
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let body = &loaded.world.bodies[0];
    let p = mesh::mass_properties_of_file(&fixture("torus.obj"), [1.0; 3], 500.0, &MeshLimits::default()).unwrap().0;
    close("mass", body.mass.mass, p.mass, 1e-15, p.mass);
    // the tensor in the user's (mesh) axes is the mesh's, diagonalised once
    assert!(max_abs(body.mass.inertia_user() - p.inertia) <= 1e-13 * max_abs(p.inertia));
    let Some(Shape::Mesh(shape)) = &body.shape else { panic!("{:?}", body.shape) };
    assert_eq!(shape.center_of_mass_file, p.center_of_mass);
    // the body's mesh is centred on the centre of mass
    let centred = shape.mesh.mass_properties(1.0).unwrap();
    assert!(centred.center_of_mass.length() < 1e-14, "{:?}", centred.center_of_mass);
    assert!(loaded.describe().contains("torus.obj: 2304 triangles"), "{}", loaded.describe());
    assert!(shape.hull_excess > 0.5, "{}", shape.hull_excess);
    let pieces = shape.decomposition.as_ref().expect("a concave moving mesh is decomposed");
    assert!((2..=tumble::collision::VHACD_MAX_PIECES as usize).contains(&pieces.len()), "{}", pieces.len());
    let mut world = loaded.world;
    world.step().unwrap();
}

#[test]
fn mass_and_a_mesh_scale_the_meshs_inertia_and_scale_multiplies_coordinates() {
    let text = "version = 1\n[[body]]\nname = \"a\"\nmass = 2.0\nshape = { type = \"mesh\", file = \"cube.obj\", scale = 0.5 }\n\
                [[body]]\nname = \"b\"\ndensity = 1.0\nshape = { type = \"mesh\", file = \"cube.obj\", scale = [1, 2, 3] }\n";
    let (_dir, path) = scene_with(&["cube.obj"], text);
    let world = scene::load(&path).unwrap().world;
    // a cube of side 0.5 and mass 2: I = m s²/6
    for k in 0..3 {
        close("inertia", world.bodies[0].mass.inertia_body[k], 2.0 * 0.25 / 6.0, 1e-15, 1.0);
    }
    assert_eq!(world.bodies[1].mass.mass, 6.0);
    let Some(Shape::Mesh(shape)) = &world.bodies[1].shape else { panic!() };
    assert_eq!(shape.center_of_mass_file, DVec3::new(0.5, 1.0, 1.5));
}

#[test]
fn a_bad_mesh_is_an_error_at_the_file_key() {
    let text =
        "version = 1\n[[body]]\nname = \"part\"\ndensity = 1.0\nshape = { type = \"mesh\", file = \"open_box.obj\" }\n";
    let (_dir, path) = scene_with(&["open_box.obj"], text);
    let e = load_err(&path);
    assert!(e.starts_with(&format!("{}:5:", path.display())), "{e}");
    assert!(e.contains("body[0].shape.file") && e.contains("open_box.obj") && e.contains("4 open edges"), "{e}");
    let text =
        "version = 1\n[[body]]\nname = \"part\"\ndensity = 1.0\nshape = { type = \"mesh\", file = \"nowhere.stl\" }\n";
    let (_dir, path) = scene_with(&[], text);
    assert!(load_err(&path).contains("cannot read"), "{}", load_err(&path));
}

/// Where a scene's mesh is looked for: relative to the scene file's directory (`..` included), or
/// an absolute path as written; no directory confines it (scenes are trusted input, as URDFs whose
/// absolute mesh paths ROS tools write).
#[test]
fn u17_a_scene_mesh_is_relative_to_the_scene_file_or_absolute() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("scenes")).unwrap();
    std::fs::copy(fixture("cube.obj"), dir.path().join("cube.obj")).unwrap();
    let path = dir.path().join("scenes/scene.toml");
    let mass_with = |file: &str| {
        let text = format!(
            "version = 1\n[[body]]\nname = \"a\"\ndensity = 2.0\nshape = {{ type = \"mesh\", file = {file:?} }}\n"
        );
        std::fs::write(&path, text).unwrap();
        let loaded = scene::load(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
        loaded.world.bodies[0].mass.mass
    };
    // a unit cube of density 2: 2 kg, found one level up and by its absolute path
    assert_eq!(mass_with("../cube.obj"), 2.0);
    let absolute = dir.path().join("cube.obj");
    assert!(absolute.is_absolute());
    assert_eq!(mass_with(absolute.to_str().unwrap()), 2.0);
    // relative to the scene file, not to the working directory: `cube.obj` is not beside the scene
    std::fs::write(
        &path,
        "version = 1\n[[body]]\nname = \"a\"\ndensity = 2.0\nshape = { type = \"mesh\", file = \"cube.obj\" }\n",
    )
    .unwrap();
    let e = load_err(&path);
    assert!(e.contains("scene.toml:5:") && e.contains("body[0].shape.file"), "{e}");
}

#[test]
fn an_inside_out_mesh_is_a_scene_warning() {
    let text = "version = 1\n[[body]]\nname = \"part\"\ndensity = 1.0\nshape = { type = \"mesh\", file = \"inside_out.stl\" }\n";
    let (_dir, path) = scene_with(&["inside_out.stl"], text);
    let loaded = scene::load(&path).unwrap();
    assert_eq!(loaded.warnings.len(), 1);
    assert!(
        loaded.warnings[0].contains("body[0].shape.file") && loaded.warnings[0].contains("flipped"),
        "{:?}",
        loaded.warnings
    );
    assert_eq!(loaded.world.bodies[0].mass.mass, 1.0);
}

#[test]
fn mesh_keys_are_checked() {
    let cases = [
        ("{ type = \"mesh\" }", "a mesh needs `file`"),
        ("{ type = \"mesh\", file = \"cube.obj\", scale = -1.0 }", "mesh scale must be finite and > 0"),
        ("{ type = \"mesh\", file = \"cube.obj\", scale = [1, 2] }", "body[0].shape.scale"),
        ("{ type = \"mesh\", file = \"cube.obj\", radius = 1.0 }", "a mesh has no `radius`"),
        ("{ type = \"box\", half_extents = [1, 1, 1], file = \"cube.obj\" }", "a box has no `file`"),
        ("{ type = \"mesh\", file = 3 }", "body[0].shape.file"),
    ];
    for (shape, expected) in cases {
        let text = format!("version = 1\n[[body]]\nname = \"p\"\ndensity = 1.0\nshape = {shape}\n");
        let (_dir, path) = scene_with(&["cube.obj"], &text);
        let e = load_err(&path);
        assert!(e.contains(expected), "{shape}: {e}");
    }
}

#[test]
fn json_scenes_take_meshes_too() {
    let text = r#"{"version": 1, "body": [{"name": "p", "density": 2.0, "shape": {"type": "mesh", "file": "cube.stl", "scale": 2}}]}"#;
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(fixture("cube.stl"), dir.path().join("cube.stl")).unwrap();
    let path = dir.path().join("scene.json");
    std::fs::write(&path, text).unwrap();
    assert_eq!(scene::load(&path).unwrap().world.bodies[0].mass.mass, 16.0);
}

/// A convex mesh body (a cube) keeps its hull (no decomposition): dropped on a plane it comes to rest
/// on a face, its centre of mass half a side above the plane; loading it gives no warning.
#[test]
fn a_convex_mesh_body_lands_and_rests_on_a_plane() {
    let text = "version = 1\n[world]\ndt = 0.005\n\n[[body]]\nname = \"ground\"\nfixed = true\n\
                shape = { type = \"plane\" }\n\n[[body]]\nname = \"cube\"\ndensity = 1000.0\n\
                shape = { type = \"mesh\", file = \"cube.obj\" }\nposition = [0.0, 0.0, 1.0]\n";
    let (_dir, path) = scene_with(&["cube.obj"], text);
    let loaded = scene::load(&path).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let Some(Shape::Mesh(shape)) = &loaded.world.bodies[1].shape else { panic!() };
    assert!(shape.decomposition.is_none() && shape.hull_excess.abs() < 1e-12, "{}", shape.hull_excess);
    assert!(loaded.describe().contains("collides as its convex hull"), "{}", loaded.describe());
    let mut world = loaded.world;
    for _ in 0..600 {
        world.step().unwrap();
    }
    let cube = &world.bodies[1];
    // the unit cube's centre rests 0.5 m above the plane (within the contact slop), at rest
    assert!((cube.state.position.z - 0.5).abs() < 2e-3, "z = {}", cube.state.position.z);
    assert!(cube.state.velocity.length() < 1e-2, "v = {:?}", cube.state.velocity);
}
