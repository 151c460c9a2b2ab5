//! `lock` and `package_paths` of a `[[robot]]` entry.
//!
//! - a Panda with its elbow and fingers locked runs: the locked link keeps its pose relative to its
//!   parent (the URDF's joint origin at the locked angle) to round-off, its links stay in the
//!   trajectory, and at the start every link is where the unlocked Panda puts it;
//! - Romeo, whose hand joints move no mass, loads when they are locked, and the error without `lock`
//!   says so; an inertia that is not physical names `balance_inertia` and `lock`;
//! - errors name the file, line, column and field (`robot[0].lock`);
//! - `package://NAME/…` is found under a scene's `package_paths`; without it the error names where
//!   it looked.

use std::path::{Path, PathBuf};
use tumble::math::{DMat3, DVec3};
use tumble::multibody::link_shapes::collision_shapes;
use tumble::multibody::{FrameOrigin, GeometryShape};
use tumble::scene::{self, Scene, SceneError};
use tumble::trajectory::{self, ReadOptions, TrajectoryWriter};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Writes `text` as `scene.toml` in `dir` and loads it.
fn load_in(dir: &Path, text: &str) -> Result<Scene, SceneError> {
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    scene::load(&path)
}

fn panda_scene(robot: &str) -> (tempfile::TempDir, Result<Scene, SceneError>) {
    let dir = tempfile::tempdir().unwrap();
    let urdf = repo().join("scenes/robots/panda.urdf");
    let text = format!(
        "version = 1\n[world]\nintegrator = \"rk4\"\ndt = 1e-3\n[[robot]]\nname = \"panda\"\nurdf = \"{}\"\n{robot}\n",
        urdf.display()
    );
    let loaded = load_in(dir.path(), &text);
    (dir, loaded)
}

