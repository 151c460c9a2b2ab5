//! Dormand–Prince 5(4): an embedded explicit Runge–Kutta pair with step-size control.
//!
//! Reference: J. R. Dormand, P. J. Prince, "A family of embedded Runge–Kutta formulae",
//! J. Comp. Appl. Math. 6 (1980); the error norm and controller of Hairer, Nørsett, Wanner,
//! *Solving ODEs I*, §II.4:
//!
//! `err = sqrt( 1/n Σ_i ((y5_i − y4_i) / (atol + rtol · max(|y0_i|, |y1_i|)))² )` over the 13 state
//! components; a step is accepted when `err ≤ 1`, and the next step is `h · clamp(0.9 err^(−1/5), 0.2, 5)`.
//!
//! The world's `dt` is the largest step and the output step: [`dopri5_advance`] covers exactly `dt`
//! with as many internal steps as the tolerance needs, remembering the last step size per body.
//! The stage after an accepted step is the first stage of the next (FSAL).

use super::{euler_stage, renormalize, BodyRhs, StepSizeUnderflow, Tolerances};
use crate::body::dynamics::StateRate;
use crate::body::BodyState;

// stage times c = (0, 1/5, 3/10, 4/5, 8/9, 1, 1) are not needed: the ODE is autonomous
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0],
    [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0],
    // the 5th-order weights b (the last stage is evaluated at the new point: FSAL)
    [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0],
];
/// `b − b̂`: the 5th-order weights minus the embedded 4th-order ones.
const E: [f64; 7] =
    [71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0];

#[inline]
fn combine(k: &[StateRate; 7], w: &[f64], n: usize) -> StateRate {
    let mut r = StateRate::default();
    for j in 0..n {
        if w[j] != 0.0 {
            r.velocity += w[j] * k[j].velocity;
            r.acceleration += w[j] * k[j].acceleration;
            r.orientation_rate += w[j] * k[j].orientation_rate;
            r.alpha_body += w[j] * k[j].alpha_body;
        }
    }
    r
}

#[inline]
fn components(s: &BodyState) -> [f64; 13] {
    let (p, q, v, w) = (s.position, s.orientation, s.velocity, s.omega_body);
    [p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, w.x, w.y, w.z]
}

#[inline]
fn rate_components(r: &StateRate) -> [f64; 13] {
    let (p, q, v, w) = (r.velocity, r.orientation_rate, r.acceleration, r.alpha_body);
    [p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, w.x, w.y, w.z]
}

/// Advances one body by exactly `h` seconds with adaptive internal steps.
///
/// `step_hint` (s) carries the step-size controller's proposal from one call to the next; a value
/// `≤ 0` starts with `h`.
pub fn dopri5_advance(
    rhs: &BodyRhs,
    state: &mut BodyState,
    h: f64,
    tol: Tolerances,
    step_hint: &mut f64,
) -> Result<(), StepSizeUnderflow> {
    let mut k = [StateRate::default(); 7];
    let mut elapsed = 0.0;
    let mut step = if *step_hint > 0.0 { step_hint.min(h) } else { h };
    k[0] = rhs.rate(state);
    while elapsed < h {
        let remaining = h - elapsed;
        let last = step >= remaining * (1.0 - 1e-12);
        let hs = if last { remaining } else { step };
        for i in 1..7 {
            let slope = combine(&k, &A[i], i);
            k[i] = rhs.rate(&euler_stage(state, &slope, hs));
        }
        // the 7th stage was evaluated at y5 = y + hs Σ b_j k_j
        let y5 = euler_stage(state, &combine(&k, &A[6], 6), hs);
        let err_rate = rate_components(&combine(&k, &E, 7));
        let y0c = components(state);
        let y1c = components(&y5);
        let mut sum = 0.0;
        for i in 0..13 {
            let scale = tol.atol + tol.rtol * y0c[i].abs().max(y1c[i].abs());
            let e = hs * err_rate[i] / scale;
            sum += e * e;
        }
        let err = (sum / 13.0).sqrt();
        let factor = if err == 0.0 { 5.0 } else { (0.9 * err.powf(-0.2)).clamp(0.2, 5.0) };
        if err <= 1.0 && y5.is_finite() {
            *state = y5;
            elapsed += hs;
            k[0] = k[6];
            // a step shortened to land on the output time says nothing about the next one
            step = if last { step.max(hs * factor) } else { hs * factor };
        } else {
            step = hs * factor.min(1.0);
            if !err.is_finite() {
                step = hs * 0.2;
            }
        }
        if step < 1e-14 * h.max(1e-300) {
            return Err(StepSizeUnderflow { step, elapsed });
        }
    }
    *step_hint = step;
    state.orientation = renormalize(state.orientation);
    Ok(())
}
