//! The collision matrix of a point on a link, three ways: test impulses through ABA's articulated
//! inertias (`multibody::impulse_aba`), the sparse `LᵀDL` factor (`multibody::contact_point`), and a
//! dense `J_c M⁻¹ J_cᵀ` with `M` from CRBA; Pinocchio as the oracle through a committed fixture.
//!
//! - On random trees (fixed and floating bases, spherical joints): `J_c` against finite differences
//!   of forward kinematics and `J_c v` against the body velocity of `fk`; `K` and `Δv = M⁻¹ J_cᵀ p` by
//!   the three ways; `K` symmetric positive semi-definite.
//! - `tests/fixtures/contact_point.json` (written by `tools/pinocchio_impulse.py`): `J_c`, `K` and the
//!   velocity after a rigid impact (`pin.impulseDynamics`, restitution 0 and 1) on the Panda and the
//!   double pendulum (fixed base) and the Panda on a free-flyer base.
//!
//! Each test prints its largest relative error (`--nocapture`). The sweeps allocate nothing (counted by
//! a per-thread counting allocator, as in `tumble-cli/tests/no_alloc.rs`).

mod multibody_common;

use multibody_common::{assert_close, random_q, random_tree, Base, Rng};
use nalgebra::{DMatrix, Matrix3, Vector3};
use serde_json::Value;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use tumble::math::{DMat3, DVec3};
use tumble::multibody::contact_point::{collision_matrix, impulse_response, point_jacobian};
use tumble::multibody::impulse_aba::{collision_matrix_aba, impulse_velocity_change, ImpulseScratch};
use tumble::multibody::{
    aba, crba, forward_kinematics, load_urdf, ltdl_factor, update_placements, ChildOrder, MultibodyModel, UrdfOptions,
    Workspace,
};

struct Counting;

thread_local! {
    /// Allocations (and reallocations) made by this thread.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // `try_with`: the slot may be gone while the thread ends
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Relative tolerance of `J_c`, `K` and `Δv` (round-off of `O(n)` operations).
const TOL: f64 = 1e-12;
/// Relative tolerance of the velocity after an impact (a 3 × 3 solve with `K` on top).
const TOL_IMPACT: f64 = 1e-10;

/// The random cases: (seed, bodies, base, spherical joints allowed).
fn cases() -> Vec<(u64, usize, Base, bool)> {
    (0..40u64)
        .map(|seed| {
            let n = 1 + (seed as usize * 5) % 13;
            let base = if seed % 2 == 0 { Base::Fixed } else { Base::Floating };
            (seed, n, base, seed % 3 != 0)
        })
        .collect()
}

/// `max |a − b| / max(1, max |b|)`: the measure of [`assert_close`].
fn rel_err(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max) / scale
}

fn mat3(k: DMat3) -> [f64; 9] {
    k.transpose().to_cols_array() // row-major
}

/// A random point fixed on a random body, in body coordinates (within 0.5 m of its origin).
fn random_point(rng: &mut Rng, model: &MultibodyModel) -> (usize, DVec3) {
    (rng.below(model.nbodies()), rng.vec3(0.5))
}

/// The world position of a point fixed on `body` (body coordinates `point_body`) at `q`.
fn point_world_at(model: &MultibodyModel, ws: &mut Workspace, q: &[f64], body: usize, point_body: DVec3) -> DVec3 {
    update_placements(model, ws, q).unwrap();
    ws.x_world[body].inv_apply_point(point_body)
}

/// `d/dh c(q ⊕ h e_j)` at `h = 0` by central differences with two Richardson steps (`O(h⁶)`).
fn fd_column(model: &MultibodyModel, ws: &mut Workspace, q: &[f64], j: usize, body: usize, point_body: DVec3) -> DVec3 {
    let mut e = vec![0.0; model.nv()];
    e[j] = 1.0;
    let mut q_step = vec![0.0; model.nq()];
    let mut central = |h: f64| {
        model.integrate(q, &e, h, &mut q_step).unwrap();
        let plus = point_world_at(model, ws, &q_step, body, point_body);
        model.integrate(q, &e, -h, &mut q_step).unwrap();
        let minus = point_world_at(model, ws, &q_step, body, point_body);
        (plus - minus) / (2.0 * h)
    };
    let h = 1e-2;
    let (d1, d2, d4) = (central(h), central(h / 2.0), central(h / 4.0));
    // R(h) = (4 D(h/2) − D(h)) / 3, then (16 R(h/2) − R(h)) / 15
    let (r1, r2) = ((4.0 * d2 - d1) / 3.0, (4.0 * d4 - d2) / 3.0);
    (16.0 * r2 - r1) / 15.0
}

