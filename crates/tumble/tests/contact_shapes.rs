//! Convex hulls, compounds and concave meshes in contact: each rests where its geometry says, its
//! mass properties are those of its solid, and bad input is named with file, line and field.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use tumble::body::Shape;
use tumble::math::{DMat3, DVec3};
use tumble::mesh::TriMesh;
use tumble::scene;
use tumble::World;

/// A polygon in the (x, z) plane, counter-clockwise seen from −y (x right, z up), and its
/// triangles (counter-clockwise, indices into the polygon).
struct Profile {
    corners: Vec<[f64; 2]>,
    triangles: Vec<[u32; 3]>,
}

/// The U of the concave tests: 1 m wide (x), 0.6 m tall (z) with its base on z = 0; a cavity
/// 0.6 m wide whose floor is at z = 0.2, open at the top; arms 0.2 m thick.
fn u_profile() -> Profile {
    Profile {
        corners: vec![
            [-0.5, 0.0],
            [0.5, 0.0],
            [0.5, 0.6],
            [0.3, 0.6],
            [0.3, 0.2],
            [-0.3, 0.2],
            [-0.3, 0.6],
            [-0.5, 0.6],
        ],
        triangles: vec![[0, 1, 4], [0, 4, 5], [0, 5, 6], [0, 6, 7], [1, 2, 3], [1, 3, 4]],
    }
}

/// A V-shaped trough 1.2 m wide: its groove's bottom at (x, z) = (0, 0.2), its walls rising to
/// z = 0.6 at x = ±0.6 (slope 2/3), its base on z = 0.
fn v_profile() -> Profile {
    Profile {
        corners: vec![[-0.6, 0.0], [0.6, 0.0], [0.6, 0.6], [0.0, 0.2], [-0.6, 0.6]],
        triangles: vec![[0, 1, 3], [1, 2, 3], [0, 3, 4]],
    }
}

/// Vertices (m) and outward triangles of a mesh.
type Mesh = (Vec<DVec3>, Vec<[u32; 3]>);

/// The profile extruded along y over `[-half_depth, half_depth]`: a closed, outward mesh.
fn extrude(profile: &Profile, half_depth: f64) -> Mesh {
    let n = profile.corners.len() as u32;
    let mut vertices: Vec<DVec3> = profile.corners.iter().map(|&[x, z]| DVec3::new(x, -half_depth, z)).collect();
    vertices.extend(profile.corners.iter().map(|&[x, z]| DVec3::new(x, half_depth, z)));
    let mut triangles = Vec::new();
    for &[a, b, c] in &profile.triangles {
        triangles.push([a, b, c]); // front, facing −y
        triangles.push([a + n, c + n, b + n]); // back, facing +y
    }
    for k in 0..n {
        let (a0, a1) = (k, (k + 1) % n);
        let (b0, b1) = (a0 + n, a1 + n);
        triangles.push([a0, b0, b1]);
        triangles.push([a0, b1, a1]);
    }
    (vertices, triangles)
}

/// Writes `mesh` as an OBJ file.
fn write_obj(path: &Path, (vertices, triangles): &Mesh) {
    let mut text = String::new();
    for v in vertices {
        text.push_str(&format!("v {} {} {}\n", v.x, v.y, v.z));
    }
    for t in triangles {
        text.push_str(&format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1));
    }
    std::fs::write(path, text).unwrap();
}

/// A scene file `scene.toml` with `text`, beside the meshes `(name, mesh)`, in a fresh directory.
fn scene_dir(meshes: &[(&str, Mesh)], text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    for (name, mesh) in meshes {
        write_obj(&dir.path().join(name), mesh);
    }
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

fn load_str(text: &str) -> Result<scene::Scene, String> {
    scene::from_str(text, "test.toml", scene::Format::Toml).map_err(|e| e.to_string())
}

/// Steps `world` for `seconds`.
fn run(world: &mut World, seconds: f64) {
    let steps = (seconds / world.config.dt).round() as u64;
    for _ in 0..steps {
        world.step().unwrap();
    }
}

fn body<'w>(world: &'w World, name: &str) -> &'w tumble::RigidBody {
    &world.bodies[world.body_index(name).unwrap()]
}

