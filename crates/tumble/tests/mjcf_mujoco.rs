//! MJCF models against MuJoCo itself: the Gymnasium tasks and Menagerie robots read by
//! `load_mjcf`, at random states, agree with MuJoCo's mass matrix (`mj_fullM`), bias forces
//! (`qfrc_bias`), passive forces (`qfrc_passive`), contact-free forward dynamics (`qacc`) to 1e-10
//! relative, and with the body poses of `mj_kinematics` (`xpos`, `xquat`) and body velocities
//! (`mj_objectVelocity`, local) to 1e-12. The fixtures are MuJoCo's own numbers in its own
//! conventions (`tools/mjcf_fixtures.py`); `MujocoLayout` maps tumble's to them, so the joint layout
//! (free joint: linear velocity in the world frame, angular in the body frame) is under test too.

use nalgebra::DMatrix;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use tumble::math::{DMat3, DQuat, DVec3};
use tumble::multibody::mjcf::{load_mjcf, parse_mjcf, Mjcf, MjcfOptions};
use tumble::multibody::{aba, bias_forces, crba, forward_kinematics, passive_forces, Workspace};

#[derive(Deserialize)]
struct Fixture {
    nq: usize,
    nv: usize,
    qpos0: Vec<f64>,
    bodies: Vec<Option<String>>,
    joints: Vec<Option<String>>,
    gravity: Vec<f64>,
    timestep: f64,
    states: Vec<State>,
}

#[derive(Deserialize)]
struct State {
    qpos: Vec<f64>,
    qvel: Vec<f64>,
    mass_matrix: Vec<f64>,
    qfrc_bias: Vec<f64>,
    qfrc_passive: Vec<f64>,
    qacc: Vec<f64>,
    xpos: Vec<f64>,
    xquat: Vec<f64>,
    body_velocity: Vec<f64>,
    /// Models with tendons only: random controls, MuJoCo's actuator forces there (actuation on) and
    /// the tendons' lengths.
    #[serde(default)]
    ctrl: Vec<f64>,
    #[serde(default)]
    qfrc_actuator: Vec<f64>,
    #[serde(default)]
    ten_length: Vec<f64>,
}

const DYNAMICS_TOL: f64 = 1e-10;
const POSE_TOL: f64 = 1e-12;

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/mjcf")
}

