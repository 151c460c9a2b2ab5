//! URDF reading: frames, merging of fixed joints, joint order, and every rejected input with its
//! file, line, column and element (reliability catalogue U01–U13, U18, U19).

mod multibody_common;

use multibody_common::assert_close;
use std::path::{Path, PathBuf};
use tumble::math::{DMat3, DVec3};
use tumble::multibody::urdf::resolve_mesh;
use tumble::multibody::{
    aba, crba, parse_urdf, rnea, ChildOrder, CrbaError, JointKind, UrdfError, UrdfErrorKind, UrdfOptions, Workspace,
};

const INERTIAL: &str =
    r#"<inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>"#;

fn link(name: &str) -> String {
    format!(r#"<link name="{name}">{INERTIAL}</link>"#)
}

fn joint(name: &str, ty: &str, parent: &str, child: &str) -> String {
    let limit = if ty == "revolute" || ty == "prismatic" {
        r#"<limit lower="-1" upper="1" effort="1" velocity="1"/>"#
    } else {
        ""
    };
    format!(r#"<joint name="{name}" type="{ty}"><parent link="{parent}"/><child link="{child}"/>{limit}</joint>"#)
}

fn parse(text: &str) -> Result<tumble::multibody::MultibodyModel, UrdfError> {
    parse_urdf(text, "robot.urdf", UrdfOptions::default())
}

fn err(text: &str) -> UrdfError {
    match parse(text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

/// The text of one line per element, so that line numbers are easy to state.
fn robot(lines: &[String]) -> String {
    let mut s = String::from("<robot name=\"r\">\n");
    for l in lines {
        s.push_str(l);
        s.push('\n');
    }
    s.push_str("</robot>\n");
    s
}

#[test]
fn u01_malformed_xml_gives_row_and_column() {
    let e = err("<robot name=\"r\">\n  <link name=\"a\">\n</robot>\n");
    assert!(matches!(*e.kind, UrdfErrorKind::Xml(_)), "{e}");
    assert_eq!(e.line, 3, "{e}");
    assert!(e.to_string().starts_with("robot.urdf:3:"), "{e}");
    let e = err("<robot name='r><link name=\"a\"/></robot>");
    assert!(matches!(*e.kind, UrdfErrorKind::Xml(_)), "{e}");
}

#[test]
fn u02_dtds_are_rejected_unexpanded() {
    let laughs = r#"<?xml version="1.0"?><!DOCTYPE lolz [<!ENTITY lol "lol"><!ENTITY lol2 "&lol;&lol;&lol;">]><robot name="&lol2;"><link name="a"/></robot>"#;
    assert!(matches!(*err(laughs).kind, UrdfErrorKind::Xml(_)));
    let xxe = r#"<?xml version="1.0"?><!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/passwd">]><robot name="&x;"><link name="a"/></robot>"#;
    let e = err(xxe);
    assert!(matches!(*e.kind, UrdfErrorKind::Xml(_)));
    assert!(!e.to_string().contains("root:"), "{e}");
}

#[test]
fn u03_deep_nesting_is_an_error_or_a_model_never_an_abort() {
    let depth = 100_000;
    let mut text = String::from("<robot name=\"r\"><link name=\"a\">");
    text.push_str(&"<x>".repeat(depth));
    text.push_str(&"</x>".repeat(depth));
    text.push_str("</link></robot>");
    // either outcome is fine; reaching the next line is the test
    let _ = parse(&text);
}

#[test]
fn u04_joint_naming_a_missing_link() {
    let text = robot(&[link("a"), joint("j", "continuous", "a", "ghost")]);
    let e = err(&text);
    assert_eq!(*e.kind, UrdfErrorKind::MissingLink { joint: "j".into(), role: "child", link: "ghost".into() }, "{e}");
    assert_eq!(e.line, 3, "{e}");
}

#[test]
fn u05_cycles_print_their_path() {
    let text = robot(&[
        link("root"),
        link("a"),
        link("b"),
        joint("j0", "continuous", "root", "a"),
        joint("j1", "continuous", "a", "b"),
        joint("j2", "continuous", "b", "a"),
    ]);
    // a has two parents (j0, j2): that is caught first
    assert!(matches!(*err(&text).kind, UrdfErrorKind::TwoParents { .. }));
    let text = robot(&[
        link("root"),
        link("a"),
        link("b"),
        joint("j1", "continuous", "a", "b"),
        joint("j2", "continuous", "b", "a"),
    ]);
    let e = err(&text);
    match e.kind.as_ref() {
        UrdfErrorKind::Cycle(path) => {
            assert!(path.contains("(j1)") && path.contains("(j2)"), "{e}");
            assert!(path.starts_with('a') || path.starts_with('b'), "{e}");
        }
        other => panic!("{other:?}"),
    }
    // every link a child: no root at all
    let text = robot(&[link("a"), link("b"), joint("j1", "continuous", "a", "b"), joint("j2", "continuous", "b", "a")]);
    assert!(matches!(*err(&text).kind, UrdfErrorKind::Cycle(_)), "{}", err(&text));
}

#[test]
fn u06_several_roots_are_listed() {
    let text = robot(&[link("a"), link("b"), link("c"), joint("j", "continuous", "a", "c")]);
    let e = err(&text);
    assert_eq!(*e.kind, UrdfErrorKind::SeveralRoots(vec!["a".into(), "b".into()]), "{e}");
    assert_eq!(e.line, 3, "{e}");
}

#[test]
fn u07_a_link_with_two_parents() {
    let text = robot(&[
        link("a"),
        link("b"),
        link("c"),
        joint("j1", "continuous", "a", "c"),
        joint("j2", "continuous", "b", "c"),
    ]);
    let e = err(&text);
    assert_eq!(*e.kind, UrdfErrorKind::TwoParents { link: "c".into(), first: "j1".into(), second: "j2".into() });
    assert_eq!(e.line, 6, "{e}");
    assert!(e.element.contains("j2"), "{e}");
}

#[test]
fn u08_duplicate_names() {
    let e = err(&robot(&[link("a"), link("a")]));
    assert_eq!(*e.kind, UrdfErrorKind::Duplicate { what: "link", name: "a".into(), first_line: 2 });
    assert_eq!(e.line, 3);
    let e = err(&robot(&[
        link("a"),
        link("b"),
        link("c"),
        joint("j", "continuous", "a", "b"),
        joint("j", "continuous", "a", "c"),
    ]));
    assert_eq!(*e.kind, UrdfErrorKind::Duplicate { what: "joint", name: "j".into(), first_line: 5 });
}

#[test]
fn u09_unknown_joint_types_list_the_valid_ones() {
    let e = err(&robot(&[link("a"), link("b"), joint("j", "hinge", "a", "b")]));
    assert_eq!(*e.kind, UrdfErrorKind::UnknownJointType("hinge".into()));
    assert_eq!(e.line, 4);
    assert!(e.to_string().contains("revolute, continuous, prismatic, fixed, floating"), "{e}");
    let e = err(&robot(&[link("a"), link("b"), joint("j", "planar", "a", "b")]));
    assert!(matches!(*e.kind, UrdfErrorKind::UnsupportedJointType(_)), "{e}");
}

#[test]
fn u10_zero_and_non_finite_axes_are_errors_non_unit_axes_are_normalised() {
    for axis in ["0 0 0", "nan 0 1", "1 inf 0", "1 0"] {
        let j = format!(
            r#"<joint name="j" type="continuous"><parent link="a"/><child link="b"/><axis xyz="{axis}"/></joint>"#
        );
        let e = err(&robot(&[link("a"), link("b"), j]));
        assert!(matches!(*e.kind, UrdfErrorKind::BadAxis { .. } | UrdfErrorKind::BadNumber { .. }), "{axis}: {e}");
        assert_eq!(e.line, 4, "{e}");
    }
    let j = r#"<joint name="j" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 0 2"/></joint>"#;
    let model = parse(&robot(&[link("a"), link("b"), j.into()])).unwrap();
    assert_eq!(model.bodies[0].joint.kind, JointKind::Continuous { axis: DVec3::Z });
    assert!(model.warnings.iter().any(|w| w.contains("normalised")), "{:?}", model.warnings);
}

#[test]
fn u11_limits() {
    let no_limit = r#"<joint name="j" type="revolute"><parent link="a"/><child link="b"/></joint>"#;
    assert_eq!(
        *err(&robot(&[link("a"), link("b"), no_limit.into()])).kind,
        UrdfErrorKind::MissingLimit("revolute".into())
    );
    let inverted = r#"<joint name="j" type="prismatic"><parent link="a"/><child link="b"/><limit lower="1" upper="-1" effort="1" velocity="1"/></joint>"#;
    assert!(matches!(*err(&robot(&[link("a"), link("b"), inverted.into()])).kind, UrdfErrorKind::BadLimit(_)));
    let negative = r#"<joint name="j" type="revolute"><parent link="a"/><child link="b"/><limit lower="-1" upper="1" effort="-1" velocity="1"/></joint>"#;
    assert!(matches!(*err(&robot(&[link("a"), link("b"), negative.into()])).kind, UrdfErrorKind::BadLimit(_)));
    // continuous joints need none
    assert!(parse(&robot(&[link("a"), link("b"), joint("j", "continuous", "a", "b")])).is_ok());
}

#[test]
fn u12_a_movable_joint_whose_subtree_has_no_mass() {
    let text = robot(&[
        link("a"),
        link("b"),
        "<link name=\"c\"/>".into(),
        joint("j1", "continuous", "a", "b"),
        joint("j2", "continuous", "b", "c"),
    ]);
    let e = err(&text);
    assert!(matches!(*e.kind, UrdfErrorKind::Model(_)), "{e}");
    assert!(e.element.contains("j2") && e.to_string().contains("without mass"), "{e}");
    assert_eq!(e.line, 6);
    // a massless link on a fixed joint is merged and harmless; a massless link with a massive child is fine
    let text = robot(&[
        link("a"),
        "<link name=\"b\"/>".into(),
        "<link name=\"tip\"/>".into(),
        link("c"),
        joint("j1", "continuous", "a", "b"),
        joint("fix", "fixed", "b", "tip"),
        joint("j2", "continuous", "b", "c"),
    ]);
    assert!(parse(&text).is_ok());
}

#[test]
fn u13_bad_masses_and_inertias() {
    let with_inertial = |inertial: &str| {
        robot(&[link("a"), format!("<link name=\"b\">{inertial}</link>"), joint("j", "continuous", "a", "b")])
    };
    for mass in ["-1", "nan", "inf", "heavy"] {
        let e = err(&with_inertial(&format!(
            r#"<inertial><mass value="{mass}"/><inertia ixx="1" iyy="1" izz="1"/></inertial>"#
        )));
        assert!(matches!(*e.kind, UrdfErrorKind::BadMass(_)), "{mass}: {e}");
        assert_eq!(e.line, 3);
    }
    let e = err(&with_inertial(r#"<inertial><inertia ixx="1" iyy="1" izz="1"/></inertial>"#));
    assert_eq!(*e.kind, UrdfErrorKind::MissingElement("mass"));
    // zero mass with a tensor
    let e = err(&with_inertial(r#"<inertial><mass value="0"/><inertia ixx="1" iyy="1" izz="1"/></inertial>"#));
    assert!(matches!(*e.kind, UrdfErrorKind::BadInertia { .. }) && e.to_string().contains("without mass"), "{e}");
    // not positive semi-definite; triangle inequality
    for (tensor, word) in [(r#"ixx="1" iyy="-1" izz="1""#, "negative"), (r#"ixx="1" iyy="1" izz="3""#, "triangle")] {
        let e = err(&with_inertial(&format!(r#"<inertial><mass value="1"/><inertia {tensor}/></inertial>"#)));
        assert!(matches!(*e.kind, UrdfErrorKind::BadInertia { .. }) && e.to_string().contains(word), "{e}");
        assert!(e.element.starts_with("inertia"), "{e}");
    }
}

#[test]
fn u18_extension_tags_warn_once_and_mimics_are_checked() {
    let text = robot(&[
        link("a"),
        link("b"),
        joint("j", "continuous", "a", "b"),
        "<gazebo reference=\"a\"/>".into(),
        "<gazebo reference=\"b\"/>".into(),
        "<transmission name=\"t\"/>".into(),
    ]);
    let model = parse(&text).unwrap();
    assert_eq!(model.warnings.len(), 2, "{:?}", model.warnings);
    assert!(model.warnings[0].contains("robot.urdf:5:") && model.warnings[0].contains("<gazebo>"));
    let mimic = |target: &str| {
        format!(
            r#"<joint name="j" type="continuous"><parent link="a"/><child link="b"/><mimic joint="{target}"/></joint>"#
        )
    };
    assert!(matches!(*err(&robot(&[link("a"), link("b"), mimic("j")])).kind, UrdfErrorKind::BadMimic { .. }));
    // a mimic naming no joint is ignored with a warning (mimic joints are independent joints)
    let m = parse(&robot(&[link("a"), link("b"), mimic("nobody")])).unwrap();
    assert!(m.warnings.iter().any(|w| w.contains("refers to 'nobody'") && w.contains(":4:")), "{:?}", m.warnings);
}

/// 1-based column of `needle` in line `line` (1-based) of `text`.
fn column(text: &str, line: usize, needle: &str) -> usize {
    let l = text.lines().nth(line - 1).unwrap();
    l[..l.find(needle).unwrap()].chars().count() + 1
}

#[test]
fn u18_unknown_attributes_and_elements_warn_once_per_name() {
    let text = robot(&[
        link("a"),
        // line 3: a misspelt <inertial>, which leaves `b` massless
        r#"<link name="b"><inertail><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1"/></inertail></link>"#.into(),
        link("c"),
        r#"<link name="d"><inertail/></link>"#.into(),
        // line 6: `xzy` for `xyz`, which leaves the joint frame at the parent's origin
        r#"<joint name="j1" type="continuous"><parent link="a"/><child link="b"/><origin xzy="0 0 1"/></joint>"#.into(),
        // line 7: the same typo again (no warning), and two attributes outside the specification
        r#"<joint name="j2" type="continuous"><parent link="b"/><child link="c"/><origin xzy="0 0 1"/>
             <dynamics D="1" K="7000" damping="0.1"/></joint>"#
            .into(),
        joint("j3", "fixed", "a", "d"),
        // every standard element and attribute, and names in a namespace: silent
        r#"<link name="e" xmlns:x="urn:ext" x:colour="red"><inertial><origin xyz="0 0 0" rpy="0 0 0"/><mass value="1"/>
             <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
           <visual name="v"><origin xyz="0 0 0"/><geometry><cylinder radius="0.1" length="0.2"/></geometry>
             <material name="grey"><color rgba="0.5 0.5 0.5 1"/><texture filename="t.png"/></material></visual>
           <collision name="c"><geometry><sphere radius="0.1"/></geometry></collision>
           <x:sensor kind="camera"/></link>"#
            .into(),
        r#"<joint name="j4" type="revolute"><parent link="a"/><child link="e"/><origin xyz="0 0 1" rpy="0 0 0"/>
             <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
             <dynamics damping="0.1" friction="0.1"/><calibration rising="0.1" falling="0.2"/>
             <mimic joint="j2" multiplier="1" offset="0"/>
             <safety_controller soft_lower_limit="-0.9" soft_upper_limit="0.9" k_position="10" k_velocity="1"/></joint>"#
            .into(),
    ]);
    let model = parse(&text).unwrap();
    let w = &model.warnings;
    assert_eq!(w.len(), 3, "{w:#?}");
    let inertail = format!(
        "robot.urdf:3:{}: link 'b': ignored <inertail> (did you mean <inertial>?) in <link>: not a URDF element there",
        column(&text, 3, "<inertail>")
    );
    let xzy = format!(
        "robot.urdf:6:{}: joint 'j1': unknown attribute 'xzy' (did you mean 'xyz'?) on <origin>, ignored",
        column(&text, 6, "xzy=")
    );
    assert_eq!(w[0], inertail);
    assert_eq!(w[1], xzy);
    let dynamics = format!(
        "robot.urdf:8:{}: joint 'j2': unknown attributes 'D', 'K' on <dynamics>, ignored",
        column(&text, 8, "D=")
    );
    assert_eq!(w[2], dynamics);
    // what the typos did: `b` has no mass and `j1` no offset
    let b = model.frame_index("b").unwrap();
    assert_eq!(model.frames[b].inertia.mass, 0.0);
    assert_eq!(model.bodies[model.joint_index("j1").unwrap()].joint.x_tree.r, DVec3::ZERO);
}

#[test]
fn u14_a_radius_of_gyration_far_beyond_the_link_is_a_warning() {
    // link `b`: mass 1, moments `i` about its centre of mass, `geometry` beside the inertial
    let with_b = |i: f64, geometry: &str| {
        robot(&[
            link("a"),
            format!(
                r#"<link name="b"><inertial><mass value="1"/><inertia ixx="{i}" iyy="{i}" izz="{i}"/></inertial>{geometry}</link>"#
            ),
            joint("j", "continuous", "a", "b"),
        ])
    };
    let cube = r#"<collision><origin xyz="0.3 0 0"/><geometry><box size="0.1 0.1 0.1"/></geometry></collision>"#;
    // √(100 / 1) = 10 m against a 0.1 m cube (half-diagonal 0.0866 m)
    let text = with_b(100.0, cube);
    let model = parse(&text).unwrap();
    assert_eq!(model.warnings.len(), 1, "{:?}", model.warnings);
    let w = &model.warnings[0];
    let at = format!("robot.urdf:3:{}: link 'b': radius of gyration 1.000e1 m", column(&text, 3, "<inertia "));
    assert!(w.starts_with(&at), "{w}");
    assert!(w.contains("more than 10 times the half-diagonal 8.660e-2 m of its collision geometry"), "{w}");
    // the factor: 0.9 m is over 10 × 0.0866 m, 0.8 m is not; a solid 0.1 m cube (0.0408 m) is far below
    assert_eq!(parse(&with_b(0.81, cube)).unwrap().warnings.len(), 1);
    for i in [0.64, 1.0 / 600.0] {
        assert!(parse(&with_b(i, cube)).unwrap().warnings.is_empty(), "{i}");
    }
    // the bounding box holds every collision geometry (a second one 2 m away) and ignores visuals
    let far = r#"<collision><origin xyz="-1.7 0 0"/><geometry><sphere radius="0.05"/></geometry></collision>"#;
    assert!(parse(&with_b(100.0, &format!("{cube}{far}"))).unwrap().warnings.is_empty());
    let visual = cube.replace("collision>", "visual>");
    // no collision geometry: nothing to compare with, no warning
    for geometry in ["", visual.as_str()] {
        assert!(parse(&with_b(100.0, geometry)).unwrap().warnings.is_empty(), "{geometry}");
    }
}

/// A chain of 10⁵ links loads and every algorithm runs on it (no recursion anywhere).
#[test]
fn u19_a_chain_of_100000_links() {
    let n = 100_000;
    let mut lines = vec![link("l0")];
    for i in 1..=n {
        lines.push(link(&format!("l{i}")));
        lines.push(format!(
            r#"<joint name="j{i}" type="continuous"><parent link="l{}"/><child link="l{i}"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/></joint>"#,
            i - 1
        ));
    }
    let model = parse(&robot(&lines)).unwrap();
    assert_eq!(model.nv(), n);
    let mut ws = Workspace::new(&model);
    let q = vec![0.01; n];
    let v = vec![0.0; n];
    let mut tau = vec![0.0; n];
    rnea(&model, &mut ws, &q, &v, &v, &mut tau).unwrap();
    let mut qdd = vec![0.0; n];
    aba(&model, &mut ws, &q, &v, &tau, &mut qdd).unwrap();
    assert!(qdd.iter().all(|x| x.abs() < 1e-6), "gravity compensation holds the chain still");
    // a dense 10⁵ × 10⁵ mass matrix (80 GB) is refused, not attempted
    assert!(matches!(crba(&model, &mut ws, &q), Err(CrbaError::TooLarge(_))));
}

/// `rpy` is `Rz(y) Ry(p) Rx(r)`; the joint origin places the joint frame in the parent; the inertial
/// origin places the centre of mass and the tensor's axes in the link frame.
#[test]
fn frames_follow_the_urdf_conventions() {
    let text = robot(&[
        "<link name=\"base\"/>".into(),
        r#"<link name="arm"><inertial><origin xyz="0.5 0 0" rpy="0 0 1.5707963267948966"/><mass value="2"/><inertia ixx="0.1" iyy="0.2" izz="0.25"/></inertial></link>"#.into(),
        r#"<joint name="shoulder" type="continuous"><parent link="base"/><child link="arm"/><origin xyz="0 0 1" rpy="0.3 0.2 0.1"/><axis xyz="0 0 1"/></joint>"#.into(),
    ]);
    let model = parse(&text).unwrap();
    let b = &model.bodies[0];
    let r_expected = DMat3::from_rotation_z(0.1) * DMat3::from_rotation_y(0.2) * DMat3::from_rotation_x(0.3);
    assert_close(
        "rotation of the joint origin",
        &b.joint.x_tree.rotation_a_from_b().to_cols_array(),
        &r_expected.to_cols_array(),
        1e-15,
    );
    assert_close("joint origin", &b.joint.x_tree.r.to_array(), &[0.0, 0.0, 1.0], 0.0);
    // centre of mass at (0.5, 0, 0); tensor axes turned 90° about z: ixx and iyy swap
    assert_close("first moment", &b.inertia.h.to_array(), &[1.0, 0.0, 0.0], 1e-15);
    // Ī_o = R I Rᵀ + m (|c|² 1 − c cᵀ) = diag(0.2, 0.1, 0.25) + 2 diag(0, 0.25, 0.25)
    let i_o = b.inertia.i_o;
    assert_close("rotational inertia", &[i_o.x_axis.x, i_o.y_axis.y, i_o.z_axis.z], &[0.2, 0.6, 0.75], 1e-15);
}

/// Fixed joints merge the child's inertia into the parent body, and the merged model has the same
/// dynamics as the equivalent single link.
#[test]
fn fixed_joints_merge_inertia_and_keep_frames() {
    let merged = robot(&[
        "<link name=\"base\"/>".into(),
        r#"<link name="arm"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1"/></inertial></link>"#.into(),
        r#"<link name="tip"><inertial><origin xyz="0 0 0.2"/><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1"/></inertial></link>"#.into(),
        r#"<joint name="j" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="1 0 0"/></joint>"#.into(),
        r#"<joint name="weld" type="fixed"><parent link="arm"/><child link="tip"/><origin xyz="0 0 0.3"/></joint>"#.into(),
    ]);
    let single = robot(&[
        "<link name=\"base\"/>".into(),
        // two unit masses at z = 0 and z = 0.5: m = 2, c = 0.25, I_c = 0.2 + 2 · 0.25² about x and y
        r#"<link name="arm"><inertial><origin xyz="0 0 0.25"/><mass value="2"/><inertia ixx="0.325" iyy="0.325" izz="0.2"/></inertial></link>"#.into(),
        r#"<joint name="j" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="1 0 0"/></joint>"#.into(),
    ]);
    let a = parse(&merged).unwrap();
    let b = parse(&single).unwrap();
    assert_eq!(a.nv(), 1);
    let tip = a.frame_index("tip").unwrap();
    assert_eq!(a.frames[tip].body, Some(0));
    for q in [0.0, 0.7, -2.0] {
        let (mut wa, mut wb) = (Workspace::new(&a), Workspace::new(&b));
        let ma = crba(&a, &mut wa, &[q]).unwrap()[(0, 0)];
        let mb = crba(&b, &mut wb, &[q]).unwrap()[(0, 0)];
        assert!((ma - mb).abs() < 1e-14, "{ma} vs {mb}");
        let (mut ta, mut tb) = ([0.0], [0.0]);
        rnea(&a, &mut wa, &[q], &[1.3], &[0.4], &mut ta).unwrap();
        rnea(&b, &mut wb, &[q], &[1.3], &[0.4], &mut tb).unwrap();
        assert!((ta[0] - tb[0]).abs() < 1e-13, "{} vs {}", ta[0], tb[0]);
    }
}

/// Depth-first, children in file order by default, or sorted by joint name.
#[test]
fn joint_order_is_depth_first() {
    let text = robot(&[
        link("root"),
        link("l1"),
        link("l2"),
        link("l3"),
        joint("zeta", "continuous", "root", "l1"),
        joint("alpha", "continuous", "root", "l3"),
        joint("mid", "continuous", "l1", "l2"),
    ]);
    let names = |order| -> Vec<String> {
        let m = parse_urdf(&text, "r.urdf", UrdfOptions { floating: false, order, ..Default::default() }).unwrap();
        m.bodies.iter().map(|b| b.joint.name.clone()).collect()
    };
    assert_eq!(names(ChildOrder::File), ["zeta", "mid", "alpha"]);
    assert_eq!(names(ChildOrder::JointName), ["alpha", "zeta", "mid"]);
    let floating =
        parse_urdf(&text, "r.urdf", UrdfOptions { floating: true, order: ChildOrder::File, ..Default::default() })
            .unwrap();
    assert_eq!(floating.bodies[0].joint.name, "root_joint");
    assert_eq!((floating.nq(), floating.nv()), (10, 9));
}

/// Mesh URIs: `package://` under the nearest directory of that name holding the URDF, relative paths
/// under the URDF's directory, nothing that climbs out of them (U17), no other scheme.
#[test]
fn u15_u17_mesh_paths_are_resolved_without_leaving_their_roots() {
    let urdf = Path::new("/data/example-robot-data/robots/panda_description/urdf/panda.urdf");
    assert_eq!(
        resolve_mesh(urdf, "package://example-robot-data/robots/panda_description/meshes/link0.dae"),
        Ok(PathBuf::from("/data/example-robot-data/robots/panda_description/meshes/link0.dae"))
    );
    assert_eq!(
        resolve_mesh(urdf, "meshes/./hand.stl"),
        Ok(PathBuf::from("/data/example-robot-data/robots/panda_description/urdf/meshes/hand.stl"))
    );
    assert_eq!(resolve_mesh(urdf, "/abs/hand.stl"), Ok(PathBuf::from("/abs/hand.stl")));
    // an empty host, `package:///name/…` (Talos's URDFs write it so)
    assert_eq!(
        resolve_mesh(urdf, "package:///example-robot-data/robots/panda_description/meshes/hand.stl"),
        Ok(PathBuf::from("/data/example-robot-data/robots/panda_description/meshes/hand.stl"))
    );
    assert_eq!(resolve_mesh(urdf, "file:///abs/hand.stl"), Ok(PathBuf::from("/abs/hand.stl")));
    for bad in [
        "package://example-robot-data/../../etc/passwd",
        "../../../../etc/passwd",
        "package://nowhere/mesh.stl",
        "http://example.com/mesh.stl",
    ] {
        assert!(resolve_mesh(urdf, bad).is_err(), "{bad}");
    }
    // recorded on the model, with a warning for what is not resolved
    let text = robot(&[r#"<link name="a"><visual><geometry><mesh filename="meshes/a.stl"/></geometry></visual>
           <collision><geometry><mesh filename="package://nowhere/a.stl"/></geometry></collision></link>"#
        .into()]);
    let model = parse_urdf(&text, "/robots/r.urdf", UrdfOptions::default()).unwrap();
    let meshes = model.meshes();
    assert_eq!(meshes.len(), 2);
    assert_eq!(meshes[0].path.as_deref(), Some(Path::new("/robots/meshes/a.stl")));
    assert_eq!(meshes[1].path, None);
    assert!(
        model.warnings.iter().any(|w| w.contains("package://nowhere/a.stl") && w.contains("/robots/r.urdf:3")),
        "{:?}",
        model.warnings
    );
}

/// `<collision>` and `<visual>` geometry: every primitive with its size, meshes with scale and
/// resolved file, each at its `<origin>` in the link frame, and placed on the body it moves with
/// (through a fixed joint too); what cannot be used is left out with a warning naming the line.
#[test]
fn link_geometry_is_recorded_and_placed_on_its_body() {
    use tumble::multibody::{GeometryRole, GeometryShape};
    let arm = format!(
        r#"<link name="arm">{INERTIAL}
             <collision><origin xyz="0 0 -0.5"/><geometry><box size="0.1 0.2 1.0"/></geometry></collision>
             <collision><origin xyz="0 0 -1" rpy="1.5707963267948966 0 0"/><geometry><cylinder radius="0.05" length="0.3"/></geometry></collision>
             <visual><geometry><mesh filename="meshes/arm.stl" scale="0.001 -0.001 0.002"/></geometry></visual>
             <collision><geometry><sphere radius="-1"/></geometry></collision>
             <collision><geometry><capsule radius="0.1" length="1"/></geometry></collision>
           </link>"#
    );
    let tool = r#"<link name="tool"><collision><geometry><sphere radius="0.02"/></geometry></collision></link>"#;
    let text = robot(&[
        link("base"),
        arm,
        tool.into(),
        r#"<joint name="shoulder" type="continuous"><parent link="base"/><child link="arm"/><origin xyz="0 0 2"/><axis xyz="1 0 0"/></joint>"#.into(),
        r#"<joint name="mount" type="fixed"><parent link="arm"/><child link="tool"/><origin xyz="0 0.1 -1.2"/></joint>"#.into(),
    ]);
    let model = parse_urdf(&text, "/robots/r.urdf", UrdfOptions::default()).unwrap();
    let g = &model.geometries;
    assert_eq!(g.len(), 4, "{g:#?}");
    assert_eq!((g[0].link.as_str(), g[0].role), ("arm", GeometryRole::Collision));
    assert_eq!(g[0].shape, GeometryShape::Box { half_extents: DVec3::new(0.05, 0.1, 0.5) });
    assert_eq!(g[1].shape, GeometryShape::Cylinder { radius: 0.05, half_length: 0.15 });
    assert_eq!(g[2].role, GeometryRole::Visual);
    assert_eq!(
        g[2].shape,
        GeometryShape::Mesh {
            uri: "meshes/arm.stl".into(),
            path: Some(PathBuf::from("/robots/meshes/arm.stl")),
            scale: DVec3::new(0.001, -0.001, 0.002) // a mirror image
        }
    );
    assert_eq!((g[3].link.as_str(), &g[3].shape), ("tool", &GeometryShape::Sphere { radius: 0.02 }));
    // the negative radius and the unknown shape: warnings with their lines, nothing recorded
    for (what, line) in [("radius = \"-1\"", 7), ("unknown geometry <capsule>", 8)] {
        assert!(
            model.warnings.iter().any(|w| w.contains(what) && w.contains(&format!("/robots/r.urdf:{line}:"))),
            "{what}: {:?}",
            model.warnings
        );
    }
    // placements: the cylinder's centre 1 m down the arm, its axis turned from z to −y by the rpy;
    // the tool's sphere on the arm's body through the fixed joint
    let (body, x) = model.geometry_placement(&g[1]).unwrap();
    let arm_body = model.frames[model.frame_index("arm").unwrap()].body;
    assert_eq!(body, arm_body);
    assert!((x.inv_apply_point(DVec3::ZERO) - DVec3::new(0.0, 0.0, -1.0)).length() < 1e-15);
    let axis_in_body = x.rotation_a_from_b() * DVec3::Z;
    assert!((axis_in_body - DVec3::new(0.0, -1.0, 0.0)).length() < 1e-15, "{axis_in_body}");
    let (body, x) = model.geometry_placement(&g[3]).unwrap();
    assert_eq!(body, arm_body);
    assert!((x.inv_apply_point(DVec3::ZERO) - DVec3::new(0.0, 0.1, -1.2)).length() < 1e-15);
}

/// A unit cube as an ASCII STL: corners (0, 0, 0) … (1, 1, 1), twelve outward triangles.
fn cube_stl() -> String {
    let v = |i: u32| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64];
    // two triangles per face, corners by index bits (x = 1, y = 2, z = 4), counter-clockwise outside
    let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let mut s = String::from("solid cube\n");
    for [a, b, c, d] in faces {
        for tri in [[a, b, c], [a, c, d]] {
            s.push_str("facet normal 0 0 0\nouter loop\n");
            for i in tri {
                let p = v(i);
                s.push_str(&format!("vertex {} {} {}\n", p[0], p[1], p[2]));
            }
            s.push_str("endloop\nendfacet\n");
        }
    }
    s.push_str("endsolid cube\n");
    s
}

/// Link collision geometry as shapes on the bodies: primitives one to one, meshes read (scaled,
/// mirrored) as convex hulls centred on their centre of mass; a missing file, a COLLADA mesh and an
/// unresolved URI are errors naming the URDF line, the link and the path tried.
#[test]
fn link_collision_geometry_becomes_shapes_on_the_bodies() {
    use tumble::body::Shape;
    use tumble::multibody::link_shapes::collision_shapes;
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("meshes")).unwrap();
    std::fs::write(dir.path().join("meshes/cube.stl"), cube_stl()).unwrap();
    let urdf = dir.path().join("r.urdf");
    let with = |collision: &str| {
        robot(&[
            link("base"),
            format!(r#"<link name="arm">{INERTIAL}{collision}</link>"#),
            r#"<joint name="shoulder" type="continuous"><parent link="base"/><child link="arm"/><origin xyz="0 0 2"/><axis xyz="1 0 0"/></joint>"#.into(),
        ])
    };
    let shapes_of = |text: &str| {
        let model = parse_urdf(text, urdf.to_str().unwrap(), UrdfOptions::default()).unwrap();
        collision_shapes(&model, urdf.to_str().unwrap())
    };
    let text = with(
        r#"<collision><origin xyz="0 0 -0.5"/><geometry><box size="0.1 0.2 1.0"/></geometry></collision>
           <collision><origin xyz="0 0 -1"/><geometry><mesh filename="meshes/cube.stl" scale="0.1 0.1 0.1"/></geometry></collision>
           <collision><origin xyz="0 0 -1"/><geometry><mesh filename="meshes/cube.stl" scale="-0.1 0.1 0.1"/></geometry></collision>
           <visual><geometry><mesh filename="meshes/arm.dae"/></geometry></visual>"#,
    );
    let shapes = shapes_of(&text).unwrap();
    assert_eq!(shapes.len(), 3, "visual geometry is not a collision shape");
    assert!(shapes.iter().all(|s| s.link == "arm" && s.body == Some(0)));
    assert_eq!(shapes[0].shape, Shape::Box { half_extents: DVec3::new(0.05, 0.1, 0.5) });
    assert_eq!(shapes[0].position_body, DVec3::new(0.0, 0.0, -0.5));
    // the 0.1 m cube's hull, centred on its centre of mass, which lies 0.05 m along each scaled axis
    for (shape, com) in [(&shapes[1], DVec3::new(0.05, 0.05, -0.95)), (&shapes[2], DVec3::new(-0.05, 0.05, -0.95))] {
        let Shape::Convex(hull) = &shape.shape else { panic!("{:?}", shape.shape) };
        assert!((hull.volume - 1e-3).abs() < 1e-15, "volume {}", hull.volume);
        assert!((shape.position_body - com).length() < 1e-15, "{:?}", shape.position_body);
        let extent = hull.hull.vertices().iter().fold(DVec3::ZERO, |m, v| m.max(v.abs()));
        assert!((extent - DVec3::splat(0.05)).length() < 1e-15);
    }
    // errors: the line of the <collision> element (line 3 of the file, the arm's link), the path tried
    let missing = with(r#"<collision><geometry><mesh filename="meshes/gone.stl"/></geometry></collision>"#);
    let e = shapes_of(&missing).unwrap_err().to_string();
    assert!(
        e.contains("r.urdf:3: link 'arm': <collision>: mesh 'meshes/gone.stl'") && e.contains("meshes/gone.stl)"),
        "{e}"
    );
    let dae = with(r#"<collision><geometry><mesh filename="meshes/arm.dae"/></geometry></collision>"#);
    let e = shapes_of(&dae).unwrap_err().to_string();
    assert!(e.contains("mesh 'meshes/arm.dae'") && e.contains(".dae"), "{e}");
    let unresolved = with(r#"<collision><geometry><mesh filename="package://nowhere/a.stl"/></geometry></collision>"#);
    let e = shapes_of(&unresolved).unwrap_err().to_string();
    assert!(e.contains("mesh 'package://nowhere/a.stl' could not be resolved"), "{e}");
}