const GROUND: &str = "[[body]]\nname = \"ground\"\nfixed = true\nshape = { type = \"plane\" }\n";

#[test]
fn the_extruded_profiles_are_closed_outward_solids() {
    for (profile, area) in [(u_profile(), 0.6 * 1.0 - 0.6 * 0.4), (v_profile(), 1.2 * 0.6 - 0.5 * 1.2 * 0.4)] {
        let (vertices, triangles) = extrude(&profile, 0.2);
        let (mesh, warnings) = TriMesh::new(vertices, triangles).unwrap();
        assert!(warnings.is_empty(), "{warnings:?}");
        let volume = mesh.mass_properties(1.0).unwrap().volume;
        assert!((volume - 0.4 * area).abs() < 1e-12, "{volume}");
    }
}

/// The 8 corners of a cube (and a point inside, which the hull leaves out) behave as the box: the
/// same mass and inertia, and both land on the ground and rest with their centre 0.5 m up.
#[test]
fn a_convex_hull_of_cube_corners_lands_and_rests_like_the_box() {
    let corners: Vec<String> = (0..8)
        .map(|i| {
            let c = |bit: i32| if i & bit == 0 { "-0.5" } else { "0.5" };
            format!("[{}, {}, {}]", c(1), c(2), c(4))
        })
        .collect();
    let text = format!(
        "version = 1\n[world]\ndt = 0.001\n{GROUND}\
         [[body]]\nname = \"hull\"\ndensity = 800.0\nposition = [0.0, 0.0, 1.2]\nangular_velocity = [0.3, 0.2, 0.0]\n\
         shape = {{ type = \"convex\", points = [{}, [0.1, 0.1, 0.1]] }}\n\
         [[body]]\nname = \"box\"\ndensity = 800.0\nposition = [3.0, 0.0, 1.2]\nangular_velocity = [0.3, 0.2, 0.0]\n\
         shape = {{ type = \"box\", half_extents = [0.5, 0.5, 0.5] }}\n",
        corners.join(", ")
    );
    let scene = load_str(&text).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let mut world = scene.world;
    let (hull, cube) = (body(&world, "hull"), body(&world, "box"));
    let Some(Shape::Convex(convex)) = &hull.shape else { panic!("{:?}", hull.shape) };
    assert_eq!((convex.points_given, convex.hull.vertices().len()), (9, 8));
    assert!((hull.mass.mass - cube.mass.mass).abs() <= 1e-12 * cube.mass.mass);
    let moments = 800.0 * (1.0 + 1.0) / 12.0;
    for k in 0..3 {
        assert!((hull.mass.inertia_body[k] - moments).abs() <= 1e-12 * moments, "{:?}", hull.mass.inertia_body);
    }
    run(&mut world, 4.0);
    for name in ["hull", "box"] {
        let b = body(&world, name);
        assert!((b.state.position.z - 0.5).abs() < 1e-3, "{name} rests at z = {}", b.state.position.z);
        assert!(b.state.velocity.length() < 1e-3 && b.state.omega_body.length() < 1e-2, "{name} still moves");
    }
    let dz = body(&world, "hull").state.position.z - body(&world, "box").state.position.z;
    assert!(dz.abs() < 1e-3, "hull and box rest {dz} m apart in height");
}

