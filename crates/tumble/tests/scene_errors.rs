//! Bad scene inputs, S01–S14 of the reliability catalogue, plus the body rules of the format:
//! every message names the file, the line and column (TOML) or the field path (JSON), and the field.

mod scene_common;
use scene_common::{assert_has, json_error, load_json, toml_error, toml_warnings, BODY};

#[test]
fn s01_toml_syntax_error_has_position_and_snippet() {
    let m = toml_error("version = 1\n[[bodies]\n");
    assert_has(&m, &["bad.toml:2:10:", "unclosed", "2 | [[bodies]"]);
}

#[test]
fn s02_json_trailing_comma_and_comments_are_syntax_errors() {
    assert_has(&json_error("{\"version\": 1,}"), &["bad.json:1:15:", "trailing comma"]);
    assert_has(&json_error("{\"version\": 1,\n // a comment\n \"body\": []}"), &["bad.json:2:2:"]);
    // JSON has no NaN: a syntax error, with its position
    assert_has(
        &json_error("{\"version\": 1,\n\"world\": {\"dt\": NaN}}"),
        &["bad.json:2:17: world.dt", "expected value"],
    );
}

#[test]
fn s02_a_byte_order_mark_is_stripped() {
    let toml = format!("\u{feff}{BODY}fixed = true\n");
    let scene = scene_common::load_toml(&toml).expect("a TOML file with a BOM loads");
    assert_eq!(scene.world.bodies[0].name, "a");
    let json = "\u{feff}{\"version\": 1, \"body\": [{\"name\": \"a\", \"fixed\": true}]}";
    let scene = load_json(json).expect("a JSON file with a BOM loads");
    assert_eq!(scene.world.bodies[0].name, "a");
    // after the BOM, positions are those an editor shows
    assert_has(&toml_error(&format!("\u{feff}{BODY}mass = -1.0\n")), &["bad.toml:4:8: body[0].mass"]);
}

#[test]
fn s03_wrong_types_name_the_field_and_the_expected_type() {
    assert_has(&toml_error(&format!("{BODY}mass = \"heavy\"\n")), &["bad.toml:4:8: body[0].mass", "expected f64"]);
    assert_has(&toml_error(&format!("{BODY}inertia = 5\n")), &["bad.toml:4:11: body[0].inertia", "array of length 3"]);
    assert_has(
        &toml_error(&format!("{BODY}fixed = \"yes\"\n")),
        &["bad.toml:4:9: body[0].fixed", "expected a boolean"],
    );
    let m = json_error("{\"version\": 1, \"body\": [{\"name\": \"a\", \"mass\": \"heavy\"}]}");
    assert_has(&m, &["bad.json:1:", "body[0].mass", "expected f64"]);
}

#[test]
fn s03_a_table_is_not_accepted_as_an_array() {
    // serde reads structs from arrays by position; the loader does not
    assert_has(&toml_error("version = 1\nbody = [[\"a\", 1.0]]\n"), &["bad.toml:2:9: body[0]", "expected a table"]);
    assert_has(
        &json_error("{\"version\": 1, \"world\": [[0, 0, 0], 0.01]}"),
        &["bad.json:1:", "world", "expected a table"],
    );
}

#[test]
fn s04_unknown_keys_are_rejected_with_the_nearest_valid_key() {
    let m = toml_error(&format!("{BODY}mas = 1.0\n"));
    assert_has(&m, &["bad.toml:4:1: body[0].mas", "unknown key `mas`", "did you mean `mass`?"]);
    let m = toml_error("version = 1\n[world]\ngravtiy = [0.0, 0.0, 0.0]\n");
    assert_has(&m, &["bad.toml:3:1: world.gravtiy", "did you mean `gravity`?"]);
    assert_has(&toml_error("version = 1\nbodies = []\n"), &["bad.toml:2:1: bodies", "did you mean `body`?"]);
    let m = toml_error(&format!("{BODY}mass = 1.0\nshape = {{ type = \"sphere\", raduis = 1.0 }}\n"));
    assert_has(&m, &["bad.toml:5:28: body[0].shape.raduis", "did you mean `radius`?"]);
    let m = toml_error(&format!(
        "{BODY}mass = 1.0\ninertia = [1.0, 1.0, 1.0]\n[[body.point_force]]\npoint = [1.0, 0.0, 0.0]\nforse = [0.0, 1.0, 0.0]\n"
    ));
    assert_has(&m, &["bad.toml:8:1: body[0].point_force[0].forse", "did you mean `force`?"]);
    let m = toml_error("version = 1\n[[grid]]\ncount = [1, 1, 1]\nspacng = [1.0, 1.0, 1.0]\n");
    assert_has(&m, &["bad.toml:4:1: grid[0].spacng", "did you mean `spacing`?"]);
    let m = json_error("{\"version\": 1, \"body\": [{\"name\": \"a\", \"mas\": 1}]}");
    assert_has(&m, &["bad.json:1:", "body[0].mas", "did you mean `mass`?"]);
}