#[test]
fn point_jacobian_is_the_derivative_of_the_point_and_gives_its_velocity() {
    let (mut worst_fd, mut worst_v) = (0.0_f64, 0.0_f64);
    for (seed, n, base, sph) in cases() {
        let mut rng = Rng::new(seed);
        let model = random_tree(&mut rng, n, base, sph);
        let nv = model.nv();
        let mut ws = Workspace::new(&model);
        for _ in 0..4 {
            let q = random_q(&mut rng, &model);
            let v = rng.vector(nv, 2.0);
            let (body, point_body) = random_point(&mut rng, &model);
            let point_world = point_world_at(&model, &mut ws, &q, body, point_body);
            crba(&model, &mut ws, &q).unwrap();
            let mut jac = vec![0.0; 3 * nv];
            point_jacobian(&model, &ws, body, point_world, &mut jac).unwrap();

            // column j = d/dh c(q ⊕ h e_j)
            let mut fd = vec![0.0; 3 * nv];
            for j in 0..nv {
                let col = fd_column(&model, &mut ws, &q, j, body, point_body);
                fd[j] = col.x;
                fd[nv + j] = col.y;
                fd[2 * nv + j] = col.z;
            }
            let what = format!("seed {seed}: J_c against finite differences (body {body})");
            assert_close(&what, &jac, &fd, TOL);
            worst_fd = worst_fd.max(rel_err(&jac, &fd));

            // J_c v = R_k (v_k.lin + v_k.ang × c_k), from fk's body velocity
            forward_kinematics(&model, &mut ws, &q, &v).unwrap();
            let vk = ws.v[body];
            let u_fk = ws.x_world[body].rotation_a_from_b() * (vk.lin + vk.ang.cross(point_body));
            let u_jac = tumble::multibody::contact_point::point_velocity(&jac, &v);
            let what = format!("seed {seed}: J_c v against fk (body {body})");
            assert_close(&what, &u_jac.to_array(), &u_fk.to_array(), TOL);
            worst_v = worst_v.max(rel_err(&u_jac.to_array(), &u_fk.to_array()));
        }
    }
    eprintln!("J_c: largest relative error against finite differences {worst_fd:.2e}, J_c v against fk {worst_v:.2e}");
}

