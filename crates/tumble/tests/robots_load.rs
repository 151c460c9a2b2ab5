//! Real robots load: the four robots of example-robot-data 6.0.0 that tumble refused by default
//! (committed unchanged under `tests/fixtures/robots/`). Without the flag, the error names the link
//! (or joint) and its line; with `balance_inertia` the repaired inertia is physical and the nearest
//! physical tensor, and the warning names the link; with `Massless::Fuse` a massless finger is held;
//! the dynamics are finite. In scenes, a positive-definite tensor that only violates the triangle
//! inequality is a warning (PR2, and a camera-like link written here), one that is not positive
//! definite an error whose hint names `balance_inertia` and `lock` (TIAGo, an antenna-like link).

use std::path::{Path, PathBuf};
use tumble::body::mass::symmetric_eigen;
use tumble::math::{DMat3, DQuat, DVec3};
use tumble::multibody::balance::{inertia_defect, nearest_physical};
use tumble::multibody::{
    aba, bias_forces, crba, load_urdf, Massless, MultibodyModel, UrdfErrorKind, UrdfOptions, Workspace,
};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/robots").join(name)
}

/// The robots, the link or joint each one is refused for, and the element that carries the defect.
const REFUSED: [(&str, &str, &str); 4] = [
    ("anymal_c.urdf", "depth_camera_front_camera", "<inertia "),
    ("pr2.urdf", "sensor_mount_link", "<inertia "),
    ("tiago_dual.urdf", "base_antenna_left_link", "<inertia "),
    ("romeo.urdf", "LHand", "<joint"),
];

/// 1-based line of the first `element` at or after the element named `name`.
fn line_of(text: &str, name: &str, element: &str) -> u32 {
    let start = text.find(&format!("name=\"{name}\"")).expect("the name is in the file");
    let start = if element == "<joint" { text[..start].rfind("<joint").unwrap() } else { start };
    let at = start + text[start..].find(element).expect("the element follows");
    1 + text[..at].matches('\n').count() as u32
}

/// `(mass, tensor)` of the `<inertial>` of link `name`, read from the text.
fn raw_inertial(text: &str, name: &str) -> (f64, DMat3) {
    let start = text.find(&format!("<link name=\"{name}\"")).unwrap();
    let end = start + text[start..].find("</link>").unwrap();
    let link = &text[start..end];
    let attr = |tag: &str, key: &str| -> f64 {
        let t = &link[link.find(tag).unwrap()..];
        let t = &t[t.find(&format!("{key}=\"")).unwrap() + key.len() + 2..];
        t[..t.find('"').unwrap()].trim().parse().unwrap()
    };
    let i = |k| attr("<inertia ", k);
    let tensor = DMat3::from_cols(
        DVec3::new(i("ixx"), i("ixy"), i("ixz")),
        DVec3::new(i("ixy"), i("iyy"), i("iyz")),
        DVec3::new(i("ixz"), i("iyz"), i("izz")),
    );
    (attr("<mass ", "value"), tensor)
}

fn frobenius(a: DMat3) -> f64 {
    a.to_cols_array().iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn inner(a: DMat3, b: DMat3) -> f64 {
    a.to_cols_array().iter().zip(b.to_cols_array()).map(|(x, y)| x * y).sum()
}

fn sorted(mut m: [f64; 3]) -> [f64; 3] {
    m.sort_by(f64::total_cmp);
    m
}

/// Seeded random physical tensors (random axes, moments satisfying the triangle inequality), scaled
/// like `scale`.
fn random_physical(seed: u64, scale: f64) -> Vec<DMat3> {
    let mut state = seed;
    let mut uniform = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..500)
        .map(|_| {
            let (a, b) = (uniform() * scale, uniform() * scale);
            let c = (a - b).abs() + uniform() * (a + b - (a - b).abs());
            let q = DQuat::from_xyzw(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5, uniform() - 0.5).normalize();
            let r = DMat3::from_quat(q);
            r * DMat3::from_diagonal(DVec3::new(a, b, c)) * r.transpose()
        })
        .collect()
}