#[test]
fn s05_a_moving_body_without_mass_names_the_body_and_the_field() {
    assert_has(&toml_error(BODY), &["bad.toml:2:1: body[0].mass", "body `a`", "missing"]);
    let m = json_error("{\"version\": 1, \"body\": [{\"name\": \"a\"}]}");
    assert_has(&m, &["bad.json: body[0].mass", "body `a`", "missing"]);
    let m = toml_error(&format!("{BODY}mass = 2.0\n"));
    assert_has(&m, &["bad.toml:4:8: body[0].mass", "no inertia", "hint:"]);
    let m = toml_error(&format!("{BODY}inertia = [1.0, 1.0, 1.0]\n"));
    assert_has(&m, &["bad.toml:4:11: body[0].inertia", "needs `mass`"]);
}

#[test]
fn s05_name_and_version_are_required() {
    let m = toml_error("version = 1\n[[body]]\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\n");
    assert_has(&m, &["bad.toml:2:1: body[0].name", "missing"]);
    assert_has(&toml_error("[world]\ndt = 0.01\n"), &["bad.toml:1:1: version", "missing", "version = 1"]);
    assert_has(&json_error("{\"world\": {\"dt\": 0.01}}"), &["bad.json: version", "missing"]);
    assert_has(&toml_error("version = 2\n"), &["bad.toml:1:11: version", "unsupported", "(got 2)"]);
    assert_has(
        &toml_error("version = 1\n[[body]]\nname = \" \"\nfixed = true\n"),
        &["bad.toml:3:8: body[0].name", "empty"],
    );
}

#[test]
fn s06_duplicate_keys_are_parser_errors() {
    assert_has(&toml_error(&format!("{BODY}mass = 1.0\nmass = 2.0\n")), &["bad.toml:5:1:", "duplicate key"]);
    assert_has(&json_error("{\"version\": 1, \"version\": 1}"), &["bad.json:1:", "duplicate field `version`"]);
}

#[test]
fn s06_duplicate_names_cite_both_locations() {
    let m = toml_error("version = 1\n[[body]]\nname = \"a\"\nfixed = true\n[[body]]\nname = \"a\"\nfixed = true\n");
    assert_has(
        &m,
        &["bad.toml:6:8: body[1].name", "duplicate name", "body[0].name at ", "bad.toml:3:8", "(got \"a\")"],
    );
    let m = json_error(
        "{\"version\": 1, \"body\": [{\"name\": \"a\", \"fixed\": true}, {\"name\": \"a\", \"fixed\": true}]}",
    );
    assert_has(&m, &["bad.json: body[1].name", "body[0].name"]);
}