/// A dumbbell: two balls (radius 0.2 m) on a thin capsule bar along x, written off the origin and
/// with the bar turned from z onto x. Its inertia is the parallel-axis sum of the parts to 1e-12;
/// dropped tilted, it lands on one ball, then rests on both, level, with its centre 0.2 m up.
#[test]
fn a_dumbbell_compound_rests_on_both_balls_and_its_inertia_is_the_parallel_axis_sum() {
    let rho = 1200.0;
    let (r, d, bar_r, bar_hh) = (0.2, 0.5, 0.03, 0.5);
    // the bar's axis turned from z onto x: a quarter turn about y
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let text = format!(
        "version = 1\n[world]\ndt = 0.001\n{GROUND}\
         [[body]]\nname = \"dumbbell\"\ndensity = {rho}\nposition = [0.0, 0.0, 0.6]\n\
         orientation = [0.9990482215818578, 0.0, 0.043619387365336, 0.0]\n\
         shapes = [\n\
           {{ type = \"sphere\", radius = {r}, position = [{}, 0.3, -1.0] }},\n\
           {{ type = \"sphere\", radius = {r}, position = [{}, 0.3, -1.0] }},\n\
           {{ type = \"capsule\", radius = {bar_r}, half_height = {bar_hh}, position = [1.5, 0.3, -1.0], orientation = [{s}, 0.0, {s}, 0.0] }},\n\
         ]\n",
        1.5 - d,
        1.5 + d
    );
    let scene = load_str(&text).unwrap();
    let mut world = scene.world;
    let b = body(&world, "dumbbell");
    let Some(Shape::Compound(compound)) = &b.shape else { panic!("{:?}", b.shape) };
    assert!((compound.center_of_mass_given - DVec3::new(1.5, 0.3, -1.0)).length() < 1e-14);
    // the parts, each about its centre, moved to the centre of mass
    let m_ball = rho * 4.0 / 3.0 * PI * r * r * r;
    let ball =
        |x: f64| 0.4 * m_ball * r * r * DMat3::IDENTITY + m_ball * (x * x * DMat3::IDENTITY - outer(DVec3::X * x));
    let m_cyl = rho * 2.0 * PI * bar_r * bar_r * bar_hh;
    let m_caps = rho * 4.0 / 3.0 * PI * bar_r.powi(3);
    let axial = 0.5 * m_cyl * bar_r * bar_r + 0.4 * m_caps * bar_r * bar_r;
    let perp = m_cyl * (3.0 * bar_r * bar_r + 4.0 * bar_hh * bar_hh) / 12.0
        + m_caps * (0.4 * bar_r * bar_r + bar_hh * bar_hh + 0.75 * bar_hh * bar_r);
    let bar = DMat3::from_diagonal(DVec3::new(axial, perp, perp));
    let expected = ball(-d) + ball(d) + bar;
    let got = b.mass.inertia_user();
    let scale = expected.to_cols_array().iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    for (g, e) in got.to_cols_array().iter().zip(expected.to_cols_array()) {
        assert!((g - e).abs() <= 1e-12 * scale, "inertia {got:?}, expected {expected:?}");
    }
    assert!((b.mass.mass - (2.0 * m_ball + m_cyl + m_caps)).abs() <= 1e-12 * b.mass.mass);

    run(&mut world, 4.0);
    let b = body(&world, "dumbbell");
    assert!((b.state.position.z - r).abs() < 1e-3, "rests at z = {}", b.state.position.z);
    let axis = b.orientation_user() * DVec3::X;
    assert!(axis.z.abs() < 1e-3, "the bar is not level: axis {axis}");
    assert!(b.state.velocity.length() < 1e-3 && b.state.omega_body.length() < 1e-2);
    // resting on both balls: one contact under each, with distinct feature keys
    let contacts = world.contact_stage().contacts().to_vec();
    let centre = body(&world, "dumbbell").state.position;
    let mut sides: Vec<f64> = contacts.iter().map(|c| (c.point_world - centre).dot(axis)).collect();
    sides.sort_by(f64::total_cmp);
    assert_eq!(sides.len(), 2, "{contacts:?}");
    assert!((sides[0] + d).abs() < 1e-3 && (sides[1] - d).abs() < 1e-3, "{sides:?}");
    assert_ne!(contacts[0].features, contacts[1].features);
}

fn outer(v: DVec3) -> DMat3 {
    DMat3::from_cols(v * v.x, v * v.y, v * v.z)
}

/// The centre of mass of an extruded profile, in the file's coordinates (m).
fn center_of_mass(mesh: &Mesh) -> DVec3 {
    let (m, _) = TriMesh::new(mesh.0.clone(), mesh.1.clone()).unwrap();
    m.mass_properties(1.0).unwrap().center_of_mass
}

