//! Bad scene inputs, S15–S22 of the reliability catalogue: world settings, huge counts, the file
//! itself (missing, too large, not UTF-8, deeply nested), empty scenes; and the grid generator's rules.

mod scene_common;
use scene_common::{assert_has, json_error, load_json, load_toml, toml_error, toml_warnings, write, BODY};
use tumble::scene;

#[test]
fn s15_time_step_and_duration() {
    for (dt, problem) in
        [("0.0", "must be finite and > 0"), ("-1.0", "must be finite and > 0"), ("1e-12", "at least 1e-9")]
    {
        let m = toml_error(&format!("version = 1\n[world]\ndt = {dt}\n"));
        assert_has(&m, &["bad.toml:3:6: world.dt", problem]);
    }
    let m = toml_error("version = 1\n[world]\nduration = -1.0\n");
    assert_has(&m, &["bad.toml:3:12: world.duration", "≥ 0", "(got -1)"]);
    // 1e7 s at the default 1 ms step: 1e10 steps, over the cap; the implied count is stated
    let m = toml_error("version = 1\n[world]\nduration = 1e7\n");
    assert_has(&m, &["bad.toml:3:12: world.duration", "1e10 steps", "cap of 1e9"]);
    // a large step is accepted with a warning
    let warnings = toml_warnings("version = 1\n[world]\ndt = 0.5\nduration = 10.0\n");
    assert!(warnings.iter().any(|w| w.contains("bad.toml:3:6: world.dt") && w.contains("0.5 s")), "{warnings:?}");
}

#[test]
fn other_world_settings() {
    let m = toml_error("version = 1\n[world]\nintegrator = \"rk5\"\n");
    assert_has(
        &m,
        &[
            "bad.toml:3:14: world.integrator",
            "unknown integrator",
            "splitting4",
            "did you mean `rk4`?",
            "(got \"rk5\")",
        ],
    );
    let m = toml_error("version = 1\n[world]\nsample_every = 0\n");
    assert_has(&m, &["bad.toml:3:16: world.sample_every", "≥ 1"]);
    let m = toml_error("version = 1\n[world]\nrtol = 2.0\n");
    assert_has(&m, &["bad.toml:3:8: world.rtol", "(0, 1)"]);
    let m = json_error("{\"version\": 1, \"world\": {\"dt\": 0}}");
    assert_has(&m, &["bad.json: world.dt", "must be finite and > 0"]);
}

#[test]
fn s21_gravity_must_be_finite_and_sane() {
    let m = toml_error("version = 1\n[world]\ngravity = [0.0, 0.0, -2e6]\n");
    assert_has(&m, &["bad.toml:3:11: world.gravity", "1e6"]);
    let m = toml_error("version = 1\n[world]\ngravity = [0.0, 0.0, -inf]\n");
    assert_has(&m, &["bad.toml:3:11: world.gravity", "must be finite"]);
}

const TEMPLATE: &str = "[grid.body]\nname = \"r\"\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\n";

#[test]
fn s16_huge_grids_are_refused_before_allocating() {
    let m = toml_error(&format!(
        "version = 1\n[[grid]]\ncount = [100000, 100000, 100]\nspacing = [1.0, 1.0, 1.0]\n{TEMPLATE}"
    ));
    assert_has(&m, &["bad.toml:3:9: grid[0].count", "1000000000000 bodies", "limit of 10000000", "GiB of memory"]);
    let m = toml_error(&format!(
        "version = 1\n[[grid]]\ncount = [4294967296, 4294967296, 4294967296]\nspacing = [1.0, 1.0, 1.0]\n{TEMPLATE}"
    ));
    assert_has(&m, &["bad.toml:3:9: grid[0].count", "overflows"]);
    // two grids that are each under the limit but not together
    let grid = format!("[[grid]]\ncount = [1000, 1000, 6]\nspacing = [1.0, 1.0, 1.0]\n{TEMPLATE}");
    let m = toml_error(&format!("version = 1\n{grid}{}", grid.replace("\"r\"", "\"s\"")));
    assert_has(&m, &["grid[1].count", "12000000 bodies"]);
    // counts are integers
    let m =
        toml_error(&format!("version = 1\n[[grid]]\ncount = [1e5, 1e5, 100]\nspacing = [1.0, 1.0, 1.0]\n{TEMPLATE}"));
    assert_has(&m, &["bad.toml:3:10: grid[0].count[0]", "expected u64"]);
    let m = toml_error(&format!("version = 1\n[[grid]]\ncount = [2, 0, 2]\nspacing = [1.0, 1.0, 1.0]\n{TEMPLATE}"));
    assert_has(&m, &["bad.toml:3:9: grid[0].count", "≥ 1"]);
}

