//! The classical fourth-order Runge–Kutta method.
//!
//! `k1 = f(y)`, `k2 = f(y + h/2 k1)`, `k3 = f(y + h/2 k2)`, `k4 = f(y + h k3)`,
//! `y ← y + h/6 (k1 + 2 k2 + 2 k3 + k4)`, then `q` is projected back to unit length.
//! Reference: Hairer, Nørsett, Wanner, *Solving ODEs I*, §II.1.

use super::{euler_stage, renormalize, BodyRhs};
use crate::body::dynamics::StateRate;
use crate::body::BodyState;

/// One RK4 step of length `h` (s).
#[inline]
pub fn rk4_step(rhs: &BodyRhs, state: &mut BodyState, h: f64) {
    let k1 = rhs.rate(state);
    let k2 = rhs.rate(&euler_stage(state, &k1, 0.5 * h));
    let k3 = rhs.rate(&euler_stage(state, &k2, 0.5 * h));
    let k4 = rhs.rate(&euler_stage(state, &k3, h));
    let slope = StateRate {
        velocity: (k1.velocity + 2.0 * (k2.velocity + k3.velocity) + k4.velocity) / 6.0,
        acceleration: (k1.acceleration + 2.0 * (k2.acceleration + k3.acceleration) + k4.acceleration) / 6.0,
        orientation_rate: (k1.orientation_rate
            + 2.0 * (k2.orientation_rate + k3.orientation_rate)
            + k4.orientation_rate)
            / 6.0,
        alpha_body: (k1.alpha_body + 2.0 * (k2.alpha_body + k3.alpha_body) + k4.alpha_body) / 6.0,
    };
    *state = euler_stage(state, &slope, h);
    state.orientation = renormalize(state.orientation);
}
