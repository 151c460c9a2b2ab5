//! Round trips: a valid scene builds the world it describes (mass rules, frames, loads, defaults).

use super::error::{nearest, Source};
use super::*;
use crate::body::dynamics::applied;
use crate::body::Shape;
use crate::math::{DMat3, DQuat, DVec3};
use crate::world::WorldConfig;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_3, PI};

const TOL: f64 = 1e-12;

fn toml(text: &str) -> Scene {
    from_str(text, "t.toml", Format::Toml).unwrap_or_else(|e| panic!("{e}"))
}

#[track_caller]
fn close(a: DVec3, b: DVec3, tol: f64) {
    assert!((a - b).abs().max_element() <= tol * (1.0 + b.abs().max_element()), "{a:?} != {b:?}");
}

#[test]
fn mass_and_inertia_from_density_and_shape() {
    let s =
        toml("version = 1\n[[body]]\nname = \"ball\"\ndensity = 1000.0\nshape = { type = \"sphere\", radius = 0.5 }\n");
    let b = &s.world.bodies[0];
    let m = 4.0 / 3.0 * PI * 0.125 * 1000.0;
    assert!((b.mass.mass - m).abs() < TOL * m);
    close(b.mass.inertia_body, DVec3::splat(0.4 * m * 0.25), TOL);
    assert_eq!(b.shape, Some(Shape::Sphere { radius: 0.5 }));
}

#[test]
fn inertia_from_the_shape_scaled_to_the_mass() {
    let s = toml(
        "version = 1\n[[body]]\nname = \"brick\"\nmass = 12.0\nshape = { type = \"box\", half_extents = [1.0, 2.0, 3.0] }\n",
    );
    let b = &s.world.bodies[0];
    assert_eq!(b.mass.mass, 12.0);
    // I_x = m (hy² + hz²)/3, ...
    close(b.mass.inertia_body, DVec3::new(4.0 * 13.0, 4.0 * 10.0, 4.0 * 5.0), TOL);
    // given moments win over the shape's
    let s = toml(
        "version = 1\n[[body]]\nname = \"b\"\nmass = 12.0\ninertia = [1.0, 2.0, 2.5]\nshape = { type = \"box\", half_extents = [1.0, 2.0, 3.0] }\n",
    );
    close(s.world.bodies[0].mass.inertia_body, DVec3::new(1.0, 2.0, 2.5), TOL);
}

/// A tensor in axes turned by 30° about z, a body turned by 90° about x: the principal frame is
/// internal, and everything the file said in its own axes comes back unchanged.
#[test]
fn tensor_is_diagonalised_and_user_axes_are_kept() {
    let text = "version = 1\n[[body]]\nname = \"t\"\nmass = 1.0\n\
        inertia_tensor = [[2.25, -0.4330127018922193, 0.0], [-0.4330127018922193, 2.75, 0.0], [0.0, 0.0, 4.0]]\n\
        orientation = [0.7071067811865476, 0.7071067811865476, 0.0, 0.0]\n\
        angular_velocity_body = [1.0, 0.2, 0.5]\n";
    let b = &toml(text).world.bodies[0];
    let mut moments = b.mass.inertia_body.to_array();
    moments.sort_by(f64::total_cmp);
    close(DVec3::from_array(moments), DVec3::new(2.0, 3.0, 4.0), 1e-12);
    assert!(b.mass.user_from_body.angle_between(DQuat::IDENTITY) > 1e-3, "the principal axes differ from the user's");
    let world_from_user = DQuat::from_rotation_x(FRAC_PI_2);
    assert!(b.orientation_user().angle_between(world_from_user) < 1e-12);
    // the world inertia is R_user T_user R_userᵀ
    let r = DMat3::from_quat(world_from_user);
    let c = (PI / 6.0).cos();
    let s = (PI / 6.0).sin();
    let rz = DMat3::from_cols(DVec3::new(c, s, 0.0), DVec3::new(-s, c, 0.0), DVec3::Z);
    let tensor_user = rz * DMat3::from_diagonal(DVec3::new(2.0, 3.0, 4.0)) * rz.transpose();
    let expected = r * tensor_user * r.transpose();
    let got = b.inertia_world();
    for (g, e) in got.to_cols_array().iter().zip(expected.to_cols_array()) {
        assert!((g - e).abs() < 1e-12, "{got:?} != {expected:?}");
    }
    // ω in the user's axes comes back as given, and in the world frame as R ω_user
    let omega_user = DVec3::new(1.0, 0.2, 0.5);
    close(b.mass.user_from_body * b.state.omega_body, omega_user, 1e-14);
    close(b.state.omega_world(), world_from_user * omega_user, 1e-14);
}

