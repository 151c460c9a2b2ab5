//! Reduced models (locked joints) against the full model: with the locked joints at their value and
//! at rest, the reduced mass matrix is the full one's sub-matrix of the kept coordinates (CRBA of
//! the full model), the reduced bias forces are the kept rows of the full ones, every link sits at
//! the same place, and the kinetic energy and mass agree. On random trees (fixed and floating bases,
//! spherical joints locked too) and on the Panda; and against Pinocchio's `buildReducedModel` on the
//! Panda, Solo-12 and Talos (fixture `reduced.json` by `tools/pinocchio_reduced.py`).

mod multibody_common;

use multibody_common::{assert_close, random_q, random_tree, Base, Rng};
use std::path::Path;
use tumble::multibody::fk::frame_x_world;
use tumble::multibody::{
    bias_forces, crba, kept_coordinates, kinetic_energy, load_urdf, reduced_model, update_placements, FrameOrigin,
    JointKind, LockError, MultibodyModel, UrdfOptions, Workspace,
};

/// Compares the reduced model with the full one at `q_full` (locked joints at their value) and
/// `v_full` (zero on the locked joints).
/// Returns the largest relative differences of (mass matrix, bias, frame placements).
fn check_reduced(
    what: &str,
    full: &MultibodyModel,
    reduced: &MultibodyModel,
    q_full: &[f64],
    v_full: &[f64],
) -> [f64; 3] {
    let mut worst = [0.0_f64; 3];
    let (q_map, v_map) = kept_coordinates(full, reduced);
    let q_red: Vec<f64> = q_map.iter().map(|&k| q_full[k]).collect();
    let v_red: Vec<f64> = v_map.iter().map(|&k| v_full[k]).collect();
    assert_eq!((reduced.nq(), reduced.nv()), (q_red.len(), v_red.len()), "{what}: layout");

    // M_reduced = M_full[kept, kept]
    let mut ws_full = Workspace::new(full);
    let mut ws_red = Workspace::new(reduced);
    let m_full = crba(full, &mut ws_full, q_full).unwrap().clone();
    let m_red = crba(reduced, &mut ws_red, &q_red).unwrap().clone();
    let mut sub = Vec::with_capacity(v_map.len() * v_map.len());
    let mut got = Vec::with_capacity(sub.capacity());
    for (r, &fr) in v_map.iter().enumerate() {
        for (c, &fc) in v_map.iter().enumerate() {
            sub.push(m_full[(fr, fc)]);
            got.push(m_red[(r, c)]);
        }
    }
    assert_close(&format!("{what}: mass matrix"), &got, &sub, 1e-12);
    worst[0] = max_relative(&got, &sub);

    // b_reduced = b_full[kept] (locked joints at rest)
    let mut b_full = vec![0.0; full.nv()];
    let mut b_red = vec![0.0; reduced.nv()];
    bias_forces(full, &mut ws_full, q_full, v_full, &mut b_full).unwrap();
    bias_forces(reduced, &mut ws_red, &q_red, &v_red, &mut b_red).unwrap();
    let b_kept: Vec<f64> = v_map.iter().map(|&k| b_full[k]).collect();
    assert_close(&format!("{what}: bias forces"), &b_red, &b_kept, 1e-12);
    worst[1] = max_relative(&b_red, &b_kept);

    // every frame at the same place in the world
    assert_eq!(full.frames.len(), reduced.frames.len(), "{what}: frames");
    update_placements(full, &mut ws_full, q_full).unwrap();
    update_placements(reduced, &mut ws_red, &q_red).unwrap();
    for (f, frame) in full.frames.iter().enumerate() {
        assert_eq!(frame.name, reduced.frames[f].name, "{what}: frame order");
        let (a, b) = (frame_x_world(full, &ws_full, f), frame_x_world(reduced, &ws_red, f));
        let flat = |x: tumble::multibody::Xform| {
            let mut v = x.e.to_cols_array().to_vec();
            v.extend(x.r.to_array());
            v
        };
        assert_close(&format!("{what}: frame {}", frame.name), &flat(b), &flat(a), 1e-12);
        worst[2] = worst[2].max(max_relative(&flat(b), &flat(a)));
    }

    // the same kinetic energy and mass
    let t_full = kinetic_energy(full, &mut ws_full, q_full, v_full).unwrap();
    let t_red = kinetic_energy(reduced, &mut ws_red, &q_red, &v_red).unwrap();
    assert_close(&format!("{what}: kinetic energy"), &[t_red], &[t_full], 1e-12);
    assert_close(&format!("{what}: total mass"), &[reduced.total_mass], &[full.total_mass], 1e-12);
    worst
}

fn worse(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0].max(b[0]), a[1].max(b[1]), a[2].max(b[2])]
}

