//! The inertia-box fluid model against closed forms: Stokes drag of a translating box, quadratic
//! drag on its face, and the power of the drag never positive without wind.

use super::*;
use crate::multibody::joint::JointKind;
use crate::multibody::model::ModelBuilder;
use crate::multibody::spatial::{axis_angle_rotation, RigidInertia};

/// A small deterministic generator (64-bit LCG, top 53 bits).
struct Lcg(u64);

impl Lcg {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }

    fn rotation(&mut self) -> DMat3 {
        let axis = DVec3::new(self.uniform(-1.0, 1.0), self.uniform(-1.0, 1.0), self.uniform(-1.0, 1.0) + 2.0);
        axis_angle_rotation(axis.normalize(), self.uniform(-3.0, 3.0))
    }
}

/// A free box of mass `m` and full sides `s` (its inertia about its centre, principal along the
/// body axes), in `medium`.
fn free_box(m: f64, s: DVec3, medium: Medium) -> MultibodyModel {
    let moments = m / 12.0 * DVec3::new(s.y * s.y + s.z * s.z, s.x * s.x + s.z * s.z, s.x * s.x + s.y * s.y);
    let inertia = RigidInertia::from_com(m, DVec3::ZERO, DMat3::from_diagonal(moments));
    let mut b = ModelBuilder::new("box");
    b.add_body("box", None, "free", JointKind::Floating, Xform::IDENTITY, inertia).unwrap();
    let mut model = b.build().unwrap();
    let fb = FluidBox::new(0, m, DVec3::ZERO, DMat3::IDENTITY, moments).unwrap();
    model.fluid = Fluid { medium, boxes: vec![fb] };
    model
}

fn close(got: DVec3, want: DVec3, tol: f64) {
    assert!((got - want).length() <= tol * want.length().max(1e-300), "got {got:?}, want {want:?}");
}

#[test]
fn the_equivalent_box_of_a_box_is_the_box() {
    let (m, s) = (2.5, DVec3::new(0.3, 0.7, 1.1));
    let moments = m / 12.0 * DVec3::new(s.y * s.y + s.z * s.z, s.x * s.x + s.z * s.z, s.x * s.x + s.y * s.y);
    close(box_size(m, moments), s, 1e-15);
}

/// The body's generalized force from the fluid at `v` (the floating joint's coordinates: linear
/// velocity then angular velocity, body frame; the force then the moment).
fn drag(model: &MultibodyModel, v: [f64; 6]) -> [f64; 6] {
    let mut ws = Workspace::new(model);
    let q = model.neutral_configuration();
    let mut tau = vec![0.0; 6];
    add_fluid_forces(model, &mut ws, &q, &v, &mut tau).unwrap();
    tau.try_into().unwrap()
}

/// A box translating at `u` through a viscous medium: the Stokes force `−3 π μ d u`, `d` the mean
/// side; turning at `ω`: the moment `−π μ d³ ω`.
#[test]
fn stokes_drag_of_a_translating_and_turning_box() {
    let (m, s, mu) = (3.0, DVec3::new(0.2, 0.5, 0.8), 0.1);
    let model = free_box(m, s, Medium { viscosity: mu, ..Medium::default() });
    let d = (s.x + s.y + s.z) / 3.0;
    let u = DVec3::new(0.3, -1.2, 0.7);
    let omega = DVec3::new(-0.4, 0.9, 2.0);
    // the floating joint's velocity is [v; ω] in the body frame (at the identity pose, the world's)
    let tau = drag(&model, [u.x, u.y, u.z, omega.x, omega.y, omega.z]);
    let force = DVec3::new(tau[0], tau[1], tau[2]);
    let moment = DVec3::new(tau[3], tau[4], tau[5]);
    close(force, -3.0 * PI * mu * d * u, 1e-14);
    close(moment, -PI * mu * d * d * d * omega, 1e-14);
}

/// A box translating along each axis through a dense medium: `−½ ρ A |u| u` with `A` the face
/// normal to the motion.
#[test]
fn quadratic_drag_on_the_face_across_the_motion() {
    let (m, s, rho) = (3.0, DVec3::new(0.2, 0.5, 0.8), 1000.0);
    let model = free_box(m, s, Medium { density: rho, ..Medium::default() });
    let faces = [s.y * s.z, s.x * s.z, s.x * s.y];
    for (axis, area) in faces.iter().enumerate() {
        let mut v = [0.0; 6];
        v[axis] = -1.7;
        let tau = drag(&model, v);
        let want = -0.5 * rho * area * 1.7 * -1.7;
        assert!((tau[axis] - want).abs() <= 1e-13 * want.abs(), "axis {axis}: {} vs {want}", tau[axis]);
        for k in (0..6).filter(|&k| k != axis) {
            assert_eq!(tau[k], 0.0, "axis {axis}: coordinate {k}");
        }
    }
}

