//! Agreement with Pinocchio on real robots: joint layout, mass matrix (CRBA), bias forces and
//! inverse dynamics (RNEA), forward dynamics (ABA), to 1e-9 relative.
//!
//! The fixtures (`tests/fixtures/robots/*.json`) are written by `tools/pinocchio_fixtures.py`; their
//! vectors follow Pinocchio's joint order, which is depth-first with a link's children sorted by joint
//! name. With [`ChildOrder::JointName`] tumble numbers the joints the same way (checked); with the
//! default [`ChildOrder::File`] the comparison goes through the permutation given by the joint names.

mod multibody_common;

use multibody_common::assert_close;
use serde_json::Value;
use std::collections::HashMap;
use std::path::PathBuf;
use tumble::multibody::{aba, bias_forces, crba, load_urdf, rnea, ChildOrder, UrdfOptions, Workspace};

/// Relative tolerance of the comparison (relative to the largest entry of each quantity).
const TOL: f64 = 1e-9;

fn fixtures_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/robots")
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

fn check_robot(name: &str, order: ChildOrder) {
    let dir = fixtures_dir();
    let text = std::fs::read_to_string(dir.join(format!("{name}.json"))).unwrap();
    let fixture: Value = serde_json::from_str(&text).unwrap();
    let floating = fixture["floating"].as_bool().unwrap();
    let urdf = dir.join(fixture["urdf"].as_str().unwrap());
    let model = load_urdf(&urdf, UrdfOptions { floating, order, ..Default::default() }).unwrap();
    let nv = model.nv();
    assert_eq!(nv as u64, fixture["nv"].as_u64().unwrap(), "{name}: nv");

    // Pinocchio's layout: joint name → (q index, v index)
    let joints = fixture["joints"].as_array().unwrap();
    assert_eq!(model.nbodies(), joints.len(), "{name}: number of joints");
    let mut pin_index = HashMap::new();
    let (mut iq, mut iv) = (0, 0);
    for j in joints {
        let (nq, nv) = (j["nq"].as_u64().unwrap() as usize, j["nv"].as_u64().unwrap() as usize);
        pin_index.insert(j["name"].as_str().unwrap().to_string(), (iq, iv, nq, nv));
        iq += nq;
        iv += nv;
    }
    if order == ChildOrder::JointName {
        for (body, j) in model.bodies.iter().zip(joints) {
            assert_eq!(body.joint.name, j["name"].as_str().unwrap(), "{name}: joint order");
        }
    }
    // perm_q[k] / perm_v[k]: Pinocchio's index of tumble's coordinate k
    let mut perm_q = vec![usize::MAX; model.nq()];
    let mut perm_v = vec![usize::MAX; nv];
    for body in &model.bodies {
        let j = &body.joint;
        let &(pq, pv, pnq, pnv) = pin_index.get(&j.name).unwrap_or_else(|| panic!("{name}: joint {}", j.name));
        assert_eq!((j.kind.nq(), j.kind.nv()), (pnq, pnv), "{name}: nq, nv of {}", j.name);
        for k in 0..pnq {
            perm_q[j.q_index + k] = pq + k;
        }
        for k in 0..pnv {
            perm_v[j.v_index + k] = pv + k;
        }
    }
    let to_tumble = |x: &[f64], perm: &[usize]| -> Vec<f64> { perm.iter().map(|&p| x[p]).collect() };

    let moving_mass: f64 = model.bodies.iter().map(|b| b.inertia.mass).sum();
    let expected_mass = fixture["total_mass"].as_f64().unwrap();
    assert!(
        (moving_mass - expected_mass).abs() <= 1e-12 * expected_mass,
        "{name}: mass {moving_mass} vs {expected_mass}"
    );

    let mut ws = Workspace::new(&model);
    for (s, state) in fixture["states"].as_array().unwrap().iter().enumerate() {
        let q = to_tumble(&numbers(&state["q"]), &perm_q);
        let v = to_tumble(&numbers(&state["v"]), &perm_v);
        let a = to_tumble(&numbers(&state["a"]), &perm_v);
        let tau_in = to_tumble(&numbers(&state["tau_in"]), &perm_v);

        let m = crba(&model, &mut ws, &q).unwrap();
        let rows: Vec<Vec<f64>> = state["mass_matrix"].as_array().unwrap().iter().map(numbers).collect();
        let m_tumble: Vec<f64> = (0..nv).flat_map(|r| (0..nv).map(move |c| (r, c))).map(|(r, c)| m[(r, c)]).collect();
        let m_expected: Vec<f64> =
            (0..nv).flat_map(|r| (0..nv).map(move |c| (r, c))).map(|(r, c)| rows[perm_v[r]][perm_v[c]]).collect();
        assert_close(&format!("{name} state {s}: mass matrix"), &m_tumble, &m_expected, TOL);

        let mut out = vec![0.0; nv];
        bias_forces(&model, &mut ws, &q, &v, &mut out).unwrap();
        assert_close(&format!("{name} state {s}: bias"), &out, &to_tumble(&numbers(&state["bias"]), &perm_v), TOL);

        rnea(&model, &mut ws, &q, &v, &a, &mut out).unwrap();
        assert_close(&format!("{name} state {s}: tau"), &out, &to_tumble(&numbers(&state["tau"]), &perm_v), TOL);

        aba(&model, &mut ws, &q, &v, &tau_in, &mut out).unwrap();
        assert_close(&format!("{name} state {s}: qdd"), &out, &to_tumble(&numbers(&state["qdd"]), &perm_v), TOL);
    }
}

fn check_both_orders(name: &str) {
    check_robot(name, ChildOrder::JointName);
    check_robot(name, ChildOrder::File);
}

#[test]
fn double_pendulum_agrees_with_pinocchio() {
    check_both_orders("double_pendulum");
}

#[test]
fn continuous_double_pendulum_agrees_with_pinocchio() {
    check_both_orders("double_pendulum_continuous");
}

#[test]
fn ur5_agrees_with_pinocchio() {
    check_both_orders("ur5");
}

#[test]
fn panda_agrees_with_pinocchio() {
    check_both_orders("panda");
}

#[test]
fn solo12_floating_agrees_with_pinocchio() {
    check_both_orders("solo12");
}

#[test]
fn talos_floating_agrees_with_pinocchio() {
    check_both_orders("talos_reduced");
}

/// The default numbering follows the file: Talos's first joint after the base is `torso_1_joint`
/// (first in the file), where Pinocchio's is `leg_left_1_joint` (first by name).
#[test]
fn default_joint_order_is_the_file_order() {
    let urdf = fixtures_dir().join("talos_reduced.urdf");
    let file = load_urdf(&urdf, UrdfOptions { floating: true, order: ChildOrder::File, ..Default::default() }).unwrap();
    let by_name =
        load_urdf(&urdf, UrdfOptions { floating: true, order: ChildOrder::JointName, ..Default::default() }).unwrap();
    assert_eq!(file.bodies[1].joint.name, "torso_1_joint");
    assert_eq!(by_name.bodies[1].joint.name, "leg_left_1_joint");
}
