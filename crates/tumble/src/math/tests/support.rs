//! Shared by the unit tests of `math`, `body` and `world`: the one tolerance helper and the random
//! inputs of the property tests.
//!
//! Every comparison goes through [`assert_close`]: `‖actual − expected‖_∞ ≤ tol · scale`. The scale
//! is the magnitude the error should be measured against (for `a × b` it is `|a| |b|`, not `|a × b|`,
//! which may cancel to zero); tolerances are written as multiples of [`EPS`] where the computation is
//! a handful of floating-point operations, so that a tolerance says how many rounding errors it allows.
#![allow(dead_code)]

use crate::math::{DMat3, DQuat, DVec3, DVec4};
use proptest::prelude::*;
use std::fmt::Debug;

/// The unit round-off of `f64` doubled: the spacing of floating-point numbers just above 1 (`2.2e-16`).
pub const EPS: f64 = f64::EPSILON;

/// A value that can be compared component by component.
pub trait Components: Debug {
    fn components(&self) -> Vec<f64>;
}

impl Components for f64 {
    fn components(&self) -> Vec<f64> {
        vec![*self]
    }
}

impl Components for DVec3 {
    fn components(&self) -> Vec<f64> {
        self.to_array().to_vec()
    }
}

impl Components for DVec4 {
    fn components(&self) -> Vec<f64> {
        self.to_array().to_vec()
    }
}

impl Components for DQuat {
    fn components(&self) -> Vec<f64> {
        self.to_array().to_vec()
    }
}

impl Components for DMat3 {
    fn components(&self) -> Vec<f64> {
        self.to_cols_array().to_vec()
    }
}

/// The largest absolute component (`‖x‖_∞`).
pub fn max_abs<T: Components>(x: &T) -> f64 {
    x.components().iter().fold(0.0, |m, c| m.max(c.abs()))
}

/// Asserts `‖actual − expected‖_∞ ≤ tol · scale` (NaN fails); `what` names the identity in the message.
#[track_caller]
pub fn assert_close<T: Components>(what: &str, actual: T, expected: T, tol: f64, scale: f64) {
    let (a, e) = (actual.components(), expected.components());
    assert_eq!(a.len(), e.len());
    let error =
        a.iter().zip(&e).fold(0.0_f64, |m, (x, y)| if (x - y).is_nan() { f64::NAN } else { m.max((x - y).abs()) });
    assert!(
        error <= tol * scale,
        "{what}: error {error:e} > tol {tol:e} × scale {scale:e} ({:.1} × allowed)\n  actual   {actual:?}\n  expected {expected:?}",
        error / (tol * scale)
    );
}

/// [`assert_close`] with the scale taken from the values themselves, `max(‖actual‖_∞, ‖expected‖_∞)`:
/// a relative comparison.
#[track_caller]
pub fn assert_rel<T: Components>(what: &str, actual: T, expected: T, tol: f64) {
    let scale = max_abs(&actual).max(max_abs(&expected));
    assert_close(what, actual, expected, tol, scale);
}

/// Vectors with components uniform in `[−r, r]`.
pub fn vec3(r: f64) -> impl Strategy<Value = DVec3> {
    prop::array::uniform3(-r..=r).prop_map(DVec3::from_array)
}

/// Unit vectors (a direction).
pub fn unit_vec3() -> impl Strategy<Value = DVec3> {
    vec3(1.0).prop_filter("not too short", |v| v.length() > 0.1).prop_map(|v| v.normalize())
}

/// Unit quaternions: a point of the cube `[−1, 1]⁴` outside a small ball, projected on the sphere
/// (every rotation is reached, both signs of `w`).
pub fn unit_quat() -> impl Strategy<Value = DQuat> {
    prop::array::uniform4(-1.0..=1.0_f64)
        .prop_filter("not too short", |a| DVec4::from_array(*a).length() > 0.1)
        .prop_map(|a| DQuat::from_vec4(DVec4::from_array(a)).normalize())
}

/// Valid principal moments (kg·m²): `I1, I2` in `[0.1, 10] · s`, `I3` strictly between `|I1 − I2|` and
/// `I1 + I2` (at least 2 % of that interval away from its ends), and the overall scale `s` in
/// `[1e-6, 1e3]`, shuffled.
pub fn principal_moments() -> impl Strategy<Value = DVec3> {
    (0.1..10.0_f64, 0.1..10.0_f64, 0.02..0.98_f64, -6.0..3.0_f64, 0..3usize).prop_map(|(a, b, t, log_scale, k)| {
        let (lo, hi) = ((a - b).abs(), a + b);
        let c = lo + t * (hi - lo);
        let s = 10f64.powf(log_scale);
        let m = [a * s, b * s, c * s];
        DVec3::new(m[k], m[(k + 1) % 3], m[(k + 2) % 3])
    })
}