#[test]
fn grid_generates_named_placed_copies() {
    let text = format!(
        "version = 1\n[[body]]\nname = \"ground\"\nfixed = true\n[[grid]]\ncount = [2, 3, 4]\nspacing = [1.0, 2.0, 3.0]\norigin = [10.0, 0.0, 0.0]\n{TEMPLATE}angular_velocity_body = [0.0, 1.0, 0.0]\n"
    );
    let scene = load_toml(&text).expect("a valid grid");
    let bodies = &scene.world.bodies;
    assert_eq!(bodies.len(), 1 + 24);
    assert_eq!(bodies[0].name, "ground");
    assert_eq!(bodies[1].name, "r_0_0_0");
    assert_eq!(bodies[2].name, "r_0_0_1");
    let last = &bodies[24];
    assert_eq!(last.name, "r_1_2_3");
    assert_eq!(last.state.position.to_array(), [11.0, 4.0, 9.0]);
    assert_eq!(last.state.omega_body.to_array(), [0.0, 1.0, 0.0]);
    assert_eq!(last.mass.mass, 1.0);
}

#[test]
fn grid_template_rules() {
    let grid = "version = 1\n[[grid]]\ncount = [2, 2, 2]\nspacing = [1.0, 1.0, 1.0]\n";
    let m = toml_error(&format!("{grid}{TEMPLATE}position = [1.0, 0.0, 0.0]\n"));
    assert_has(&m, &["bad.toml:9:12: grid[0].body.position", "no position", "origin"]);
    let m = toml_error(&format!("{grid}[grid.body]\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\n"));
    assert_has(&m, &["bad.toml:5:1: grid[0].body.name", "missing"]);
    let m = toml_error(&format!("{grid}[grid.body]\nname = \"r\"\nmass = -1.0\ninertia = [1.0, 1.0, 1.0]\n"));
    assert_has(&m, &["bad.toml:7:8: grid[0].body.mass", "must be > 0"]);
    let m = toml_error(&format!("version = 1\n[[grid]]\ncount = [2, 2, 2]\n{TEMPLATE}"));
    assert_has(&m, &["bad.toml:2:1: grid[0].spacing", "missing"]);
    let m = toml_error(&format!("version = 1\n[[grid]]\ncount = [3, 1, 1]\nspacing = [1e10, 0.0, 0.0]\n{TEMPLATE}"));
    assert_has(&m, &["bad.toml:4:11: grid[0].spacing", "beyond 1e10 m"]);
    let m = toml_error(&format!("version = 1\n[[grid]]\ncount = [3, 1, 1]\nspacing = [1.0, nan, 0.0]\n{TEMPLATE}"));
    assert_has(&m, &["bad.toml:4:11: grid[0].spacing", "must be finite"]);
}

#[test]
fn grid_names_must_not_collide() {
    let grid = format!("[[grid]]\ncount = [2, 2, 2]\nspacing = [1.0, 1.0, 1.0]\n{TEMPLATE}");
    let m = toml_error(&format!("version = 1\n{grid}{grid}"));
    assert_has(&m, &["bad.toml:13:8: grid[1].body.name", "duplicate name", "grid[0].body.name at ", "bad.toml:6:8"]);
    let body = "[[body]]\nname = \"r_1_0_1\"\nfixed = true\n";
    let m = toml_error(&format!("version = 1\n{body}{grid}"));
    assert_has(&m, &["grid[0].body.name", "body[0].name at ", "bad.toml:3:8", "copy (1, 0, 1)"]);
    // names outside the copies' range, or with leading zeros, do not collide
    let body = "[[body]]\nname = \"r_2_0_0\"\nfixed = true\n[[body]]\nname = \"r_01_0_0\"\nfixed = true\n";
    assert_eq!(load_toml(&format!("version = 1\n{body}{grid}")).expect("valid").world.bodies.len(), 2 + 8);
}

#[test]
fn s20_deep_nesting_is_a_clean_error() {
    let deep = format!("version = 1\nx = {}{}\n", "[".repeat(100_000), "]".repeat(100_000));
    assert_has(&toml_error(&deep), &["bad.toml:2:"]);
    // the typed reader stops at the first `[` where it expects a number or a table
    let deep = format!("{{\"version\": {}{}}}", "[".repeat(100_000), "]".repeat(100_000));
    assert_has(&json_error(&deep), &["bad.json:1:12: version", "expected i64"]);
    let deep = format!("{}{}", "[".repeat(100_000), "]".repeat(100_000));
    assert_has(&json_error(&deep), &["bad.json:1:1:", "expected a table"]);
}

#[test]
fn s20_invalid_utf8_is_a_clean_error() {
    let mut bytes = b"version = 1\n[[body]]\nname = \"".to_vec();
    bytes.extend_from_slice(&[0xff, 0xfe]);
    bytes.extend_from_slice(b"\"\nfixed = true\n");
    let w = write("bad.toml", &bytes);
    let m = scene::load(&w.path).expect_err("not UTF-8").to_string();
    assert_has(&m, &["bad.toml:3:9:", "not valid UTF-8", "0xff"]);
}