/// Random trees: lock about a third of the joints (never the floating base) at a random `q`.
#[test]
fn reduced_dynamics_are_the_full_ones_restricted_on_random_trees() {
    let mut locked_total = 0;
    let mut spherical_locked = 0;
    let mut worst = [0.0_f64; 3];
    for seed in 0..60u64 {
        let mut rng = Rng::new(1000 + seed);
        let n = 2 + (seed as usize * 5) % 13;
        let base = if seed % 2 == 0 { Base::Fixed } else { Base::Floating };
        let full = random_tree(&mut rng, n, base, seed % 3 != 0);
        let q_full = random_q(&mut rng, &full);
        let mut v_full = rng.vector(full.nv(), 2.0);
        let mut locked: Vec<&str> = Vec::new();
        for b in &full.bodies {
            if b.joint.kind != JointKind::Floating && (rng.below(3) == 0 || locked.is_empty() && b.name == "link1") {
                locked.push(&b.joint.name);
                let j = &b.joint;
                v_full[j.v_index..j.v_index + j.kind.nv()].fill(0.0);
                spherical_locked += usize::from(j.kind == JointKind::Spherical);
            }
        }
        locked_total += locked.len();
        let reduced = reduced_model(&full, &locked, &q_full).unwrap();
        assert_eq!(reduced.nbodies(), full.nbodies() - locked.len());
        worst =
            worse(worst, check_reduced(&format!("seed {seed}, locked {locked:?}"), &full, &reduced, &q_full, &v_full));
    }
    eprintln!(
        "random trees: {locked_total} joints locked ({spherical_locked} spherical); largest relative differences: \
         M {:e}, bias {:e}, frames {:e}",
        worst[0], worst[1], worst[2]
    );
    assert!(locked_total > 100 && spherical_locked > 5, "{locked_total} locked, {spherical_locked} spherical");
}

/// Locking every joint of a fixed-base tree leaves no coordinates and all the mass on the world.
#[test]
fn locking_every_joint_leaves_the_world() {
    let mut rng = Rng::new(7);
    let full = random_tree(&mut rng, 6, Base::Fixed, true);
    let q = random_q(&mut rng, &full);
    let names: Vec<&str> = full.bodies.iter().map(|b| b.joint.name.as_str()).collect();
    let reduced = reduced_model(&full, &names, &q).unwrap();
    assert_eq!((reduced.nq(), reduced.nv(), reduced.nbodies()), (0, 0, 0));
    assert!(reduced.frames.iter().all(|f| f.body.is_none()));
    assert_close("world mass", &[reduced.world_inertia.mass], &[full.total_mass], 1e-12);
    // the world inertia is the sum of the links' inertias at their places
    let mut ws = Workspace::new(&full);
    update_placements(&full, &mut ws, &q).unwrap();
    let mut h = full.world_inertia.h;
    for (i, b) in full.bodies.iter().enumerate() {
        h += b.inertia.transform_to_a(&ws.x_world[i]).h;
    }
    assert_close("world first moment", &reduced.world_inertia.h.to_array(), &h.to_array(), 1e-12);
}

fn panda() -> MultibodyModel {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/robots/panda.urdf");
    load_urdf(&path, UrdfOptions::default()).unwrap()
}

#[test]
fn reduced_panda_is_the_full_panda_restricted() {
    let full = panda();
    let mut rng = Rng::new(42);
    let mut worst = [0.0_f64; 3];
    for locked in [
        vec!["panda_joint4"],
        vec!["panda_joint1"],
        vec!["panda_joint7", "panda_finger_joint1", "panda_finger_joint2"],
        vec!["panda_joint2", "panda_joint3", "panda_joint6"],
    ] {
        for _ in 0..5 {
            let q_full = random_q(&mut rng, &full);
            let mut v_full = rng.vector(full.nv(), 2.0);
            for name in &locked {
                let j = &full.bodies[full.joint_index(name).unwrap()].joint;
                v_full[j.v_index] = 0.0;
            }
            let reduced = reduced_model(&full, &locked, &q_full).unwrap();
            assert_eq!(reduced.nv(), full.nv() - locked.len());
            worst =
                worse(worst, check_reduced(&format!("panda, locked {locked:?}"), &full, &reduced, &q_full, &v_full));
            // the locked joint's link is a frame fixed by it
            let link =
                &reduced.frames[reduced.frame_index(&full.bodies[full.joint_index(locked[0]).unwrap()].name).unwrap()];
            assert!(
                matches!(&link.origin, FrameOrigin::Fixed { joint, .. } if joint == locked[0]),
                "{:?}",
                link.origin
            );
        }
    }
    eprintln!("panda: largest relative differences: M {:e}, bias {:e}, frames {:e}", worst[0], worst[1], worst[2]);
}