/// Every float key of the format, written `nan` (or `[nan, 0, 0]`), is rejected at its position.
#[test]
fn s07_every_float_is_checked_to_be_finite() {
    let dynamic = "mass = 1.0\ninertia = [1.0, 1.0, 1.0]\n";
    let scalars = ["restitution", "friction", "linear_damping", "angular_damping"];
    for key in scalars {
        let m = toml_error(&format!("{BODY}{dynamic}{key} = nan\n"));
        assert_has(&m, &[&format!("bad.toml:6:{}: body[0].{key}: must be finite (got NaN)", key.len() + 4)]);
    }
    let vectors = [
        "position",
        "velocity",
        "angular_velocity",
        "angular_velocity_body",
        "force",
        "force_body",
        "torque",
        "torque_body",
        "inertia",
    ];
    for key in vectors {
        let body = if key == "inertia" { "mass = 1.0\n" } else { dynamic };
        let m = toml_error(&format!("{BODY}{body}{key} = [0.5, nan, 0.5]\n"));
        assert_has(&m, &[&format!(": body[0].{key}: must be finite (got [0.5, NaN, 0.5])"), "bad.toml:"]);
    }
    let m = toml_error(&format!("{BODY}mass = nan\ninertia = [1.0, 1.0, 1.0]\n"));
    assert_has(&m, &["bad.toml:4:8: body[0].mass: must be finite (got NaN)"]);
    let m = toml_error(&format!("{BODY}density = inf\nshape = {{ type = \"sphere\", radius = 1.0 }}\n"));
    assert_has(&m, &["bad.toml:4:11: body[0].density: must be finite (got inf)"]);
    let m = toml_error(&format!(
        "{BODY}mass = 1.0\ninertia_tensor = [[1.0, 0.0, 0.0], [0.0, inf, 0.0], [0.0, 0.0, 1.0]]\n"
    ));
    assert_has(&m, &["bad.toml:5:18: body[0].inertia_tensor: must be finite"]);
    let m = toml_error(&format!("{BODY}fixed = true\norientation = [nan, 0.0, 0.0, 0.0]\n"));
    assert_has(&m, &["bad.toml:5:15: body[0].orientation: must be finite"]);
    for (key, value) in [("dt", "inf"), ("duration", "-inf"), ("rtol", "nan"), ("atol", "nan")] {
        let m = toml_error(&format!("version = 1\n[world]\n{key} = {value}\n"));
        assert_has(&m, &[&format!("bad.toml:3:{}: world.{key}: must be finite", key.len() + 4)]);
    }
    let m = toml_error("version = 1\n[world]\ngravity = [0.0, 0.0, nan]\n");
    assert_has(&m, &["bad.toml:3:11: world.gravity: must be finite"]);
    let m =
        toml_error(&format!("{BODY}{dynamic}[[body.point_force]]\npoint = [nan, 0.0, 0.0]\nforce = [0.0, 1.0, 0.0]\n"));
    assert_has(&m, &["bad.toml:7:9: body[0].point_force[0].point: must be finite"]);
    let m =
        toml_error(&format!("{BODY}mass = 1.0\nshape = {{ type = \"capsule\", radius = 0.1, half_height = nan }}\n"));
    assert_has(&m, &["bad.toml:5:57: body[0].shape.half_height", "(got NaN)"]);
    // keys read by shared helpers: each at its own path, line and column
    let col = |line: &str, needle: &str| line.find(needle).unwrap() + 1;
    for key in ["force", "force_body"] {
        let m = toml_error(&format!(
            "{BODY}{dynamic}[[body.point_force]]\npoint = [1.0, 0.0, 0.0]\n{key} = [nan, 0.0, 0.0]\n"
        ));
        let at = format!("bad.toml:8:{}: body[0].point_force[0].{key}: must be finite", key.len() + 4);
        assert_has(&m, &[&at, "(got [NaN, 0, 0])"]);
    }
    for (key, value) in [("position", "[nan, 0.0, 0.0]"), ("orientation", "[inf, 0.0, 0.0, 0.0]")] {
        let line = format!("shapes = [{{ type = \"sphere\", radius = 1.0, {key} = {value} }}]");
        let m = toml_error(&format!("{BODY}mass = 1.0\n{line}\n"));
        let at = format!("bad.toml:5:{}: body[0].shapes[0].{key}: must be finite", col(&line, value));
        assert_has(&m, &[&at]);
    }
    let m = toml_error(
        "version = 1\n[[grid]]\ncount = [1, 1, 1]\nspacing = [1.0, 1.0, 1.0]\norigin = [nan, 0.0, 0.0]\n\
         [grid.body]\nname = \"g\"\nmass = 1.0\nshape = { type = \"sphere\", radius = 0.5 }\n",
    );
    assert_has(&m, &["bad.toml:5:10: grid[0].origin: must be finite", "(got [NaN, 0, 0])"]);
    let line = "shape = { type = \"mesh\", file = \"cube.stl\", scale = nan }";
    let m = toml_error(&format!("{BODY}mass = 1.0\n{line}\n"));
    let at = format!("bad.toml:5:{}: body[0].shape.scale: mesh scale must be finite and > 0", col(line, "nan"));
    assert_has(&m, &[&at, "(got [NaN, NaN, NaN])"]);
    for key in [
        "restitution",
        "friction",
        "impact_speed",
        "contact_slop",
        "contact_hertz",
        "contact_damping_ratio",
        "max_correction_speed",
        "sleep_speed",
        "sleep_time",
    ] {
        for value in ["nan", "inf"] {
            let m = toml_error(&format!("version = 1\n[world]\n{key} = {value}\n"));
            assert_has(&m, &[&format!("bad.toml:3:{}: world.{key}: must be finite", key.len() + 4)]);
        }
    }
}