/// A moving U (a concave mesh) collides as convex pieces, not as its hull: it rests on its base,
/// and a ball dropped into it stops on the cavity's floor (z = 0.2 + r), far below the top of the
/// hull (z = 0.6 + r) where it would stop if the U collided as its hull.
#[test]
fn a_moving_concave_mesh_holds_a_ball_in_its_cavity() {
    let u = extrude(&u_profile(), 0.2);
    let c = center_of_mass(&u);
    let text = format!(
        "version = 1\n[world]\ndt = 0.001\n{GROUND}\
         [[body]]\nname = \"u\"\ndensity = 500.0\nposition = [0.0, 0.0, {}]\n\
         shape = {{ type = \"mesh\", file = \"u.obj\" }}\n\
         [[body]]\nname = \"ball\"\ndensity = 500.0\nposition = [0.02, 0.0, 1.2]\n\
         shape = {{ type = \"sphere\", radius = 0.1 }}\n",
        c.z + 0.05
    );
    let (_dir, path) = scene_dir(&[("u.obj", u)], &text);
    let loaded = scene::load(&path).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let described = loaded.describe();
    let mut world = loaded.world;
    let Some(Shape::Mesh(mesh)) = &body(&world, "u").shape else { panic!() };
    let pieces = mesh.decomposition.as_ref().expect("a concave moving mesh is decomposed").len();
    assert!(pieces >= 2, "{pieces} pieces");
    assert!(mesh.hull_excess > 0.5, "{}", mesh.hull_excess);
    assert!(described.contains(&format!("collides as {pieces} convex pieces")), "{described}");
    run(&mut world, 4.0);
    let (u, ball) = (body(&world, "u"), body(&world, "ball"));
    println!("U rests at z = {} (expected {}), ball at {}", u.state.position.z, c.z, ball.state.position);
    assert!((u.state.position.z - c.z).abs() < 1e-3, "the U rests at z = {}, not {}", u.state.position.z, c.z);
    let up = u.orientation_user() * DVec3::Z;
    assert!(up.z > 1.0 - 1e-6, "the U tipped over: {up}");
    let floor = u.state.position.z - c.z + 0.2;
    let height = ball.state.position.z - floor;
    // the pieces follow the mesh's own faces (measured: the ball rests at 0.1 m to 1e-15)
    assert!((height - 0.1).abs() < 5e-3, "the ball rests {height} m above the cavity's floor, not 0.1 m");
    assert!(ball.state.velocity.length() < 1e-2, "{}", ball.state.velocity);
}

/// Fixed concave meshes collide as their triangles: a ball dropped into a V-shaped groove rolls to
/// its bottom and rests on both walls (centre at `0.2 + r/cos θ`, `tan θ = 2/3`); balls dropped into
/// a U's trough and onto its arm rest on the trough's floor (`0.2 + r`) and on the arm (`0.6 + r`).
/// As their hulls, every ball would rest on a flat top at `0.6 + r`.
#[test]
fn balls_dropped_on_fixed_concave_meshes_land_on_their_triangles() {
    let (u, v) = (extrude(&u_profile(), 0.2), extrude(&v_profile(), 0.2));
    let (cu, cv) = (center_of_mass(&u), center_of_mass(&v));
    let r = 0.1;
    let ball = |name: &str, x: f64, y: f64| {
        format!(
            "[[body]]\nname = \"{name}\"\ndensity = 500.0\nposition = [{x}, {y}, 1.0]\n\
             shape = {{ type = \"sphere\", radius = {r} }}\n"
        )
    };
    let text = format!(
        "version = 1\n[world]\ndt = 0.001\n\
         [[body]]\nname = \"groove\"\nfixed = true\nposition = [{}, 0.0, {}]\nshape = {{ type = \"mesh\", file = \"v.obj\" }}\n\
         [[body]]\nname = \"trough\"\nfixed = true\nposition = [{}, 2.0, {}]\nshape = {{ type = \"mesh\", file = \"u.obj\" }}\n\
         {}{}{}",
        cv.x,
        cv.z,
        cu.x,
        cu.z,
        ball("in_groove", 0.15, 0.0),
        ball("in_trough", 0.05, 2.0),
        ball("on_arm", 0.4, 2.0),
    );
    let (_dir, path) = scene_dir(&[("u.obj", u), ("v.obj", v)], &text);
    let loaded = scene::load(&path).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    assert!(loaded.describe().contains("collides as its triangles"));
    let mut world = loaded.world;
    run(&mut world, 6.0);
    let at = |name: &str| body(&world, name).state.position;
    let groove = 0.2 + r * (13.0_f64).sqrt() / 3.0;
    println!("groove {} (expected z {groove}), trough {}, arm {}", at("in_groove"), at("in_trough"), at("on_arm"));
    assert!(at("in_groove").x.abs() < 1e-3 && (at("in_groove").z - groove).abs() < 1e-3, "{}", at("in_groove"));
    assert!((at("in_trough").z - (0.2 + r)).abs() < 1e-3, "{}", at("in_trough"));
    assert!((at("on_arm").z - (0.6 + r)).abs() < 1e-3, "{}", at("on_arm"));
    for name in ["in_groove", "in_trough", "on_arm"] {
        assert!(body(&world, name).state.velocity.length() < 1e-2, "{name} still moves");
    }
}

