//! The torque-free rigid body in closed form: the symmetric top and the asymmetric top.
//!
//! References: L. D. Landau, E. M. Lifshitz, *Mechanics*, 3rd ed., §33 (free symmetric top) and §37
//! (asymmetric top, Jacobi elliptic functions); H. Goldstein, *Classical Mechanics*, §5.6–5.7.
//!
//! Body frame = principal axes, `ω = (ω1, ω2, ω3)` body angular velocity (rad/s), Euler's equations
//! `I1 ω̇1 = (I2 − I3) ω2 ω3` and cyclic. Conserved: `2E = Σ I_i ω_i²` and `M² = Σ I_i² ω_i²`.
//!
//! ## Symmetric top (`I1 = I2 = I⊥`)
//! `ω3` is constant and `(ω1, ω2)` turns about body axis 3 at `Ω = (I3 − I⊥)/I⊥ · ω3`:
//! `ω_body(t) = Rot_3(Ω t) ω_body(0)`. In the world, with `L = R I ω` fixed, the body turns about
//! `L̂` at `|L|/I⊥` while spinning about its own axis 3 at `−Ω`:
//! `q(t) = exp(t |L|/I⊥ · L̂_world) ⊗ q(0) ⊗ exp(−Ω t e3)` (check: the body angular velocity is
//! `|L|/I⊥ · L̂_body − Ω e3 = L_body/I⊥ + L3 (1/I3 − 1/I⊥) e3 = I⁻¹ L_body`).
//!
//! ## Asymmetric top (`I1 < I2 < I3`; [`AsymmetricTop`] sorts any three distinct moments first)
//! With the cancellation-free combinations
//! `d1 = M² − 2E I1 = I2(I2 − I1) ω2² + I3(I3 − I1) ω3² ≥ 0`,
//! `d3 = 2E I3 − M² = I1(I3 − I1) ω1² + I2(I3 − I2) ω2² ≥ 0`,
//! `d2 = M² − 2E I2 = I3(I3 − I2) ω3² − I1(I2 − I1) ω1²`:
//!
//! - `d2 ≥ 0` (the angular velocity circles axis 3):
//!   `ω1 = s A1 cn τ`, `ω2 = A2 sn τ`, `ω3 = s A3 dn τ` with `A1² = d3/(I1(I3 − I1))`,
//!   `A2² = d3/(I2(I3 − I2))`, `A3² = d1/(I3(I3 − I1))`, `λ² = (I3 − I2) d1/(I1 I2 I3)`,
//!   `m = k² = (I2 − I1) d3/((I3 − I2) d1)`, `1 − m = (I3 − I1) d2/((I3 − I2) d1)`, `s = sign ω3`;
//! - `d2 < 0` (it circles axis 1): the same with the indices 1 and 3 exchanged,
//!   `ω1 = s A1 dn τ`, `ω2 = A2 sn τ`, `ω3 = s A3 cn τ`, `A1² = d3/(I1(I3 − I1))`,
//!   `A2² = d1/(I2(I2 − I1))`, `A3² = d1/(I3(I3 − I1))`, `λ² = (I2 − I1) d3/(I1 I2 I3)`,
//!   `m = (I3 − I2) d1/((I2 − I1) d3)`, `1 − m = −(I3 − I1) d2/((I2 − I1) d3)`, `s = sign ω1`;
//!
//! and `τ = λ t + τ0`. Euler's equations fix the signs up to `s1 s2 s3 = +1`; the remaining freedom
//! (`ω2`'s sign) is the shift `τ → τ + 2K`, so `ω2` is taken with `+A2`. The initial phase is the
//! amplitude of the initial point: `τ0 = F(atan2(sn τ0, cn τ0), m)` with `sn τ0 = ω2(0)/A2` and
//! `cn τ0 = ω1(0)/(s A1)` (resp. `ω3(0)/(s A3)`). `1 − m` is computed from `d2`, never as `1 − m`,
//! so that the solution keeps its digits next to the separatrix (`d2 = 0`).
//!
//! The period of `ω_body` is `4K(m)/λ`; `ω2` changes sign every half period, so a body spun near
//! its intermediate axis flips every `2K(m)/λ` (the Dzhanibekov effect).
//!
//! ### World orientation of the asymmetric top
//! Take a reference frame with `Z` along the constant `L_world` and Euler angles `(φ, θ, ψ)` (z-x-z,
//! Landau §35): `world_from_body = A · R_z(φ) R_x(θ) R_z(ψ)` with `A` constant. The body components
//! of `L` give two angles directly, `L_body = M (sin θ sin ψ, sin θ cos ψ, cos θ)`, and the third obeys
//! `φ̇ = M (I1 ω1² + I2 ω2²)/(I1² ω1² + I2² ω2²)` (Landau §37). Since `I1² ω1² + I2² ω2² = M² − I3² ω3²`
//! and `ω3² = A3² (1 − n0 sn² τ)` (`n0 = m` about axis 3, `n0 = 1` about axis 1), and the value of
//! `M² − I3² ω3²` at `sn τ = 0` is `I1² A1²`,
//! `φ̇ = M/I3 + M (I3 − I1)/(I1 I3) · 1/(1 − n sn² τ)` with `n = −n0 I3² A3² / (I1² A1²) ≤ 0`, so
//! `φ(t) = M t / I3 + M (I3 − I1)/(I1 I3 λ) · (Π(n; am τ | m) − Π(n; am τ0 | m))`,
//! with `Π` the incomplete elliptic integral of the third kind (Carlson's `R_J`), continued past
//! `am τ = ±π/2` by `Π(φ + kπ) = Π(φ) + 2k Π(n | m)`. `A` is fixed by `q(0)`.

