//! Spatial (6D) vector algebra in Featherstone's `[angular; linear]` order.
//!
//! Reference: R. Featherstone, *Rigid Body Dynamics Algorithms* (Springer 2008), ch. 2 (motion and
//! force vectors, `crm`/`crf` (2.31)–(2.32), Plücker transforms (2.24)–(2.27)) and §2.13 (rigid-body
//! inertia (2.62)–(2.63)).
//!
//! - [`Motion`]: a velocity or acceleration `[ω; v]`, with `v` the velocity of the point at the
//!   frame's origin (rad/s, m/s).
//! - [`Force`]: a wrench `[n; f]`, with `n` the moment about the frame's origin (N·m, N).
//! - [`Xform`]: the Plücker transform `B_X_A` from frame A to frame B, stored as `E` (rotation taking
//!   A coordinates to B coordinates) and `r` (position of B's origin in A coordinates):
//!   `B_X_A = [E 0; −E r̃ E]`.
//! - [`RigidInertia`]: mass `m`, first moment `h = m c` and rotational inertia `Ī_o` about the frame's
//!   origin: `I = [Ī_o  h̃; h̃ᵀ  m 1]`.
//! - [`ArticulatedInertia`]: a symmetric 6×6 inertia `[A B; Bᵀ C]` (ABA's articulated-body inertias).

use crate::math::{skew, DMat3, DVec3};
use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

/// A spatial motion vector `[ω; v]` (rad/s, m/s; or rad/s², m/s² for accelerations).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Motion {
    /// Angular part `ω`.
    pub ang: DVec3,
    /// Linear part: the velocity of the point at the frame's origin.
    pub lin: DVec3,
}

/// A spatial force vector `[n; f]` (N·m about the frame's origin, N).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Force {
    /// Moment about the frame's origin `n`.
    pub ang: DVec3,
    /// Force `f`.
    pub lin: DVec3,
}

impl Motion {
    pub const ZERO: Self = Self { ang: DVec3::ZERO, lin: DVec3::ZERO };

    #[inline]
    pub const fn new(ang: DVec3, lin: DVec3) -> Self {
        Self { ang, lin }
    }

    /// `m ×ₘ other = crm(m) other = [ω × ω₂; ω × v₂ + v × ω₂]` (2.31).
    #[inline]
    pub fn cross_motion(self, other: Motion) -> Motion {
        Motion { ang: self.ang.cross(other.ang), lin: self.ang.cross(other.lin) + self.lin.cross(other.ang) }
    }

    /// `m ×* f = crf(m) f = [ω × n + v × f; ω × f]` (2.32).
    #[inline]
    pub fn cross_force(self, f: Force) -> Force {
        Force { ang: self.ang.cross(f.ang) + self.lin.cross(f.lin), lin: self.ang.cross(f.lin) }
    }

    /// The scalar product with a force, `m · f = ωᵀ n + vᵀ f` (power, W).
    #[inline]
    pub fn dot(self, f: Force) -> f64 {
        self.ang.dot(f.ang) + self.lin.dot(f.lin)
    }

    /// `[ω; v]` as an array in `[angular; linear]` order.
    #[inline]
    pub fn to_array(self) -> [f64; 6] {
        [self.ang.x, self.ang.y, self.ang.z, self.lin.x, self.lin.y, self.lin.z]
    }

    #[inline]
    pub fn is_finite(self) -> bool {
        self.ang.is_finite() && self.lin.is_finite()
    }
}

impl Force {
    pub const ZERO: Self = Self { ang: DVec3::ZERO, lin: DVec3::ZERO };

    #[inline]
    pub const fn new(ang: DVec3, lin: DVec3) -> Self {
        Self { ang, lin }
    }

    /// `[n; f]` as an array in `[angular; linear]` order.
    #[inline]
    pub fn to_array(self) -> [f64; 6] {
        [self.ang.x, self.ang.y, self.ang.z, self.lin.x, self.lin.y, self.lin.z]
    }
}

macro_rules! vector_ops {
    ($t:ident) => {
        impl Add for $t {
            type Output = $t;
            #[inline]
            fn add(self, o: $t) -> $t {
                $t { ang: self.ang + o.ang, lin: self.lin + o.lin }
            }
        }
        impl Sub for $t {
            type Output = $t;
            #[inline]
            fn sub(self, o: $t) -> $t {
                $t { ang: self.ang - o.ang, lin: self.lin - o.lin }
            }
        }
        impl AddAssign for $t {
            #[inline]
            fn add_assign(&mut self, o: $t) {
                self.ang += o.ang;
                self.lin += o.lin;
            }
        }
        impl SubAssign for $t {
            #[inline]
            fn sub_assign(&mut self, o: $t) {
                self.ang -= o.ang;
                self.lin -= o.lin;
            }
        }
        impl Neg for $t {
            type Output = $t;
            #[inline]
            fn neg(self) -> $t {
                $t { ang: -self.ang, lin: -self.lin }
            }
        }
        impl Mul<$t> for f64 {
            type Output = $t;
            #[inline]
            fn mul(self, m: $t) -> $t {
                $t { ang: self * m.ang, lin: self * m.lin }
            }
        }
    };
}
vector_ops!(Motion);
vector_ops!(Force);