#[test]
fn s08_overflowing_literals_and_absurd_values() {
    assert_has(&toml_error(&format!("{BODY}mass = 1e400\n")), &["bad.toml:4:8: body[0].mass", "overflow"]);
    let dynamic = "mass = 1.0\ninertia = [1.0, 1.0, 1.0]\n";
    let m = toml_error(&format!("{BODY}{dynamic}position = [2e10, 0.0, 0.0]\n"));
    assert_has(&m, &["bad.toml:6:12: body[0].position", "exceeds the limit of 1e10 m"]);
    let m = toml_error(&format!("{BODY}{dynamic}velocity = [0.0, 2e8, 0.0]\n"));
    assert_has(&m, &["bad.toml:6:12: body[0].velocity", "exceeds the limit of 1e8 m/s"]);
    let m = toml_error(&format!("{BODY}{dynamic}angular_velocity = [0.0, 0.0, -2e8]\n"));
    assert_has(&m, &["bad.toml:6:20: body[0].angular_velocity", "1e8 rad/s"]);
    // the limits themselves are accepted
    toml_warnings(&format!("{BODY}{dynamic}position = [1e10, 0.0, 0.0]\nvelocity = [0.0, 1e8, 0.0]\n"));
}

#[test]
fn s09_mass_must_be_positive() {
    for value in ["0.0", "-1.0"] {
        let m = toml_error(&format!("{BODY}mass = {value}\ninertia = [1.0, 1.0, 1.0]\n"));
        assert_has(&m, &["bad.toml:4:8: body[0].mass: must be > 0 (kg)", "fixed = true"]);
    }
    let m = json_error("{\"version\": 1, \"body\": [{\"name\": \"a\", \"mass\": 0, \"inertia\": [1, 1, 1]}]}");
    assert_has(&m, &["bad.json: body[0].mass: must be > 0"]);
}

#[test]
fn s10_inertia_must_be_positive_definite() {
    let m = toml_error(&format!("{BODY}mass = 1.0\ninertia = [1.0, 0.0, 1.0]\n"));
    assert_has(&m, &["bad.toml:5:11: body[0].inertia", "positive definite", "[1.0, 0.0, 1.0]"]);
    let m = toml_error(&format!("{BODY}mass = 1.0\ninertia = [-1.0, 2.0, 2.0]\n"));
    assert_has(&m, &["bad.toml:5:11: body[0].inertia", "positive definite"]);
}

#[test]
fn s11_principal_moments_obey_the_triangle_inequality() {
    let m = toml_error(&format!("{BODY}mass = 1.0\ninertia = [1.0, 1.0, 5.0]\n"));
    assert_has(&m, &["bad.toml:5:11: body[0].inertia", "triangle inequality", "short by 60.000%"]);
    // a flat plate sits on the bound and is accepted
    toml_warnings(&format!("{BODY}mass = 1.0\ninertia = [1.0, 2.0, 3.0]\n"));
}