#[test]
fn collision_matrix_three_ways_on_random_trees() {
    let (mut worst_k, mut worst_dv, mut worst_sym, mut min_eig) = (0.0_f64, 0.0_f64, 0.0_f64, f64::INFINITY);
    for (seed, n, base, sph) in cases() {
        let mut rng = Rng::new(1000 + seed);
        let model = random_tree(&mut rng, n, base, sph);
        let nv = model.nv();
        let mut ws = Workspace::new(&model);
        let mut scratch = ImpulseScratch::new(&model);
        for _ in 0..4 {
            let q = random_q(&mut rng, &model);
            let (body, point_body) = random_point(&mut rng, &model);
            let point_world = point_world_at(&model, &mut ws, &q, body, point_body);

            // dense: K = J_c M⁻¹ J_cᵀ, M from CRBA inverted by nalgebra
            let m = crba(&model, &mut ws, &q).unwrap().clone();
            let m_inv = m.clone().cholesky().expect("M positive definite").inverse();
            let mut jac = vec![0.0; 3 * nv];
            point_jacobian(&model, &ws, body, point_world, &mut jac).unwrap();
            let j_dense = DMatrix::from_row_slice(3, nv, &jac);
            let k_dense = &j_dense * &m_inv * j_dense.transpose();
            let k_dense: Vec<f64> = (0..3).flat_map(|r| (0..3).map(move |c| (r, c))).map(|rc| k_dense[rc]).collect();

            // LᵀDL: W = M⁻¹ J_cᵀ, K = J_c W
            ltdl_factor(&model, &mut ws).unwrap();
            let mut w = vec![0.0; 3 * nv];
            impulse_response(&model, &ws, &jac, &mut w).unwrap();
            let k_ltdl = mat3(collision_matrix(&jac, &w, nv));

            // test impulses through ABA's articulated inertias (any v and τ: they depend on q only)
            let (v, tau) = (rng.vector(nv, 2.0), rng.vector(nv, 5.0));
            let mut qdd = vec![0.0; nv];
            aba(&model, &mut ws, &q, &v, &tau, &mut qdd).unwrap();
            let k_aba = mat3(collision_matrix_aba(&model, &ws, &mut scratch, body, point_world).unwrap());

            assert_close(&format!("seed {seed}: K (ABA) against J M⁻¹ Jᵀ"), &k_aba, &k_dense, TOL);
            assert_close(&format!("seed {seed}: K (LᵀDL) against J M⁻¹ Jᵀ"), &k_ltdl, &k_dense, TOL);
            assert_close(&format!("seed {seed}: K (ABA) against K (LᵀDL)"), &k_aba, &k_ltdl, TOL);
            worst_k = worst_k.max(rel_err(&k_aba, &k_dense)).max(rel_err(&k_ltdl, &k_dense));

            // Δv of a random impulse: ABA sweep, W p (LᵀDL), M⁻¹ J_cᵀ p (dense)
            let p = rng.vec3(3.0);
            let mut dv_aba = vec![0.0; nv];
            impulse_velocity_change(&model, &ws, &mut scratch, body, point_world, p, &mut dv_aba).unwrap();
            let mut dv_ltdl = vec![0.0; nv];
            tumble::multibody::contact_point::apply_impulse(&w, p, &mut dv_ltdl);
            let dv_dense = &m_inv * j_dense.transpose() * Vector3::new(p.x, p.y, p.z);
            let dv_dense: Vec<f64> = dv_dense.iter().copied().collect();
            assert_close(&format!("seed {seed}: Δv (ABA) against M⁻¹ Jᵀ p"), &dv_aba, &dv_dense, TOL);
            assert_close(&format!("seed {seed}: Δv (LᵀDL) against M⁻¹ Jᵀ p"), &dv_ltdl, &dv_dense, TOL);
            worst_dv = worst_dv.max(rel_err(&dv_aba, &dv_dense)).max(rel_err(&dv_ltdl, &dv_dense));

            // symmetry without the symmetrisation: e_sᵀ J_c Δv(e_r) = e_rᵀ J_c Δv(e_s), Δv from the whole sweep
            let mut k_cols = [[0.0; 3]; 3];
            for (r, col) in k_cols.iter_mut().enumerate() {
                impulse_velocity_change(&model, &ws, &mut scratch, body, point_world, DVec3::AXES[r], &mut dv_aba)
                    .unwrap();
                *col = tumble::multibody::contact_point::point_velocity(&jac, &dv_aba).to_array();
            }
            let raw: Vec<f64> = (0..3).flat_map(|r| (0..3).map(move |s| (r, s))).map(|(r, s)| k_cols[s][r]).collect();
            let raw_t: Vec<f64> = (0..3).flat_map(|r| (0..3).map(move |s| (r, s))).map(|(r, s)| k_cols[r][s]).collect();
            assert_close(&format!("seed {seed}: K (ABA, unsymmetrised) symmetric"), &raw, &raw_t, TOL);
            assert_close(&format!("seed {seed}: J_c Δv(e_r) against K"), &raw, &k_dense, TOL);
            worst_sym = worst_sym.max(rel_err(&raw, &raw_t));

            // positive semi-definite: eigenvalues ≥ −round-off (rank ≤ min(3, nv), so zeros occur)
            let km = Matrix3::from_row_slice(&k_aba);
            let eig = km.symmetric_eigenvalues();
            let scale = km.abs().max();
            assert!(eig.min() >= -TOL * scale, "seed {seed}: K has eigenvalue {:e} (scale {scale:e})", eig.min());
            min_eig = min_eig.min(eig.min() / scale);
        }
    }
    eprintln!(
        "K: largest relative error {worst_k:.2e}; Δv {worst_dv:.2e}; asymmetry {worst_sym:.2e}; \
         smallest eigenvalue / max |K| {min_eig:.2e}"
    );
}

