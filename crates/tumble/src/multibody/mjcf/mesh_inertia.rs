//! The mass properties MuJoCo gives a mesh geom, computed as its compiler does.
//!
//! Reference: MuJoCo documentation, XML reference `mesh/inertia` (`legacy`, the default, and
//! `exact`), and its compiler's mesh processing (the method, re-derived here):
//!
//! 1. `c_f = Σ A_t m_t / Σ A_t`, the area-weighted mean of the triangles' centroids `m_t`;
//! 2. each triangle is the base of a pyramid with apex `c_f`: volume `V_t = (m_t − c_f)·n_t A_t / 3`
//!    (`n_t` the unit normal), its centre of mass `¾ m_t + ¼ c_f`; the centre of mass is
//!    `c = Σ V_t (¾ m_t + ¼ c_f) / Σ V_t`;
//! 3. with the vertices relative to `c`, pyramids with apex `c`: `V_t = m_t·n_t A_t / 3` and the
//!    second moments `P_ab = Σ_t V_t/20 (2 Σ_i x_ia x_ib + Σ_{i≠j} x_ia x_jb)` over the triangle's
//!    corners `x_1, x_2, x_3` (the tetrahedron with a corner at the origin), the volume
//!    `V = Σ_t V_t`, and the inertia per unit density `I = tr(P) 1 − P`.
//!
//! `legacy` takes `|V_t|` in both sums, so that a mesh with flipped or inconsistent triangles still
//! has a positive volume, and a non-convex one more volume than it encloses (the Allegro hand's
//! palm: 0.35 kg where the solid weighs 0.12 kg); `exact` keeps the sign (the solid's true mass
//! properties for a closed, outward-oriented mesh).
//!
//! 4. MuJoCo then moves the mesh to `c` and to the principal axes its Jacobi eigen-solver finds,
//!    stopped at an off-diagonal of 1e-7 of the tensor's largest element, and gives the geom the
//!    diagonal there: the tensor it simulates is `R diag(Rᵀ I R) Rᵀ`, `I` less that residual
//!    off-diagonal ([`mujoco_principal_tensor`]). A body's inertia is the same with that tensor at
//!    `c` in the mesh frame, which is what is returned.

use crate::math::{DMat3, DQuat, DVec3};
use crate::mesh::read::{read_file, MeshLimits};
use std::path::Path;

/// The volume (m³), the centre of mass (mesh frame, m) and the inertia tensor per unit density
/// about it (mesh axes, m⁵) of a mesh file scaled by `scale`, as MuJoCo computes them (the tensor
/// as its compiler keeps it after turning the mesh to its principal axes, step 4).
pub fn mesh_mass_properties(path: &Path, scale: DVec3, legacy: bool) -> Result<(f64, DVec3, DMat3), String> {
    let soup = read_file(path, &MeshLimits::default()).map_err(|e| e.to_string())?;
    let v: Vec<DVec3> = soup.vertices.iter().map(|p| *p * scale).collect();
    // a mirroring scale reverses the triangles' orientation: MuJoCo swaps two corners
    let mirrored = scale.x * scale.y * scale.z < 0.0;
    let triangles: Vec<[DVec3; 3]> = soup
        .triangles
        .iter()
        .map(|t| {
            let (a, b, c) = (v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]);
            if mirrored {
                [a, c, b]
            } else {
                [a, b, c]
            }
        })
        .collect();
    // area A, unit normal n and centroid m of a triangle
    let face = |t: &[DVec3; 3]| {
        let cross = (t[1] - t[0]).cross(t[2] - t[0]);
        let twice_area = cross.length();
        let n = if twice_area > 0.0 { cross / twice_area } else { DVec3::ZERO };
        (0.5 * twice_area, n, (t[0] + t[1] + t[2]) / 3.0)
    };
    // 1. c_f = Σ A m / Σ A
    let (mut area, mut c_f) = (0.0, DVec3::ZERO);
    for t in &triangles {
        let (a, _, m) = face(t);
        area += a;
        c_f += a * m;
    }
    if !(area > 1e-14) {
        return Err("the mesh's surface area is too small".into());
    }
    c_f /= area;
    // 2. c = Σ V_t (¾ m + ¼ c_f) / Σ V_t, pyramids with apex c_f
    let signed = |x: f64| if legacy { x.abs() } else { x };
    let (mut volume, mut moment) = (0.0, DVec3::ZERO);
    for t in &triangles {
        let (a, n, m) = face(t);
        let vt = signed((m - c_f).dot(n) * a / 3.0);
        volume += vt;
        moment += vt * (0.75 * m + 0.25 * c_f);
    }
    if !(volume > 1e-14) {
        return Err(format!("the mesh's volume {volume:e} m³ is not positive (misoriented triangles?)"));
    }
    let com = moment / volume;
    // 3. second moments about c, pyramids with apex c; V recomputed
    let mut p = [[0.0_f64; 3]; 3];
    let mut volume_c = 0.0;
    for t in &triangles {
        let x = [t[0] - com, t[1] - com, t[2] - com];
        let (a, n, m) = face(&[x[0], x[1], x[2]]);
        let vt = signed(m.dot(n) * a / 3.0);
        volume_c += vt;
        for r in 0..3 {
            for s in r..3 {
                // 2 Σ_i x_ir x_is + Σ_{i<j} (x_ir x_js + x_is x_jr)
                let mut sum = 0.0;
                for i in 0..3 {
                    sum += 2.0 * x[i][r] * x[i][s];
                    for j in i + 1..3 {
                        sum += x[i][r] * x[j][s] + x[i][s] * x[j][r];
                    }
                }
                p[r][s] += vt / 20.0 * sum;
            }
        }
    }
    if !(volume_c > 1e-14) {
        return Err(format!("the mesh's volume {volume_c:e} m³ is not positive (misoriented triangles?)"));
    }
    let (p00, p11, p22, p01, p02, p12) = (p[0][0], p[1][1], p[2][2], p[0][1], p[0][2], p[1][2]);
    // I = tr(P) 1 − P
    let inertia = DMat3::from_cols(
        DVec3::new(p11 + p22, -p01, -p02),
        DVec3::new(-p01, p00 + p22, -p12),
        DVec3::new(-p02, -p12, p00 + p11),
    );
    Ok((volume_c, com, mujoco_principal_tensor(inertia)))
}

