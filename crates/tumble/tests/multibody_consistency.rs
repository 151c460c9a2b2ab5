//! The algorithms checked against each other on random trees (random axes, placements, inertias,
//! spherical joints, floating bases): RNEA, CRBA, LTDL, ABA, energy and the Jacobian.

mod multibody_common;

use multibody_common::{assert_close, random_q, random_tree, Base, Rng};
use nalgebra::{DMatrix, DVector};
use tumble::multibody::{
    aba, bias_forces, crba, forward_kinematics, frame_jacobian, kinetic_energy, ltdl_factor, ltdl_solve,
    potential_energy, rnea, MultibodyModel, Workspace,
};

/// The cases: (seed, bodies, base, spherical joints allowed).
fn cases() -> Vec<(u64, usize, Base, bool)> {
    let mut v = Vec::new();
    for seed in 0..40u64 {
        let n = 1 + (seed as usize * 7) % 14;
        let base = if seed % 2 == 0 { Base::Fixed } else { Base::Floating };
        v.push((seed, n, base, seed % 3 != 0));
    }
    v
}

fn model_and_state(seed: u64, n: usize, base: Base, spherical: bool) -> (MultibodyModel, Vec<f64>, Vec<f64>, Rng) {
    let mut rng = Rng::new(seed);
    let model = random_tree(&mut rng, n, base, spherical);
    let q = random_q(&mut rng, &model);
    let v = rng.vector(model.nv(), 2.0);
    (model, q, v, rng)
}

#[test]
fn aba_inverts_rnea() {
    for (seed, n, base, sph) in cases() {
        let (model, q, v, mut rng) = model_and_state(seed, n, base, sph);
        let mut ws = Workspace::new(&model);
        let a = rng.vector(model.nv(), 3.0);
        let mut tau = vec![0.0; model.nv()];
        rnea(&model, &mut ws, &q, &v, &a, &mut tau).unwrap();
        let mut qdd = vec![0.0; model.nv()];
        aba(&model, &mut ws, &q, &v, &tau, &mut qdd).unwrap();
        assert_close(&format!("seed {seed}: aba(q, v, rnea(q, v, a))"), &qdd, &a, 1e-10);
    }
}

#[test]
fn mass_matrix_times_a_plus_bias_is_rnea() {
    for (seed, n, base, sph) in cases() {
        let (model, q, v, mut rng) = model_and_state(seed, n, base, sph);
        let mut ws = Workspace::new(&model);
        let a = rng.vector(model.nv(), 3.0);
        let mut tau = vec![0.0; model.nv()];
        rnea(&model, &mut ws, &q, &v, &a, &mut tau).unwrap();
        let mut bias = vec![0.0; model.nv()];
        bias_forces(&model, &mut ws, &q, &v, &mut bias).unwrap();
        let m = crba(&model, &mut ws, &q).unwrap().clone();
        let m_a = &m * DVector::from_column_slice(&a);
        let lhs: Vec<f64> = m_a.iter().zip(&bias).map(|(x, b)| x + b).collect();
        assert_close(&format!("seed {seed}: M a + b"), &lhs, &tau, 1e-11);
    }
}

#[test]
fn mass_matrix_is_symmetric_positive_definite() {
    for (seed, n, base, sph) in cases() {
        let (model, q, _, _) = model_and_state(seed, n, base, sph);
        let mut ws = Workspace::new(&model);
        let m = crba(&model, &mut ws, &q).unwrap().clone();
        let asym = (&m - m.transpose()).abs().max();
        assert!(asym <= 1e-13 * m.abs().max(), "seed {seed}: M not symmetric ({asym:e})");
        let eig = m.clone().symmetric_eigenvalues();
        assert!(eig.min() > 0.0, "seed {seed}: M has eigenvalue {}", eig.min());
        // independent of the above: every leading minor through Cholesky
        assert!(m.cholesky().is_some(), "seed {seed}: Cholesky failed");
    }
}