/// Bad convex points and compounds: an error naming the file, the line and column of the value,
/// and the field.
#[test]
fn bad_convex_points_and_compounds_are_named_with_line_and_field() {
    let body = |shape: &str| format!("version = 1\n[[body]]\nname = \"b\"\ndensity = 1.0\n{shape}\n");
    let cases = [
        // (the body's shape lines, the field, the line, words of the message)
        (
            "shape = { type = \"convex\", points = [[0, 0, 0], [1, 0, 0], [0, 1, 0]] }",
            "body[0].shape.points",
            5,
            "at least 4 points",
        ),
        (
            "shape = { type = \"convex\", points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0.5, 0.2, 0]] }",
            "body[0].shape.points",
            5,
            "coplanar",
        ),
        (
            "shape = { type = \"convex\", points = [[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]] }",
            "body[0].shape.points",
            5,
            "coplanar",
        ),
        (
            "shape = { type = \"convex\", points = [\n  [0, 0, 0],\n  [1, 0, 0],\n  [0, nan, 0],\n  [0, 0, 1],\n] }",
            "body[0].shape.points[2]",
            8,
            "must be finite",
        ),
        (
            "shape = { type = \"convex\", points = [[0, 0, 0], [1, 0, 0], [0, inf, 0], [0, 0, 1]] }",
            "body[0].shape.points[2]",
            5,
            "must be finite",
        ),
        ("shape = { type = \"convex\" }", "body[0].shape", 5, "needs `points`"),
        (
            "shape = { type = \"sphere\", radius = 1.0, points = [[0, 0, 0]] }",
            "body[0].shape.points",
            5,
            "a sphere has no `points`",
        ),
        (
            "shape = { type = \"sphere\", radius = 1.0, position = [0, 0, 1] }",
            "body[0].shape.position",
            5,
            "places a part of a compound",
        ),
        (
            "shape = { type = \"sphere\", radius = 1.0 }\nshapes = [{ type = \"sphere\", radius = 1.0 }]",
            "body[0].shapes",
            6,
            "not both",
        ),
        ("shapes = []", "body[0].shapes", 5, "at least one part"),
        (
            "shapes = [{ type = \"sphere\", radius = 1.0 }, { type = \"plane\" }]",
            "body[0].shapes[1].type",
            5,
            "a plane cannot be part of a compound",
        ),
        (
            "shapes = [{ type = \"mesh\", file = \"u.obj\" }]",
            "body[0].shapes[0].type",
            5,
            "a mesh cannot be part of a compound",
        ),
        (
            "shapes = [\n  { type = \"sphere\", radius = 1.0 },\n  { type = \"box\", half_extents = [1, -1, 1] },\n]",
            "body[0].shapes[1].half_extents",
            7,
            "finite and > 0",
        ),
        (
            "shapes = [{ type = \"sphere\", radius = 1.0, orientation = [2, 0, 0, 0] }]",
            "body[0].shapes[0].orientation",
            5,
            "unit quaternion",
        ),
        (
            "shapes = [{ type = \"sphere\", radius = 1.0, position = [0, nan, 0] }]",
            "body[0].shapes[0].position",
            5,
            "must be finite",
        ),
        (
            "shapes = [{ type = \"convex\", points = [[0, 0, 0], [1, 0, 0], [0, 1, 0]] }]",
            "body[0].shapes[0].points",
            5,
            "at least 4 points",
        ),
        (
            "shapes = [{ type = \"sphere\", radius = 1.0, mass = 2.0 }]",
            "body[0].shapes[0].mass",
            5,
            "unknown key `mass`",
        ),
    ];
    for (shape, field, line, words) in cases {
        let err = load_str(&body(shape)).unwrap_err();
        assert!(err.starts_with(&format!("test.toml:{line}:")), "`{shape}`: {err}");
        assert!(err.contains(&format!("{field}:")), "`{shape}`: no `{field}` in {err}");
        assert!(err.contains(words), "`{shape}`: no `{words}` in {err}");
    }
    // JSON: the field path stands in for the position
    let json = r#"{"version": 1, "body": [{"name": "b", "density": 1, "shape": {"type": "convex", "points": [[0,0,0],[1,0,0],[0,1,0],[2,2,0]]}}]}"#;
    let err = scene::from_str(json, "test.json", scene::Format::Json).unwrap_err().to_string();
    assert!(err.contains("body[0].shape.points") && err.contains("coplanar"), "{err}");
}