/// The largest off-diagonal element MuJoCo's compiler leaves in a mesh's inertia tensor when it
/// turns the mesh to its principal axes, relative to the tensor's largest element.
pub const MESH_PRINCIPAL_TOLERANCE: f64 = 1e-7;

/// The mesh's inertia tensor per unit density as MuJoCo's compiler keeps it: `R diag(d) Rᵀ`, with
/// `R` the principal frame its eigen-solver finds for `inertia` and `d` the diagonal of
/// `Rᵀ inertia R` in that frame; the off-diagonal it leaves is dropped.
///
/// MuJoCo 4.0.1's compiler (`mjCMesh::Process`, after the volume, centre of mass and tensor of
/// steps 1–3) moves a mesh to its principal axes with its 3×3 Jacobi eigen-solver (`mjuu_eig3`),
/// called for meshes with a relative tolerance of 1e-7: starting from `R = 1`, while the largest
/// off-diagonal element `b = D_ij` of `D = Rᵀ I R` exceeds `1e-7 · max_kl |I_kl|`, it turns `R`
/// about the third axis `k` by the angle `θ` that zeroes `D_ij`:
///
/// `τ = (D_jj − D_ii) / (2 b)`, `tan θ = sgn(τ) / (|τ| + √(1 + τ²))` (the smaller root, `|θ| ≤ π/4`).
///
/// The geom then gets the moments `d = diag(D)` in the frame `R` (`geom_quat = quat · q(R)`, and a
/// body whose mass is that geom copies both into `body_iquat`, `body_inertia`): the tensor MuJoCo
/// simulates is `R diag(d) Rᵀ`, not `I`. It differs from `I` by the off-diagonal left, up to 1e-7 of
/// the largest element (7.7e-8 of the largest moment for the Allegro hand's palm, a frame 1e-7 to
/// 6e-7 rad from the exact principal axes): enough to move the mass matrix by 3e-10. (The other
/// inertia frames MuJoCo compiles — `fullinertia`, several geoms — use the same solver at 4e-15.)
/// The frame's order and signs (MuJoCo sorts the moments by 90° turns) do not change the tensor.
/// Established by disassembling `libmujoco.so.4.0.1` (the call's constant 1e-7) and reproducing
/// every Allegro mesh's `mesh_quat` and body's `body_iquat` / `body_inertia` to 2e-15
/// (`tools/mjcf_allegro_frames.py`).
pub fn mujoco_principal_tensor(inertia: DMat3) -> DMat3 {
    let m = inertia.to_cols_array();
    let tol = MESH_PRINCIPAL_TOLERANCE * m.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    let at = |d: &DMat3, r: usize, c: usize| d.col(c)[r];
    let mut q = DQuat::IDENTITY;
    let mut d = inertia;
    for _ in 0..500 {
        let r = DMat3::from_quat(q);
        d = r.transpose() * inertia * r;
        // the largest off-diagonal: (0,1) if strictly the largest, else (0,2) if strictly larger than (1,2)
        let (a01, a02, a12) = (at(&d, 0, 1).abs(), at(&d, 0, 2).abs(), at(&d, 1, 2).abs());
        let (i, j, axis) = if a01 > a02 && a01 > a12 {
            (0, 1, DVec3::Z)
        } else if a02 > a12 {
            (0, 2, DVec3::Y)
        } else {
            (1, 2, DVec3::X)
        };
        let b = at(&d, i, j);
        if b.abs() <= tol {
            break;
        }
        let tau = (at(&d, j, j) - at(&d, i, i)) / (2.0 * b);
        let root = (1.0 + tau * tau).sqrt();
        let tan = if tau >= 0.0 { 1.0 / (tau + root) } else { -1.0 / (root - tau) };
        // the new axes e_i' = cos θ e_i − sin θ e_j, e_j' = sin θ e_i + cos θ e_j: a turn by −θ about
        // e_k when (i, j, k) is cyclic ((0,1,2), (1,2,0)), by +θ when not ((0,2,1))
        let tan_half = tan / (1.0 + (1.0 + tan * tan).sqrt());
        let cos_half = 1.0 / (1.0 + tan_half * tan_half).sqrt();
        let sin_half = if axis == DVec3::Y { tan_half * cos_half } else { -tan_half * cos_half };
        let turn = DQuat::from_xyzw(axis.x * sin_half, axis.y * sin_half, axis.z * sin_half, cos_half);
        q = (q * turn).normalize();
    }
    let r = DMat3::from_quat(q);
    let moments = DVec3::new(d.x_axis.x, d.y_axis.y, d.z_axis.z);
    r * DMat3::from_diagonal(moments) * r.transpose()
}
