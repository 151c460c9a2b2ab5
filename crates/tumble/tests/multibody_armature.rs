//! Joint armature, damping and springs (MuJoCo's `armature`, `damping`, `stiffness`/`springref`),
//! checked across the algorithms on random trees: CRBA's `M` gains `diag(a)`, ABA inverts that `M`,
//! RNEA adds `a q̈`, the kinetic energy is `½ vᵀ M v`, and the passive forces are `−d v − k (q − q_ref)`.

mod multibody_common;

use multibody_common::{assert_close, random_inertia, random_q, Rng};
use nalgebra::{DMatrix, DVector};
use tumble::math::DMat3;
use tumble::multibody::{
    aba, bias_forces, crba, kinetic_energy, passive_forces, potential_energy, rnea, Control, JointDynamics, JointKind,
    Method, ModelBuilder, MultibodyModel, Simulator, Workspace, Xform,
};

/// A random tree as `multibody_common::random_tree` builds it, and the same tree with random
/// armature, damping and (on one-coordinate joints) springs.
fn trees(seed: u64, n: usize, floating: bool) -> (MultibodyModel, MultibodyModel, Rng) {
    let mut rng = Rng::new(seed);
    let mut plain = ModelBuilder::new("plain");
    let mut with = ModelBuilder::new("with");
    for i in 0..n {
        let parent = if i == 0 { None } else { Some(rng.below(i)) };
        let kind = if i == 0 && floating {
            JointKind::Floating
        } else {
            match rng.below(4) {
                0 => JointKind::Revolute { axis: rng.unit() },
                1 => JointKind::Continuous { axis: rng.unit() },
                2 => JointKind::Prismatic { axis: rng.unit() },
                _ => JointKind::Spherical,
            }
        };
        let x_tree = Xform::from_pose(DMat3::from_quat(rng.quat()), rng.vec3(0.5));
        let inertia = random_inertia(&mut rng);
        plain.add_body(format!("link{i}"), parent, format!("joint{i}"), kind, x_tree, inertia).unwrap();
        let b = with.add_body(format!("link{i}"), parent, format!("joint{i}"), kind, x_tree, inertia).unwrap();
        let spring = kind.nv() == 1;
        let dynamics = JointDynamics {
            armature: rng.range(0.0, 0.5),
            damping: rng.range(0.0, 2.0),
            stiffness: if spring { rng.range(0.0, 5.0) } else { 0.0 },
            spring_ref: if spring { rng.range(-0.5, 0.5) } else { 0.0 },
            friction_loss: 0.0,
        };
        with.set_dynamics(b, dynamics).unwrap();
    }
    (plain.build().unwrap(), with.build().unwrap(), rng)
}

fn mass_matrix(model: &MultibodyModel, q: &[f64]) -> DMatrix<f64> {
    let mut ws = Workspace::new(model);
    crba(model, &mut ws, q).unwrap().clone()
}

#[test]
fn armature_adds_to_the_mass_matrix_diagonal_only() {
    for seed in 0..20 {
        let (plain, with, mut rng) = trees(seed, 1 + seed as usize % 9, seed % 2 == 1);
        let q = random_q(&mut rng, &with);
        let mut expected = mass_matrix(&plain, &q);
        for b in &with.bodies {
            for k in b.joint.v_index..b.joint.v_index + b.joint.kind.nv() {
                expected[(k, k)] += b.joint.dynamics.armature;
            }
        }
        let m = mass_matrix(&with, &q);
        assert_close("M with armature", m.as_slice(), expected.as_slice(), 1e-14);
    }
}