use super::elliptic::{ellipf_m1, ellipk_m1, ellippi_complete_m1, ellippi_sc, jacobi_m1};
use crate::math::{quat_exp, DMat3, DQuat, DVec3};

/// Why a closed-form top could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TopError {
    /// A moment or an angular velocity component is not finite, or a moment is not positive.
    #[error("moments {moments:?} and angular velocity {omega:?} must be finite, moments > 0")]
    NonFinite { moments: [f64; 3], omega: [f64; 3] },
    /// The asymmetric solution needs three distinct moments (use [`SymmetricTop`] otherwise).
    #[error("asymmetric top needs three distinct principal moments (got {moments:?})")]
    EqualMoments { moments: [f64; 3] },
    /// The symmetric solution needs `I1 = I2` (to 1e-12 relative).
    #[error("symmetric top needs I1 = I2 (axis 3 is the symmetry axis; got {moments:?})")]
    NotSymmetric { moments: [f64; 3] },
}

fn check_finite(inertia_body: DVec3, omega_body: DVec3) -> Result<(), TopError> {
    if !inertia_body.is_finite() || !omega_body.is_finite() || inertia_body.min_element() <= 0.0 {
        return Err(TopError::NonFinite { moments: inertia_body.to_array(), omega: omega_body.to_array() });
    }
    Ok(())
}

/// A torque-free symmetric top, `I1 = I2 = I⊥`, symmetry axis = body axis 3.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SymmetricTop {
    inertia_body: DVec3,
    omega_body0: DVec3,
    orientation0: DQuat,
    /// `Ω = (I3 − I⊥)/I⊥ · ω3` (rad/s).
    body_rate: f64,
    /// `L_world`, constant (kg·m²/s).
    l_world: DVec3,
}

impl SymmetricTop {
    /// From the principal moments (kg·m², `I1 = I2`), the initial body angular velocity (rad/s) and the
    /// initial orientation `world_from_body`.
    pub fn new(inertia_body: DVec3, omega_body0: DVec3, orientation0: DQuat) -> Result<Self, TopError> {
        check_finite(inertia_body, omega_body0)?;
        let [i1, i2, i3] = inertia_body.to_array();
        if (i1 - i2).abs() > 1e-12 * i1.max(i2) {
            return Err(TopError::NotSymmetric { moments: [i1, i2, i3] });
        }
        let body_rate = (i3 - i1) / i1 * omega_body0.z;
        let l_world = orientation0 * (inertia_body * omega_body0);
        Ok(Self { inertia_body, omega_body0, orientation0: orientation0.normalize(), body_rate, l_world })
    }