#[test]
fn mass_matrix_is_zero_off_the_root_paths() {
    for (seed, n, base, sph) in cases() {
        let (model, q, _, _) = model_and_state(seed, n, base, sph);
        let mut ws = Workspace::new(&model);
        let m = crba(&model, &mut ws, &q).unwrap().clone();
        for r in 0..model.nv() {
            let mut ancestors = vec![false; model.nv()];
            let mut k = r;
            loop {
                ancestors[k] = true;
                let p = model.dof_parent(k);
                if p == usize::MAX {
                    break;
                }
                k = p;
            }
            for c in 0..r {
                if !ancestors[c] {
                    assert_eq!(m[(r, c)], 0.0, "seed {seed}: M[{r},{c}] links two branches");
                }
            }
        }
    }
}

#[test]
fn ltdl_solve_matches_dense_cholesky_and_aba() {
    for (seed, n, base, sph) in cases() {
        let (model, q, v, mut rng) = model_and_state(seed, n, base, sph);
        let mut ws = Workspace::new(&model);
        let tau = rng.vector(model.nv(), 5.0);
        let mut bias = vec![0.0; model.nv()];
        bias_forces(&model, &mut ws, &q, &v, &mut bias).unwrap();
        let m = crba(&model, &mut ws, &q).unwrap().clone();
        ltdl_factor(&model, &mut ws).unwrap();
        let mut x: Vec<f64> = tau.iter().zip(&bias).map(|(t, b)| t - b).collect();
        let rhs = DVector::from_column_slice(&x);
        ltdl_solve(&model, &ws, &mut x).unwrap();
        let dense = m.cholesky().unwrap().solve(&rhs);
        assert_close(&format!("seed {seed}: LTDL vs Cholesky"), &x, dense.as_slice(), 1e-10);
        let mut qdd = vec![0.0; model.nv()];
        aba(&model, &mut ws, &q, &v, &tau, &mut qdd).unwrap();
        assert_close(&format!("seed {seed}: M⁻¹ (τ − b) vs ABA"), &x, &qdd, 1e-10);
    }
}

#[test]
fn kinetic_energy_is_half_v_m_v() {
    for (seed, n, base, sph) in cases() {
        let (model, q, v, _) = model_and_state(seed, n, base, sph);
        let mut ws = Workspace::new(&model);
        let t = kinetic_energy(&model, &mut ws, &q, &v).unwrap();
        let m = crba(&model, &mut ws, &q).unwrap().clone();
        let vv = DVector::from_column_slice(&v);
        let t_m = 0.5 * vv.dot(&(&m * &vv));
        assert!((t - t_m).abs() <= 1e-12 * t_m.abs().max(1.0), "seed {seed}: T {t} vs ½ vᵀMv {t_m}");
    }
}

/// One RK4 step of `q̇ = G(q) v`, `v̇ = ABA(q, v, τ)`, written independently of `multibody::simulate`
/// (quaternions are left off the unit sphere by O(h⁵); the joint transforms normalise them).
fn rk4_step(model: &MultibodyModel, ws: &mut Workspace, q: &mut [f64], v: &mut [f64], tau: &[f64], h: f64) {
    let (nq, nv) = (model.nq(), model.nv());
    let f = |ws: &mut Workspace, q: &[f64], v: &[f64]| {
        let mut qd = vec![0.0; nq];
        model.coordinate_rate(q, v, &mut qd).unwrap();
        let mut vd = vec![0.0; nv];
        aba(model, ws, q, v, tau, &mut vd).unwrap();
        (qd, vd)
    };
    let axpy = |x: &[f64], k: &[f64], s: f64| -> Vec<f64> { x.iter().zip(k).map(|(a, b)| a + s * b).collect() };
    let (k1q, k1v) = f(ws, q, v);
    let (k2q, k2v) = f(ws, &axpy(q, &k1q, h / 2.0), &axpy(v, &k1v, h / 2.0));
    let (k3q, k3v) = f(ws, &axpy(q, &k2q, h / 2.0), &axpy(v, &k2v, h / 2.0));
    let (k4q, k4v) = f(ws, &axpy(q, &k3q, h), &axpy(v, &k3v, h));
    for i in 0..nq {
        q[i] += h / 6.0 * (k1q[i] + 2.0 * k2q[i] + 2.0 * k3q[i] + k4q[i]);
    }
    for i in 0..nv {
        v[i] += h / 6.0 * (k1v[i] + 2.0 * k2v[i] + 2.0 * k3v[i] + k4v[i]);
    }
}