/// Without `orientation`, the user's axes are the world's, also when the principal axes differ.
#[test]
fn tensor_without_orientation_keeps_the_user_axes_on_the_world_axes() {
    let text = "version = 1\n[[body]]\nname = \"t\"\nmass = 1.0\n\
        inertia_tensor = [[2.25, -0.4330127018922193, 0.0], [-0.4330127018922193, 2.75, 0.0], [0.0, 0.0, 4.0]]\n\
        angular_velocity_body = [1.0, 0.2, 0.5]\n";
    let b = &toml(text).world.bodies[0];
    assert!(b.mass.user_from_body.angle_between(DQuat::IDENTITY) > 1e-3);
    assert!(b.orientation_user().angle_between(DQuat::IDENTITY) < 1e-12, "{:?}", b.orientation_user());
    close(b.state.omega_world(), DVec3::new(1.0, 0.2, 0.5), 1e-14);
    let d = toml(text).describe();
    assert!(d.contains("orientation  [1, 0, 0, 0]"), "{d}");
}

#[test]
fn angular_velocity_world_versus_body() {
    let body = "version = 1\n[[body]]\nname = \"b\"\nmass = 1.0\ninertia = [1.0, 2.0, 2.5]\n\
        orientation = [0.7071067811865476, 0.0, 0.0, 0.7071067811865476]\n";
    // 90° about z: body x is world y
    let world = toml(&format!("{body}angular_velocity = [1.0, 0.0, 0.0]\n"));
    close(world.world.bodies[0].state.omega_world(), DVec3::X, 1e-15);
    close(world.world.bodies[0].state.omega_body, -DVec3::Y, 1e-15);
    let in_body = toml(&format!("{body}angular_velocity_body = [1.0, 0.0, 0.0]\n"));
    close(in_body.world.bodies[0].state.omega_body, DVec3::X, 1e-15);
    close(in_body.world.bodies[0].state.omega_world(), DVec3::Y, 1e-15);
}

/// `force_body`, `torque_body` and point-force points are in the user's axes; the engine works in
/// principal axes. The resultant in the world frame must be what the file says.
#[test]
fn body_frame_loads_are_converted_to_principal_axes() {
    let text = "version = 1\n[world]\ngravity = [0.0, 0.0, 0.0]\n[[body]]\nname = \"t\"\nmass = 2.0\n\
        inertia_tensor = [[2.25, -0.4330127018922193, 0.0], [-0.4330127018922193, 2.75, 0.0], [0.0, 0.0, 4.0]]\n\
        orientation = [0.5, 0.5, 0.5, 0.5]\n\
        force = [0.0, 0.0, 1.0]\nforce_body = [1.0, 0.0, 0.0]\ntorque = [0.0, 0.5, 0.0]\ntorque_body = [0.0, 0.0, 2.0]\n\
        linear_damping = 0.1\nangular_damping = 0.2\n\
        [[body.point_force]]\npoint = [0.0, 1.0, 0.0]\nforce_body = [3.0, 0.0, 0.0]\n\
        [[body.point_force]]\npoint = [1.0, 0.0, 0.0]\nforce = [0.0, 0.0, 5.0]\n";
    let b = &toml(text).world.bodies[0];
    let r = b.orientation_user();
    let (force_world, torque_body) = applied(&b.mass, &b.loads, &b.state, DVec3::ZERO);
    let torque_world = b.state.orientation * torque_body;
    let p1 = DVec3::Y;
    let f1_user = DVec3::new(3.0, 0.0, 0.0);
    let p2 = DVec3::X;
    let f2_world = DVec3::new(0.0, 0.0, 5.0);
    let expected_force = DVec3::Z + r * DVec3::X + r * f1_user + f2_world;
    let expected_torque =
        DVec3::new(0.0, 0.5, 0.0) + r * (2.0 * DVec3::Z) + r * p1.cross(f1_user) + (r * p2).cross(f2_world);
    close(force_world, expected_force, 1e-14);
    close(torque_world, expected_torque, 1e-14);
    assert_eq!((b.loads.linear_damping, b.loads.angular_damping), (0.1, 0.2));
}