fn error_of(loaded: Result<Scene, SceneError>) -> String {
    match loaded {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

/// `link3_from_link4` of the Panda at elbow angle `q4`, from the URDF's `panda_joint4`:
/// `<origin rpy="π/2 0 0" xyz="0.0825 0 0"/>`, axis z.
fn panda_elbow(q4: f64) -> (DMat3, DVec3) {
    (DMat3::from_rotation_x(std::f64::consts::FRAC_PI_2) * DMat3::from_rotation_z(q4), DVec3::new(0.0825, 0.0, 0.0))
}

#[test]
fn a_locked_elbow_keeps_its_pose_while_the_arm_swings() {
    let q4 = -1.2;
    let keys = format!(
        "q = {{ panda_joint2 = 0.4, panda_joint4 = {q4}, panda_finger_joint1 = 0.02 }}\n\
         lock = [\"panda_joint4\", \"panda_finger_joint1\", \"panda_finger_joint2\"]\njoint_limits = false"
    );
    let (dir, loaded) = panda_scene(&keys);
    let mut scene = loaded.unwrap();
    let described = scene.describe();
    assert!(described.contains("locked: panda_joint4 at [-1.2]"), "{described}");
    let (_, full) = panda_scene("q = { panda_joint2 = 0.4, panda_joint4 = -1.2, panda_finger_joint1 = 0.02 }");
    let full = full.unwrap();
    let world = &mut scene.world;
    let robot = &world.robots[0];
    assert_eq!((robot.model.nq(), robot.model.nv()), (6, 6));
    assert!(robot.model.joint_index("panda_joint4").is_none());
    assert_eq!(robot.model.locked.len(), 3);
    assert_eq!(robot.model.locked[0], ("panda_joint4".to_string(), vec![q4]));
    // the same links move, and start where the unlocked Panda has them
    let full_robot = &full.world.robots[0];
    assert_eq!(robot.link_names(), full_robot.link_names());
    let mut start_error = 0.0_f64;
    for k in 0..robot.link_names().len() {
        let (a, b) = (robot.link_state(k), full_robot.link_state(k));
        start_error = start_error.max((a.position - b.position).length());
        start_error = start_error.max(1.0 - a.orientation.dot(b.orientation).abs());
    }
    assert!(start_error < 1e-14, "the reduced Panda starts {start_error:e} away from the full one");
    let link = |name: &str| robot.link_names().iter().position(|n| n == name).unwrap();
    let (l3, l4) = (link("panda/panda_link3"), link("panda/panda_link4"));
    let frame4 = robot.link_frame(l4);
    assert!(matches!(&frame4.origin, FrameOrigin::Fixed { joint, .. } if joint == "panda_joint4"));

    // the arm falls under gravity for a second, written to a trajectory
    let out = dir.path().join("out.csv");
    let mut writer =
        TrajectoryWriter::new(std::fs::File::create(&out).unwrap(), trajectory::Format::Csv, world).unwrap();
    let e0 = world.energy();
    let (want_rotation, want_offset) = panda_elbow(q4);
    let mut worst_pose = 0.0_f64;
    let mut worst_energy = 0.0_f64;
    for step in 0..1000 {
        world.step().unwrap();
        if step % 100 == 99 {
            writer.write_sample(world).unwrap();
        }
        let robot = &world.robots[0];
        let (a, b) = (robot.link_state(l3), robot.link_state(l4));
        // link3_from_link4 = world_from_link3ᵀ world_from_link4
        let rotation = DMat3::from_quat(a.orientation).transpose() * DMat3::from_quat(b.orientation);
        let offset = DMat3::from_quat(a.orientation).transpose() * (b.position - a.position);
        worst_pose = worst_pose.max((rotation - want_rotation).to_cols_array().iter().fold(0.0, |m, x| m.max(x.abs())));
        worst_pose = worst_pose.max((offset - want_offset).length());
        worst_energy = worst_energy.max((world.energy() - e0).abs() / e0.abs().max(1.0));
    }
    writer.finish().unwrap();
    let moved = world.robots[0].q()[1] - 0.4;
    eprintln!(
        "locked elbow: link3_from_link4 off by at most {worst_pose:e} over 1000 steps; energy drift {worst_energy:e} \
         (relative); joint 2 moved {moved} rad; start {start_error:e} from the full model"
    );
    assert!(moved.abs() > 0.05, "the arm should fall: joint 2 moved {moved}");
    assert!(worst_pose < 1e-13, "the locked link moved relative to its parent by {worst_pose:e}");
    assert!(worst_energy < 1e-6, "energy drift {worst_energy:e}");
    let read = trajectory::read(&out, ReadOptions::default()).unwrap();
    assert!(read.bodies.iter().any(|b| b == "panda/panda_link4"), "{:?}", read.bodies);
    assert!(read.bodies.iter().any(|b| b == "panda/panda_leftfinger"), "{:?}", read.bodies);
    assert_eq!(read.frames.len(), 10);
}

#[test]
fn lock_errors_name_the_file_line_and_field() {
    let e = error_of(panda_scene("lock = [\"panda_joint4\", \"panda_jiont5\"]").1);
    assert!(e.contains("scene.toml:8:25: robot[0].lock: unknown joint `panda_jiont5`"), "{e}");
    assert!(e.contains("did you mean `panda_joint5`?"), "{e}");
    let e = error_of(panda_scene("lock = [\"panda_hand_joint\"]").1);
    assert!(e.contains("scene.toml:8:9: robot[0].lock: joint `panda_hand_joint` is fixed already"), "{e}");
    let e = error_of(panda_scene("lock = [\"panda_joint4\", \"panda_joint4\"]").1);
    assert!(e.contains("scene.toml:8:25: robot[0].lock: joint `panda_joint4` is locked twice"), "{e}");
    let e = error_of(panda_scene("base = \"floating\"\nlock = [\"root_joint\"]").1);
    assert!(e.contains("scene.toml:9:9: robot[0].lock: joint `root_joint` is the floating base"), "{e}");
    assert!(e.contains("base = \"fixed\""), "{e}");
    let e = error_of(panda_scene("lock = \"panda_joint4\"").1);
    assert!(e.contains("robot[0].lock") || e.contains("lock"), "{e}");
    // a locked joint has no velocity, torque, damping or PD
    for (key, line) in [
        ("v = { panda_joint4 = 0.1 }", "robot[0].v.panda_joint4: joint `panda_joint4` is locked"),
        ("torque = { panda_joint4 = 1.0 }", "robot[0].torque.panda_joint4: joint `panda_joint4` is locked"),
        ("damping = { panda_joint4 = 1.0 }", "robot[0].damping.panda_joint4: joint `panda_joint4` is locked"),
        (
            "pd = { panda_joint4 = { target = 0.1, kp = 1.0 } }",
            "robot[0].pd.panda_joint4: joint `panda_joint4` is locked",
        ),
    ] {
        let e = error_of(panda_scene(&format!("lock = [\"panda_joint4\"]\n{key}")).1);
        assert!(e.contains("scene.toml:9:") && e.contains(line), "{e}");
    }
    // a locked joint's value is checked like any q
    let e = error_of(panda_scene("lock = [\"panda_joint4\"]\nq = { panda_joint4 = nan }").1);
    assert!(e.contains("robot[0].q.panda_joint4: must be finite"), "{e}");
}

fn romeo_scene(lock: &str) -> (tempfile::TempDir, Result<Scene, SceneError>) {
    let dir = tempfile::tempdir().unwrap();
    let urdf = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/robots/romeo.urdf");
    let text = format!(
        "version = 1\n[[robot]]\nname = \"romeo\"\nurdf = \"{}\"\nbase = \"floating\"\nposition = [0.0, 0.0, 1.0]\n{lock}\n\
         collision = false\n",
        urdf.display()
    );
    let loaded = load_in(dir.path(), &text);
    (dir, loaded)
}

#[test]
fn romeo_loads_with_its_massless_hands_locked() {
    // the hint lists every joint that moves no mass, as a `lock` to copy
    let e = error_of(romeo_scene("").1);
    assert!(e.contains("robot[0].urdf") && e.contains("subtree without mass"), "{e}");
    let hint = e.split("hint: ").nth(1).expect("a hint");
    let lock = hint.split('`').nth(1).expect("a quoted lock").to_string();
    assert!(lock.starts_with("lock = [\"") && lock.contains("\"LHand\"") && lock.contains("\"RHand\""), "{e}");
    // one hand locked: the joints still without mass are named, with the `lock` that holds them all
    let e = error_of(romeo_scene("lock = [\"LHand\"]").1);
    assert!(e.contains("scene.toml:7:8: robot[0].lock: joints `LFinger12`, "), "{e}");
    assert!(e.contains("`RHand`") && e.contains("lock them too, `lock = [\"LHand\", \"LFinger12\""), "{e}");
    let (_dir, loaded) = romeo_scene(&lock);
    let mut scene = loaded.unwrap();
    let robot = &scene.world.robots[0];
    let fused = tumble::multibody::load_urdf(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/robots/romeo.urdf"),
        tumble::multibody::UrdfOptions {
            floating: true,
            massless: tumble::multibody::Massless::Fuse,
            ..Default::default()
        },
    )
    .unwrap();
    // the same joints as the reader's fusing at q = 0 (the hands at their neutral value)
    assert_eq!((robot.model.nq(), robot.model.nv()), (fused.nq(), fused.nv()));
    assert!((robot.model.total_mass - fused.total_mass).abs() < 1e-12 * fused.total_mass);
    let e0 = scene.world.energy();
    for _ in 0..100 {
        scene.world.step().unwrap();
    }
    assert!(scene.world.energy().is_finite() && scene.world.energy() < e0 + 1e-6 * e0.abs());
}

#[test]
fn a_bad_inertia_names_balance_inertia_and_lock() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bad.urdf"),
        r#"<robot name="b">
  <link name="base"/>
  <link name="antenna"><inertial><mass value="0.1"/><inertia ixx="0.01" iyy="0.01" izz="-0.001"/></inertial></link>
  <joint name="j" type="continuous"><parent link="base"/><child link="antenna"/></joint>
</robot>"#,
    )
    .unwrap();
    let e = error_of(load_in(dir.path(), "version = 1\n[[robot]]\nname = \"r\"\nurdf = \"bad.urdf\"\n"));
    assert!(e.contains("robot[0].urdf") && e.contains("inertia of link 'antenna'"), "{e}");
    assert!(e.contains("balance_inertia = true") && e.contains("lock = ["), "{e}");
}

