//! Identities of the spatial algebra (Featherstone (2008) ch. 2) on random vectors and transforms.

mod multibody_common;

use multibody_common::{assert_close, random_inertia, Rng};
use tumble::math::{DMat3, DVec3};
use tumble::multibody::spatial::{axis_angle_rotation, rpy_rotation};
use tumble::multibody::{ArticulatedInertia, Force, Motion, Xform};

fn motion(rng: &mut Rng) -> Motion {
    Motion::new(rng.vec3(2.0), rng.vec3(2.0))
}
fn force(rng: &mut Rng) -> Force {
    Force::new(rng.vec3(2.0), rng.vec3(2.0))
}
fn xform(rng: &mut Rng) -> Xform {
    Xform::from_pose(DMat3::from_quat(rng.quat()), rng.vec3(1.0))
}

#[test]
fn transforms_preserve_power_and_invert() {
    let mut rng = Rng::new(1);
    for _ in 0..100 {
        let (x, m, f) = (xform(&mut rng), motion(&mut rng), force(&mut rng));
        // (X m) · (X* f) = m · f: power is frame-independent
        let p = x.apply_motion(m).dot(x.apply_force(f));
        assert!((p - m.dot(f)).abs() < 1e-12 * (1.0 + p.abs()));
        // X⁻¹ X m = m, and Xᵀ (the inverse of X*) X* f = f
        assert_close("X⁻¹ X m", &x.inv_apply_motion(x.apply_motion(m)).to_array(), &m.to_array(), 1e-14);
        assert_close("Xᵀ X* f", &x.inv_apply_force(x.apply_force(f)).to_array(), &f.to_array(), 1e-14);
        assert_close("inverse()", &x.inverse().apply_motion(m).to_array(), &x.inv_apply_motion(m).to_array(), 1e-14);
        // composition
        let y = xform(&mut rng);
        let composed = y.compose(&x).apply_motion(m);
        assert_close("Y (X m)", &composed.to_array(), &y.apply_motion(x.apply_motion(m)).to_array(), 1e-14);
        // points
        let p = rng.vec3(1.0);
        assert_close("points", &x.inv_apply_point(x.apply_point(p)).to_array(), &p.to_array(), 1e-14);
    }
}

/// The velocity of a point: `v_B` at the origin of B equals `v_A + ω × (r)` expressed in B.
#[test]
fn motion_transform_moves_the_reference_point() {
    let x = Xform::from_pose(DMat3::IDENTITY, DVec3::new(1.0, 0.0, 0.0));
    let m = Motion::new(DVec3::new(0.0, 0.0, 2.0), DVec3::ZERO);
    // spinning at 2 rad/s about z through A's origin: B's origin at x = 1 moves at 2 m/s along y
    assert_close("v_B", &x.apply_motion(m).lin.to_array(), &[0.0, 2.0, 0.0], 0.0);
}

#[test]
fn cross_products_are_consistent() {
    let mut rng = Rng::new(2);
    for _ in 0..100 {
        let (v, m, f) = (motion(&mut rng), motion(&mut rng), force(&mut rng));
        // v ×ₘ v = 0
        assert_close("v × v", &v.cross_motion(v).to_array(), &[0.0; 6], 1e-15);
        // crf = −crmᵀ: (v ×ₘ m) · f = −m · (v ×* f)
        let a = v.cross_motion(m).dot(f);
        let b = -m.dot(v.cross_force(f));
        assert!((a - b).abs() < 1e-12 * (1.0 + a.abs()), "{a} vs {b}");
        // transforms commute with the cross products: X (v ×ₘ m) = (X v) ×ₘ (X m)
        let x = xform(&mut rng);
        let lhs = x.apply_motion(v.cross_motion(m));
        let rhs = x.apply_motion(v).cross_motion(x.apply_motion(m));
        assert_close("X (v × m)", &lhs.to_array(), &rhs.to_array(), 1e-13);
        let lhs = x.apply_force(v.cross_force(f));
        let rhs = x.apply_motion(v).cross_force(x.apply_force(f));
        assert_close("X* (v ×* f)", &lhs.to_array(), &rhs.to_array(), 1e-13);
    }
}

#[test]
fn inertias_transform_as_x_transpose_i_x() {
    let mut rng = Rng::new(3);
    for _ in 0..100 {
        let inertia = random_inertia(&mut rng);
        let x = xform(&mut rng);
        let m = motion(&mut rng);
        // (Xᵀ I X) m = Xᵀ (I (X m))
        let expected = x.inv_apply_force(inertia.mul_motion(x.apply_motion(m)));
        assert_close("rigid", &inertia.transform_to_a(&x).mul_motion(m).to_array(), &expected.to_array(), 1e-13);
        let art = ArticulatedInertia::from(inertia);
        assert_close("articulated", &art.transform_to_a(&x).mul_motion(m).to_array(), &expected.to_array(), 1e-13);
        // kinetic energy is frame-independent
        let t = inertia.kinetic_energy(x.apply_motion(m));
        assert!((t - inertia.transform_to_a(&x).kinetic_energy(m)).abs() < 1e-12 * (1.0 + t));
    }
}

#[test]
fn rotations_match_glam() {
    let mut rng = Rng::new(4);
    for _ in 0..100 {
        let (axis, angle) = (rng.unit(), rng.range(-4.0, 4.0));
        let expected = DMat3::from_axis_angle(axis, angle);
        assert_close("Rodrigues", &axis_angle_rotation(axis, angle).to_cols_array(), &expected.to_cols_array(), 1e-14);
    }
    // rpy = (r, p, y): Rz(y) Ry(p) Rx(r), fixed axes
    let r = rpy_rotation(DVec3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2));
    assert_close("yaw 90°", &(r * DVec3::X).to_array(), &[0.0, 1.0, 0.0], 1e-15);
    let r = rpy_rotation(DVec3::new(std::f64::consts::FRAC_PI_2, 0.0, std::f64::consts::FRAC_PI_2));
    // roll first about the fixed x, then yaw about the fixed z: y → z → z
    assert_close("roll then yaw", &(r * DVec3::Y).to_array(), &[0.0, 0.0, 1.0], 1e-15);
}