#[test]
fn aba_rnea_and_energy_use_the_mass_matrix_with_armature() {
    for seed in 0..30 {
        let (_, model, mut rng) = trees(seed, 1 + seed as usize % 11, seed % 2 == 0);
        let nv = model.nv();
        let q = random_q(&mut rng, &model);
        let v = rng.vector(nv, 2.0);
        let tau = rng.vector(nv, 3.0);
        let mut ws = Workspace::new(&model);
        let m = mass_matrix(&model, &q);
        let mut b = vec![0.0; nv];
        bias_forces(&model, &mut ws, &q, &v, &mut b).unwrap();
        // q̈ = M⁻¹ (τ − b)
        let rhs = DVector::from_iterator(nv, tau.iter().zip(&b).map(|(t, b)| t - b));
        let expected = m.clone().cholesky().unwrap().solve(&rhs);
        let mut qdd = vec![0.0; nv];
        aba(&model, &mut ws, &q, &v, &tau, &mut qdd).unwrap();
        assert_close("ABA vs M⁻¹(τ − b)", &qdd, expected.as_slice(), 1e-10);
        // RNEA(q, v, ABA(τ)) = τ
        let mut tau_back = vec![0.0; nv];
        rnea(&model, &mut ws, &q, &v, &qdd, &mut tau_back).unwrap();
        assert_close("RNEA(ABA(τ))", &tau_back, &tau, 1e-10);
        // T = ½ vᵀ M v
        let vv = DVector::from_column_slice(&v);
        let t = kinetic_energy(&model, &mut ws, &q, &v).unwrap();
        assert_close("T", &[t], &[0.5 * vv.dot(&(&m * &vv))], 1e-12);
    }
}

#[test]
fn passive_forces_are_damping_and_springs() {
    let (_, model, mut rng) = trees(7, 8, true);
    let q = random_q(&mut rng, &model);
    let v = rng.vector(model.nv(), 2.0);
    let mut tau = vec![0.0; model.nv()];
    let mut ws = Workspace::new(&model);
    passive_forces(&model, &mut ws, &q, &v, &mut tau).unwrap();
    for b in &model.bodies {
        let j = &b.joint;
        for k in j.v_index..j.v_index + j.kind.nv() {
            let mut expected = -j.dynamics.damping * v[k];
            if j.kind.nv() == 1 {
                expected -= j.dynamics.stiffness * (q[j.q_index] - j.dynamics.spring_ref);
            }
            assert_close(&format!("τ_passive[{k}]"), &[tau[k]], &[expected], 1e-15);
        }
    }
}

/// Springs alone conserve `T + V` (RK4 at a small step); damping only takes energy away.
#[test]
fn springs_conserve_and_damping_dissipates_energy() {
    let mut rng = Rng::new(3);
    let mut builder = ModelBuilder::new("springs");
    for i in 0..4 {
        let parent = if i == 0 { None } else { Some(i - 1) };
        let x_tree = Xform::from_pose(DMat3::from_quat(rng.quat()), rng.vec3(0.5));
        let b = builder
            .add_body(
                format!("l{i}"),
                parent,
                format!("j{i}"),
                JointKind::Continuous { axis: rng.unit() },
                x_tree,
                random_inertia(&mut rng),
            )
            .unwrap();
        builder
            .set_dynamics(
                b,
                JointDynamics { armature: 0.1, damping: 0.0, stiffness: 3.0, spring_ref: 0.3, friction_loss: 0.0 },
            )
            .unwrap();
    }
    let springs = builder.build().unwrap();
    let energy = |model: &MultibodyModel, q: &[f64], v: &[f64]| {
        let mut ws = Workspace::new(model);
        kinetic_energy(model, &mut ws, q, v).unwrap() + potential_energy(model, &mut ws, q).unwrap()
    };
    let q0 = vec![0.5, -0.4, 0.2, 0.1];
    let v0 = vec![0.0; 4];
    let e0 = energy(&springs, &q0, &v0);
    let control = Control::passive(&springs);
    let mut sim = Simulator::new(&springs, q0.clone(), v0.clone()).unwrap();
    for _ in 0..2000 {
        sim.step(&springs, &control, Method::Rk4, 1e-3).unwrap();
    }
    let e1 = energy(&springs, &sim.q, &sim.v);
    assert!((e1 - e0).abs() <= 1e-8 * e0.abs().max(1.0), "springs: energy {e0} → {e1}");

    let mut damped = springs.clone();
    for b in damped.bodies.iter_mut() {
        b.joint.dynamics.damping = 0.5;
    }
    let mut sim = Simulator::new(&damped, q0, v0).unwrap();
    let mut last = e0;
    for _ in 0..200 {
        for _ in 0..10 {
            sim.step(&damped, &control, Method::Rk4, 1e-3).unwrap();
        }
        let e = energy(&damped, &sim.q, &sim.v);
        assert!(e <= last + 1e-9, "damping gained energy: {last} → {e}");
        last = e;
    }
    assert!(last < e0 - 1e-3, "damping took no energy: {e0} → {last}");
}