/// The dynamics at the neutral configuration and at a few others: finite, `M` symmetric, and ABA
/// inverts `M q̈ + b = τ`.
fn check_dynamics(name: &str, model: &MultibodyModel) {
    let mut ws = Workspace::new(model);
    let nv = model.nv();
    for k in 0..3 {
        let mut q = model.neutral_configuration();
        for body in model.bodies.iter().filter(|b| b.joint.kind.nq() == 1) {
            let i = body.joint.q_index;
            q[i] += 0.1 * ((i + k) as f64).sin();
        }
        let v: Vec<f64> = (0..nv).map(|i| 0.2 * ((i * 3 + k) as f64).cos()).collect();
        let tau: Vec<f64> = (0..nv).map(|i| ((i + 2 * k) as f64).sin()).collect();
        let m = crba(model, &mut ws, &q).unwrap().clone();
        let mut b = vec![0.0; nv];
        bias_forces(model, &mut ws, &q, &v, &mut b).unwrap();
        let mut qdd = vec![0.0; nv];
        aba(model, &mut ws, &q, &v, &tau, &mut qdd).unwrap();
        assert!(m.iter().chain(&b).chain(&qdd).all(|x| x.is_finite()), "{name}: not finite");
        let scale = m.iter().fold(1.0_f64, |a, x| a.max(x.abs()));
        for r in 0..nv {
            let mut residual = b[r] - tau[r];
            for c in 0..nv {
                assert!((m[(r, c)] - m[(c, r)]).abs() <= 1e-12 * scale, "{name}: M not symmetric");
                residual += m[(r, c)] * qdd[c];
            }
            let size = tau[r].abs().max(b[r].abs()).max(1.0);
            assert!(residual.abs() <= 1e-6 * size, "{name}: M qdd + b − τ = {residual} at row {r}");
        }
    }
}

#[test]
fn without_the_flags_the_error_names_the_link_and_its_line() {
    for (file, name, element) in REFUSED {
        let text = std::fs::read_to_string(fixture(file)).unwrap();
        let e = load_urdf(&fixture(file), UrdfOptions::default()).expect_err(file);
        let message = e.to_string();
        assert!(message.contains(&format!("'{name}'")), "{file}: {message}");
        assert_eq!(e.line, line_of(&text, name, element), "{file}: {message}");
        let flag = if element == "<joint" { "--massless fuse" } else { "--balance-inertia" };
        assert!(message.contains(flag), "{file}: the error does not name {flag}: {message}");
        if element == "<inertia " {
            assert!(matches!(*e.kind, UrdfErrorKind::BadInertia { .. }), "{file}: {message}");
        }
    }
}

#[test]
fn with_balance_inertia_each_repaired_inertia_is_physical_and_nearest() {
    for (file, name, _) in REFUSED.iter().filter(|r| r.2 == "<inertia ") {
        let text = std::fs::read_to_string(fixture(file)).unwrap();
        let options = UrdfOptions { balance_inertia: true, ..Default::default() };
        let model = load_urdf(&fixture(file), options).unwrap_or_else(|e| panic!("{file}: {e}"));
        let warning = model
            .warnings
            .iter()
            .find(|w| w.contains(&format!("link '{name}': inertia balanced")))
            .unwrap_or_else(|| panic!("{file}: no warning names {name}: {:?}", model.warnings));
        assert!(warning.contains(&format!(":{}:", line_of(&text, name, "<inertia "))), "{warning}");

        // the documented repair of the tensor as written
        let (mass, tensor) = raw_inertial(&text, name);
        assert!(inertia_defect(mass, tensor).is_some(), "{file}: {name} was physical");
        let balanced = nearest_physical(mass, tensor);
        assert_eq!(inertia_defect(mass, balanced.tensor), None, "{file}: {name} still not physical");
        let (after, _) = symmetric_eigen(balanced.tensor);
        assert!(after.min_element() >= 0.0 || after.min_element() > -1e-15 * after.max_element());
        // nearest: the projection onto a convex cone leaves a residual orthogonal to the result and
        // at an obtuse angle with every member, so no physical tensor is nearer
        let residual = tensor - balanced.tensor;
        let scale = frobenius(tensor);
        assert!(inner(residual, balanced.tensor).abs() <= 1e-12 * scale * scale, "{file}: not orthogonal");
        for p in random_physical(7, scale) {
            assert!(inner(residual, p) <= 1e-12 * scale * frobenius(p), "{file}: a physical tensor is nearer");
            assert!(frobenius(tensor - p) >= frobenius(residual) * (1.0 - 1e-12), "{file}: a nearer tensor");
        }
        // the model carries it: the link's own inertia about its centre of mass has those moments
        let frame = &model.frames[model.frame_index(name).unwrap()].inertia;
        let c = frame.com();
        let i_c = frame.i_o - (DMat3::from_diagonal(DVec3::splat(c.length_squared())) - outer(c, c)) * frame.mass;
        let (moments, _) = symmetric_eigen(i_c);
        let (want, got) = (sorted(balanced.after), sorted(moments.to_array()));
        for k in 0..3 {
            assert!((want[k] - got[k]).abs() <= 1e-9 * want[2], "{file}: moments {got:?} against {want:?}");
        }
        check_dynamics(file, &model);
    }
}

fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

#[test]
fn a_massless_finger_is_fused_only_when_asked() {
    let options = UrdfOptions { massless: Massless::Fuse, floating: true, ..Default::default() };
    let model = load_urdf(&fixture("romeo.urdf"), options).unwrap();
    assert!(model.warnings.iter().any(|w| w.contains("joint 'LHand'") && w.contains("fused")), "{:?}", model.warnings);
    assert!(model.joint_index("LHand").is_none() && model.joint_index("RHand").is_none());
    // every joint that moves mass is still there
    assert!(model.joint_index("LWristPitch").is_some() || model.nv() > 30, "nv = {}", model.nv());
    check_dynamics("romeo", &model);
}

/// A triangle-inequality violation well inside the tolerance of round-off is accepted unchanged; the
/// thin-rod limit (one moment zero) and the point mass are physical.
#[test]
fn round_off_and_limits_are_physical() {
    assert_eq!(inertia_defect(1.0, DMat3::from_diagonal(DVec3::new(1.0, 1.0, 2.0 + 1e-12))), None);
    assert_eq!(inertia_defect(1.0, DMat3::from_diagonal(DVec3::new(1.0, 1.0, 0.0))), None);
    assert_eq!(inertia_defect(1.0, DMat3::ZERO), None);
    assert!(inertia_defect(1.0, DMat3::from_diagonal(DVec3::new(1.0, 1.0, 2.0 + 1e-6))).is_some());
    assert!(inertia_defect(0.0, DMat3::from_diagonal(DVec3::new(1.0, 1.0, 1.0))).is_some());
    assert_eq!(nearest_physical(0.0, DMat3::IDENTITY).tensor, DMat3::ZERO);
    // the usual case: the two smaller moments rise and the largest falls by a third of the shortfall
    let b = nearest_physical(1.0, DMat3::from_diagonal(DVec3::new(1.0, 1.0, 5.0)));
    let want = [1.0 + 1.0, 1.0 + 1.0, 5.0 - 1.0];
    for (got, want) in sorted(b.after).iter().zip(want) {
        assert!((got - want).abs() < 1e-12, "{:?}", b.after);
    }
}

/// A scene of one robot whose URDF is `urdf` (a path), without collision geometry, with `key`.
fn robot_scene(urdf: &Path, key: &str) -> String {
    // (the fixture directory holds the URDFs without their meshes: no collision geometry)
    format!(
        "version = 1\n\n[world]\ndt = 0.001\n\n[[robot]]\nname = \"robot\"\nurdf = {:?}\ncollision = false\n{key}\n",
        urdf.to_str().unwrap()
    )
}

/// In a scene, PR2's sensor mount (principal moments that violate the triangle inequality, the
/// tensor positive definite) loads with a warning naming the link, its URDF line and the defect; with
/// `balance_inertia = true` the warning says it was balanced.
#[test]
fn in_a_scene_a_triangle_inequality_violation_is_a_warning() {
    use tumble::scene::{self, Format};
    let urdf = fixture("pr2.urdf");
    let text = std::fs::read_to_string(&urdf).unwrap();
    let line = line_of(&text, "sensor_mount_link", "<inertia ");
    let origin = fixture("scene.toml");
    let origin = origin.to_str().unwrap();
    let loaded = scene::from_str(&robot_scene(&urdf, ""), origin, Format::Toml).unwrap_or_else(|e| panic!("{e}"));
    let warning = loaded
        .warnings
        .iter()
        .find(|w| w.contains("link 'sensor_mount_link': inertia kept as written"))
        .unwrap_or_else(|| panic!("{:?}", loaded.warnings));
    assert!(warning.contains(&format!("pr2.urdf:{line}:")), "{warning}");
    assert!(warning.contains("triangle inequality") && warning.contains("balance_inertia = true"), "{warning}");
    // the link's inertia is the file's: its moments still violate the inequality
    let robot = &loaded.world.robots[0];
    assert!(robot.model.nv() > 0);
    let loaded = scene::from_str(&robot_scene(&urdf, "balance_inertia = true"), origin, Format::Toml).unwrap();
    assert!(
        loaded.warnings.iter().any(|w| w.contains("link 'sensor_mount_link': inertia balanced")),
        "{:?}",
        loaded.warnings
    );
    assert!(!loaded.warnings.iter().any(|w| w.contains("inertia kept as written")), "{:?}", loaded.warnings);
}