#[test]
fn s12_tensors_must_be_symmetric_and_positive_definite() {
    let asymmetric = "[[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]";
    let m = toml_error(&format!("{BODY}mass = 1.0\ninertia_tensor = {asymmetric}\n"));
    assert_has(&m, &["bad.toml:5:18: body[0].inertia_tensor", "symmetric"]);
    // positive diagonal, eigenvalues 3, 1, −1
    let indefinite = "[[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]]";
    let m = toml_error(&format!("{BODY}mass = 1.0\ninertia_tensor = {indefinite}\n"));
    assert_has(&m, &["bad.toml:5:18: body[0].inertia_tensor", "positive definite", "principal moments [-"]);
    let m = toml_error(&format!("{BODY}mass = 1.0\ninertia = [1.0, 1.0, 1.0]\ninertia_tensor = {indefinite}\n"));
    assert_has(&m, &["bad.toml:6:18: body[0].inertia_tensor", "not both"]);
}

#[test]
fn s13_quaternions_zero_nan_and_far_from_unit_are_errors() {
    let m = toml_error(&format!("{BODY}fixed = true\norientation = [0.0, 0.0, 0.0, 0.0]\n"));
    assert_has(&m, &["bad.toml:5:15: body[0].orientation", "not zero", "[w, x, y, z]"]);
    let m = toml_error(&format!("{BODY}fixed = true\norientation = [1.01, 0.0, 0.0, 0.0]\n"));
    assert_has(
        &m,
        &["bad.toml:5:15: body[0].orientation", "|q| = 1.01", "[w, x, y, z]", "hint: normalised it is [1, 0, 0, 0]"],
    );
}

#[test]
fn s13_quaternions_near_unit_are_normalised() {
    // |q| − 1 = 1e-5: normalised, with a warning at the value's position
    let warnings = toml_warnings(&format!("{BODY}fixed = true\norientation = [1.00001, 0.0, 0.0, 0.0]\n"));
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_has(&warnings[0], &["bad.toml:5:15: body[0].orientation", "normalised"]);
    // |q| − 1 = 1e-13: round-off in the file, normalised silently
    let text = format!("{BODY}fixed = true\norientation = [0.6, 0.8000000000001, 0.0, 0.0]\n");
    let scene = scene_common::load_toml(&text).expect("accepted");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let q = scene.world.bodies[0].state.orientation;
    assert!((q.length() - 1.0).abs() < 1e-15, "|q| = {}", q.length());
}

#[test]
fn s14_shapes_need_positive_sizes() {
    let cases = [
        ("{ type = \"sphere\", radius = 0.0 }", "5:37: body[0].shape.radius"),
        ("{ type = \"box\", half_extents = [1.0, -1.0, 1.0] }", "5:40: body[0].shape.half_extents"),
        ("{ type = \"capsule\", radius = 0.1, half_height = -0.5 }", "5:57: body[0].shape.half_height"),
        ("{ type = \"cylinder\", radius = 0.0, half_height = 1.0 }", "5:39: body[0].shape.radius"),
    ];
    for (shape, at) in cases {
        let m = toml_error(&format!("{BODY}mass = 1.0\nshape = {shape}\n"));
        assert_has(&m, &[&format!("bad.toml:{at}"), "must be finite and > 0 (m)", "(got "]);
    }
}

#[test]
fn s14_shapes_take_exactly_their_sizes() {
    let m = toml_error(&format!("{BODY}mass = 1.0\nshape = {{ type = \"sphere\" }}\n"));
    assert_has(&m, &["bad.toml:5:9: body[0].shape", "a sphere needs `radius`"]);
    let m = toml_error(&format!("{BODY}mass = 1.0\nshape = {{ type = \"sphere\", half_extents = [1.0, 1.0, 1.0] }}\n"));
    assert_has(
        &m,
        &[
            "bad.toml:5:43: body[0].shape.half_extents",
            "a sphere has no `half_extents`",
            "hint: a sphere takes: radius",
        ],
    );
    let m = toml_error(&format!("{BODY}mass = 1.0\nshape = {{ type = \"sphre\", radius = 1.0 }}\n"));
    assert_has(&m, &["bad.toml:5:18: body[0].shape.type", "unknown shape type", "did you mean `sphere`?"]);
}

#[test]
fn a_plane_belongs_to_a_fixed_body() {
    let m = toml_error(&format!("{BODY}mass = 1.0\ninertia = [1.0, 1.0, 1.0]\nshape = {{ type = \"plane\" }}\n"));
    assert_has(&m, &["bad.toml:6:9: body[0].shape", "fixed bodies only", "fixed = true"]);
    let scene =
        scene_common::load_toml(&format!("{BODY}fixed = true\nshape = {{ type = \"plane\" }}\n")).expect("ground");
    assert!(scene.world.bodies[0].fixed);
}

