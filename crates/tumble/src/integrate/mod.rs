//! Time integrators for the Newton–Euler ODE of a free rigid body.
//!
//! | name                  | order | what it keeps                                               | file            |
//! |-----------------------|-------|-------------------------------------------------------------|-----------------|
//! | `euler`               | 1     | nothing (energy of a tumbling body grows)                   | [`euler`]       |
//! | `semi_implicit_euler` | 1     | symplectic in translation; implicit gyroscopic term: `T` and `|L|` never grow | [`euler`] |
//! | `rk4`                 | 4     | nothing exactly; small errors                               | [`rk4`]         |
//! | `dopri5`              | 5(4)  | error per step below `rtol`/`atol` (adaptive)               | [`dopri5`]      |
//! | `splitting`           | 2     | `L_world` to round-off, bounded energy error, symplectic    | [`splitting`]   |
//! | `splitting4`          | 4     | the same, with 4th-order phase accuracy                     | [`splitting`]   |
//!
//! Orientations stay unit quaternions: the Lie-group updates (`euler`'s exponential map, the
//! splittings' exact axis rotations) keep `|q| = 1` to round-off, and every integrator ends a step by
//! projecting `q` back onto the unit sphere ([`renormalize`]); for `rk4` and `dopri5`, which move `q`
//! through ℝ⁴, that projection keeps their order.

pub mod batch;
pub mod dopri5;
pub mod euler;
pub(crate) mod lanes;
pub mod rk4;
pub mod splitting;

use crate::body::dynamics::{state_rate, StateRate};
use crate::body::{BodyState, Loads, MassProperties};
use crate::math::{quat_add, DQuat, DVec3};
use std::fmt;
use std::str::FromStr;

/// The integrators a scene may name (`[world] integrator = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Integrator {
    Euler,
    SemiImplicitEuler,
    Rk4,
    Dopri5,
    Splitting,
    Splitting4,
}

impl Integrator {
    /// Every integrator, in the order of the table above.
    pub const ALL: [Integrator; 6] = [
        Integrator::Euler,
        Integrator::SemiImplicitEuler,
        Integrator::Rk4,
        Integrator::Dopri5,
        Integrator::Splitting,
        Integrator::Splitting4,
    ];

    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Integrator::Euler => "euler",
            Integrator::SemiImplicitEuler => "semi_implicit_euler",
            Integrator::Rk4 => "rk4",
            Integrator::Dopri5 => "dopri5",
            Integrator::Splitting => "splitting",
            Integrator::Splitting4 => "splitting4",
        }
    }

    /// The formal order of accuracy.
    pub fn order(self) -> u32 {
        match self {
            Integrator::Euler | Integrator::SemiImplicitEuler => 1,
            Integrator::Splitting => 2,
            Integrator::Rk4 | Integrator::Splitting4 => 4,
            Integrator::Dopri5 => 5,
        }
    }

    /// How far the positions of a step run ahead of the velocity, as a fraction of the step's
    /// velocity change. Under a constant acceleration `a` every integrator moves a body along a
    /// parabola, `x(t) = x + (v + lead · a dt) t + ½ a t²`, and ends the step at `x(dt)`:
    /// explicit Euler (`x' = x + v dt`) has `lead = −½`, semi-implicit Euler (`x' = x + (v + a dt) dt`)
    /// `+½`; the others integrate a constant acceleration exactly, `0`. The contact stage predicts
    /// where surfaces meet along this parabola, so that it sees the collisions the step will make.
    pub fn position_lead(self) -> f64 {
        match self {
            Integrator::Euler => -0.5,
            Integrator::SemiImplicitEuler => 0.5,
            Integrator::Rk4 | Integrator::Dopri5 | Integrator::Splitting | Integrator::Splitting4 => 0.0,
        }
    }

    /// All names, comma separated (for error messages).
    pub fn names() -> String {
        Self::ALL.iter().map(|i| i.name()).collect::<Vec<_>>().join(", ")
    }
}

impl fmt::Display for Integrator {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An integrator name that is not one of [`Integrator::ALL`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown integrator `{name}` (expected one of: {})", Integrator::names())]
pub struct UnknownIntegrator {
    pub name: String,
}

impl FromStr for Integrator {
    type Err = UnknownIntegrator;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL.into_iter().find(|i| i.name() == s).ok_or_else(|| UnknownIntegrator { name: s.to_string() })
    }
}

/// Error tolerances of the adaptive integrator (`dopri5`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance (in the units of each state component).
    pub atol: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Self { rtol: 1e-9, atol: 1e-12 }
    }
}

/// The right-hand side of one body's ODE: what the integrators need besides the state.
#[derive(Debug, Clone, Copy)]
pub struct BodyRhs<'a> {
    pub mass: &'a MassProperties,
    pub loads: &'a Loads,
    /// Gravitational acceleration, world frame (m/s²).
    pub gravity_world: DVec3,
}

impl BodyRhs<'_> {
    /// `ẏ = f(y)`, the Newton–Euler equations in the body-frame form.
    #[inline]
    pub fn rate(&self, state: &BodyState) -> StateRate {
        state_rate(self.mass, self.loads, state, self.gravity_world)
    }
}

/// The adaptive integrator could not meet its tolerance with a step larger than round-off.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("step size underflow (h = {step:e} s) at t + {elapsed:e} s within the step")]
pub struct StepSizeUnderflow {
    pub step: f64,
    pub elapsed: f64,
}

/// Advances one body by `h` seconds with `integrator`.
///
/// `step_hint` is the adaptive integrator's last accepted internal step for this body (s); the other
/// integrators ignore it.
#[inline]
pub fn advance_body(
    integrator: Integrator,
    tolerances: Tolerances,
    rhs: &BodyRhs,
    state: &mut BodyState,
    h: f64,
    step_hint: &mut f64,
) -> Result<(), StepSizeUnderflow> {
    match integrator {
        Integrator::Euler => euler::euler_step(rhs, state, h),
        Integrator::SemiImplicitEuler => euler::semi_implicit_euler_step(rhs, state, h),
        Integrator::Rk4 => rk4::rk4_step(rhs, state, h),
        Integrator::Dopri5 => return dopri5::dopri5_advance(rhs, state, h, tolerances, step_hint),
        Integrator::Splitting => splitting::splitting_step(rhs, state, h),
        Integrator::Splitting4 => splitting::splitting4_step(rhs, state, h),
    }
    Ok(())
}

/// `y + h ẏ`, with the quaternion moved through ℝ⁴ (an explicit Runge–Kutta stage; not normalised).
#[inline]
pub(crate) fn euler_stage(state: &BodyState, rate: &StateRate, h: f64) -> BodyState {
    BodyState {
        position: state.position + h * rate.velocity,
        orientation: quat_add(state.orientation, h * rate.orientation_rate),
        velocity: state.velocity + h * rate.acceleration,
        omega_body: state.omega_body + h * rate.alpha_body,
    }
}

/// Projects a quaternion that is within round-off (or a small integration error) of unit length back
/// onto the unit sphere: one Newton step of `|q|² = 1`, `q ← q (3 − |q|²)/2`, which leaves
/// `| |q| − 1 |` at the square of what it was, without a square root or a division.
/// Quaternions further than 1e-4 from unit length are normalised exactly.
#[inline]
pub fn renormalize(q: DQuat) -> DQuat {
    let n2 = q.length_squared();
    if (n2 - 1.0).abs() < 1e-4 {
        q * (0.5 * (3.0 - n2))
    } else {
        q.normalize()
    }
}

#[cfg(test)]
mod tests;