#[test]
fn impulse_sweeps_allocate_nothing() {
    let mut rng = Rng::new(7);
    let model = random_tree(&mut rng, 12, Base::Floating, true);
    let nv = model.nv();
    let mut ws = Workspace::new(&model);
    let mut scratch = ImpulseScratch::new(&model);
    let q = random_q(&mut rng, &model);
    let (v, tau) = (rng.vector(nv, 2.0), rng.vector(nv, 5.0));
    let mut qdd = vec![0.0; nv];
    aba(&model, &mut ws, &q, &v, &tau, &mut qdd).unwrap();
    let mut dv = vec![0.0; nv];
    let mut trace = 0.0;
    let before = ALLOCATIONS.with(Cell::get);
    for body in 0..model.nbodies() {
        let point_world = DVec3::new(0.1 * body as f64, -0.2, 0.3);
        impulse_velocity_change(&model, &ws, &mut scratch, body, point_world, DVec3::ONE, &mut dv).unwrap();
        let k = collision_matrix_aba(&model, &ws, &mut scratch, body, point_world).unwrap();
        trace += k.x_axis.x + k.y_axis.y + k.z_axis.z + dv[0];
    }
    let allocations = ALLOCATIONS.with(Cell::get) - before;
    assert!(trace.is_finite());
    assert_eq!(allocations, 0, "allocations in {} impulse sweeps", 2 * model.nbodies());
}