fn energy(model: &MultibodyModel, ws: &mut Workspace, q: &[f64], v: &[f64]) -> f64 {
    kinetic_energy(model, ws, q, v).unwrap() + potential_energy(model, ws, q).unwrap()
}

/// `d/dt (T + V) = vᵀ τ` along the motion that ABA computes: a central difference of the energy over
/// two RK4 steps of `h = 1e-4` s forward and backward, against `vᵀ τ` at the midpoint.
#[test]
fn energy_rate_equals_power() {
    for (seed, n, base, sph) in cases() {
        let (model, q0, v0, mut rng) = model_and_state(seed, n, base, sph);
        let mut ws = Workspace::new(&model);
        let tau = rng.vector(model.nv(), 3.0);
        let h = 1e-4;
        let (mut qf, mut vf) = (q0.clone(), v0.clone());
        rk4_step(&model, &mut ws, &mut qf, &mut vf, &tau, h);
        let (mut qb, mut vb) = (q0.clone(), v0.clone());
        rk4_step(&model, &mut ws, &mut qb, &mut vb, &tau, -h);
        let rate = (energy(&model, &mut ws, &qf, &vf) - energy(&model, &mut ws, &qb, &vb)) / (2.0 * h);
        let power: f64 = v0.iter().zip(&tau).map(|(v, t)| v * t).sum();
        let scale = power.abs().max(1.0);
        // central difference: error O(h²) times third derivatives of E, ~1e-7 here
        assert!((rate - power).abs() <= 1e-5 * scale, "seed {seed}: dE/dt {rate} vs vᵀτ {power}");
    }
}

/// With no torque the total energy stays constant over 0.2 s of RK4 at `h = 1e-3` s.
#[test]
fn passive_trees_conserve_energy() {
    for (seed, n, base, sph) in cases().into_iter().take(12) {
        let (model, mut q, mut v, _) = model_and_state(seed, n, base, sph);
        let mut ws = Workspace::new(&model);
        let tau = vec![0.0; model.nv()];
        let e0 = energy(&model, &mut ws, &q, &v);
        for _ in 0..200 {
            rk4_step(&model, &mut ws, &mut q, &mut v, &tau, 1e-3);
        }
        let e1 = energy(&model, &mut ws, &q, &v);
        let scale = kinetic_energy(&model, &mut ws, &q, &v).unwrap().abs().max(1.0);
        assert!((e1 - e0).abs() <= 1e-6 * scale, "seed {seed}: energy {e0} → {e1}");
    }
}

/// The Jacobian of each body's frame maps `q̇` to the body velocity that FK computes.
#[test]
fn jacobian_maps_joint_rates_to_body_velocities() {
    for (seed, n, base, sph) in cases() {
        let (model, q, v, _) = model_and_state(seed, n, base, sph);
        let mut ws = Workspace::new(&model);
        let mut jac = DMatrix::zeros(6, model.nv());
        for (b, body) in model.bodies.iter().enumerate() {
            let f = model.frame_index(&body.name).unwrap();
            frame_jacobian(&model, &mut ws, &q, f, &mut jac).unwrap();
            let jv = &jac * DVector::from_column_slice(&v);
            forward_kinematics(&model, &mut ws, &q, &v).unwrap();
            assert_close(&format!("seed {seed} body {b}: J v"), jv.as_slice(), &ws.v[b].to_array(), 1e-12);
        }
    }
}

/// Wrong lengths are errors, not panics.
#[test]
fn wrong_lengths_are_errors() {
    let (model, q, v, _) = model_and_state(3, 5, Base::Floating, true);
    let mut ws = Workspace::new(&model);
    let mut out = vec![0.0; model.nv()];
    assert!(rnea(&model, &mut ws, &q[1..], &v, &v, &mut out).is_err());
    assert!(aba(&model, &mut ws, &q, &v[1..], &v, &mut out).is_err());
    assert!(aba(&model, &mut ws, &q, &v, &v, &mut out[1..]).is_err());
    assert!(crba(&model, &mut ws, &[]).is_err());
    let mut jac = DMatrix::zeros(6, model.nv());
    assert!(frame_jacobian(&model, &mut ws, &q, 999, &mut jac).is_err());
}