/// A Plücker transform `B_X_A` (2.24): `E` takes A coordinates to B coordinates and `r` is the
/// position of B's origin in A coordinates (m).
///
/// In terms of the rigid transform `A_from_B` (rotation `R`, translation `p`, so that
/// `point_A = R point_B + p`): `E = Rᵀ`, `r = p`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Xform {
    /// Rotation `E`: A coordinates → B coordinates.
    pub e: DMat3,
    /// Position of B's origin in A coordinates (m).
    pub r: DVec3,
}

impl Default for Xform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Xform {
    pub const IDENTITY: Self = Self { e: DMat3::IDENTITY, r: DVec3::ZERO };

    /// `B_X_A` from the rigid transform `A_from_B`: `point_A = a_from_b_rotation · point_B + b_origin_in_a`.
    #[inline]
    pub fn from_pose(a_from_b_rotation: DMat3, b_origin_in_a: DVec3) -> Self {
        Self { e: a_from_b_rotation.transpose(), r: b_origin_in_a }
    }

    /// The rotation `A_from_B = Eᵀ` of the corresponding rigid transform.
    #[inline]
    pub fn rotation_a_from_b(&self) -> DMat3 {
        self.e.transpose()
    }

    /// `X m = [E ω; E (v − r × ω)]`: a motion vector from A to B coordinates.
    #[inline]
    pub fn apply_motion(&self, m: Motion) -> Motion {
        Motion { ang: self.e * m.ang, lin: self.e * (m.lin - self.r.cross(m.ang)) }
    }

    /// `X⁻¹ m = [Eᵀ ω; Eᵀ v + r × Eᵀ ω]`: a motion vector from B to A coordinates.
    #[inline]
    pub fn inv_apply_motion(&self, m: Motion) -> Motion {
        let ang = self.e.transpose() * m.ang;
        Motion { ang, lin: self.e.transpose() * m.lin + self.r.cross(ang) }
    }

    /// `X* f = [E (n − r × f); E f]`: a force vector from A to B coordinates.
    #[inline]
    pub fn apply_force(&self, f: Force) -> Force {
        Force { ang: self.e * (f.ang - self.r.cross(f.lin)), lin: self.e * f.lin }
    }

    /// `Xᵀ f = (X*)⁻¹ f = [Eᵀ n + r × Eᵀ f; Eᵀ f]`: a force vector from B to A coordinates.
    #[inline]
    pub fn inv_apply_force(&self, f: Force) -> Force {
        let lin = self.e.transpose() * f.lin;
        Force { ang: self.e.transpose() * f.ang + self.r.cross(lin), lin }
    }

    /// `C_X_A = C_X_B · B_X_A` with `self = C_X_B`: `E = E_cb E_ba`, `r = r_ba + E_baᵀ r_cb`.
    #[inline]
    pub fn compose(&self, b_x_a: &Xform) -> Xform {
        Xform { e: self.e * b_x_a.e, r: b_x_a.r + b_x_a.e.transpose() * self.r }
    }

    /// `A_X_B = (B_X_A)⁻¹`: `E' = Eᵀ`, `r' = −E r`.
    #[inline]
    pub fn inverse(&self) -> Xform {
        Xform { e: self.e.transpose(), r: -(self.e * self.r) }
    }

    /// A point given in A coordinates, expressed in B coordinates: `E (p − r)` (m).
    #[inline]
    pub fn apply_point(&self, p_a: DVec3) -> DVec3 {
        self.e * (p_a - self.r)
    }

    /// A point given in B coordinates, expressed in A coordinates: `Eᵀ p + r` (m).
    #[inline]
    pub fn inv_apply_point(&self, p_b: DVec3) -> DVec3 {
        self.e.transpose() * p_b + self.r
    }
}

/// The spatial inertia of a rigid body in some frame (2.63): `I = [Ī_o h̃; h̃ᵀ m1]`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RigidInertia {
    /// Mass `m` (kg).
    pub mass: f64,
    /// First moment of mass `h = m c`, with `c` the centre of mass in this frame (kg·m).
    pub h: DVec3,
    /// Rotational inertia about the frame's origin in this frame's axes, `Ī_o = Ī_c + m c̃ c̃ᵀ` (kg·m²).
    pub i_o: DMat3,
}

impl RigidInertia {
    pub const ZERO: Self = Self { mass: 0.0, h: DVec3::ZERO, i_o: DMat3::ZERO };