/// A singular pose: a planar two-link arm struck at its tip, so the point moves in a plane and `K`
/// has a zero eigenvalue; the three ways still agree and the null direction is the plane's normal.
#[test]
fn collision_matrix_is_singular_for_a_planar_arm() {
    let urdf = repo().join("scenes/robots/double_pendulum.urdf");
    let model = load_urdf(&urdf, UrdfOptions::default()).unwrap();
    let mut ws = Workspace::new(&model);
    let mut scratch = ImpulseScratch::new(&model);
    let q = [0.4, -1.1];
    let body = model.nbodies() - 1;
    let point_world = point_world_at(&model, &mut ws, &q, body, DVec3::new(0.0, 0.0, -1.0));
    let mut qdd = [0.0; 2];
    aba(&model, &mut ws, &q, &[0.3, 0.2], &[0.0; 2], &mut qdd).unwrap();
    let k = collision_matrix_aba(&model, &ws, &mut scratch, body, point_world).unwrap();
    // the arm swings about x: no velocity along x, K e_x = 0
    let eig = Matrix3::from_row_slice(&mat3(k)).symmetric_eigenvalues();
    assert!(k.x_axis.length() <= TOL * eig.max(), "K e_x of an arm in the y–z plane: {}", k.x_axis);
    assert!(eig.min().abs() <= TOL * eig.max(), "one zero eigenvalue: {eig:?}");
    assert!(eig.iter().filter(|&&e| e > 1e-6).count() == 2, "rank 2: {eig:?}");
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

fn rows(v: &Value) -> Vec<Vec<f64>> {
    v.as_array().unwrap().iter().map(numbers).collect()
}

fn vec3(v: &Value) -> DVec3 {
    let x = numbers(v);
    DVec3::new(x[0], x[1], x[2])
}

/// Largest relative errors of one fixture model: (J_c, K, v⁺, J_cᵀ p).
fn check_pinocchio_model(fixture: &Value, order: ChildOrder) -> [f64; 4] {
    let name = fixture["name"].as_str().unwrap();
    let floating = fixture["floating"].as_bool().unwrap();
    let urdf = repo().join(fixture["urdf"].as_str().unwrap());
    let model = load_urdf(&urdf, UrdfOptions { floating, order, ..Default::default() }).unwrap();
    let nv = model.nv();
    assert_eq!(nv as u64, fixture["nv"].as_u64().unwrap(), "{name}: nv");
    let moving_mass: f64 = model.bodies.iter().map(|b| b.inertia.mass).sum();
    let expected_mass = fixture["moving_mass"].as_f64().unwrap();
    assert!(
        (moving_mass - expected_mass).abs() <= 1e-12 * expected_mass,
        "{name}: mass {moving_mass} vs {expected_mass}"
    );

    // perm_q[k] / perm_v[k]: Pinocchio's index of tumble's coordinate k (as in multibody_pinocchio.rs)
    let mut pin_index = HashMap::new();
    let (mut iq, mut iv) = (0, 0);
    for j in fixture["joints"].as_array().unwrap() {
        let (jq, jv) = (j["nq"].as_u64().unwrap() as usize, j["nv"].as_u64().unwrap() as usize);
        pin_index.insert(j["name"].as_str().unwrap().to_string(), (iq, iv, jq, jv));
        iq += jq;
        iv += jv;
    }
    assert_eq!(model.nbodies(), pin_index.len(), "{name}: number of joints");
    let mut perm_q = vec![usize::MAX; model.nq()];
    let mut perm_v = vec![usize::MAX; nv];
    for body in &model.bodies {
        let j = &body.joint;
        let &(pq, pv, pnq, pnv) = pin_index.get(&j.name).unwrap_or_else(|| panic!("{name}: joint {}", j.name));
        assert_eq!((j.kind.nq(), j.kind.nv()), (pnq, pnv), "{name}: nq, nv of {}", j.name);
        (0..pnq).for_each(|k| perm_q[j.q_index + k] = pq + k);
        (0..pnv).for_each(|k| perm_v[j.v_index + k] = pv + k);
    }
    let to_tumble = |x: &[f64], perm: &[usize]| -> Vec<f64> { perm.iter().map(|&p| x[p]).collect() };

    let mut ws = Workspace::new(&model);
    let mut scratch = ImpulseScratch::new(&model);
    let mut worst = [0.0_f64; 4];
    for (s, state) in fixture["states"].as_array().unwrap().iter().enumerate() {
        let q = to_tumble(&numbers(&state["q"]), &perm_q);
        let v_before = to_tumble(&numbers(&state["v_before"]), &perm_v);
        crba(&model, &mut ws, &q).unwrap();
        ltdl_factor(&model, &mut ws).unwrap();
        let mut qdd = vec![0.0; nv];
        aba(&model, &mut ws, &q, &v_before, &vec![0.0; nv], &mut qdd).unwrap();
        update_placements(&model, &mut ws, &q).unwrap();
        for (c, contact) in state["contacts"].as_array().unwrap().iter().enumerate() {
            let what = format!("{name} ({order:?}) state {s} contact {c}");
            let link = contact["link"].as_str().unwrap();
            let frame = &model.frames[model.frame_index(link).unwrap_or_else(|| panic!("{what}: link {link}"))];
            let body = frame.body.unwrap_or_else(|| panic!("{what}: {link} is fixed to the world"));
            // c_body = body_X_frame c_link, c_world = 0_X_body c_body
            let point_body = frame.x_from_body.inv_apply_point(vec3(&contact["point_link"]));
            let point_world = ws.x_world[body].inv_apply_point(point_body);
            assert_close(&format!("{what}: point"), &point_world.to_array(), &numbers(&contact["point_world"]), TOL);

            let mut jac = vec![0.0; 3 * nv];
            point_jacobian(&model, &ws, body, point_world, &mut jac).unwrap();
            let jac_pin: Vec<f64> = rows(&contact["jacobian"]).iter().flat_map(|row| to_tumble(row, &perm_v)).collect();
            assert_close(&format!("{what}: J_c"), &jac, &jac_pin, TOL);
            worst[0] = worst[0].max(rel_err(&jac, &jac_pin));

            let mut w = vec![0.0; 3 * nv];
            impulse_response(&model, &ws, &jac, &mut w).unwrap();
            let k_ltdl = collision_matrix(&jac, &w, nv);
            let k_aba = collision_matrix_aba(&model, &ws, &mut scratch, body, point_world).unwrap();
            let k_pin: Vec<f64> = rows(&contact["collision_matrix"]).concat();
            assert_close(&format!("{what}: K (LᵀDL)"), &mat3(k_ltdl), &k_pin, TOL);
            assert_close(&format!("{what}: K (ABA)"), &mat3(k_aba), &k_pin, TOL);
            worst[1] = worst[1].max(rel_err(&mat3(k_ltdl), &k_pin)).max(rel_err(&mat3(k_aba), &k_pin));

            // the impact: K p = −(1 + r) J_c v⁻, v⁺ = v⁻ + W p (K is singular for a planar arm: the
            // least-norm p, whose W p is the unique velocity jump since ker K = ker J_cᵀ)
            let u_before = tumble::multibody::contact_point::point_velocity(&jac, &v_before);
            for r in [0, 1] {
                let rhs = -(1.0 + r as f64) * u_before;
                let v_pin = to_tumble(&numbers(&contact[format!("v_after_r{r}").as_str()]), &perm_v);
                let impulse_pin = numbers(&contact[format!("impulse_r{r}").as_str()]);
                for (way, k) in [("LᵀDL", k_ltdl), ("ABA", k_aba)] {
                    let p = solve_psd(k, rhs);
                    let mut v_after = v_before.clone();
                    if way == "ABA" {
                        let mut dv = vec![0.0; nv];
                        impulse_velocity_change(&model, &ws, &mut scratch, body, point_world, p, &mut dv).unwrap();
                        v_after.iter_mut().zip(&dv).for_each(|(x, d)| *x += d);
                    } else {
                        tumble::multibody::contact_point::apply_impulse(&w, p, &mut v_after);
                    }
                    assert_close(&format!("{what}: v⁺ (r = {r}, {way})"), &v_after, &v_pin, TOL_IMPACT);
                    // p itself is not unique where K is singular (a point of the Panda's links 1–3 moves on a
                    // sphere about the shoulder): compare the joint-space impulse J_cᵀ p
                    let generalized = |p: &[f64]| -> Vec<f64> {
                        (0..nv).map(|j| (0..3).map(|r| jac[r * nv + j] * p[r]).sum()).collect()
                    };
                    let (ours, theirs) = (generalized(&p.to_array()), generalized(&impulse_pin));
                    assert_close(&format!("{what}: J_cᵀ p (r = {r}, {way})"), &ours, &theirs, TOL_IMPACT);
                    worst[2] = worst[2].max(rel_err(&v_after, &v_pin));
                    worst[3] = worst[3].max(rel_err(&ours, &theirs));
                }
            }
        }
    }
    worst
}

/// The least-norm solution of `K p = b` for a symmetric positive semi-definite `K` (an SVD that
/// drops singular values below `1e-12 σ_max`).
fn solve_psd(k: DMat3, b: DVec3) -> DVec3 {
    let km = Matrix3::from_row_slice(&mat3(k));
    let svd = km.svd(true, true);
    let eps = 1e-12 * svd.singular_values.max();
    let p = svd.solve(&Vector3::new(b.x, b.y, b.z), eps).unwrap();
    DVec3::new(p[0], p[1], p[2])
}

#[test]
fn contact_point_agrees_with_pinocchio() {
    let path = repo().join("crates/tumble/tests/fixtures/contact_point.json");
    let fixture: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let models = fixture["models"].as_array().unwrap();
    let names: Vec<&str> = models.iter().map(|m| m["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["panda", "double_pendulum", "panda_floating"]);
    for m in models {
        for order in [ChildOrder::JointName, ChildOrder::File] {
            let worst = check_pinocchio_model(m, order);
            eprintln!(
                "{:16} {order:?}: largest relative error J_c {:.2e}, K {:.2e}, v⁺ {:.2e}, J_cᵀ p {:.2e}",
                m["name"].as_str().unwrap(),
                worst[0],
                worst[1],
                worst[2],
                worst[3]
            );
        }
    }
}

/// The dense check of the fixture's own `K` against its `J_c` and tumble's `M` (catches a fixture
/// written with a different `M` than the one the URDF gives).
#[test]
fn pinocchio_fixture_is_consistent_with_tumbles_mass_matrix() {
    let path = repo().join("crates/tumble/tests/fixtures/contact_point.json");
    let fixture: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    for m in fixture["models"].as_array().unwrap() {
        let floating = m["floating"].as_bool().unwrap();
        let urdf = repo().join(m["urdf"].as_str().unwrap());
        let model =
            load_urdf(&urdf, UrdfOptions { floating, order: ChildOrder::JointName, ..Default::default() }).unwrap();
        let names: Vec<&str> = m["joints"].as_array().unwrap().iter().map(|j| j["name"].as_str().unwrap()).collect();
        let ours: Vec<&str> = model.bodies.iter().map(|b| b.joint.name.as_str()).collect();
        assert_eq!(ours, names, "joint order by name is Pinocchio's");
        let mut ws = Workspace::new(&model);
        for state in m["states"].as_array().unwrap() {
            let q = numbers(&state["q"]);
            let m_inv = crba(&model, &mut ws, &q).unwrap().clone().cholesky().unwrap().inverse();
            for contact in state["contacts"].as_array().unwrap() {
                let j = DMatrix::from_row_slice(3, model.nv(), &rows(&contact["jacobian"]).concat());
                let k = &j * &m_inv * j.transpose();
                let k: Vec<f64> = (0..3).flat_map(|r| (0..3).map(move |c| (r, c))).map(|rc| k[rc]).collect();
                assert_close("fixture K against J M⁻¹ Jᵀ", &k, &rows(&contact["collision_matrix"]).concat(), TOL);
            }
        }
    }
}