/// TIAGo's antenna (a slightly negative principal moment: not positive definite) stays an error in
/// a scene, naming the link, its URDF line, and in its hint `balance_inertia = true` and `lock`; with
/// `balance_inertia = true` it loads.
#[test]
fn in_a_scene_an_inertia_that_is_not_positive_definite_is_an_error_naming_balance_inertia_and_lock() {
    use tumble::scene::{self, Format};
    let urdf = fixture("tiago_dual.urdf");
    let text = std::fs::read_to_string(&urdf).unwrap();
    let line = line_of(&text, "base_antenna_left_link", "<inertia ");
    let origin = fixture("scene.toml");
    let origin = origin.to_str().unwrap();
    let e = scene::from_str(&robot_scene(&urdf, ""), origin, Format::Toml).map(|_| ()).unwrap_err();
    let message = e.to_string();
    assert!(message.contains("'base_antenna_left_link'"), "{message}");
    assert!(message.contains(&format!("tiago_dual.urdf:{line}:")), "{message}");
    assert!(message.contains("not positive semi-definite"), "{message}");
    let hint = message.split("\nhint: ").nth(1).unwrap_or_else(|| panic!("no hint: {message}"));
    assert!(hint.contains("`balance_inertia = true`") && hint.contains("`lock = ["), "{hint}");
    let loaded = scene::from_str(&robot_scene(&urdf, "balance_inertia = true"), origin, Format::Toml);
    assert!(loaded.is_ok(), "{}", loaded.map(|_| ()).unwrap_err());
}