    /// The rate at which `(ω1, ω2)` turns about body axis 3, `Ω = (I3 − I⊥)/I⊥ · ω3` (rad/s).
    pub fn body_precession_rate(&self) -> f64 {
        self.body_rate
    }

    /// The rate at which the symmetry axis precesses about `L_world`, `|L|/I⊥` (rad/s).
    pub fn world_precession_rate(&self) -> f64 {
        self.l_world.length() / self.inertia_body.x
    }

    /// The constant angular momentum, world frame (kg·m²/s).
    pub fn angular_momentum_world(&self) -> DVec3 {
        self.l_world
    }

    /// `ω_body(t) = Rot_3(Ω t) ω_body(0)` (rad/s), `t` in s.
    pub fn omega_body(&self, t: f64) -> DVec3 {
        let (s, c) = (self.body_rate * t).sin_cos();
        let w = self.omega_body0;
        DVec3::new(c * w.x - s * w.y, s * w.x + c * w.y, w.z)
    }

    /// `world_from_body` at `t` (s): `exp(t |L|/I⊥ L̂) ⊗ q(0) ⊗ exp(−Ω t e3)`.
    pub fn orientation(&self, t: f64) -> DQuat {
        let about_l = quat_exp(t / self.inertia_body.x * self.l_world);
        let spin = quat_exp(DVec3::new(0.0, 0.0, -self.body_rate * t));
        about_l * self.orientation0 * spin
    }
}

/// Which axis the angular velocity circles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Regime {
    /// `M² ≥ 2E I2`: around the axis of largest moment (axis 3); `ω3` keeps its sign.
    AboutAxis3,
    /// `M² < 2E I2`: around the axis of smallest moment (axis 1); `ω1` keeps its sign.
    AboutAxis1,
    /// `ω` lies along the intermediate axis (or is zero): a steady (unstable) rotation.
    Steady,
}

/// The asymmetric top in a frame where `I1 < I2 < I3` (the formulas of the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
struct SortedTop {
    inertia_body: DVec3,
    omega_body0: DVec3,
    regime: Regime,
    /// Amplitudes `(A1, A2, A3)`, the sign `s` already applied to the cn/dn components (rad/s).
    amplitude: DVec3,
    /// `λ` (1/s).
    lambda: f64,
    /// `m = k²` and `m1 = 1 − m`.
    m: f64,
    m1: f64,
    /// `τ0` (dimensionless).
    tau0: f64,
    /// Orientation: `world_from_body(0)`, the constant `A` (world from the frame with `Z ∥ L`), the
    /// characteristic `n`, the coefficient `M (I3 − I1)/(I1 I3 λ)` of `Π`, and `Π` at `τ0`.
    orientation0: DQuat,
    world_from_reference: DQuat,
    characteristic: f64,
    pi_coefficient: f64,
    pi0: f64,
}