    /// The inertia of a body of mass `m` (kg) whose centre of mass is at `com` (m, this frame), with
    /// rotational inertia `inertia_com` about the centre of mass in this frame's axes (kg·m²).
    #[inline]
    pub fn from_com(mass: f64, com: DVec3, inertia_com: DMat3) -> Self {
        let c = skew(com);
        // Ī_o = Ī_c + m c̃ c̃ᵀ (parallel-axis theorem, 2.63)
        Self { mass, h: mass * com, i_o: inertia_com + mass * (c * c.transpose()) }
    }

    /// The centre of mass in this frame, `c = h / m` (m); zero for a massless body.
    #[inline]
    pub fn com(&self) -> DVec3 {
        if self.mass > 0.0 {
            self.h / self.mass
        } else {
            DVec3::ZERO
        }
    }

    /// `I v = [Ī_o ω + h × v; m v − h × ω]` (2.63).
    #[inline]
    pub fn mul_motion(&self, v: Motion) -> Force {
        Force { ang: self.i_o * v.ang + self.h.cross(v.lin), lin: self.mass * v.lin - self.h.cross(v.ang) }
    }

    /// The inertia expressed in frame A, `Xᵀ I X`, given `x = B_X_A` and `self` in frame B.
    ///
    /// `h_A = Eᵀ h + m r`, `Ī_A = Eᵀ Ī E − r̃ h̃' − h̃' r̃ − m r̃ r̃` with `h' = Eᵀ h`.
    ///
    /// Products of cross-product matrices are formed as `ã b̃ = b aᵀ − (a·b) 1`, so
    /// `r̃ h̃' + h̃' r̃ = h' rᵀ + r h'ᵀ − 2 (r·h') 1` and `r̃ r̃ = r rᵀ − |r|² 1`.
    #[inline]
    pub fn transform_to_a(&self, x: &Xform) -> RigidInertia {
        let et = x.e.transpose();
        let h_rot = et * self.h;
        let r = x.r;
        let i_rot = rotate_symmetric(et, self.i_o);
        let rh = r.dot(h_rot);
        let rr = r.length_squared();
        // −(r̃ h̃' + h̃' r̃) − m r̃ r̃ = −(h' rᵀ + r h'ᵀ) − m r rᵀ + (2 r·h' + m |r|²) 1
        let shift = DMat3::from_diagonal(DVec3::splat(2.0 * rh + self.mass * rr))
            - outer(h_rot, r)
            - outer(r, h_rot)
            - outer(self.mass * r, r);
        RigidInertia { mass: self.mass, h: h_rot + self.mass * r, i_o: i_rot + shift }
    }

    /// Kinetic energy `½ vᵀ I v` (J) of a body moving with `v` (same frame).
    #[inline]
    pub fn kinetic_energy(&self, v: Motion) -> f64 {
        0.5 * v.dot(self.mul_motion(v))
    }
}

impl Add for RigidInertia {
    type Output = RigidInertia;
    #[inline]
    fn add(self, o: RigidInertia) -> RigidInertia {
        RigidInertia { mass: self.mass + o.mass, h: self.h + o.h, i_o: self.i_o + o.i_o }
    }
}

impl AddAssign for RigidInertia {
    #[inline]
    fn add_assign(&mut self, o: RigidInertia) {
        self.mass += o.mass;
        self.h += o.h;
        self.i_o += o.i_o;
    }
}

/// A symmetric 6×6 inertia `[A B; Bᵀ C]` acting on motion vectors `[ω; v]` (kg·m², kg·m, kg).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArticulatedInertia {
    /// `A`, symmetric (kg·m²).
    pub aa: DMat3,
    /// `B` (kg·m).
    pub ab: DMat3,
    /// `C`, symmetric (kg).
    pub bb: DMat3,
}

impl Default for ArticulatedInertia {
    fn default() -> Self {
        Self::ZERO
    }
}

impl From<RigidInertia> for ArticulatedInertia {
    #[inline]
    fn from(i: RigidInertia) -> Self {
        Self { aa: i.i_o, ab: skew(i.h), bb: DMat3::from_diagonal(DVec3::splat(i.mass)) }
    }
}

impl ArticulatedInertia {
    pub const ZERO: Self = Self { aa: DMat3::ZERO, ab: DMat3::ZERO, bb: DMat3::ZERO };

    /// `I v = [A ω + B v; Bᵀ ω + C v]`.
    #[inline]
    pub fn mul_motion(&self, v: Motion) -> Force {
        Force { ang: self.aa * v.ang + self.ab * v.lin, lin: self.ab.transpose() * v.ang + self.bb * v.lin }
    }

