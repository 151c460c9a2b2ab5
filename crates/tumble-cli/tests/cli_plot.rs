//! `tumble plot` and `tumble run --plot`: the panels and their labels, SVG and PNG, the bad inputs
//! (exit 2, naming what is wrong, nothing written), a trajectory cut short (plotted as it is).

mod common;

use assert_cmd::prelude::*;
use common::tumble;
use predicates::prelude::PredicateBooleanExt;
use predicates::str::contains;
use std::fs;
use std::path::{Path, PathBuf};

fn demo_scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/demo.toml")
}

/// The demo, 3 s of it, written to `dir/demo.csv`.
fn demo_trajectory(dir: &Path) -> PathBuf {
    tumble(dir).args(["run", "--duration", "3", "--out", "demo.csv", "--quiet"]).assert().success();
    dir.join("demo.csv")
}

#[test]
fn an_svg_has_every_panel_with_units_and_a_legend() {
    let dir = tempfile::tempdir().unwrap();
    let csv = demo_trajectory(dir.path());
    tumble(dir.path())
        .args(["plot", csv.to_str().unwrap(), "--scene", demo_scene().to_str().unwrap(), "--out", "p.svg"])
        .assert()
        .success();
    let svg = fs::read_to_string(dir.path().join("p.svg")).unwrap();
    for text in [
        // E₀ of the demo: the spinning pair's ½ (1·0.01² + 2·5² + 2.6·0.01²) + ½ (1·0.01² + 2·0.01² +
        // 2.6·5²) = 57.50033 J (they float: no potential energy), plus the thrown bodies' kinetic
        // energy and their potential energy m g z above z = 0
        "relative energy error (E − E₀)/|E₀|, moving bodies, E₀ = 2108.338 J",
        "angular-momentum error |L − L₀|/|L₀| about the origin",
        "flipper: angular velocity in body axes",
        "stable: position of the centre of mass, world frame",
        "time (s)",
        "ω_body (rad/s)",
        "position (m)",
        "ω_x",
        "ω_z",
    ] {
        assert!(svg.contains(text), "missing `{text}`");
    }
    // the two error panels, then ω_body and position of the first 4 bodies (the default)
    assert_eq!(svg.matches("time (s)").count(), 10, "ten stacked panels");
}

#[test]
fn a_png_is_drawn_with_the_carried_font() {
    let dir = tempfile::tempdir().unwrap();
    let csv = demo_trajectory(dir.path());
    tumble(dir.path())
        .args(["plot", csv.to_str().unwrap(), "--scene", demo_scene().to_str().unwrap(), "--out", "p.png"])
        .args(["--bodies", "flipper"])
        .assert()
        .success();
    let image = image::open(dir.path().join("p.png")).unwrap().to_rgb8();
    // energy, angular momentum, ω and position of one body: 4 panels of 230 px and a 40 px title
    assert_eq!(image.dimensions(), (1200, 4 * 230 + 40));
    let count = |f: &dyn Fn(&image::Rgb<u8>) -> bool| image.pixels().filter(|p| f(p)).count();
    let red = count(&|p| p.0 == [214, 39, 40]);
    let dark_text = count(&|p| p.0[0] < 60 && p.0[1] < 60 && p.0[2] < 60);
    assert!(red > 500, "the energy and ω_x lines are drawn: {red} red pixels");
    assert!(dark_text > 2000, "text and axes are drawn: {dark_text} dark pixels");
}

#[test]
fn without_a_scene_only_the_kinematics_are_plotted() {
    let dir = tempfile::tempdir().unwrap();
    let csv = demo_trajectory(dir.path());
    tumble(dir.path()).args(["plot", csv.to_str().unwrap(), "--out", "p.svg"]).assert().success();
    let svg = fs::read_to_string(dir.path().join("p.svg")).unwrap();
    assert!(!svg.contains("energy error") && svg.contains("energy and angular momentum need --scene"));
    assert_eq!(svg.matches("time (s)").count(), 8, "ω_body and position of the first 4 bodies");
}

#[test]
fn a_trajectory_of_another_scene_names_the_bodies() {
    let dir = tempfile::tempdir().unwrap();
    let csv = demo_trajectory(dir.path());
    let text = fs::read_to_string(&csv).unwrap().replace(",stable,", ",wobbly,");
    fs::write(&csv, text).unwrap();
    tumble(dir.path())
        .args(["plot", "demo.csv", "--scene", demo_scene().to_str().unwrap(), "--out", "p.svg"])
        .assert()
        .code(2)
        .stderr(contains("the trajectory does not match the scene"))
        .stderr(contains("`wobbly`"))
        .stderr(contains("lacks moving bodies of the scene").and(contains("`stable`")));
    assert!(!dir.path().join("p.svg").exists(), "nothing written");
}