#[test]
fn s20_a_long_string_loads() {
    let name = "n".repeat(10 << 20);
    let scene = load_toml(&format!("version = 1\n[[body]]\nname = \"{name}\"\nfixed = true\n")).expect("loads");
    assert_eq!(scene.world.bodies[0].name.len(), 10 << 20);
}

#[test]
fn s22_empty_files_and_zero_bodies_are_valid_with_a_warning() {
    for text in ["", "\n  \n"] {
        let scene = load_toml(text).expect("an empty TOML file is valid");
        assert!(scene.world.bodies.is_empty());
        assert_has(&scene.warnings.join("\n"), &["bad.toml", "empty"]);
        let scene = load_json(text).expect("an empty JSON file is valid");
        assert_has(&scene.warnings.join("\n"), &["bad.json", "empty"]);
    }
    let warnings = toml_warnings("version = 1\n[world]\ndt = 0.01\n");
    assert_has(&warnings.join("\n"), &["bad.toml", "no bodies"]);
    let scene = load_json("{\"version\": 1, \"body\": []}").expect("valid");
    assert_has(&scene.warnings.join("\n"), &["bad.json", "no bodies"]);
    // a world with no bodies steps without trouble
    let mut world = scene.world;
    world.step().expect("steps");
}

#[test]
fn file_errors_name_the_path() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let missing = dir.path().join("nowhere.toml");
    let m = scene::load(&missing).expect_err("missing").to_string();
    assert_has(&m, &["nowhere.toml", "cannot read", "No such file"]);
    let as_dir = dir.path().join("scene.toml");
    std::fs::create_dir(&as_dir).expect("mkdir");
    assert_has(&scene::load(&as_dir).expect_err("a directory").to_string(), &["scene.toml", "directory"]);
    let w = write("scene.yaml", b"version: 1\n");
    assert_has(&scene::load(&w.path).expect_err("yaml").to_string(), &["scene.yaml", ".toml or .json", "(got .yaml)"]);
}

/// The size is checked from the metadata, before reading: the test files are sparse.
#[test]
fn r01_files_too_large_are_refused_before_reading() {
    let dir = tempfile::tempdir().expect("a temporary directory");
    for (name, size, limit) in [("big.toml", 65u64 << 20, "64 MiB"), ("big.json", 513u64 << 20, "512 MiB")] {
        let path = dir.path().join(name);
        let file = std::fs::File::create(&path).expect("create");
        file.set_len(size).expect("a sparse file");
        let m = scene::load(&path).expect_err("too large").to_string();
        assert_has(&m, &[name, "too large", limit, &format!("{size} bytes")]);
    }
}

#[test]
fn json_has_the_same_structure() {
    let json = r#"{
        "version": 1,
        "world": {"gravity": [0, 0, -1], "dt": 0.01, "duration": 1, "integrator": "splitting", "sample_every": 5},
        "body": [
            {"name": "a", "mass": 2, "inertia": [1, 2, 2.5], "angular_velocity": [0, 0, 1],
             "point_force": [{"point": [1, 0, 0], "force_body": [0, 1, 0]}]}
        ],
        "grid": [{"count": [1, 2, 1], "spacing": [1, 1, 1], "origin": [5, 0, 0],
                  "body": {"name": "g", "density": 1000, "shape": {"type": "sphere", "radius": 0.1}}}]
    }"#;
    let toml = "version = 1\n[world]\ngravity = [0, 0, -1]\ndt = 0.01\nduration = 1\nintegrator = \"splitting\"\nsample_every = 5\n\
        [[body]]\nname = \"a\"\nmass = 2\ninertia = [1, 2, 2.5]\nangular_velocity = [0, 0, 1]\n\
        [[body.point_force]]\npoint = [1, 0, 0]\nforce_body = [0, 1, 0]\n\
        [[grid]]\ncount = [1, 2, 1]\nspacing = [1, 1, 1]\norigin = [5, 0, 0]\n\
        [grid.body]\nname = \"g\"\ndensity = 1000\nshape = { type = \"sphere\", radius = 0.1 }\n";
    let from_json = load_json(json).expect("valid JSON");
    let from_toml = load_toml(toml).expect("valid TOML");
    assert_eq!(from_json.world.config, from_toml.world.config);
    assert_eq!(from_json.world.bodies, from_toml.world.bodies);
    assert_eq!(from_json.world.bodies.len(), 3);
}

#[test]
fn from_str_reads_text_without_a_file() {
    let scene = scene::from_str(&format!("{BODY}fixed = true\n"), "<stdin>", scene::Format::Toml).expect("valid");
    assert_eq!(scene.origin, "<stdin>");
    let m = scene::from_str(&format!("{BODY}mass = 0.0\n"), "<stdin>", scene::Format::Toml).expect_err("bad");
    assert_eq!(m.position(), Some(scene::LineCol { line: 4, column: 8 }));
    assert_eq!(m.path(), "body[0].mass");
    assert!(m.to_string().starts_with("<stdin>:4:8: body[0].mass: must be > 0 (kg) (got 0)"), "{m}");
}