/// An OBJ cube of side 0.2 m.
const CUBE_OBJ: &str = "v -0.1 -0.1 -0.1\nv 0.1 -0.1 -0.1\nv 0.1 0.1 -0.1\nv -0.1 0.1 -0.1\n\
v -0.1 -0.1 0.1\nv 0.1 -0.1 0.1\nv 0.1 0.1 0.1\nv -0.1 0.1 0.1\n\
f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";

const MESH_ROBOT: &str = r#"<robot name="m">
  <link name="base"/>
  <link name="arm"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial>
    <collision><geometry><mesh filename="package://mypkg/meshes/cube.obj"/></geometry></collision></link>
  <joint name="j" type="continuous"><parent link="base"/><child link="arm"/></joint>
</robot>"#;

/// `robot/m.urdf` and `pkgs/mypkg/meshes/cube.obj` in a fresh directory: no parent directory of the
/// URDF is named `mypkg`.
fn mesh_dir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("robot")).unwrap();
    std::fs::create_dir_all(dir.path().join("pkgs/mypkg/meshes")).unwrap();
    std::fs::create_dir_all(dir.path().join("other")).unwrap();
    std::fs::write(dir.path().join("robot/m.urdf"), MESH_ROBOT).unwrap();
    std::fs::write(dir.path().join("pkgs/mypkg/meshes/cube.obj"), CUBE_OBJ).unwrap();
    dir
}