/// Small URDFs written here: a camera-like link (moments 1e-5, 1e-5, 3e-5 kg·m²: the triangle
/// inequality violated, positive definite) loads in a scene with a warning and keeps its tensor (the
/// mass matrix stays positive definite and the robot falls as ABA says); an antenna-like link with
/// a slightly negative moment, and a rod-like tensor that violates the inequality with a zero moment
/// (positive semi-definite only), are errors. Outside scenes (`UrdfOptions::default()`, as
/// `tumble model`), the camera stays an error.
#[test]
fn small_urdfs_camera_antenna_and_singular_rod() {
    use tumble::scene::{self, Format};
    let urdf = |ixx: f64, iyy: f64, izz: f64| {
        format!(
            "<robot name=\"r\">\n  <link name=\"base\"/>\n  <link name=\"arm\"><inertial><origin xyz=\"0.3 0 0\"/><mass value=\"1\"/>\
             <inertia ixx=\"0.01\" iyy=\"0.02\" izz=\"0.02\"/></inertial></link>\n  <link name=\"sensor\"><inertial>\
             <mass value=\"0.1\"/><inertia ixx=\"{ixx:e}\" iyy=\"{iyy:e}\" izz=\"{izz:e}\"/></inertial></link>\n  \
             <joint name=\"hinge\" type=\"continuous\"><parent link=\"base\"/><child link=\"arm\"/><axis xyz=\"0 1 0\"/></joint>\n  \
             <joint name=\"mount\" type=\"continuous\"><parent link=\"arm\"/><child link=\"sensor\"/><origin xyz=\"0.6 0 0\"/>\
             <axis xyz=\"1 0 0\"/></joint>\n</robot>\n"
        )
    };
    let dir = tempfile::tempdir().unwrap();
    let origin = dir.path().join("scene.toml");
    let origin = origin.to_str().unwrap();
    let write = |name: &str, text: String| {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let camera = write("camera.urdf", urdf(1e-5, 1e-5, 3e-5));
    let loaded = scene::from_str(&robot_scene(&camera, ""), origin, Format::Toml).unwrap_or_else(|e| panic!("{e}"));
    let warning = loaded.warnings.iter().find(|w| w.contains("link 'sensor': inertia kept as written"));
    let warning = warning.unwrap_or_else(|| panic!("{:?}", loaded.warnings));
    assert!(warning.contains("camera.urdf:4:") && warning.contains("short by 33.333%"), "{warning}");
    // the tensor is the file's: the mount joint's diagonal of M is the sensor's ixx exactly
    let robot = &loaded.world.robots[0];
    let model = &robot.model;
    let mut ws = Workspace::new(model);
    let q = vec![0.0; model.nq()];
    let m = crba(model, &mut ws, &q).unwrap().clone();
    let mount = model.bodies[model.joint_index("mount").unwrap()].joint.v_index;
    assert!((m[(mount, mount)] - 1e-5).abs() <= 1e-18, "M[mount, mount] = {}", m[(mount, mount)]);
    // positive definite: ABA is defined and agrees with M⁻¹ (τ − b)
    let (v, tau) = (vec![0.3, -0.7], vec![0.0, 0.0]);
    let mut b = vec![0.0; 2];
    bias_forces(model, &mut ws, &q, &v, &mut b).unwrap();
    let mut qdd = vec![0.0; 2];
    aba(model, &mut ws, &q, &v, &tau, &mut qdd).unwrap();
    for r in 0..2 {
        let residual = m[(r, 0)] * qdd[0] + m[(r, 1)] * qdd[1] + b[r] - tau[r];
        assert!(residual.abs() <= 1e-12 * (1.0 + b[r].abs()), "row {r}: M qdd + b − τ = {residual}");
    }
    // outside scenes the default is still an error
    let e = load_urdf(&camera, UrdfOptions::default()).expect_err("camera");
    assert!(matches!(*e.kind, UrdfErrorKind::BadInertia { .. }), "{e}");
    for (name, (ixx, iyy, izz), defect) in [
        ("antenna.urdf", (-1e-9, 1e-5, 1e-5), "not positive semi-definite"),
        ("rod.urdf", (0.0, 1e-5, 3e-5), "triangle"),
    ] {
        let path = write(name, urdf(ixx, iyy, izz));
        let e = scene::from_str(&robot_scene(&path, ""), origin, Format::Toml).map(|_| ()).unwrap_err();
        let message = e.to_string();
        assert!(message.contains(&format!("{name}:4:")) && message.contains("'sensor'"), "{message}");
        assert!(message.contains(defect), "{message}");
        assert!(message.contains("hint: `balance_inertia = true`") && message.contains("`lock = ["), "{message}");
    }
}

/// Every URDF of example-robot-data 6.0.0, where the package is installed (the environment variable
/// `EXAMPLE_ROBOT_DATA_ROBOTS` names its `robots/` directory; otherwise the test says so and checks
/// only the fixture): each loads with the flags the fixture lists and not without them, and its `nv`
/// (plus the joints fused) and total mass are Pinocchio's. The fixture is written by
/// `tools/erd_load_all.py --fixture`.
#[test]
fn every_example_robot_data_urdf_loads_with_the_listed_flags() {
    let text = std::fs::read_to_string(fixture("example_robot_data.json")).unwrap();
    let listed: serde_json::Value = serde_json::from_str(&text).unwrap();
    let rows = listed["robots"].as_array().unwrap();
    assert_eq!(rows.len(), 69, "the package's URDFs");
    let Some(root) = std::env::var_os("EXAMPLE_ROBOT_DATA_ROBOTS").map(PathBuf::from) else {
        eprintln!("EXAMPLE_ROBOT_DATA_ROBOTS is not set: the {} URDFs are not loaded", rows.len());
        return;
    };
    for row in rows {
        let urdf = root.join(row["urdf"].as_str().unwrap());
        let options = UrdfOptions {
            balance_inertia: row["balance_inertia"].as_bool().unwrap(),
            massless: if row["massless_fuse"].as_bool().unwrap() { Massless::Fuse } else { Massless::Error },
            ..Default::default()
        };
        let model = load_urdf(&urdf, options).unwrap_or_else(|e| panic!("{e}"));
        if options != UrdfOptions::default() {
            assert!(load_urdf(&urdf, UrdfOptions::default()).is_err(), "{}: loads without flags", urdf.display());
        }
        let fused = model.warnings.iter().filter(|w| w.contains("fused (held at q = 0)")).count();
        if let (Some(nv), Some(mass)) = (row["pinocchio_nv"].as_u64(), row["pinocchio_mass"].as_f64()) {
            assert_eq!(model.nv() + fused, nv as usize, "{}", urdf.display());
            assert!(
                (model.total_mass - mass).abs() <= 1e-9 * mass.max(1.0),
                "{}: {}",
                urdf.display(),
                model.total_mass
            );
        }
        check_dynamics(row["urdf"].as_str().unwrap(), &model);
    }
    eprintln!("{} URDFs of {} loaded", rows.len(), root.display());
}

/// Every URDF the tests and scenes load (ten robots of example-robot-data and the scenes' own):
/// the names outside the URDF vocabulary inside links and joints are the vendors' extensions
/// listed here, one warning each, and the only links whose radius of gyration is beyond 10 times
/// their primitive collision geometry are TIAGo's 34 hand links, whose inertias the file itself says
/// are inflated ("To stabilize simulation": 0.001 kg·m² on 0.01–0.05 kg, around 1–2 mm spheres and
/// boxes).
#[test]
fn real_robots_warn_only_about_vendor_extensions_and_tiagos_inflated_hand_inertias() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in [root.join("tests/fixtures/robots"), root.join("../../scenes/robots")] {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "urdf") {
                files.push(path);
            }
        }
    }
    files.sort();
    assert!(files.len() >= 15, "{files:?}");
    let franka = "joint 'panda_joint1': unknown attributes 'D', 'K', 'mu_coulomb', 'mu_viscous' on <dynamics>, ignored";
    // the vendors' files as published (tests/fixtures/robots); the scenes' own URDFs (scenes/robots)
    // carry no extension: a shipped scene loads without a warning (scene_files.rs)
    let extensions: [(&str, &[&str]); 5] = [
        ("anymal_c.urdf", &["link 'base': ignored <self_filter> in <link>: not a URDF element there"]),
        ("panda.urdf", &[franka]),
        (
            "pr2.urdf",
            &[
                "link 'base_laser_link': unknown attribute 'type' on <link>, ignored",
                "link 'r_gripper_palm_link': ignored <verbose> in <collision>: not a URDF element there",
            ],
        ),
        ("solo12.urdf", &["link 'base_link': ignored <contact> in <link>: not a URDF element there"]),
        (
            "tiago_dual.urdf",
            &[
                "link 'base_link': ignored <material> in <collision>: not a URDF element there",
                "link 'suspension_right_link': ignored <kinematic>, <gravity> in <link>: not URDF elements there",
            ],
        ),
    ];
    let options = UrdfOptions { balance_inertia: true, massless: Massless::Allow, ..UrdfOptions::default() };
    let mut gyration_links = Vec::new();
    for path in &files {
        let name = path.file_name().unwrap().to_str().unwrap();
        let model = load_urdf(path, options).unwrap_or_else(|e| panic!("{name}: {e}"));
        let vocabulary: Vec<&str> = model
            .warnings
            .iter()
            .filter(|w| w.contains("unknown attribute") || w.contains("URDF element"))
            .map(|w| w.split_once(": ").unwrap().1)
            .collect();
        let vendor = path.starts_with(root.join("tests/fixtures/robots"));
        let expected = extensions.iter().find(|(f, _)| vendor && *f == name).map_or(&[][..], |(_, w)| *w);
        assert_eq!(vocabulary, expected, "{name}");
        for w in model.warnings.iter().filter(|w| w.contains("radius of gyration")) {
            let link = w.split("link '").nth(1).unwrap().split('\'').next().unwrap();
            let number =
                |after: &str| -> f64 { w.split(after).nth(1).unwrap().split(' ').next().unwrap().parse().unwrap() };
            let ratio = number("radius of gyration ") / number("half-diagonal ");
            eprintln!("{name}: link '{link}': radius of gyration / half-diagonal = {ratio:.1}");
            assert!(ratio > 30.0, "{w}");
            gyration_links.push(format!("{name}/{link}"));
        }
    }
    assert_eq!(gyration_links.len(), 34, "{gyration_links:#?}");
    assert!(gyration_links.iter().all(|l| l.starts_with("tiago_dual.urdf/hand_")), "{gyration_links:#?}");
}