impl SortedTop {
    /// From the principal moments `I1 < I2 < I3` (kg·m²) and the initial angular velocity (rad/s).
    fn new(inertia_body: DVec3, omega_body0: DVec3) -> Self {
        let [i1, i2, i3] = inertia_body.to_array();
        debug_assert!(i1 < i2 && i2 < i3);
        let [w1, w2, w3] = omega_body0.to_array();
        let d1 = i2 * (i2 - i1) * w2 * w2 + i3 * (i3 - i1) * w3 * w3;
        let d3 = i1 * (i3 - i1) * w1 * w1 + i2 * (i3 - i2) * w2 * w2;
        let d2 = i3 * (i3 - i2) * w3 * w3 - i1 * (i2 - i1) * w1 * w1;
        let steady = Self {
            inertia_body,
            omega_body0,
            regime: Regime::Steady,
            amplitude: omega_body0,
            lambda: 0.0,
            m: 1.0,
            m1: 0.0,
            tau0: 0.0,
            orientation0: DQuat::IDENTITY,
            world_from_reference: DQuat::IDENTITY,
            characteristic: 0.0,
            pi_coefficient: 0.0,
            pi0: 0.0,
        };
        // ω along a principal axis (or zero): a steady rotation
        let zeros = [w1, w2, w3].iter().filter(|w| **w == 0.0).count();
        if zeros >= 2 {
            return steady;
        }
        let top = if d2 >= 0.0 {
            let s = if w3 >= 0.0 { 1.0 } else { -1.0 };
            let a1 = (d3 / (i1 * (i3 - i1))).sqrt();
            let a2 = (d3 / (i2 * (i3 - i2))).sqrt();
            let a3 = (d1 / (i3 * (i3 - i1))).sqrt();
            let lambda = ((i3 - i2) * d1 / (i1 * i2 * i3)).sqrt();
            let m = (i2 - i1) * d3 / ((i3 - i2) * d1);
            let m1 = (i3 - i1) * d2 / ((i3 - i2) * d1);
            let tau0 = if a2 > 0.0 { ellipf_m1((w2 / a2).atan2(w1 / (s * a1)), m1) } else { 0.0 };
            Self {
                inertia_body,
                omega_body0,
                regime: Regime::AboutAxis3,
                amplitude: DVec3::new(s * a1, a2, s * a3),
                lambda,
                m,
                m1,
                tau0,
                characteristic: -m * (i3 * a3).powi(2) / (i1 * a1).powi(2),
                ..steady
            }
        } else {
            let s = if w1 >= 0.0 { 1.0 } else { -1.0 };
            let a1 = (d3 / (i1 * (i3 - i1))).sqrt();
            let a2 = (d1 / (i2 * (i2 - i1))).sqrt();
            let a3 = (d1 / (i3 * (i3 - i1))).sqrt();
            let lambda = ((i2 - i1) * d3 / (i1 * i2 * i3)).sqrt();
            let m = (i3 - i2) * d1 / ((i2 - i1) * d3);
            let m1 = -(i3 - i1) * d2 / ((i2 - i1) * d3);
            let tau0 = if a2 > 0.0 { ellipf_m1((w2 / a2).atan2(w3 / (s * a3)), m1) } else { 0.0 };
            Self {
                inertia_body,
                omega_body0,
                regime: Regime::AboutAxis1,
                amplitude: DVec3::new(s * a1, a2, s * a3),
                lambda,
                m,
                m1,
                tau0,
                characteristic: -(i3 * a3).powi(2) / (i1 * a1).powi(2),
                ..steady
            }
        };
        let m_length = (inertia_body * omega_body0).length();
        let pi_coefficient = m_length * (i3 - i1) / (i1 * i3 * top.lambda);
        let top = Self { pi_coefficient, ..top };
        let pi0 = top.pi_of_tau(top.tau0);
        Self { pi0, ..top }.with_orientation(DQuat::IDENTITY)
    }

    /// The same top with the initial orientation `world_from_body(0) = orientation0` (unit quaternion).
    fn with_orientation(self, orientation0: DQuat) -> Self {
        let orientation0 = orientation0.normalize();
        let mut top = Self { orientation0, ..self };
        if top.regime != Regime::Steady {
            top.world_from_reference = orientation0 * top.reference_from_body(0.0).conjugate();
        }
        top
    }

    /// `Π(n; am τ | m)`, continued over all `τ` by the quasi-periodicity.
    fn pi_of_tau(&self, tau: f64) -> f64 {
        let k = ellipk_m1(self.m1);
        // τ = τr + 2jK with |τr| ≤ K, where cn τr ≥ 0 and am τr = atan2(sn, cn)
        let j = if k.is_finite() { (tau / (2.0 * k)).round() } else { 0.0 };
        let reduced = jacobi_m1(tau - 2.0 * j * k, self.m1);
        let partial = ellippi_sc(self.characteristic, reduced.sn, reduced.cn, reduced.dn * reduced.dn);
        if j == 0.0 {
            partial
        } else {
            partial + 2.0 * j * ellippi_complete_m1(self.characteristic, self.m1)
        }
    }