fn mesh_scene(dir: &Path, keys: &str) -> Result<Scene, SceneError> {
    load_in(dir, &format!("version = 1\n[[robot]]\nname = \"m\"\nurdf = \"robot/m.urdf\"\n{keys}\n"))
}

#[test]
fn a_mesh_is_found_under_the_package_paths() {
    let dir = mesh_dir();
    let scene = mesh_scene(dir.path(), "package_paths = [\"other\", \"pkgs\"]").unwrap();
    let model = &scene.world.robots[0].model;
    let want = dir.path().join("pkgs/mypkg/meshes/cube.obj");
    match &model.geometries[0].shape {
        GeometryShape::Mesh { path, .. } => assert_eq!(path.as_deref(), Some(want.as_path())),
        other => panic!("{other:?}"),
    }
    let shapes = collision_shapes(model, "m.urdf").unwrap();
    assert_eq!(shapes.len(), 1);
    assert!(scene.warnings.iter().all(|w| !w.contains("not resolved")), "{:?}", scene.warnings);

    // without the key: an error naming the URDF line and where the package was looked for
    let e = error_of(mesh_scene(dir.path(), ""));
    assert!(e.contains("scene.toml:4:8: robot[0].urdf: ") && e.contains("m.urdf:4: link 'arm': <collision>"), "{e}");
    assert!(e.contains("mesh 'package://mypkg/meshes/cube.obj' could not be resolved"), "{e}");
    assert!(e.contains("no directory named 'mypkg' contains") && e.contains("package_paths"), "{e}");
    // so is the warning, when the robot does not collide
    let scene = mesh_scene(dir.path(), "collision = false").unwrap();
    let warning = scene.warnings.iter().find(|w| w.contains("not resolved")).expect("a warning");
    assert!(warning.contains("m.urdf:4: link 'arm': mesh 'package://mypkg/meshes/cube.obj'"), "{warning}");
    assert!(warning.contains("no directory named 'mypkg' contains"), "{warning}");

    // a package path without the file: every path tried is named
    let e = error_of(mesh_scene(dir.path(), "package_paths = [\"other\"]"));
    let tried = dir.path().join("other/mypkg/meshes/cube.obj");
    assert!(e.contains("m.urdf:4: link 'arm'") && e.contains("the paths tried"), "{e}");
    assert!(e.contains(&tried.display().to_string()), "{e}");

    // a package path that is not a directory
    let e = error_of(mesh_scene(dir.path(), "package_paths = [\"pkgs\", \"nowhere\"]"));
    assert!(
        e.contains("scene.toml:5:26: robot[0].package_paths: ") && e.contains("nowhere` is not a directory"),
        "{e}"
    );
}