#[test]
fn lock_errors_name_the_joint() {
    let full = panda();
    let q = full.neutral_configuration();
    let err = |names: &[&str], q: &[f64]| reduced_model(&full, names, q).unwrap_err();
    assert_eq!(err(&["elbow"], &q), LockError::UnknownJoint { joint: "elbow".into() });
    // a fixed joint has nothing to lock
    assert_eq!(err(&["panda_hand_joint"], &q), LockError::UnknownJoint { joint: "panda_hand_joint".into() });
    assert_eq!(err(&["panda_joint2", "panda_joint2"], &q), LockError::Twice { joint: "panda_joint2".into() });
    assert_eq!(err(&["panda_joint2"], &q[1..]), LockError::Length { got: 8, expected: 9 });
    let floating = load_urdf(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/robots/panda.urdf"),
        UrdfOptions { floating: true, ..Default::default() },
    )
    .unwrap();
    let q = floating.neutral_configuration();
    assert_eq!(
        reduced_model(&floating, &["root_joint"], &q).unwrap_err(),
        LockError::FloatingBase { joint: "root_joint".into() }
    );
}

/// Relative tolerance against Pinocchio (measured: below 1e-15 on every case).
const PIN_TOL: f64 = 1e-12;

fn numbers(v: &serde_json::Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

fn rows(v: &serde_json::Value) -> Vec<f64> {
    v.as_array().unwrap().iter().flat_map(numbers).collect()
}

fn max_relative(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    a.iter().zip(b).fold(0.0_f64, |m, (x, y)| m.max((x - y).abs() / scale))
}

/// Pinocchio's `buildReducedModel` (fixture by `tools/pinocchio_reduced.py`): the same joints in the
/// same order (tumble numbering by joint name, as Pinocchio), the same mass matrix, bias forces and
/// link placements on random states of the reduced model.
#[test]
fn reduced_models_agree_with_pinocchio_build_reduced_model() {
    use tumble::multibody::ChildOrder;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/robots");
    let text = std::fs::read_to_string(dir.join("reduced.json")).unwrap();
    let fixture: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut worst = [0.0_f64; 3];
    for case in fixture["cases"].as_array().unwrap() {
        let floating = case["floating"].as_bool().unwrap();
        let options = UrdfOptions { floating, order: ChildOrder::JointName, ..Default::default() };
        let full = load_urdf(&dir.join(case["urdf"].as_str().unwrap()), options).unwrap();
        let locked: Vec<&str> = case["locked"].as_array().unwrap().iter().map(|n| n.as_str().unwrap()).collect();
        let what = format!("{} locked {locked:?}", case["robot"]);
        let reduced = reduced_model(&full, &locked, &numbers(&case["q_ref"])).unwrap();
        let names: Vec<&str> = reduced.bodies.iter().map(|b| b.joint.name.as_str()).collect();
        let want: Vec<&str> = case["joints"].as_array().unwrap().iter().map(|n| n.as_str().unwrap()).collect();
        assert_eq!(names, want, "{what}: joints");
        let layout = (case["nq"].as_u64().unwrap() as usize, case["nv"].as_u64().unwrap() as usize);
        assert_eq!((reduced.nq(), reduced.nv()), layout, "{what}: nq, nv");
        let mut ws = Workspace::new(&reduced);
        for state in case["states"].as_array().unwrap() {
            let (q, v) = (numbers(&state["q"]), numbers(&state["v"]));
            let m: Vec<f64> = crba(&reduced, &mut ws, &q).unwrap().transpose().iter().copied().collect();
            let m_pin = rows(&state["mass_matrix"]);
            assert_close(&format!("{what}: mass matrix"), &m, &m_pin, PIN_TOL);
            worst[0] = worst[0].max(max_relative(&m, &m_pin));
            let mut bias = vec![0.0; reduced.nv()];
            bias_forces(&reduced, &mut ws, &q, &v, &mut bias).unwrap();
            let bias_pin = numbers(&state["bias"]);
            assert_close(&format!("{what}: bias forces"), &bias, &bias_pin, PIN_TOL);
            worst[1] = worst[1].max(max_relative(&bias, &bias_pin));
            update_placements(&reduced, &mut ws, &q).unwrap();
            let frames = state["frames"].as_object().unwrap();
            let mut checked = 0;
            for (name, placement) in frames {
                // Pinocchio's BODY frames are the links; tumble keeps each link as a frame
                let Some(f) = reduced.frame_index(name) else { continue };
                let x = frame_x_world(&reduced, &ws, f);
                // world_from_link = Eᵀ, row by row; the origin is r
                let mut got: Vec<f64> = x.e.to_cols_array().to_vec();
                got.extend(x.r.to_array());
                let mut want = rows(&placement["rotation"]);
                want.extend(numbers(&placement["origin"]));
                assert_close(&format!("{what}: link {name}"), &got, &want, PIN_TOL);
                worst[2] = worst[2].max(max_relative(&got, &want));
                checked += 1;
            }
            assert_eq!(checked, full.frames.len(), "{what}: every link checked");
        }
    }
    eprintln!(
        "reduced models against Pinocchio's buildReducedModel: largest relative differences: mass matrix {:e}, bias \
         {:e}, link placements {:e}",
        worst[0], worst[1], worst[2]
    );
}