fn fixture(name: &str) -> Fixture {
    let text = std::fs::read_to_string(dir().join(format!("{name}.json"))).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// `max |a − b| / max |b|` (the largest entry of `b` sets the scale; 1 if `b` is all zero).
fn relative(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let diff = a.iter().zip(b).fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    if scale > 0.0 {
        diff / scale
    } else {
        diff
    }
}

/// The largest relative errors of one model over its states.
#[derive(Debug, Default)]
struct Errors {
    mass_matrix: f64,
    bias: f64,
    passive: f64,
    qacc: f64,
    pose: f64,
    velocity: f64,
}

fn compare(name: &str, model_file: &Path, options: MjcfOptions) -> Errors {
    let fx = fixture(name);
    let mjcf: Mjcf = load_mjcf(model_file, options).unwrap_or_else(|e| panic!("{name}: {e}"));
    let model = &mjcf.model;
    assert_eq!((model.nq(), model.nv()), (fx.nq, fx.nv), "{name}: nq, nv");
    assert_eq!(mjcf.layout.qpos0(), fx.qpos0, "{name}: qpos0");
    assert_eq!(mjcf.layout.joints.len(), fx.joints.len(), "{name}: joints");
    for (j, want) in mjcf.layout.joints.iter().zip(&fx.joints) {
        if let Some(want) = want {
            assert_eq!(&j.name, want, "{name}: joint order");
        }
    }
    assert_eq!(mjcf.bodies.len(), fx.bodies.len(), "{name}: bodies");
    for (b, want) in mjcf.bodies.iter().zip(&fx.bodies) {
        if let Some(want) = want {
            assert_eq!(&b.name, want, "{name}: body order");
        }
    }
    assert_eq!(model.gravity.to_array().to_vec(), fx.gravity, "{name}: gravity");
    assert_eq!(mjcf.option.timestep, fx.timestep, "{name}: timestep");
    let nv = model.nv();
    let mut ws = Workspace::new(model);
    let mut e = Errors::default();
    for s in &fx.states {
        let (q, v) = mjcf.layout.state_from_mujoco(&s.qpos, &s.qvel).unwrap();
        // and back
        let (qpos, qvel) = mjcf.layout.state_to_mujoco(&q, &v).unwrap();
        assert!(relative(&qpos, &s.qpos) <= 1e-14 && relative(&qvel, &s.qvel) <= 1e-14, "{name}: layout round trip");

        let m: DMatrix<f64> = crba(model, &mut ws, &q).unwrap().clone();
        let m_mj = mjcf.layout.mass_matrix_to_mujoco(&q, &m).unwrap();
        // fixture rows → column-major nalgebra
        let want_m = DMatrix::from_row_slice(nv, nv, &s.mass_matrix);
        e.mass_matrix = e.mass_matrix.max(relative(m_mj.as_slice(), want_m.as_slice()));

        let mut b = vec![0.0; nv];
        bias_forces(model, &mut ws, &q, &v, &mut b).unwrap();
        let b_mj = mjcf.layout.bias_to_mujoco(&q, &v, &b, &m).unwrap();
        e.bias = e.bias.max(relative(&b_mj, &s.qfrc_bias));

        let mut passive = vec![0.0; nv];
        passive_forces(model, &mut ws, &q, &v, &mut passive).unwrap();
        let passive_mj = mjcf.layout.force_to_mujoco(&q, &passive).unwrap();
        e.passive = e.passive.max(relative(&passive_mj, &s.qfrc_passive));

        let mut qdd = vec![0.0; nv];
        aba(model, &mut ws, &q, &v, &passive, &mut qdd).unwrap();
        let qacc = mjcf.layout.acceleration_to_mujoco(&q, &v, &qdd).unwrap();
        e.qacc = e.qacc.max(relative(&qacc, &s.qacc));
        // and the other way
        let qdd_back = mjcf.layout.acceleration_from_mujoco(&q, &v, &qacc).unwrap();
        assert!(relative(&qdd_back, &qdd) <= 1e-13, "{name}: acceleration map round trip");

        forward_kinematics(model, &mut ws, &q, &v).unwrap();
        let mut pos = Vec::new();
        let mut quat_err = 0.0_f64;
        let mut vel = Vec::new();
        for (k, body) in mjcf.bodies.iter().enumerate() {
            // world_from_mjcfbody = world_from_body ∘ body_from_mjcfbody
            let (rot_body, origin_body, omega_body, v_origin_body) = match body.body {
                Some(i) => {
                    let x = &ws.x_world[i];
                    (DQuat::from_mat3(&x.rotation_a_from_b()), x.r, ws.v[i].ang, ws.v[i].lin)
                }
                None => (DQuat::IDENTITY, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO),
            };
            let p = body.pose_in_body;
            let xpos = origin_body + rot_body * p.pos;
            let xquat = (rot_body * p.rot).normalize();
            pos.extend(xpos.to_array());
            let want = DQuat::from_xyzw(s.xquat[4 * k + 1], s.xquat[4 * k + 2], s.xquat[4 * k + 3], s.xquat[4 * k]);
            // q and −q are one rotation
            quat_err = quat_err.max((xquat - want).length().min((xquat + want).length()));
            // [ω; v] of the MJCF body's origin in its frame: Rᵀ ω, Rᵀ (v_O + ω × p)
            let r_t = DMat3::from_quat(p.rot).transpose();
            vel.extend((r_t * omega_body).to_array());
            vel.extend((r_t * (v_origin_body + omega_body.cross(p.pos))).to_array());
        }
        e.pose = e.pose.max(relative(&pos, &s.xpos)).max(quat_err);
        e.velocity = e.velocity.max(relative(&vel, &s.body_velocity));
    }
    e
}

fn check(name: &str, file: PathBuf) {
    check_with(name, file, MjcfOptions::default())
}

fn check_with(name: &str, file: PathBuf, options: MjcfOptions) {
    let e = compare(name, &file, options);
    eprintln!(
        "{name:>26}: M {:.1e}  bias {:.1e}  passive {:.1e}  qacc {:.1e}  poses {:.1e}  velocities {:.1e}",
        e.mass_matrix, e.bias, e.passive, e.qacc, e.pose, e.velocity
    );
    for (what, err, tol) in [
        ("mass matrix", e.mass_matrix, DYNAMICS_TOL),
        ("qfrc_bias", e.bias, DYNAMICS_TOL),
        ("qfrc_passive", e.passive, DYNAMICS_TOL),
        ("qacc", e.qacc, DYNAMICS_TOL),
        ("xpos/xquat", e.pose, POSE_TOL),
        ("body velocity", e.velocity, POSE_TOL),
    ] {
        assert!(err <= tol, "{name}: {what} differs from MuJoCo's by {err:e} relative (allowed {tol:e})");
    }
}

fn gymnasium(name: &str) {
    check(name, dir().join("gymnasium").join(format!("{name}.xml")));
}

#[test]
fn ant() {
    gymnasium("ant");
}
#[test]
fn half_cheetah() {
    gymnasium("half_cheetah");
}
#[test]
fn hopper() {
    gymnasium("hopper");
}
#[test]
fn walker2d() {
    gymnasium("walker2d");
}
#[test]
fn humanoid() {
    gymnasium("humanoid");
}
#[test]
fn humanoidstandup() {
    gymnasium("humanoidstandup");
}
#[test]
fn reacher() {
    gymnasium("reacher");
}
#[test]
fn pusher() {
    gymnasium("pusher");
}
#[test]
fn inverted_pendulum() {
    gymnasium("inverted_pendulum");
}
#[test]
fn inverted_double_pendulum() {
    gymnasium("inverted_double_pendulum");
}
/// ANYmal C's joints have `frictionloss`, a constraint (a bounded impulse of the step), which
/// none of the compared quantities holds: it loads with it and agrees as read, and with it
/// dropped (the fixtures disable friction loss in MuJoCo for every model).
#[test]
fn anymal_c() {
    let path = dir().join("menagerie/anymal_c.xml");
    check("anymal_c", path.clone());
    check_with("anymal_c", path, MjcfOptions { drop_frictionloss: true });
}
#[test]
fn iiwa14() {
    check("iiwa14", dir().join("menagerie/iiwa14.xml"));
}

/// The swimmer moves through a dense, viscous medium (`<option density="4000" viscosity="0.1">`):
/// MuJoCo's inertia-box fluid forces are in its `qfrc_passive` (the swimmer has no joint damping or
/// springs, so they are all of it) and hence in `qacc`.
#[test]
fn swimmer() {
    gymnasium("swimmer");
    let mjcf = load_mjcf(&dir().join("gymnasium/swimmer.xml"), MjcfOptions::default()).unwrap();
    let fluid = &mjcf.model.fluid;
    assert_eq!((fluid.medium.density, fluid.medium.viscosity), (4000.0, 0.1));
    // one box per MJCF body (torso, mid, back), on the body of its last joint
    assert_eq!(fluid.boxes.len(), 3);
}

/// MuJoCo's ellipsoid fluid model is refused, naming the attribute and what is read instead.
#[test]
fn the_ellipsoid_fluid_model_is_refused() {
    let text = std::fs::read_to_string(dir().join("gymnasium/swimmer.xml")).unwrap().replacen(
        r#"<geom density="1000""#,
        r#"<geom fluidshape="ellipsoid" density="1000""#,
        1,
    );
    let err = parse_mjcf(&text, "swimmer.xml", MjcfOptions::default()).unwrap_err();
    let msg = err.to_string();
    assert!(err.is_unsupported(), "{msg}");
    assert!(msg.contains("fluidshape") && msg.contains("ellipsoid"), "{msg}");
}

/// Small models written for the conventions: every orientation form in degrees, a frame,
/// `childclass`, a slide `ref`, a hinge `ref` and anchor.
#[test]
fn synthetic_orientations() {
    check("orientations", dir().join("synthetic/orientations.xml"));
}

/// `eulerseq="ZYX"` (fixed axes) in radians, a ball joint, two joints in one body with a spring
/// and `springref`, a limited hinge.
#[test]
fn synthetic_eulerseq_radian() {
    check("eulerseq_radian", dir().join("synthetic/eulerseq_radian.xml"));
}

/// `eulerseq="zXy"` (mixed), a `<freejoint>` body whose inertia comes from a geom with `mass` and
/// one with the default density.
#[test]
fn synthetic_eulerseq_mixed() {
    check("eulerseq_mixed", dir().join("synthetic/eulerseq_mixed.xml"));
}

/// Nested default classes from an `<include>`d file, `childclass` and `class`, inertia from geoms
/// (density, mass, a geom outside `inertiagrouprange`), a welded body, `fullinertia`, three joints
/// in one body.
#[test]
fn synthetic_defaults_inertia() {
    check("defaults_inertia", dir().join("synthetic/defaults_inertia.xml"));
}

/// The Allegro hand has no `<inertial>`: every body's inertia comes from its geoms, the visual
/// meshes among them (group 2, inside `inertiagrouprange`), with MuJoCo's `legacy` mesh inertia.
/// Menagerie's `wonik_allegro/right_hand.xml` with its LICENSE and the eleven meshes it uses, copied
/// beside the fixtures (the test reads no file outside the repository).
///
/// Each mesh's tensor is the one MuJoCo's compiler keeps after turning the mesh to its principal
/// axes with its Jacobi solver stopped at an off-diagonal of 1e-7 of the largest element
/// (`mesh_inertia::mujoco_principal_tensor`): with the exact tensor instead, M differed by
/// 3.0e-10 and `qacc` by 7.5e-10 (the frames 1e-7 to 6e-7 rad apart; `tools/mjcf_allegro_frames.py`).
#[test]
fn allegro_right_hand_inertia_from_meshes() {
    check("allegro_right", dir().join("menagerie/wonik_allegro/right_hand.xml"));
}

/// Fixed tendons (`tools/mjcf_fixtures.py --tendons`): a tendon with a spring and damper from a
/// default class, one with a dead-band spring (`springlength` two values) over a hinge and a slide
/// with `ref`, one without; the spring lengths MuJoCo computes at `qpos_spring`. The dynamics and
/// the passive forces as for every model, and then the tendons' lengths and the actuator forces
/// (a `position` servo on a tendon with a `forcerange`, a `motor` with a gear and a `general` with
/// an affine bias on tendons, a servo on a joint) at random controls, some outside their
/// `ctrlrange`.
#[test]
fn synthetic_tendons() {
    check("tendons", dir().join("synthetic/tendons.xml"));
    check_actuators("tendons", &dir().join("synthetic/tendons.xml"), MjcfOptions::default());
}

/// The Shadow hand (Menagerie): four fixed tendons couple each finger's two distal joints, and a
/// `position` actuator with a `forcerange` drives each tendon. Its joints' `frictionloss` is read
/// (a constraint: MuJoCo's fixture disables it, and it is no force of the dynamics compared here);
/// the same with it dropped.
#[test]
fn shadow_hand() {
    let path = dir().join("menagerie/right_hand_shadow_hand.xml");
    check("shadow_right", path.clone());
    check_with("shadow_right", path.clone(), MjcfOptions { drop_frictionloss: true });
    check_actuators("shadow_right", &path, MjcfOptions::default());
}

/// The tendons' lengths and the joint forces of the actuators and passive elements of the model
/// as a scene's robot holds them (`[[robot]] mjcf`, every actuator at the fixture's control):
/// MuJoCo's `ten_length` and `qfrc_actuator + qfrc_passive`.
fn check_actuators(name: &str, file: &Path, options: MjcfOptions) {
    let fx = fixture(name);
    let mjcf: Mjcf = load_mjcf(file, options).unwrap();
    let nv = mjcf.model.nv();
    let (mut length_err, mut force_err) = (0.0_f64, 0.0_f64);
    for (k, s) in fx.states.iter().enumerate() {
        assert_eq!(s.ctrl.len(), mjcf.actuators.len(), "{name}: one control per actuator");
        let (q, v) = mjcf.layout.state_from_mujoco(&s.qpos, &s.qvel).unwrap();
        let lengths: Vec<f64> = mjcf.model.tendons.iter().map(|t| t.length(&q)).collect();
        length_err = length_err.max(relative(&lengths, &s.ten_length));

        let dir = tempfile::tempdir().unwrap();
        let ctrl: Vec<String> =
            mjcf.actuators.iter().zip(&s.ctrl).map(|(a, u)| format!("{} = {u:e}", a.name)).collect();
        let scene_text = format!(
            "version = 1\n[world]\ndt = 1e-3\nduration = 0.001\n[[robot]]\nname = \"r\"\nmjcf = {:?}\nctrl = {{ {} }}\n",
            file.display().to_string(),
            ctrl.join(", ")
        );
        let scene_path = dir.path().join("scene.toml");
        std::fs::write(&scene_path, scene_text).unwrap();
        let scene = tumble::scene::load(&scene_path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let robot = &scene.world.robots[0];
        let mut tau = vec![0.0; nv];
        let mut robot_ws = Workspace::new(&robot.model);
        robot.control.joint_forces(&robot.model, &mut robot_ws, &q, &v, &mut tau).unwrap();
        let tau_mj = mjcf.layout.force_to_mujoco(&q, &tau).unwrap();
        let want: Vec<f64> = s.qfrc_actuator.iter().zip(&s.qfrc_passive).map(|(a, p)| a + p).collect();
        let err = relative(&tau_mj, &want);
        assert!(err.is_finite(), "{name}: state {k}");
        force_err = force_err.max(err);
    }
    eprintln!("{name:>26}: tendon lengths {length_err:.1e}  actuator + passive forces {force_err:.1e}");
    assert!(length_err <= POSE_TOL, "{name}: tendon lengths differ from MuJoCo's by {length_err:e} relative");
    assert!(force_err <= DYNAMICS_TOL, "{name}: actuator forces differ from MuJoCo's by {force_err:e} relative");
}