#[test]
fn json_scenes_take_lock_and_package_paths() {
    let dir = mesh_dir();
    let text =
        r#"{"version": 1, "robot": [{"name": "m", "urdf": "robot/m.urdf", "package_paths": ["pkgs"], "lock": ["j"]}]}"#;
    let path = dir.path().join("scene.json");
    std::fs::write(&path, text).unwrap();
    let scene = scene::load(&path).unwrap();
    let robot = &scene.world.robots[0];
    assert_eq!(robot.model.nv(), 0);
    // everything is fixed to the world: no link moves
    assert!(robot.link_names().is_empty());
}

/// A joint that hangs from a placed fixed base, locked: its link joins the world (no longer a
/// trajectory row) and every other link starts where the unlocked Panda puts it.
#[test]
fn a_locked_first_joint_joins_the_placed_base() {
    let base = "position = [0.3, -0.2, 0.5]\norientation = [0.8, 0.0, 0.6, 0.0]\n";
    let (_d1, locked) = panda_scene(&format!("{base}q = {{ panda_joint1 = 0.7 }}\nlock = [\"panda_joint1\"]"));
    let (_d2, full) = panda_scene(&format!("{base}q = {{ panda_joint1 = 0.7 }}"));
    let (locked, full) = (locked.unwrap(), full.unwrap());
    let (a, b) = (&locked.world.robots[0], &full.world.robots[0]);
    assert_eq!(a.model.nv(), 8);
    let names_b: Vec<&String> = b.link_names().iter().filter(|n| *n != "panda/panda_link1").collect();
    assert_eq!(a.link_names().iter().collect::<Vec<_>>(), names_b);
    let mut worst = 0.0_f64;
    for (k, name) in a.link_names().iter().enumerate() {
        let kb = b.link_names().iter().position(|n| n == name).unwrap();
        let (sa, sb) = (a.link_state(k), b.link_state(kb));
        worst = worst.max((sa.position - sb.position).length()).max(1.0 - sa.orientation.dot(sb.orientation).abs());
    }
    assert!(worst < 1e-14, "links start {worst:e} apart");
    // the locked link is fixed to the world, where the placed base and the locked angle put it
    let frame = &a.model.frames[a.model.frame_index("panda_link1").unwrap()];
    assert!(frame.body.is_none());
    // its potential energy leaves the robot's (what is fixed to the world counts for nothing):
    // E_full − E_locked = −m₁ g·c₁, c₁ its centre of mass in the world
    let com_world = frame.x_from_body.inv_apply_point(frame.inertia.com());
    let link1 = -frame.inertia.mass * a.model.gravity.dot(com_world);
    let difference = b.energy() - a.energy();
    assert!((difference - link1).abs() < 1e-12 * b.energy().abs().max(1.0), "{difference} against {link1} J");
}