/// JSON and `[[body.shapes]]` tables give the same compound as an inline array.
#[test]
fn compounds_read_the_same_from_json_and_from_arrays_of_tables() {
    let inline = "version = 1\n[[body]]\nname = \"b\"\ndensity = 2.0\nshapes = [\n\
                  { type = \"box\", half_extents = [0.1, 0.2, 0.3], position = [1.0, 0.0, 0.0] },\n\
                  { type = \"convex\", points = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], orientation = [0.0, 0.0, 0.0, 1.0] },\n]\n";
    let tables = "version = 1\n[[body]]\nname = \"b\"\ndensity = 2.0\n\
                  [[body.shapes]]\ntype = \"box\"\nhalf_extents = [0.1, 0.2, 0.3]\nposition = [1.0, 0.0, 0.0]\n\
                  [[body.shapes]]\ntype = \"convex\"\npoints = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]\norientation = [0.0, 0.0, 0.0, 1.0]\n";
    let json = r#"{"version": 1, "body": [{"name": "b", "density": 2, "shapes": [
        {"type": "box", "half_extents": [0.1, 0.2, 0.3], "position": [1, 0, 0]},
        {"type": "convex", "points": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]], "orientation": [0, 0, 0, 1]}]}]}"#;
    let a = load_str(inline).unwrap().world.bodies.remove(0);
    let b = load_str(tables).unwrap().world.bodies.remove(0);
    let c = scene::from_str(json, "test.json", scene::Format::Json).unwrap().world.bodies.remove(0);
    assert_eq!(a.shape, b.shape);
    assert_eq!(a.shape, c.shape);
    assert_eq!(a.mass, c.mass);
    // the tetrahedron turned half a turn about z: its centre of mass (1/4, 1/4, 1/4) goes to (−1/4, −1/4, 1/4)
    let Some(Shape::Compound(compound)) = &a.shape else { panic!() };
    let (v_box, v_tet) = (0.048, 1.0 / 6.0);
    let expected = (v_box * DVec3::X + v_tet * DVec3::new(-0.25, -0.25, 0.25)) / (v_box + v_tet);
    assert!((compound.center_of_mass_given - expected).length() < 1e-15, "{}", compound.center_of_mass_given);
    assert!((a.mass.mass - 2.0 * (v_box + v_tet)).abs() < 1e-15);
}