#[test]
fn conflicting_and_incomplete_keys() {
    let dynamic = "mass = 1.0\ninertia = [1.0, 1.0, 1.0]\n";
    let m = toml_error(&format!(
        "{BODY}{dynamic}angular_velocity = [1.0, 0.0, 0.0]\nangular_velocity_body = [1.0, 0.0, 0.0]\n"
    ));
    assert_has(&m, &["bad.toml:7:25: body[0].angular_velocity_body", "not both"]);
    let m = toml_error(&format!("{BODY}mass = 1.0\ndensity = 1000.0\nshape = {{ type = \"sphere\", radius = 1.0 }}\n"));
    assert_has(&m, &["bad.toml:5:11: body[0].density", "not both"]);
    assert_has(&toml_error(&format!("{BODY}density = 1000.0\n")), &["bad.toml:4:11: body[0].density", "no shape"]);
    let m = toml_error(&format!(
        "{BODY}density = 1000.0\nshape = {{ type = \"sphere\", radius = 1.0 }}\ninertia = [1.0, 1.0, 1.0]\n"
    ));
    assert_has(&m, &["bad.toml:6:11: body[0].inertia", "density"]);
    let m = toml_error(&format!("{BODY}density = -1.0\nshape = {{ type = \"sphere\", radius = 1.0 }}\n"));
    assert_has(&m, &["bad.toml:4:11: body[0].density: must be > 0"]);
    let pf = "[[body.point_force]]\npoint = [1.0, 0.0, 0.0]\n";
    let m = toml_error(&format!("{BODY}{dynamic}{pf}force = [0.0, 1.0, 0.0]\nforce_body = [0.0, 1.0, 0.0]\n"));
    assert_has(&m, &["bad.toml:9:14: body[0].point_force[0].force_body", "not both"]);
    let m = toml_error(&format!("{BODY}{dynamic}{pf}"));
    assert_has(&m, &["bad.toml:6:1: body[0].point_force[0]", "missing `force`"]);
    let m = toml_error(&format!("{BODY}{dynamic}[[body.point_force]]\nforce = [0.0, 1.0, 0.0]\n"));
    assert_has(&m, &["bad.toml:6:1: body[0].point_force[0]", "missing `point`"]);
}

#[test]
fn a_fixed_body_takes_no_motion_and_no_loads() {
    let m = toml_error(&format!("{BODY}fixed = true\nvelocity = [1.0, 0.0, 0.0]\n"));
    assert_has(&m, &["bad.toml:5:12: body[0].velocity", "fixed body never moves"]);
    let m = toml_error(&format!("{BODY}fixed = true\ntorque_body = [0.0, 0.0, 1.0]\n"));
    assert_has(&m, &["bad.toml:5:15: body[0].torque_body", "fixed body never moves"]);
    // zeros are harmless and accepted
    toml_warnings(&format!("{BODY}fixed = true\nvelocity = [0.0, 0.0, 0.0]\n"));
}

#[test]
fn s17_friction_and_restitution_ranges() {
    let dynamic = "mass = 1.0\ninertia = [1.0, 1.0, 1.0]\n";
    for (key, value, problem, got) in [
        ("friction", "-0.1", "must be ≥ 0", "-0.1"),
        ("restitution", "1.5", "must be in [0, 1]", "1.5"),
        ("restitution", "-0.1", "must be in [0, 1]", "-0.1"),
        ("linear_damping", "-1.0", "must be ≥ 0 (1/s)", "-1"),
        ("angular_damping", "-1.0", "must be ≥ 0 (1/s)", "-1"),
    ] {
        let m = toml_error(&format!("{BODY}{dynamic}{key} = {value}\n"));
        assert_has(&m, &[&format!("bad.toml:6:{}: body[0].{key}: {problem} (got {got})", key.len() + 4)]);
    }
    toml_warnings(&format!("{BODY}{dynamic}restitution = 1.0\nfriction = 0.0\n"));
}