#[test]
fn missing_columns_are_named() {
    let dir = tempfile::tempdir().unwrap();
    fs::write(dir.path().join("t.csv"), "t,body,x,y,z,qw,qx,qy,qz\n0,a,0,0,0,1,0,0,0\n").unwrap();
    tumble(dir.path())
        .args(["plot", "t.csv", "--out", "p.svg"])
        .assert()
        .code(2)
        .stderr(contains("t.csv:1: missing columns `vx`, `vy`, `vz`, `wx`, `wy`, `wz`"));
    assert!(!dir.path().join("p.svg").exists());
}

#[test]
fn bad_arguments_are_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let csv = demo_trajectory(dir.path());
    let csv = csv.to_str().unwrap();
    tumble(dir.path())
        .args(["plot", csv, "--out", "p.pdf"])
        .assert()
        .code(2)
        .stderr(contains("use FILE.svg or FILE.png"));
    tumble(dir.path())
        .args(["plot", csv, "--out", "p.svg", "--bodies", "flipper,nobody"])
        .assert()
        .code(2)
        .stderr(contains("`nobody` is not a body of"));
    let many: Vec<String> = (0..17).map(|_| "flipper".to_string()).collect();
    tumble(dir.path()).args(["plot", csv, "--out", "p.svg", "--bodies", &many.join(",")]).assert().success();
    fs::remove_file(dir.path().join("p.svg")).unwrap();
    tumble(dir.path()).args(["plot", "missing.csv", "--out", "p.svg"]).assert().code(2).stderr(contains("missing.csv"));
    tumble(dir.path()).args(["plot", csv, "--out", "no/such/dir/p.svg"]).assert().code(4);
    assert!(!dir.path().join("p.svg").exists() && !dir.path().join("p.pdf").exists());
}

#[test]
fn a_trajectory_cut_short_is_plotted_as_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let csv = demo_trajectory(dir.path());
    let text = fs::read_to_string(&csv).unwrap();
    fs::write(&csv, &text[..text.len() * 2 / 3]).unwrap();
    tumble(dir.path())
        .args(["plot", "demo.csv", "--scene", demo_scene().to_str().unwrap(), "--out", "p.svg"])
        .assert()
        .success()
        .stderr(contains("the file was cut short"));
    assert!(fs::read_to_string(dir.path().join("p.svg")).unwrap().contains("(cut short)"));
}

#[test]
fn run_plots_right_after_the_run() {
    let dir = tempfile::tempdir().unwrap();
    tumble(dir.path())
        .args(["run", "--duration", "1", "--out", "d.jsonl", "--plot", "d.svg", "--quiet"])
        .assert()
        .success();
    let svg = fs::read_to_string(dir.path().join("d.svg")).unwrap();
    assert!(svg.contains("E₀ = 2108.338 J") && svg.contains("flipper: angular velocity in body axes"));
    // a bad plot file is refused before the run: nothing is written
    let fresh = tempfile::tempdir().unwrap();
    tumble(fresh.path())
        .args(["run", "--duration", "1", "--out", "d.csv", "--plot", "d.txt"])
        .assert()
        .code(2)
        .stderr(contains("--plot d.txt"));
    assert_eq!(fs::read_dir(fresh.path()).unwrap().count(), 0);
    tumble(fresh.path())
        .args(["run", "--duration", "1", "--out", "d.csv", "--summary", "d.svg", "--plot", "d.svg"])
        .assert()
        .code(2)
        .stderr(contains("--plot d.svg: the same file as the trajectory, the summary or the scene"));
    assert_eq!(fs::read_dir(fresh.path()).unwrap().count(), 0);
}

#[test]
fn extreme_values_are_plotted_without_failing() {
    let dir = tempfile::tempdir().unwrap();
    let rows = [
        "0,a,1e300,-1e300,0,1,0,0,0,1e200,0,0,0,0,0",
        "1e-300,a,-1.7976931348623157e308,0,5e-324,0,0,0,1,0,-1e200,0,1e300,0,0",
        "2e-300,a,0,0,0,0.5,0.5,0.5,0.5,0,0,0,0,0,0",
    ];
    fs::write(dir.path().join("x.csv"), format!("{}\n{}\n", common::HEADER, rows.join("\n"))).unwrap();
    fs::write(
        dir.path().join("x.toml"),
        "version = 1\n[[body]]\nname = \"a\"\nmass = 1e-3\ninertia = [1e-3, 1e-3, 1e-3]\n",
    )
    .unwrap();
    for out in ["x.svg", "x.png"] {
        tumble(dir.path()).args(["plot", "x.csv", "--scene", "x.toml", "--out", out]).assert().success();
        assert!(fs::metadata(dir.path().join(out)).unwrap().len() > 1000);
    }
}

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name)
}