/// A table (a compound of a top and four legs) stands on the ground with a box on it: after they
/// settle, neither moves by more than 1e-5 m in the next 5 s (the contacts of the four legs are
/// warm-started by their own feature keys), and the box rests on the top.
#[test]
fn a_compound_table_stands_still_with_a_box_on_it() {
    let leg = |x: f64, y: f64| {
        format!("{{ type = \"box\", half_extents = [0.05, 0.05, 0.25], position = [{x}, {y}, 0.25] }},\n")
    };
    let text = format!(
        "version = 1\n[world]\ndt = 0.001\n{GROUND}\
         [[body]]\nname = \"table\"\ndensity = 600.0\nposition = [0.0, 0.0, 0.55]\n\
         shapes = [\n{{ type = \"box\", half_extents = [0.5, 0.5, 0.05], position = [0.0, 0.0, 0.55] }},\n{}{}{}{}]\n\
         [[body]]\nname = \"box\"\ndensity = 300.0\nposition = [0.1, -0.1, 0.9]\n\
         shape = {{ type = \"box\", half_extents = [0.1, 0.1, 0.1] }}\n",
        leg(0.4, 0.4),
        leg(-0.4, 0.4),
        leg(0.4, -0.4),
        leg(-0.4, -0.4),
    );
    let mut world = load_str(&text).unwrap().world;
    let Some(Shape::Compound(table)) = &body(&world, "table").shape else { panic!() };
    // the top's volume 0.1 m³ at z = 0.55, four legs of 0.005 m³ at z = 0.25
    let c = table.center_of_mass_given.z;
    assert!((c - (0.1 * 0.55 + 0.02 * 0.25) / 0.12).abs() < 1e-15, "{c}");
    run(&mut world, 3.0);
    let before = (body(&world, "table").state, body(&world, "box").state);
    run(&mut world, 5.0);
    let (table, cube) = (body(&world, "table"), body(&world, "box"));
    assert!((table.state.position.z - c).abs() < 1e-3, "the table's centre is at z = {}", table.state.position.z);
    assert!((cube.state.position.z - 0.7).abs() < 1e-3, "the box rests at z = {}", cube.state.position.z);
    for (b, start) in [(table, before.0), (cube, before.1)] {
        let moved = (b.state.position - start.position).length();
        let turned = b.state.orientation.angle_between(start.orientation);
        assert!(moved < 1e-5 && turned < 1e-5, "{} moved {moved} m and turned {turned} rad", b.name);
    }
}

/// A dumbbell lying across a fixed V groove (a compound against a triangle mesh: composite against
/// composite) rolls down into it and rests with both balls on both walls.
#[test]
fn a_dumbbell_rests_across_a_fixed_groove() {
    let v = extrude(&v_profile(), 0.5);
    let cv = center_of_mass(&v);
    let r = 0.1;
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let text = format!(
        "version = 1\n[world]\ndt = 0.001\n\
         [[body]]\nname = \"groove\"\nfixed = true\nposition = [{}, 0.0, {}]\nshape = {{ type = \"mesh\", file = \"v.obj\" }}\n\
         [[body]]\nname = \"dumbbell\"\ndensity = 800.0\nposition = [0.12, 0.0, 0.8]\n\
         shapes = [\n\
           {{ type = \"sphere\", radius = {r}, position = [0.0, -0.3, 0.0] }},\n\
           {{ type = \"sphere\", radius = {r}, position = [0.0, 0.3, 0.0] }},\n\
           {{ type = \"capsule\", radius = 0.02, half_height = 0.3, orientation = [{s}, {}, 0.0, 0.0] }},\n\
         ]\n",
        cv.x,
        cv.z,
        -s
    );
    let (_dir, path) = scene_dir(&[("v.obj", v)], &text);
    let mut world = scene::load(&path).unwrap().world;
    run(&mut world, 6.0);
    let b = body(&world, "dumbbell");
    let groove = 0.2 + r * (13.0_f64).sqrt() / 3.0;
    let axis = b.orientation_user() * DVec3::Y;
    println!("dumbbell at {}, axis {axis}", b.state.position);
    assert!(b.state.position.x.abs() < 1e-3 && (b.state.position.z - groove).abs() < 1e-3, "{}", b.state.position);
    assert!(axis.y > 1.0 - 1e-6, "the bar is not along the groove: {axis}");
    assert!(b.state.velocity.length() < 1e-2);
    let contacts = world.contact_stage().contacts().to_vec();
    assert_eq!(contacts.len(), 4, "each ball on both walls: {contacts:?}");
}
