//! The MJCF reader's refusals and remarks: what changes the dynamics and is not read is an error
//! `file:line:col: <element attr>: not supported (…)`; what is malformed names its position too;
//! soft-contact parameters are reported once; the closed-loop Menagerie robots are refused at
//! their first equality constraint.

use std::path::{Path, PathBuf};
use tumble::multibody::mjcf::{load_mjcf, parse_mjcf, MjcfError, MjcfOptions};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/mjcf")
}

fn parse(text: &str) -> Result<tumble::multibody::mjcf::Mjcf, MjcfError> {
    parse_mjcf(text, "test.xml", MjcfOptions::default())
}

fn refused(text: &str) -> MjcfError {
    match parse(text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

/// `<body>` with one hinge and a sphere inside `<worldbody>`, around `inner`.
fn model(inner: &str) -> String {
    format!(
        "<mujoco>\n<worldbody>\n<body name=\"b\">\n<geom size=\"0.1\"/>\n{inner}\n</body>\n</worldbody>\n</mujoco>\n"
    )
}

#[test]
fn robotiq_2f85_is_refused_at_its_first_equality_through_the_scene_include() {
    let e = load_mjcf(&dir().join("menagerie/robotiq_2f85/scene.xml"), MjcfOptions::default()).unwrap_err();
    let text = e.to_string();
    assert!(e.is_unsupported(), "{text}");
    assert!(text.contains("2f85.xml:173:5: <connect>: not supported (an <equality> constraint"), "{text}");
}

#[test]
fn cassie_is_refused_at_its_first_equality() {
    let e = load_mjcf(&dir().join("menagerie/agility_cassie/cassie.xml"), MjcfOptions::default()).unwrap_err();
    let text = e.to_string();
    assert!(text.contains("cassie.xml:228:5: <connect>: not supported (an <equality> constraint"), "{text}");
}

#[test]
fn refusals_name_the_element_attribute_and_position() {
    let cases: &[(&str, &str)] = &[
        (&model("<joint type=\"ball\" stiffness=\"1\"/>"), "<joint stiffness>: not supported (springs on ball"),
        (&model("<joint type=\"ball\" range=\"0 30\"/>"), "<joint range>: not supported (limits of ball"),
        (
            &model("<geom size=\"0.1\" fluidshape=\"ellipsoid\"/>"),
            "<geom fluidshape>: not supported (fluidshape=\"ellipsoid\"",
        ),
        ("<mujoco><option><flag contact=\"disable\"/></option></mujoco>", "<flag contact>: not supported"),
        ("<mujoco><compiler coordinate=\"global\"/></mujoco>", "<compiler coordinate>: not supported"),
        ("<mujoco><tendon><spatial/></tendon></mujoco>", "<spatial>: not supported (spatial tendons)"),
        (
            "<mujoco><tendon><fixed frictionloss=\"1\"><joint joint=\"a\" coef=\"1\"/></fixed></tendon></mujoco>",
            "<fixed frictionloss>: not supported (tendon frictionloss",
        ),
        ("<mujoco><equality><weld body1=\"a\"/></equality></mujoco>", "<weld>: not supported (an <equality>"),
        (&model("<geom type=\"hfield\" hfield=\"h\"/>"), "<geom type>: not supported (heightfields)"),
        (&model("<composite/>"), "<composite>: not supported"),
        ("<mujoco><worldbody><body mocap=\"true\"/></worldbody></mujoco>", "<body mocap>: not supported"),
        ("<mujoco><contact><pair geom1=\"a\" geom2=\"b\"/></contact></mujoco>", "<pair>: not supported"),
        ("<mujoco><extension><plugin plugin=\"x\"/></extension></mujoco>", "<extension>: not supported"),
        (
            &format!(
                "{}<actuator><motor site=\"s\"/></actuator></mujoco>",
                &model("<joint/>")[..model("<joint/>").len() - 10]
            ),
            "<motor site>: not supported (actuators on anything but a joint or a fixed tendon)",
        ),
        (
            &format!(
                "{}<actuator><muscle joint=\"j\"/></actuator></mujoco>",
                &model("<joint/>")[..model("<joint/>").len() - 10]
            ),
            "<muscle>: not supported",
        ),
    ];
    for (text, want) in cases {
        let e = refused(text);
        assert!(e.is_unsupported(), "{e}");
        assert!(e.to_string().contains(want), "for\n{text}\ngot: {e}\nwanted: {want}");
    }
}

#[test]
fn malformed_input_names_its_position() {
    let cases: &[(&str, &str)] = &[
        (&model("<joint axis=\"0 0\"/>"), "test.xml:5:8: <joint axis>: '0 0': expected 3 finite numbers"),
        (&model("<joint axis=\"0 0 0\"/>"), "<joint axis>: a zero axis"),
        (&model("<joint dampin=\"1\"/>"), "<joint dampin>: unknown attribute 'dampin'"),
        (
            &model("<joint frictionloss=\"-0.1\"/>"),
            "test.xml:5:8: <joint frictionloss>: '-0.1': expected a finite number ≥ 0",
        ),
        (&model("<joint class=\"nope\"/>"), "<joint class>: no default class 'nope'"),
        (&model("<joint type=\"screw\"/>"), "<joint type>: 'screw': expected one of hinge, slide, ball, free"),
        (&model("<geom type=\"sphere\" fromto=\"0 0 0 1 0 0\" size=\"0.1\"/>"), "<geom fromto>: fromto on a sphere"),
        (&model("<geom type=\"box\" size=\"0.1 0.2\"/>"), "<geom size>: the third half size must be > 0"),
        (&model("<joint name=\"j\"/><joint name=\"j\"/>"), "repeated joint name 'j'"),
        (
            &format!(
                "{}<actuator><motor tendon=\"t\"/></actuator></mujoco>",
                &model("<joint/>")[..model("<joint/>").len() - 10]
            ),
            "<motor tendon>: no tendon named 't'",
        ),
        (
            &format!(
                "{}<tendon><fixed name=\"t\"><joint joint=\"nope\" coef=\"1\"/></fixed></tendon></mujoco>",
                &model("<joint/>")[..model("<joint/>").len() - 10]
            ),
            "<joint joint>: no joint named 'nope'",
        ),
        (
            &format!(
                "{}<tendon><fixed name=\"t\"><joint joint=\"j\"/></fixed></tendon></mujoco>",
                &model("<joint name=\"j\"/>")[..model("<joint name=\"j\"/>").len() - 10]
            ),
            "<joint>: missing attribute 'coef'",
        ),
        (
            "<mujoco><tendon><fixed range=\"1 0\"><joint joint=\"a\" coef=\"1\"/></fixed></tendon></mujoco>",
            "test.xml:1:24: <fixed range>: lower 1 > upper 0",
        ),
        (
            "<mujoco><tendon><fixed limited=\"true\"><joint joint=\"a\" coef=\"1\"/></fixed></tendon></mujoco>",
            "<fixed limited>: limited without a range",
        ),
        ("<mujoco><worldbody><body quat=\"1 0 0 0\" euler=\"0 0 0\"/></worldbody></mujoco>", "orientation given twice"),
        ("<mujoco><worldbody><body><joint/></body></worldbody></mujoco>", "moves a subtree without mass"),
        ("<mujoco><include file=\"missing.xml\"/></mujoco>", "test.xml:1:18: <include file>: cannot read the file"),
        ("<robot/>", "the root element must be <mujoco>"),
        ("<mujoco><worldbody></mujoco>", "test.xml:1:"),
        ("<mujoco><wordlbody/></mujoco>", "unknown element <wordlbody>"),
    ];
    for (text, want) in cases {
        let e = refused(text);
        assert!(!e.is_unsupported(), "{e}");
        assert!(e.to_string().contains(want), "for\n{text}\ngot: {e}\nwanted: {want}");
    }
}

#[test]
fn soft_contact_parameters_are_reported_once() {
    let text = model(
        "<joint/><geom size=\"0.1\" solref=\"0.02 1\" margin=\"0.01\"/><geom size=\"0.1\" solref=\"0.01 1\" \
               solimp=\"0.9 0.95 0.001\"/><geom size=\"0.1\" solimp=\"0.8 0.9 0.001\"/>",
    );
    let m = parse(&text).unwrap();
    let solimp = m.model.warnings.iter().filter(|w| w.contains("<geom solimp>")).count();
    assert_eq!(solimp, 1, "{:?}", m.model.warnings);
    let solref: Vec<&String> = m.model.warnings.iter().filter(|w| w.contains("<geom solref>")).collect();
    assert_eq!(solref.len(), 1, "{:?}", m.model.warnings);
    assert!(solref[0].starts_with("test.xml:5:26:"), "{}", solref[0]);
    assert!(m.model.warnings.iter().any(|w| w.contains("<geom margin>")), "{:?}", m.model.warnings);
}

/// The first Rust example of docs/mjcf.md, as written there (its path, relative to the repository
/// root there, made absolute here: the tests share one working directory).
#[test]
fn the_docs_first_example_runs() -> Result<(), Box<dyn std::error::Error>> {
    let ant = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/mjcf/gymnasium/ant.xml");
    let mjcf = load_mjcf(&ant, MjcfOptions::default())?;
    // MuJoCo's qpos (15: free joint position, quaternion w-first, 8 hinges) and qvel (14)
    let mut qpos = vec![0.0; 15];
    (qpos[2], qpos[3]) = (0.75, 1.0);
    let qvel = vec![0.0; 14];
    let (q, v) = mjcf.layout.state_from_mujoco(&qpos, &qvel)?; // MuJoCo's state → tumble's
    assert_eq!((q.len(), v.len()), (15, 14));
    assert_eq!(&q[..4], &[0.0, 0.0, 0.75, 1.0]);
    Ok(())
}

#[test]
fn visual_elements_are_skipped_silently() {
    let text = "<mujoco><visual><map znear=\"0.01\"/></visual><asset><texture name=\"t\" builtin=\"flat\"/>\
                <material name=\"m\" texture=\"t\"/></asset><worldbody><light pos=\"0 0 1\"/><camera name=\"c\"/>\
                <body><site name=\"s\"/><joint/><geom size=\"0.1\" material=\"m\" rgba=\"1 0 0 1\"/></body>\
                </worldbody><sensor><jointpos joint=\"joint0\"/></sensor></mujoco>";
    let m = parse(text).unwrap();
    assert!(m.model.warnings.is_empty(), "{:?}", m.model.warnings);
    assert_eq!(m.model.nv(), 1);
}

#[test]
fn frictionloss_is_read_and_dropped_only_when_asked_with_a_warning() {
    let text = model("<joint name=\"j\" frictionloss=\"0.3\"/>");
    let m = parse(&text).unwrap();
    assert_eq!(m.model.bodies[0].joint.dynamics.friction_loss, 0.3);
    assert!(m.model.warnings.is_empty(), "{:?}", m.model.warnings);
    let m = parse_mjcf(&text, "test.xml", MjcfOptions { drop_frictionloss: true }).unwrap();
    assert_eq!(m.model.bodies[0].joint.dynamics.friction_loss, 0.0);
    assert!(
        m.model.warnings.iter().any(|w| w.contains("joint 'j': frictionloss 0.3 dropped")),
        "{:?}",
        m.model.warnings
    );
}

/// `frictionloss` through a `<default>` class, per joint; a ball joint's on each of its three
/// coordinates.
#[test]
fn frictionloss_is_read_through_default_classes() {
    let text = "<mujoco><default><joint frictionloss=\"0.7\"/><default class=\"f\"><joint frictionloss=\"2\"/></default></default>\
                <worldbody><body><geom size=\"0.1\"/><joint name=\"a\"/>\
                <body><geom size=\"0.1\"/><joint name=\"b\" class=\"f\" type=\"slide\"/>\
                <body><geom size=\"0.1\"/><joint name=\"c\" type=\"ball\" frictionloss=\"0.25\"/></body></body></body>\
                </worldbody></mujoco>";
    let m = parse(text).unwrap();
    let f: Vec<(String, f64)> =
        m.model.bodies.iter().map(|b| (b.joint.name.clone(), b.joint.dynamics.friction_loss)).collect();
    assert_eq!(f, [("a".to_string(), 0.7), ("b".to_string(), 2.0), ("c".to_string(), 0.25)]);
}

/// The joint layout: a hinge's `q = qpos − ref`, its limits shifted alike; `springref` in the
/// same coordinates; MuJoCo's qpos0 back from the layout.
#[test]
fn hinge_ref_shifts_coordinates_limits_and_spring() {
    let text = model("<joint name=\"j\" ref=\"30\" range=\"-10 50\" stiffness=\"2\" springref=\"40\"/>");
    let m = parse(&text).unwrap();
    let j = &m.model.bodies[0].joint;
    let d = std::f64::consts::PI / 180.0;
    let (lo, hi) = j.limits.position.unwrap();
    assert!((lo - (-40.0 * d)).abs() < 1e-15 && (hi - 20.0 * d).abs() < 1e-15, "{lo} {hi}");
    assert!((j.dynamics.spring_ref - 10.0 * d).abs() < 1e-15);
    assert_eq!(m.layout.qpos0(), vec![30.0 * d]);
    let (q, _) = m.layout.state_from_mujoco(&[30.0 * d], &[0.0]).unwrap();
    assert_eq!(q, vec![0.0]);
}

/// Geometry keeps MuJoCo's collision filter and friction; `contype = conaffinity = 0` is visual.
#[test]
fn geometry_roles_filters_and_friction() {
    use tumble::multibody::{GeometryRole, GeometryShape};
    let text = "<mujoco><worldbody><geom type=\"plane\" size=\"1 1 1\"/><body name=\"b\"><joint/>\
                <geom type=\"capsule\" fromto=\"0 0 0 0 0 1\" size=\"0.1\" friction=\"0.7 0.1 0.1\" contype=\"2\" conaffinity=\"3\"/>\
                <geom size=\"0.1\" contype=\"0\" conaffinity=\"0\"/></body></worldbody></mujoco>";
    let m = parse(text).unwrap();
    let g = &m.model.geometries;
    assert_eq!(g.len(), 3);
    assert_eq!((g[0].link.as_str(), &g[0].shape, g[0].role), ("world", &GeometryShape::Plane, GeometryRole::Collision));
    assert_eq!(g[1].shape, GeometryShape::Capsule { radius: 0.1, half_length: 0.5 });
    assert_eq!((g[1].contype, g[1].conaffinity, g[1].friction), (2, 3, Some(0.7)));
    assert_eq!(g[2].role, GeometryRole::Visual);
    let (body, x) = m.model.geometry_placement(&g[1]).unwrap();
    assert_eq!(body, Some(0));
    assert!((x.r - tumble::math::DVec3::new(0.0, 0.0, 0.5)).length() < 1e-15);
}

/// The Gymnasium ant's geoms become collision shapes as a URDF robot's do: the floor a plane of
/// the world, the torso a sphere, the legs capsules placed along their `fromto`.
#[test]
fn ant_collision_shapes() {
    use tumble::body::Shape;
    use tumble::multibody::link_shapes::collision_shapes;
    let path = dir().join("gymnasium/ant.xml");
    let m = load_mjcf(&path, MjcfOptions::default()).unwrap();
    // the ant's geoms have conaffinity 0 but contype 1: they collide (with the floor's conaffinity 1)
    let shapes = collision_shapes(&m.model, &path.display().to_string()).unwrap();
    assert_eq!(shapes.len(), 14);
    assert!(matches!(shapes[0].shape, Shape::Plane) && shapes[0].body.is_none());
    assert!(matches!(shapes[1].shape, Shape::Sphere { radius } if radius == 0.25));
    let capsules = shapes.iter().filter(|s| matches!(s.shape, Shape::Capsule { radius, .. } if radius == 0.08)).count();
    assert_eq!(capsules, 12);
    // aux_1_geom: fromto 0 0 0 → 0.2 0.2 0 on the torso: centre (0.1, 0.1, 0), z along from − to,
    // −(1, 1, 0), as MuJoCo turns it
    let aux = &shapes[2];
    assert_eq!(aux.body, Some(0));
    assert!((aux.position_body - tumble::math::DVec3::new(0.1, 0.1, 0.0)).length() < 1e-15);
    let axis = aux.orientation_body * tumble::math::DVec3::Z;
    assert!((axis + tumble::math::DVec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-15);
    match aux.shape {
        Shape::Capsule { half_height, .. } => assert!((half_height - 0.5 * 0.2_f64.hypot(0.2)).abs() < 1e-15),
        _ => unreachable!(),
    }
}

/// A box or an ellipsoid given by `fromto` is MuJoCo's: its first size on both sides across the
/// axis (MuJoCo 4.0.1's `geom_size` for `size="0.05 0.02 0.07"` is `(0.05, 0.05, |to − from| / 2)`),
/// its z axis along `from − to` and its x axis where MuJoCo's minimal turn of z puts it (the
/// `geom_quat` MuJoCo compiles for this geom: `(0.93348309, 0.19892737, −0.29839106, 0)`), and
/// so the body's mass is MuJoCo's `body_mass` at density 1000 (box 5.3851648071345055 kg, ellipsoid
/// 2.819665699410676 kg).
#[test]
fn a_box_and_an_ellipsoid_from_fromto_are_mujocos() {
    use tumble::body::Shape;
    use tumble::math::{DQuat, DVec3};
    use tumble::multibody::link_shapes::collision_shapes;
    let half_length = 0.5 * DVec3::new(0.3, 0.2, -0.4).length();
    for ty in ["box", "ellipsoid"] {
        let text = format!(
            "<mujoco><worldbody><body name=\"arm\"><joint type=\"ball\"/>\
             <geom type=\"{ty}\" fromto=\"0 0 0 0.3 0.2 -0.4\" size=\"0.05 0.02 0.07\"/></body></worldbody></mujoco>"
        );
        let mjcf = parse(&text).unwrap();
        if ty == "box" {
            // (an ellipsoid does not collide yet: its sizes and frame show in its mass alone)
            let shapes = collision_shapes(&mjcf.model, "test").unwrap();
            let Shape::Box { half_extents } = shapes[0].shape else { panic!("{:?}", shapes[0].shape) };
            assert!((half_extents - DVec3::new(0.05, 0.05, half_length)).length() < 1e-15, "{half_extents}");
            let mujoco = DQuat::from_xyzw(0.19892737, -0.29839106, 0.0, 0.93348309);
            let turn = shapes[0].orientation_body.angle_between(mujoco);
            assert!(turn < 1e-8, "{turn} rad from MuJoCo's geom_quat");
        }
        let mass = mjcf.model.total_mass;
        let mujoco_mass = if ty == "box" { 5.3851648071345055 } else { 2.819665699410676 };
        assert!((mass - mujoco_mass).abs() < 1e-12 * mujoco_mass, "{ty}: {mass}");
    }
}

/// A chain nested deeper than the reader recurses is refused, not a stack overflow.
#[test]
fn deep_nesting_is_refused() {
    let n = 20_000;
    let text = format!(
        "<mujoco><worldbody>{}{}</worldbody></mujoco>",
        "<body><joint/><geom size=\"0.1\"/>".repeat(n),
        "</body>".repeat(n)
    );
    let e = refused(&text);
    assert!(e.to_string().contains("nested deeper than 1000"), "{e}");
    // a chain of 500 bodies is read
    let n = 500;
    let text = format!(
        "<mujoco><worldbody>{}{}</worldbody></mujoco>",
        "<body pos=\"0 0 0.1\"><joint/><geom size=\"0.1\"/>".repeat(n),
        "</body>".repeat(n)
    );
    assert_eq!(parse(&text).unwrap().model.nv(), n);
}