    /// The inertia expressed in frame A, `Xᵀ I X`, given `x = B_X_A` and `self` in frame B.
    ///
    /// With `A' = Eᵀ A E`, `B' = Eᵀ B E`, `C' = Eᵀ C E`:
    /// `[A' + r̃ B'ᵀ − B' r̃ − r̃ C' r̃,  B' + r̃ C';  ·,  C']`.
    #[inline]
    pub fn transform_to_a(&self, x: &Xform) -> ArticulatedInertia {
        let e = x.e;
        let et = e.transpose();
        let a = et * self.aa * e;
        let b = et * self.ab * e;
        let c = et * self.bb * e;
        let r = x.r;
        // B' + r̃ C'  (r̃ M: r × each column of M)
        let b_new = b + cross_cols(r, c);
        // A' + r̃ B'ᵀ − B' r̃ − r̃ C' r̃ = A' + r̃ B'ᵀ − (B' + r̃ C') r̃, with M r̃ = −(r̃ Mᵀ)ᵀ
        let a_new = a + cross_cols(r, b.transpose()) + cross_cols(r, b_new.transpose()).transpose();
        ArticulatedInertia { aa: symmetrize(a_new), ab: b_new, bb: symmetrize(c) }
    }

    /// `self − c uᵢ uⱼᵀ` for two 6-vectors (stored as forces) and a scalar `c`; summed over the entries
    /// of `D⁻¹` it forms `I − U D⁻¹ Uᵀ` (ABA, Table 7.1).
    #[inline]
    pub fn sub_outer(&mut self, u_i: Force, u_j: Force, c: f64) {
        let cu = c * u_i.ang;
        self.aa -= outer(cu, u_j.ang);
        self.ab -= outer(cu, u_j.lin);
        self.bb -= outer(c * u_i.lin, u_j.lin);
    }
}

impl AddAssign for ArticulatedInertia {
    #[inline]
    fn add_assign(&mut self, o: ArticulatedInertia) {
        self.aa += o.aa;
        self.ab += o.ab;
        self.bb += o.bb;
    }
}

/// `R S Rᵀ` for a symmetric `S`: `S Rᵀ` (27 products), then only the six distinct entries of the
/// symmetric result (18 products).
#[inline]
fn rotate_symmetric(r: DMat3, s: DMat3) -> DMat3 {
    // columns of S Rᵀ are S times the rows of R
    let rt = r.transpose();
    let srt = s * rt;
    let (r0, r1, r2) = (rt.x_axis, rt.y_axis, rt.z_axis); // rows of R
    let (c0, c1, c2) = (srt.x_axis, srt.y_axis, srt.z_axis);
    let (a00, a01, a02) = (r0.dot(c0), r0.dot(c1), r0.dot(c2));
    let (a11, a12, a22) = (r1.dot(c1), r1.dot(c2), r2.dot(c2));
    DMat3::from_cols(DVec3::new(a00, a01, a02), DVec3::new(a01, a11, a12), DVec3::new(a02, a12, a22))
}

/// `r̃ M`: the cross product of `r` with each column of `M`.
#[inline]
fn cross_cols(r: DVec3, m: DMat3) -> DMat3 {
    DMat3::from_cols(r.cross(m.x_axis), r.cross(m.y_axis), r.cross(m.z_axis))
}

/// `a bᵀ`.
#[inline]
pub fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

#[inline]
fn symmetrize(m: DMat3) -> DMat3 {
    0.5 * (m + m.transpose())
}

/// The rotation by `angle` (rad) about the unit vector `axis` (Rodrigues):
/// `R = 1 + sin θ k̃ + (1 − cos θ) k̃² = cos θ 1 + sin θ k̃ + (1 − cos θ) k kᵀ` (as `k̃² = k kᵀ − 1`).
#[inline]
pub fn axis_angle_rotation(axis: DVec3, angle: f64) -> DMat3 {
    let (s, c) = angle.sin_cos();
    let t = 1.0 - c;
    let (x, y, z) = (axis.x, axis.y, axis.z);
    let (tx, ty, tz) = (t * x, t * y, t * z);
    let (sx, sy, sz) = (s * x, s * y, s * z);
    // columns of c 1 + s k̃ + t k kᵀ
    DMat3::from_cols(
        DVec3::new(tx * x + c, tx * y + sz, tx * z - sy),
        DVec3::new(tx * y - sz, ty * y + c, ty * z + sx),
        DVec3::new(tx * z + sy, ty * z - sx, tz * z + c),
    )
}

/// The rotation of URDF's `rpy`: fixed-axis roll, pitch, yaw, `R = Rz(y) Ry(p) Rx(r)`.
#[inline]
pub fn rpy_rotation(rpy: DVec3) -> DMat3 {
    DMat3::from_rotation_z(rpy.z) * DMat3::from_rotation_y(rpy.y) * DMat3::from_rotation_x(rpy.x)
}
