//! Coordinate frames, rotations and cross-product matrices (the seed's §1 and §2).
//!
//! References: B. Mirtich, *Impulse-based dynamic simulation of rigid body systems*, PhD thesis,
//! UC Berkeley 1996, appendix (frames, `R⁻¹ = Rᵀ` (1.1), `I_world = R I_body Rᵀ` (1.2),
//! `ã b = a × b` (2.1), `ã_G = R ã_F Rᵀ` (2.2), `Ṙ = ω̃_world R = R ω̃_body` (2.3)).
//!
//! Conventions: a rotation `R = world_from_body` maps body coordinates to world coordinates,
//! `v_world = R v_body`. Quaternions are unit quaternions with the same meaning; glam stores
//! them `x, y, z, w`, files write them `[w, x, y, z]` (see [`quat_to_wxyz`]).

pub use glamx::{DMat3, DQuat, DVec3, DVec4};

mod hash;
pub use hash::StateHasher;

/// The cross-product matrix `ã` of the seed's (2.1): `skew(a) * b == a.cross(b)`.
///
/// ```text
///        [  0   −a_z   a_y ]
/// ã  =   [  a_z   0   −a_x ]
///        [ −a_y  a_x    0  ]
/// ```
#[inline]
pub fn skew(a: DVec3) -> DMat3 {
    // glam matrices are built from columns
    DMat3::from_cols(DVec3::new(0.0, a.z, -a.y), DVec3::new(-a.z, 0.0, a.x), DVec3::new(a.y, -a.x, 0.0))
}

/// The vector `a` of a skew-symmetric matrix `ã` (inverse of [`skew`]); the symmetric part is ignored.
#[inline]
pub fn unskew(m: DMat3) -> DVec3 {
    0.5 * DVec3::new(m.y_axis.z - m.z_axis.y, m.z_axis.x - m.x_axis.z, m.x_axis.y - m.y_axis.x)
}

/// A matrix given in frame F expressed in frame G: `M_G = R M_F Rᵀ` with `R = G_from_F`.
///
/// With `M = I_body` and `R = world_from_body` this is the seed's (1.2), `I_world = R I_body Rᵀ`;
/// with `M = ã` it is (2.2), `ã_G = R ã_F Rᵀ`.
#[inline]
pub fn change_frame(g_from_f: DMat3, m_f: DMat3) -> DMat3 {
    g_from_f * m_f * g_from_f.transpose()
}

/// The inertia tensor in the world frame from the principal moments in the body frame (1.2).
#[inline]
pub fn inertia_world(world_from_body: DMat3, inertia_body: DVec3) -> DMat3 {
    change_frame(world_from_body, DMat3::from_diagonal(inertia_body))
}

/// `Ṙ = ω̃_world R` (2.3), with `ω_world` the angular velocity in the world frame (rad/s).
#[inline]
pub fn rotation_rate_world(world_from_body: DMat3, omega_world: DVec3) -> DMat3 {
    skew(omega_world) * world_from_body
}

/// `Ṙ = R ω̃_body` (2.3), with `ω_body` the angular velocity in the body frame (rad/s).
#[inline]
pub fn rotation_rate_body(world_from_body: DMat3, omega_body: DVec3) -> DMat3 {
    world_from_body * skew(omega_body)
}

/// `q̇ = ½ q ⊗ (0, ω_body)`, the quaternion form of `Ṙ = R ω̃_body`; returned as a 4-vector `(x, y, z, w)`.
#[inline]
pub fn quat_rate_body(q: DQuat, omega_body: DVec3) -> DVec4 {
    let w = DQuat::from_xyzw(omega_body.x, omega_body.y, omega_body.z, 0.0);
    DVec4::from(q * w) * 0.5
}

/// The exponential map: the unit quaternion of a rotation by `|φ|` radians about `φ/|φ|`.
///
/// `exp(φ) = (cos(|φ|/2), sin(|φ|/2) φ/|φ|)`. For `|φ|/2 < 0.1` (every step of a simulation that
/// resolves its rotations) `sin(x)/x` and `cos(x)` come from their Taylor series to `x⁸` and `x¹⁰`,
/// whose truncation errors (`< x¹⁰/11! < 3e-18` and `< x¹²/12! < 3e-21`) are below round-off: the
/// result is as accurate as `sin_cos`, loses no digits as `φ → 0`, and costs a few multiplications.
#[inline]
pub fn quat_exp(phi: DVec3) -> DQuat {
    let x2 = 0.25 * phi.length_squared();
    let (sinc_half, cos_half) = if x2 < 0.01 {
        // sin(x)/x = 1 − x²/3! + x⁴/5! − x⁶/7! + x⁸/9!
        let sinc = 1.0 + x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362880.0))));
        // cos(x) = 1 − x²/2! + x⁴/4! − x⁶/6! + x⁸/8! − x¹⁰/10!
        let cos = 1.0
            + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40320.0 + x2 * (-1.0 / 3628800.0)))));
        (0.5 * sinc, cos)
    } else {
        let half_angle = x2.sqrt();
        let (s, c) = half_angle.sin_cos();
        (0.5 * s / half_angle, c)
    };
    let v = phi * sinc_half;
    DQuat::from_xyzw(v.x, v.y, v.z, cos_half)
}

/// The logarithm map, inverse of [`quat_exp`]: the rotation vector `φ` (rad) of a unit quaternion,
/// with `|φ| ≤ π` (the sign of `q` is chosen so that `w ≥ 0`).
#[inline]
pub fn quat_log(q: DQuat) -> DVec3 {
    let q = if q.w < 0.0 { -q } else { q };
    let v = DVec3::new(q.x, q.y, q.z);
    let s = v.length();
    if s < 1e-8 {
        // atan2(s, w)/s = (1/w)(1 − s²/(3w²) + …)
        v * (2.0 / q.w) * (1.0 - s * s / (3.0 * q.w * q.w))
    } else {
        v * (2.0 * s.atan2(q.w) / s)
    }
}

/// A quaternion as written in files: `[w, x, y, z]`.
#[inline]
pub fn quat_to_wxyz(q: DQuat) -> [f64; 4] {
    [q.w, q.x, q.y, q.z]
}

/// A quaternion read from a file's `[w, x, y, z]` (not normalised).
#[inline]
pub fn quat_from_wxyz(wxyz: [f64; 4]) -> DQuat {
    DQuat::from_xyzw(wxyz[1], wxyz[2], wxyz[3], wxyz[0])
}

/// Adds a 4-vector increment to a quaternion seen as a point of ℝ⁴ (for explicit Runge–Kutta stages).
#[inline]
pub fn quat_add(q: DQuat, dq: DVec4) -> DQuat {
    DQuat::from_vec4(DVec4::from(q) + dq)
}

#[cfg(test)]
mod tests;