#[test]
fn world_defaults_and_overrides() {
    let s = toml("version = 1\n[[body]]\nname = \"g\"\nfixed = true\n");
    assert_eq!(s.world.config, WorldConfig::default());
    let s = toml("version = 1\n[world]\ndt = 0.01\nintegrator = \"dopri5\"\nrtol = 1e-6\nsample_every = 3\n");
    let c = s.world.config;
    assert_eq!((c.dt, c.integrator, c.tolerances.rtol, c.sample_every), (0.01, Integrator::Dopri5, 1e-6, 3));
    assert_eq!(c.tolerances.atol, WorldConfig::default().tolerances.atol);
    assert_eq!(c.gravity, WorldConfig::default().gravity);
}

use crate::integrate::Integrator;

#[test]
fn fixed_bodies_need_no_mass() {
    let s =
        toml("version = 1\n[[body]]\nname = \"ground\"\nfixed = true\nshape = { type = \"plane\" }\nfriction = 0.5\n");
    let b = &s.world.bodies[0];
    assert!(b.fixed);
    assert_eq!((b.mass.mass, b.mass.inertia_body), (1.0, DVec3::ONE));
    assert_eq!(b.material.friction, Some(0.5));
    assert_eq!(b.material.restitution, None);
    let s = toml("version = 1\n[[body]]\nname = \"wall\"\nfixed = true\nmass = 50.0\ninertia = [1.0, 1.0, 1.0]\n");
    assert_eq!(s.world.bodies[0].mass.mass, 50.0);
}

#[test]
fn orientation_is_read_w_first() {
    // [w, x, y, z] = [cos 30°, sin 30°, 0, 0]: 60° about x
    let s =
        toml("version = 1\n[[body]]\nname = \"g\"\nfixed = true\norientation = [0.8660254037844387, 0.5, 0.0, 0.0]\n");
    assert!(s.world.bodies[0].state.orientation.angle_between(DQuat::from_rotation_x(FRAC_PI_3)) < 1e-12);
}

#[test]
fn describe_tells_what_was_understood() {
    let text = "version = 1\n[world]\nintegrator = \"dopri5\"\n[[body]]\nname = \"t\"\nmass = 1.0\n\
        inertia_tensor = [[2.25, -0.4330127018922193, 0.0], [-0.4330127018922193, 2.75, 0.0], [0.0, 0.0, 4.0]]\n\
        torque_body = [0.0, 0.0, 1.0]\n[[body]]\nname = \"ground\"\nfixed = true\nshape = { type = \"plane\" }\n";
    let d = toml(text).describe();
    for part in [
        "t.toml",
        "dopri5",
        "rtol",
        "body `t`",
        "principal axes",
        "torque [0, 0, 1] N·m (body axes)",
        "(fixed)",
        "plane",
        "2 bodies (1 moving, 1 fixed)",
    ] {
        assert!(d.contains(part), "{part:?} not in\n{d}");
    }
}

#[test]
fn positions_count_characters() {
    let src = Source { origin: "x", text: "a\néé x", format: Format::Toml };
    let offset = "a\néé ".len();
    assert_eq!(src.line_col(offset), LineCol { line: 2, column: 4 });
    // an offset inside a character is moved back to its start
    assert_eq!(src.line_col(3), LineCol { line: 2, column: 1 });
}

#[test]
fn suggestions_catch_typos_only() {
    let keys = ["name", "mass", "density", "gravity", "body"];
    assert_eq!(nearest("mas", &keys), Some("mass"));
    assert_eq!(nearest("gravtiy", &keys), Some("gravity"));
    assert_eq!(nearest("bodies", &keys), Some("body"));
    assert_eq!(nearest("zzzzzz", &keys), None);
}