    /// `R_z(φ) R_x(θ) R_z(ψ)`: body to the frame with `Z ∥ L` whose `X` axis is at `φ = 0` at `t = 0`.
    fn reference_from_body(&self, t: f64) -> DQuat {
        let l_body = self.inertia_body * self.omega_body(t);
        let theta = l_body.truncate().length().atan2(l_body.z);
        let psi = l_body.x.atan2(l_body.y);
        let m_length = (self.inertia_body * self.omega_body0).length();
        let phi = m_length * t / self.inertia_body.z
            + self.pi_coefficient * (self.pi_of_tau(self.lambda * t + self.tau0) - self.pi0);
        DQuat::from_rotation_z(phi) * DQuat::from_rotation_x(theta) * DQuat::from_rotation_z(psi)
    }

    /// `world_from_body` at `t` (s).
    pub fn orientation(&self, t: f64) -> DQuat {
        match self.regime {
            Regime::Steady => self.orientation0 * quat_exp(t * self.omega_body0),
            _ => self.world_from_reference * self.reference_from_body(t),
        }
    }

    /// The constant angular momentum, world frame (kg·m²/s).
    pub fn angular_momentum_world(&self) -> DVec3 {
        self.orientation0 * (self.inertia_body * self.omega_body0)
    }

    /// Twice the kinetic energy, `2E = Σ I_i ω_i²` (J).
    pub fn twice_energy(&self) -> f64 {
        self.omega_body0.dot(self.inertia_body * self.omega_body0)
    }

    /// `M² = |L|² = Σ I_i² ω_i²` ((kg·m²/s)²).
    pub fn angular_momentum_squared(&self) -> f64 {
        (self.inertia_body * self.omega_body0).length_squared()
    }

    /// The period of `ω_body`, `4K(m)/λ` (s); `+∞` for a steady rotation or on the separatrix.
    pub fn period(&self) -> f64 {
        2.0 * self.flip_interval()
    }

    /// The time between two sign changes of `ω2`, `2K(m)/λ` (s): the flip interval of a body spun
    /// near its intermediate axis.
    pub fn flip_interval(&self) -> f64 {
        if self.regime == Regime::Steady {
            return f64::INFINITY;
        }
        2.0 * ellipk_m1(self.m1) / self.lambda
    }

    /// The body angular velocity at `t` (s), rad/s.
    pub fn omega_body(&self, t: f64) -> DVec3 {
        let a = self.amplitude;
        match self.regime {
            Regime::Steady => self.omega_body0,
            Regime::AboutAxis3 => {
                let j = jacobi_m1(self.lambda * t + self.tau0, self.m1);
                DVec3::new(a.x * j.cn, a.y * j.sn, a.z * j.dn)
            }
            Regime::AboutAxis1 => {
                let j = jacobi_m1(self.lambda * t + self.tau0, self.m1);
                DVec3::new(a.x * j.dn, a.y * j.sn, a.z * j.cn)
            }
        }
    }
}

/// A torque-free asymmetric top (three distinct principal moments): body angular velocity by Jacobi
/// elliptic functions, world orientation through the elliptic integral of the third kind.
///
/// The moments may come in any order: the solution is computed in the frame of the sorted axes,
/// reached from the body frame by a proper rotation that permutes the axes (with one sign change
/// when the permutation is odd, so that Euler's equations keep their form). Everything this type
/// returns is in the body frame given; "axis 1" and "axis 3" in [`Regime`] are the axes of the
/// smallest and largest moments.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AsymmetricTop {
    inertia_body: DVec3,
    sorted_from_body: DMat3,
    sorted_from_body_q: DQuat,
    sorted: SortedTop,
}