/// Moving with the wind, a body feels nothing.
#[test]
fn a_body_carried_by_the_wind_feels_no_drag() {
    let wind = DVec3::new(0.5, -0.25, 1.0);
    let model = free_box(1.0, DVec3::new(0.1, 0.2, 0.3), Medium { density: 1.2, viscosity: 1e-3, wind });
    let tau = drag(&model, [wind.x, wind.y, wind.z, 0.0, 0.0, 0.0]);
    assert!(tau.iter().all(|t| t.abs() <= 1e-15), "{tau:?}");
}

/// A void medium: no force and `tau` untouched (bit for bit).
#[test]
fn a_void_medium_costs_nothing_and_changes_nothing() {
    let model = free_box(1.0, DVec3::new(0.1, 0.2, 0.3), Medium { wind: DVec3::X, ..Medium::default() });
    assert!(!model.fluid.is_active());
    let mut ws = Workspace::new(&model);
    let q = model.neutral_configuration();
    let mut tau = vec![0.125; 6];
    add_fluid_forces(&model, &mut ws, &q, &[1.0; 6], &mut tau).unwrap();
    assert_eq!(tau, vec![0.125; 6]);
}

/// Without wind the drag only takes energy: `τ_fluid · v ≤ 0` at random states of a random chain
/// of boxes (hinges, slides and a ball on a floating base), boxes off the joint axes.
#[test]
fn the_drag_never_adds_energy() {
    let mut rng = Lcg(11);
    let medium = Medium { density: 800.0, viscosity: 0.3, wind: DVec3::ZERO };
    let mut b = ModelBuilder::new("chain");
    let kinds = [
        JointKind::Floating,
        JointKind::Revolute { axis: DVec3::new(0.3, 1.0, -0.2) },
        JointKind::Prismatic { axis: DVec3::new(1.0, 0.5, 0.0) },
        JointKind::Spherical,
        JointKind::Continuous { axis: DVec3::Z },
    ];
    let mut boxes = Vec::new();
    for (i, kind) in kinds.into_iter().enumerate() {
        let com = DVec3::new(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5));
        let moments = DVec3::new(0.2, 0.3, 0.4);
        let axes = rng.rotation();
        let inertia = RigidInertia::from_com(2.0, com, axes * DMat3::from_diagonal(moments) * axes.transpose());
        let x_tree = Xform::from_pose(DMat3::IDENTITY, DVec3::new(0.0, 0.4, 0.1));
        let parent = i.checked_sub(1);
        b.add_body(format!("b{i}"), parent, format!("j{i}"), kind, x_tree, inertia).unwrap();
        boxes.push(FluidBox::new(i, 2.0, com, axes, moments).unwrap());
    }
    let mut model = b.build().unwrap();
    model.fluid = Fluid { medium, boxes };
    let mut ws = Workspace::new(&model);
    let mut worst = f64::NEG_INFINITY;
    for _ in 0..200 {
        let mut q = model.neutral_configuration();
        let v: Vec<f64> = (0..model.nv()).map(|_| rng.uniform(-3.0, 3.0)).collect();
        let dq: Vec<f64> = (0..model.nv()).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let q0 = q.clone();
        model.integrate(&q0, &dq, 1.0, &mut q).unwrap();
        let mut tau = vec![0.0; model.nv()];
        add_fluid_forces(&model, &mut ws, &q, &v, &mut tau).unwrap();
        let power: f64 = tau.iter().zip(&v).map(|(t, v)| t * v).sum();
        let scale: f64 = tau.iter().zip(&v).map(|(t, v)| (t * v).abs()).sum();
        assert!(power <= 1e-12 * scale, "power {power} > 0");
        worst = worst.max(power);
    }
    assert!(worst < 0.0);
}

/// The principal axes from the eigen-solver diagonalise the tensor and form a rotation.
#[test]
fn principal_axes_diagonalise_the_tensor() {
    let r = Lcg(5).rotation();
    let tensor = r * DMat3::from_diagonal(DVec3::new(0.5, 0.9, 1.2)) * r.transpose();
    let (moments, axes) = principal_axes(tensor);
    let d = axes.transpose() * tensor * axes;
    assert!((axes.determinant() - 1.0).abs() < 1e-14);
    close(DVec3::new(d.x_axis.x, d.y_axis.y, d.z_axis.z), moments, 1e-14);
    assert!(d.x_axis.y.abs() + d.x_axis.z.abs() + d.y_axis.z.abs() < 1e-14);
}
