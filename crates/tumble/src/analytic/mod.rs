//! Exact reference solutions: what the integrators are measured against.
//!
//! - [`elliptic`]: the complete and incomplete elliptic integrals of the first kind, `K(m)` (by the
//!   arithmetic–geometric mean), `F(φ, m)` and `Π(n; φ | m)` (by Carlson's `R_F`, `R_J`), and the Jacobi elliptic
//!   functions `sn, cn, dn(u, m)` (by the descending Landen transformation), each also in a form
//!   that takes the complementary parameter `1 − m`, which stays accurate as `m → 1`.
//! - [`torque_free`]: the torque-free rigid body in closed form, the symmetric top (body angular
//!   velocity and world orientation) and the asymmetric top (three distinct moments in any order;
//!   body angular velocity and world orientation from any initial condition, in both regimes
//!   `M² > 2E I2` and `M² < 2E I2`), and the intermediate-axis flip interval `2K(m)/λ`.
//!
//! Units are SI; angular velocities are in the body (principal) frame, rad/s.
//!
//! ```
//! use tumble::analytic::AsymmetricTop;
//! use tumble::math::DVec3;
//! // spun close to the intermediate axis of I = (1, 2, 3) kg·m²: it flips every 5.026 s
//! let top = AsymmetricTop::new(DVec3::new(1.0, 2.0, 3.0), DVec3::new(0.01, 5.0, 0.01)).unwrap();
//! assert!((top.flip_interval() - 5.0259291).abs() < 1e-6);
//! ```

pub mod elliptic;
pub mod torque_free;

pub use elliptic::{ellipf, ellipf_m1, ellipk, ellipk_m1, ellippi, jacobi, jacobi_m1, Jacobi};
pub use torque_free::{AsymmetricTop, Regime, SymmetricTop, TopError};

#[cfg(test)]
mod tests;