impl AsymmetricTop {
    /// From three distinct principal moments (kg·m²) and the initial body angular velocity (rad/s), with
    /// the identity as initial orientation (see [`AsymmetricTop::with_orientation`]).
    pub fn new(inertia_body: DVec3, omega_body0: DVec3) -> Result<Self, TopError> {
        check_finite(inertia_body, omega_body0)?;
        let moments = inertia_body.to_array();
        let mut order = [0usize, 1, 2];
        order.sort_by(|&a, &b| moments[a].total_cmp(&moments[b]));
        if moments[order[0]] == moments[order[1]] || moments[order[1]] == moments[order[2]] {
            return Err(TopError::EqualMoments { moments });
        }
        // row k of sorted_from_body picks body axis order[k]; an odd permutation flips the last row
        let odd = matches!(order, [0, 2, 1] | [1, 0, 2] | [2, 1, 0]);
        let row = |k: usize, sign: f64| {
            let mut v = DVec3::ZERO;
            v[order[k]] = sign;
            v
        };
        let sorted_from_body =
            DMat3::from_cols(row(0, 1.0), row(1, 1.0), row(2, if odd { -1.0 } else { 1.0 })).transpose();
        let sorted_inertia = DVec3::new(moments[order[0]], moments[order[1]], moments[order[2]]);
        let sorted = SortedTop::new(sorted_inertia, sorted_from_body * omega_body0);
        let sorted_from_body_q = DQuat::from_mat3(&sorted_from_body);
        Ok(Self { inertia_body, sorted_from_body, sorted_from_body_q, sorted })
    }

    /// The same top with the initial orientation `world_from_body(0) = orientation0` (unit quaternion).
    pub fn with_orientation(self, orientation0: DQuat) -> Self {
        let world_from_sorted = orientation0.normalize() * self.sorted_from_body_q.conjugate();
        Self { sorted: self.sorted.with_orientation(world_from_sorted), ..self }
    }

    /// The principal moments, in the order given (kg·m²).
    pub fn inertia_body(&self) -> DVec3 {
        self.inertia_body
    }

    /// The rotation from the body frame to the frame of sorted moments, `ω_sorted = S ω_body`.
    pub fn sorted_from_body(&self) -> DMat3 {
        self.sorted_from_body
    }

    /// Which axis `ω` circles (axes numbered by increasing moment).
    pub fn regime(&self) -> Regime {
        self.sorted.regime
    }

    /// The parameter `m = k²` of the Jacobi functions.
    pub fn parameter(&self) -> f64 {
        self.sorted.m
    }

    /// The complementary parameter `1 − m`, computed without cancellation.
    pub fn complementary_parameter(&self) -> f64 {
        self.sorted.m1
    }

    /// `λ` (1/s): `τ = λ t + τ0`.
    pub fn lambda(&self) -> f64 {
        self.sorted.lambda
    }

    /// `τ0`, the phase at `t = 0`.
    pub fn tau0(&self) -> f64 {
        self.sorted.tau0
    }

    /// Twice the kinetic energy, `2E = Σ I_i ω_i²` (J).
    pub fn twice_energy(&self) -> f64 {
        self.sorted.twice_energy()
    }

    /// `M² = |L|² = Σ I_i² ω_i²` ((kg·m²/s)²).
    pub fn angular_momentum_squared(&self) -> f64 {
        self.sorted.angular_momentum_squared()
    }

    /// The period of `ω_body`, `4K(m)/λ` (s); `+∞` for a steady rotation or on the separatrix.
    pub fn period(&self) -> f64 {
        self.sorted.period()
    }

    /// The time between two sign changes of the intermediate-axis component of `ω`, `2K(m)/λ` (s): the
    /// flip interval of a body spun near its intermediate axis.
    pub fn flip_interval(&self) -> f64 {
        self.sorted.flip_interval()
    }

    /// The body angular velocity at `t` (s), rad/s.
    pub fn omega_body(&self, t: f64) -> DVec3 {
        self.sorted_from_body.transpose() * self.sorted.omega_body(t)
    }

    /// `world_from_body` at `t` (s).
    pub fn orientation(&self, t: f64) -> DQuat {
        self.sorted.orientation(t) * self.sorted_from_body_q
    }

    /// The constant angular momentum, world frame (kg·m²/s).
    pub fn angular_momentum_world(&self) -> DVec3 {
        self.sorted.angular_momentum_world()
    }
}