/// The double pendulum: the energy error of the links, the robot's energies, and per link its
/// angular velocity in link axes and the path of its frame's origin; no angular-momentum panel (a
/// fixed base: the world holds the robot, its momentum is not counted).
#[test]
fn a_robot_has_its_energy_and_link_panels() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_path("double_pendulum.toml");
    let scene = scene.to_str().unwrap();
    tumble(dir.path()).args(["run", scene, "--duration", "2", "--out", "dp.csv", "-q"]).assert().success();
    tumble(dir.path()).args(["plot", "dp.csv", "--scene", scene, "--out", "p.svg"]).assert().success();
    let svg = fs::read_to_string(dir.path().join("p.svg")).unwrap();
    for text in [
        "relative energy error (E − E₀)/|E₀|, moving bodies and robot links, E₀ = 36.79491 J",
        "pendulum: kinetic, potential (zero at z = 0) and total energy of its links",
        "energy (J)",
        "kinetic",
        "pendulum/upper: angular velocity in link axes",
        "ω_link (rad/s)",
        "pendulum/tip: position of the link frame&apos;s origin, world frame",
    ] {
        assert!(svg.contains(text) || svg.contains(&text.replace("&apos;", "'")), "missing `{text}`");
    }
    assert!(!svg.contains("angular-momentum error"));
    assert_eq!(svg.matches("time (s)").count(), 8, "energy error, robot energy, 2 panels for each of 3 links");
    // without the scene: the kinematics, and the titles say what a link's row holds
    tumble(dir.path()).args(["plot", "dp.csv", "--out", "k.svg", "--bodies", "pendulum/tip"]).assert().success();
    let svg = fs::read_to_string(dir.path().join("k.svg")).unwrap();
    assert!(svg.contains("pendulum/tip: position (a robot link: its frame"), "title for a link without the scene");
    assert_eq!(svg.matches("time (s)").count(), 2);
}

/// A body beside a floating-base robot: the momentum panel is back (both are counted).
#[test]
fn a_floating_robot_beside_a_body_keeps_the_momentum_panel() {
    let dir = tempfile::tempdir().unwrap();
    let urdf = fs::read_to_string(scene_path("robots/double_pendulum.urdf")).unwrap();
    let base =
        r#"<link name="base"><inertial><mass value="3"/><inertia ixx="0.1" iyy="0.2" izz="0.25"/></inertial></link>"#;
    fs::write(dir.path().join("flyer.urdf"), urdf.replace(r#"<link name="base"/>"#, base)).unwrap();
    let scene = "version = 1\n[world]\nduration = 0.5\ndt = 0.001\nintegrator = \"rk4\"\n\
                 [[body]]\nname = \"ball\"\nmass = 1.0\ninertia = [0.1, 0.1, 0.1]\nvelocity = [1.0, 0.0, 3.0]\n\
                 [[robot]]\nname = \"flyer\"\nurdf = \"flyer.urdf\"\nbase = \"floating\"\nposition = [0.0, 2.0, 3.0]\n\
                 v = { root_joint = [0.0, 0.0, 1.0, 0.5, 0.0, 0.2], shoulder = 1.0 }\n";
    fs::write(dir.path().join("s.toml"), scene).unwrap();
    tumble(dir.path())
        .args(["run", "s.toml", "--out", "s.csv", "--plot", "s.svg", "--view", "s.html", "-q"])
        .assert()
        .success();
    let svg = fs::read_to_string(dir.path().join("s.svg")).unwrap();
    assert!(svg.contains("angular-momentum error") && svg.contains("flyer: kinetic, potential"));
    assert!(
        svg.contains("ball: angular velocity in body axes")
            && svg.contains("flyer/base: angular velocity in link axes")
    );
    // energy, momentum, the robot's energy, and 2 panels for each of the first 4 rows
    assert_eq!(svg.matches("time (s)").count(), 3 + 2 * 4);
}

#[test]
fn a_robot_trajectory_against_another_scene_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_path("double_pendulum.toml");
    let scene = scene.to_str().unwrap();
    tumble(dir.path()).args(["run", scene, "--duration", "0.1", "--out", "dp.csv", "-q"]).assert().success();
    let text = fs::read_to_string(dir.path().join("dp.csv")).unwrap();
    fs::write(dir.path().join("dp.csv"), text.replace(",pendulum/tip,", ",pendulum/nolink,")).unwrap();
    tumble(dir.path())
        .args(["plot", "dp.csv", "--scene", scene, "--out", "p.svg"])
        .assert()
        .code(2)
        .stderr(contains("`pendulum/nolink`").and(contains("robot `pendulum` has no moving link `nolink`")));
    tumble(dir.path())
        .args(["plot", "dp.csv", "--scene", demo_scene().to_str().unwrap(), "--out", "p.svg"])
        .assert()
        .code(2)
        .stderr(contains("the scene has no robot `pendulum`"));
    assert!(!dir.path().join("p.svg").exists());
}
