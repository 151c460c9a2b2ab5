//! A one-link floating model moves exactly like the free rigid body of `tumble::body::dynamics`.

mod multibody_common;

use multibody_common::Rng;
use tumble::body::dynamics::state_rate;
use tumble::body::{BodyState, Loads};
use tumble::math::{DMat3, DVec3};
use tumble::multibody::{aba, JointKind, ModelBuilder, RigidInertia, Workspace, Xform};
use tumble::MassProperties;

/// `|a − b| ≤ 1e-12 · max(1, |b|)` componentwise.
fn assert_vec_close(what: &str, a: DVec3, b: DVec3) {
    let scale = b.abs().max_element().max(1.0);
    assert!((a - b).abs().max_element() <= 1e-12 * scale, "{what}: {a} vs {b} (difference {:e})", (a - b).length());
}

/// The link frame differs from the body's principal frame by a rotation and an offset of the centre
/// of mass, so the comparison goes through every frame change.
#[test]
fn one_link_floating_model_is_a_free_rigid_body() {
    let mut rng = Rng::new(7);
    for case in 0..20 {
        let mass = rng.range(0.5, 5.0);
        let (i1, i2) = (rng.range(0.1, 0.5), rng.range(0.1, 0.5));
        let moments = DVec3::new(i1, i2, rng.range((i1 - i2).abs() + 0.01, i1 + i2));
        // principal axes in link coordinates, centre of mass in link coordinates
        let link_from_principal = DMat3::from_quat(rng.quat());
        let com_link = rng.vec3(0.4);
        let inertia_link = link_from_principal * DMat3::from_diagonal(moments) * link_from_principal.transpose();
        let mut b = ModelBuilder::new("one link");
        let inertia = RigidInertia::from_com(mass, com_link, inertia_link);
        b.add_body("link", None, "root_joint", JointKind::Floating, Xform::IDENTITY, inertia).unwrap();
        let model = b.build().unwrap();
        let mut ws = Workspace::new(&model);

        // state of the link: origin x, world_from_link R, v_link (child frame), ω_link (child frame)
        let world_from_link = rng.quat();
        let origin_world = rng.vec3(2.0);
        let v_link = rng.vec3(2.0);
        let omega_link = rng.vec3(3.0);
        let q = [
            origin_world.x,
            origin_world.y,
            origin_world.z,
            world_from_link.w,
            world_from_link.x,
            world_from_link.y,
            world_from_link.z,
        ];
        let v = [v_link.x, v_link.y, v_link.z, omega_link.x, omega_link.y, omega_link.z];
        let mut qdd = [0.0; 6];
        aba(&model, &mut ws, &q, &v, &[0.0; 6], &mut qdd).unwrap();
        let vdot_link = DVec3::new(qdd[0], qdd[1], qdd[2]);
        let omegadot_link = DVec3::new(qdd[3], qdd[4], qdd[5]);

        // the same body as a free rigid body: frame at the centre of mass along the principal axes
        let props = MassProperties::from_principal(mass, moments).unwrap();
        let r = DMat3::from_quat(world_from_link);
        let world_from_body = world_from_link * tumble::math::DQuat::from_mat3(&link_from_principal);
        let omega_world = r * omega_link;
        let com_world = origin_world + r * com_link;
        // velocity of the centre of mass: v_o + ω × (R c)
        let v_com_world = r * v_link + omega_world.cross(r * com_link);
        let state = BodyState {
            position: com_world,
            orientation: world_from_body,
            velocity: v_com_world,
            omega_body: world_from_body.conjugate() * omega_world,
        };
        let gravity = DVec3::new(0.0, 0.0, -9.81);
        let rate = state_rate(&props, &Loads::default(), &state, gravity);

        // angular acceleration in the world frame: R α_link = R_body α_body
        let alpha_world_aba = r * omegadot_link;
        let alpha_world_free = world_from_body * rate.alpha_body;
        assert_vec_close(&format!("case {case}: angular acceleration"), alpha_world_aba, alpha_world_free);
        // acceleration of the link origin in the world: R (v̇_link + ω_link × v_link)
        let a_origin_world = r * (vdot_link + omega_link.cross(v_link));
        // of the centre of mass: a_o + α × (R c) + ω × (ω × R c)
        let rc = r * com_link;
        let a_com_world = a_origin_world + alpha_world_aba.cross(rc) + omega_world.cross(omega_world.cross(rc));
        assert_vec_close(&format!("case {case}: acceleration of the centre of mass"), a_com_world, rate.acceleration);
        assert_vec_close(&format!("case {case}: gravity"), rate.acceleration, gravity);
    }
}
