//! Shared helpers of the multibody tests: a seeded generator, random trees and states, the one
//! tolerance check.
#![allow(dead_code)]

use tumble::math::{DMat3, DQuat, DVec3};
use tumble::multibody::{JointKind, ModelBuilder, MultibodyModel, RigidInertia, Xform};

/// SplitMix64: small, seeded, reproducible.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
    pub fn vec3(&mut self, scale: f64) -> DVec3 {
        DVec3::new(self.range(-scale, scale), self.range(-scale, scale), self.range(-scale, scale))
    }
    pub fn unit(&mut self) -> DVec3 {
        loop {
            let v = self.vec3(1.0);
            let n = v.length();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }
    pub fn quat(&mut self) -> DQuat {
        DQuat::from_axis_angle(self.unit(), self.range(-3.0, 3.0))
    }
    pub fn vector(&mut self, n: usize, scale: f64) -> Vec<f64> {
        (0..n).map(|_| self.range(-scale, scale)).collect()
    }
}

/// A random rigid inertia: mass in [0.5, 3] kg, centre of mass within 0.3 m, principal moments that
/// satisfy the triangle inequality, rotated axes.
pub fn random_inertia(rng: &mut Rng) -> RigidInertia {
    let mass = rng.range(0.5, 3.0);
    let a = rng.range(0.02, 0.2);
    let b = rng.range(0.02, 0.2);
    let c = rng.range((a - b).abs() + 0.01, a + b);
    let r = DMat3::from_quat(rng.quat());
    RigidInertia::from_com(mass, rng.vec3(0.3), r * DMat3::from_diagonal(DVec3::new(a, b, c)) * r.transpose())
}

/// Which joints a random tree may use.
#[derive(Clone, Copy, PartialEq)]
pub enum Base {
    Fixed,
    Floating,
}

/// A random tree of `n` bodies: random parents (parents first), revolute, continuous, prismatic
/// and spherical joints about random axes, random placements and inertias; with a floating base
/// the first body hangs from the world by a floating joint.
pub fn random_tree(rng: &mut Rng, n: usize, base: Base, spherical: bool) -> MultibodyModel {
    let mut b = ModelBuilder::new("random");
    for i in 0..n {
        let parent = if i == 0 { None } else { Some(rng.below(i)) };
        let kind = if i == 0 && base == Base::Floating {
            JointKind::Floating
        } else {
            match rng.below(if spherical { 4 } else { 3 }) {
                0 => JointKind::Revolute { axis: rng.unit() },
                1 => JointKind::Continuous { axis: rng.unit() },
                2 => JointKind::Prismatic { axis: rng.unit() },
                _ => JointKind::Spherical,
            }
        };
        let x_tree = Xform::from_pose(DMat3::from_quat(rng.quat()), rng.vec3(0.5));
        b.add_body(format!("link{i}"), parent, format!("joint{i}"), kind, x_tree, random_inertia(rng)).unwrap();
    }
    b.build().unwrap()
}

/// A random configuration: angles and displacements in [−1, 1], random unit quaternions.
pub fn random_q(rng: &mut Rng, model: &MultibodyModel) -> Vec<f64> {
    let mut q = vec![0.0; model.nq()];
    for body in &model.bodies {
        let j = &body.joint;
        let qi = j.q_index;
        match j.kind {
            JointKind::Spherical => {
                let r = rng.quat();
                q[qi..qi + 4].copy_from_slice(&[r.w, r.x, r.y, r.z]);
            }
            JointKind::Floating => {
                let p = rng.vec3(1.0);
                let r = rng.quat();
                q[qi..qi + 7].copy_from_slice(&[p.x, p.y, p.z, r.w, r.x, r.y, r.z]);
            }
            _ => q[qi] = rng.range(-1.0, 1.0),
        }
    }
    q
}

/// `|a − b| ≤ tol · max(1, |b|)` entry by entry (the one tolerance check), with a message naming
/// the entry.
pub fn assert_close(what: &str, a: &[f64], b: &[f64], tol: f64) {
    assert_eq!(a.len(), b.len(), "{what}: lengths differ");
    let scale = b.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= tol * scale,
            "{what}[{k}]: {x} vs {y} (difference {:e}, allowed {:e})",
            (x - y).abs(),
            tol * scale
        );
    }
}
