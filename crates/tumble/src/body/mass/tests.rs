//! Mass properties: the solid-shape formulas against hand values and an independent quadrature,
//! the diagonalisation of full tensors, and every validation error.

// the one tolerance helper of the unit tests (test modules are private to their parents, so it is
// included by path rather than imported)
#[allow(clippy::duplicate_mod)]
#[path = "../../math/tests/support.rs"]
mod support;

use super::*;
use crate::math::{inertia_world, DVec4};
use proptest::prelude::*;
use support::{assert_close, assert_rel, principal_moments, unit_quat, EPS};

/// A slice `[z0, z1]` (m) of a solid of revolution and its squared radius `a(z)²` (m²) there.
type Piece<'a> = (f64, f64, &'a dyn Fn(f64) -> f64);

/// Mass (kg) and principal moments (kg·m²) of a solid of revolution about body z, centred at the origin,
/// by slicing it into discs: a disc of radius `a`, thickness `dz` at height `z` has mass `ρ π a² dz`,
/// axial moment `ρ π a⁴/2 dz` and, about a transverse axis through the origin,
/// `ρ (π a⁴/4 + π a² z²) dz` (its own diameter moment plus the parallel-axis term).
///
/// Each piece `[z0, z1]` on which `a(z)²` is a polynomial of degree ≤ 2 is integrated with 4-point
/// Gauss–Legendre, exact for the integrands (polynomials of degree ≤ 4 in `z`), so the result is exact
/// up to round-off — a check of the closed forms that shares no algebra with them.
fn solid_of_revolution(rho: f64, pieces: &[Piece]) -> (f64, DVec3) {
    let nodes = [
        (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
        (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    ];
    let (mut m, mut i_axial, mut i_perp) = (0.0, 0.0, 0.0);
    for (z0, z1, radius_sq) in pieces {
        let (mid, half) = (0.5 * (z0 + z1), 0.5 * (z1 - z0));
        for (x, w) in nodes {
            let z = mid + half * x;
            let a2 = radius_sq(z);
            let dz = half * w * rho * PI;
            m += dz * a2;
            i_axial += dz * a2 * a2 / 2.0;
            i_perp += dz * (a2 * a2 / 4.0 + a2 * z * z);
        }
    }
    (m, DVec3::new(i_perp, i_perp, i_axial))
}

#[test]
fn sphere_matches_hand_values() {
    // r = 0.1 m, ρ = 1000 kg/m³: m = 4/3 π 10⁻³ · 10³ = 4.18879020478639 kg, I = 2/5 m r² = 0.0167551608191456
    let (m, i) = solid_sphere(1000.0, 0.1);
    assert_close("sphere mass", m, 4.188_790_204_786_391, 4.0 * EPS, m);
    assert_close("sphere moments", i, DVec3::splat(0.016_755_160_819_145_56), 8.0 * EPS, i.x);
}

#[test]
fn box_matches_hand_values() {
    // half extents (1, 2, 3), ρ = 1: m = 8·6 = 48, Ix = 48 (4 + 9)/3 = 208, Iy = 48 (1 + 9)/3 = 160, Iz = 48 (1 + 4)/3 = 80
    let (m, i) = solid_box(1.0, DVec3::new(1.0, 2.0, 3.0));
    assert_eq!(m, 48.0);
    assert_close("box moments", i, DVec3::new(208.0, 160.0, 80.0), 4.0 * EPS, 208.0);
}

#[test]
fn cylinder_matches_hand_values_and_quadrature() {
    // r = 1, half height 1, ρ = 1: m = 2π, Iz = m r²/2 = π, Ix = m (3 + 4)/12 = 7π/6
    let (m, i) = solid_cylinder(1.0, 1.0, 1.0);
    assert_close("cylinder mass", m, 2.0 * PI, 4.0 * EPS, m);
    assert_close("cylinder moments", i, DVec3::new(7.0 * PI / 6.0, 7.0 * PI / 6.0, PI), 8.0 * EPS, i.x);
    let (r, hh, rho) = (0.3, 0.7, 2700.0);
    let (m, i) = solid_cylinder(rho, r, hh);
    let (mq, iq) = solid_of_revolution(rho, &[(-hh, hh, &|_| r * r)]);
    assert_close("cylinder mass vs quadrature", m, mq, 16.0 * EPS, m);
    assert_close("cylinder moments vs quadrature", i, iq, 64.0 * EPS, i.max_element());
}

#[test]
fn sphere_matches_quadrature() {
    let (r, rho) = (0.25, 7800.0);
    let (m, i) = solid_sphere(rho, r);
    let (mq, iq) = solid_of_revolution(rho, &[(-r, r, &|z| r * r - z * z)]);
    assert_close("sphere mass vs quadrature", m, mq, 16.0 * EPS, m);
    assert_close("sphere moments vs quadrature", i, iq, 64.0 * EPS, i.x);
}

/// The capsule formula (hemisphere centroids `3r/8` beyond the cylinder, parallel-axis theorem)
/// against slicing the solid: a cylinder piece and two spherical caps.
#[test]
fn capsule_matches_quadrature() {
    for (r, hh) in [(0.2, 0.5), (1.0, 0.1), (0.05, 2.0), (0.3, 0.3)] {
        let rho = 1100.0;
        let (m, i) = solid_capsule(rho, r, hh);
        let cap = |z: f64| r * r - (z.abs() - hh).powi(2);
        let (mq, iq) = solid_of_revolution(rho, &[(-hh - r, -hh, &cap), (-hh, hh, &|_| r * r), (hh, hh + r, &cap)]);
        assert_close("capsule mass vs quadrature", m, mq, 16.0 * EPS, m);
        assert_close("capsule moments vs quadrature", i, iq, 64.0 * EPS, i.max_element());
    }
}

/// A capsule of half height 0 is a sphere; a capsule is its cylinder plus a sphere's mass.
#[test]
fn capsule_of_zero_half_height_is_a_sphere() {
    for r in [1e-3, 0.1, 1.0, 40.0] {
        let (mc, ic) = solid_capsule(500.0, r, 0.0);
        let (ms, is) = solid_sphere(500.0, r);
        assert_rel("capsule(r, 0) mass vs sphere", mc, ms, 2.0 * EPS);
        assert_rel("capsule(r, 0) moments vs sphere", ic, is, 4.0 * EPS);
        let (m_cap, _) = solid_capsule(500.0, r, 2.0 * r);
        let (m_cyl, _) = solid_cylinder(500.0, r, 2.0 * r);
        assert_rel("capsule mass = cylinder + sphere", m_cap, m_cyl + ms, 4.0 * EPS);
    }
}

/// A long thin cylinder approaches a rod: `Ix → m L²/12` (the relative excess is `3 r²/L²`), `Iz → 0`.
#[test]
fn thin_cylinder_approaches_rod() {
    let length = 2.0;
    for r in [1e-2, 1e-3, 1e-4] {
        let (m, i) = solid_cylinder(1.0, r, 0.5 * length);
        let rod = m * length * length / 12.0;
        let excess = 3.0 * (r / length).powi(2);
        assert!((i.x / rod - 1.0).abs() <= 1.01 * excess, "Ix/(m L²/12) − 1 = {:e} for r = {r}", i.x / rod - 1.0);
        assert!(i.z / i.x <= 6.0 * (r / length).powi(2), "Iz/Ix = {:e} for r = {r}", i.z / i.x);
        // a rod sits on the triangle bound Ix + Iz ≥ Iy with a margin of Iz only; it is accepted
        assert!(MassProperties::from_principal(m, i).is_ok());
    }
}

/// A thin flat plate has `Iz = Ix + Iy`: on the bound of the triangle inequality, and accepted.
#[test]
fn thin_plate_on_the_bound_is_accepted() {
    let (m, i) = solid_box(1.0, DVec3::new(1.0, 0.5, 1e-9));
    assert_rel("plate Iz vs Ix + Iy", i.z, i.x + i.y, 1e-17 / 0.25 + 4.0 * EPS);
    assert!(MassProperties::from_principal(m, i).is_ok());
    // exactly on the bound, in every order
    for moments in [[1.0, 1.0, 2.0], [2.0, 1.0, 1.0], [0.5, 1.5, 1.0]] {
        assert!(MassProperties::from_principal(1.0, DVec3::from_array(moments)).is_ok(), "{moments:?}");
    }
    // within the relative tolerance 1e-9 of the bound: accepted; beyond it: rejected
    assert!(MassProperties::from_principal(1.0, DVec3::new(1.0, 1.0, 2.0 + 1e-10)).is_ok());
    assert!(MassProperties::from_principal(1.0, DVec3::new(1.0, 1.0, 2.0 + 1e-8)).is_err());
}

#[test]
fn triangle_inequality_violation_is_rejected() {
    let err = MassProperties::from_principal(1.0, DVec3::new(1.0, 1.0, 5.0)).unwrap_err();
    match err {
        MassError::TriangleInequality { moments, short_by_percent } => {
            assert_eq!(moments, [1.0, 1.0, 5.0]);
            // 1 + 1 falls short of 5 by 3, i.e. 60 % of the largest moment
            assert_close("short by", short_by_percent, 60.0, 4.0 * EPS, 60.0);
        }
        other => panic!("expected TriangleInequality, got {other:?}"),
    }
    // the largest moment may come in any position
    for moments in [[5.0, 1.0, 1.0], [1.0, 5.0, 1.0]] {
        let err = MassProperties::from_principal(1.0, DVec3::from_array(moments)).unwrap_err();
        assert!(matches!(err, MassError::TriangleInequality { .. }), "{moments:?}: {err:?}");
    }
}

#[test]
fn bad_masses_are_rejected() {
    let moments = DVec3::ONE;
    for mass in [0.0, -0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let err = MassProperties::from_principal(mass, moments).unwrap_err();
        assert!(matches!(err, MassError::NonPositiveMass { .. }), "mass {mass}: {err:?}");
        let err = MassProperties::from_tensor(mass, DMat3::IDENTITY).unwrap_err();
        assert!(matches!(err, MassError::NonPositiveMass { .. }), "mass {mass}: {err:?}");
    }
    assert!(MassProperties::from_principal(f64::MIN_POSITIVE, moments).is_ok());
}

#[test]
fn bad_moments_are_rejected() {
    for moments in [[0.0, 1.0, 1.0], [1.0, -1.0, 1.0], [1.0, 1.0, -0.0], [-1.0, -1.0, -1.0]] {
        let err = MassProperties::from_principal(1.0, DVec3::from_array(moments)).unwrap_err();
        assert!(matches!(err, MassError::NotPositiveDefinite { .. }), "{moments:?}: {err:?}");
    }
    for moments in [[f64::NAN, 1.0, 1.0], [1.0, f64::INFINITY, 1.0]] {
        let err = MassProperties::from_principal(1.0, DVec3::from_array(moments)).unwrap_err();
        assert!(matches!(err, MassError::NonFiniteInertia { .. }), "{moments:?}: {err:?}");
    }
    let mut tensor = DMat3::IDENTITY;
    tensor.y_axis.x = f64::NAN;
    let err = MassProperties::from_tensor(1.0, tensor).unwrap_err();
    assert!(matches!(err, MassError::NonFiniteInertia { .. }), "{err:?}");
}

#[test]
fn asymmetric_tensor_is_rejected() {
    let tensor = DMat3::from_cols(DVec3::new(2.0, 0.1, 0.0), DVec3::new(0.0, 2.0, 0.0), DVec3::new(0.0, 0.0, 2.0));
    match MassProperties::from_tensor(1.0, tensor).unwrap_err() {
        MassError::NotSymmetric { asymmetry } => assert_eq!(asymmetry, 0.1),
        other => panic!("expected NotSymmetric, got {other:?}"),
    }
    // an asymmetry within 1e-9 of the largest entry is round-off, and is accepted
    let nearly =
        DMat3::from_cols(DVec3::new(2.0, 0.1 + 1e-10, 0.0), DVec3::new(0.1, 2.0, 0.0), DVec3::new(0.0, 0.0, 2.0));
    assert!(MassProperties::from_tensor(1.0, nearly).is_ok());
}

/// Positive on the diagonal but indefinite: the eigenvalues of `[[1, 2, 0], [2, 1, 0], [0, 0, 1]]` are
/// `−1, 1, 3`; a check of the diagonal alone would accept it.
#[test]
fn tensor_positive_on_diagonal_but_indefinite_is_rejected() {
    let tensor = DMat3::from_cols(DVec3::new(1.0, 2.0, 0.0), DVec3::new(2.0, 1.0, 0.0), DVec3::new(0.0, 0.0, 1.0));
    match MassProperties::from_tensor(1.0, tensor).unwrap_err() {
        MassError::NotPositiveDefinite { moments } => {
            let mut sorted = moments;
            sorted.sort_by(f64::total_cmp);
            assert_close("reported eigenvalues", DVec3::from_array(sorted), DVec3::new(-1.0, 1.0, 3.0), 8.0 * EPS, 3.0);
        }
        other => panic!("expected NotPositiveDefinite, got {other:?}"),
    }
    // positive definite, but the eigenvalues (1 − √2·0.9, 1, 1 + √2·0.9)·… break the triangle inequality
    let s = 0.9;
    let tensor = DMat3::from_cols(DVec3::new(1.0, s, s), DVec3::new(s, 1.0, s), DVec3::new(s, s, 1.0));
    // eigenvalues 1 + 2s = 2.8, 1 − s = 0.1 (twice): 0.1 + 0.1 < 2.8
    let err = MassProperties::from_tensor(1.0, tensor).unwrap_err();
    assert!(matches!(err, MassError::TriangleInequality { .. }), "{err:?}");
}

/// A diagonal tensor takes the principal path: the moments are kept in the user's order and the
/// frame is the identity.
#[test]
fn diagonal_tensor_keeps_user_axes() {
    let mp = MassProperties::from_tensor(2.0, DMat3::from_diagonal(DVec3::new(3.0, 1.0, 2.5))).unwrap();
    assert_eq!(mp.inertia_body, DVec3::new(3.0, 1.0, 2.5));
    assert_eq!(mp.user_from_body, DQuat::IDENTITY);
    assert_eq!(mp.inv_inertia_body, DVec3::new(1.0 / 3.0, 1.0, 0.4));
}

proptest! {
    /// A diagonal tensor turned by a random rotation, `Q diag(d) Qᵀ`, is diagonalised back: the moments
    /// are `d` (in some order), and the frame `P = user_from_body` is a proper rotation with
    /// `P diag(I_body) Pᵀ = tensor`, at every overall scale of the moments.
    #[test]
    fn from_tensor_recovers_rotated_diagonal(q in unit_quat(), moments in principal_moments(), mass in 0.01..100.0_f64) {
        let tensor = inertia_world(DMat3::from_quat(q), moments);
        let mp = MassProperties::from_tensor(mass, tensor).unwrap();
        let big = moments.max_element();
        let (mut expected, mut actual) = (moments.to_array(), mp.inertia_body.to_array());
        expected.sort_by(f64::total_cmp);
        actual.sort_by(f64::total_cmp);
        assert_close("principal moments", DVec3::from_array(actual), DVec3::from_array(expected), 1e-12, big);
        let p = DMat3::from_quat(mp.user_from_body);
        assert_close("det P", p.determinant(), 1.0, 16.0 * EPS, 1.0);
        // the matrix of a normalised quaternion: det and orthonormality to < 16ε
        // (see math::tests::rotation_inverse_is_transpose)
        assert_close("Pᵀ P", p.transpose() * p, DMat3::IDENTITY, 16.0 * EPS, 1.0);
        assert_close("P diag(I_body) Pᵀ vs tensor", inertia_world(p, mp.inertia_body), tensor, 1e-12, big);
        assert_close("inertia_user vs tensor", mp.inertia_user(), tensor, 1e-12, big);
        prop_assert_eq!(mp.mass, mass);
        prop_assert!((DVec4::from(mp.user_from_body).length() - 1.0).abs() <= 4.0 * EPS);
    }

    /// Whether moments pass the triangle check does not depend on the axes they are given in: principal
    /// moments and the same moments as a randomly rotated full tensor are accepted or rejected alike.
    /// (The moments stay at least 1e-6 of the largest away from the bound, far beyond round-off.)
    #[test]
    fn triangle_check_is_rotation_invariant(
        q in unit_quat(),
        a in 0.1..10.0_f64,
        b in 0.1..10.0_f64,
        excess in prop_oneof![-0.9..-1e-6_f64, 1e-6..0.9_f64],
    ) {
        // c = a + b + excess · (a + b): valid when excess < 0 (and c > |a − b|), invalid when excess > 0
        let c = (a + b) * (1.0 + excess);
        prop_assume!(c > (a - b).abs() * (1.0 + 1e-6));
        let moments = DVec3::new(a, b, c);
        let principal = MassProperties::from_principal(1.0, moments);
        let rotated = MassProperties::from_tensor(1.0, inertia_world(DMat3::from_quat(q), moments));
        prop_assert_eq!(principal.is_ok(), excess < 0.0);
        prop_assert_eq!(rotated.is_ok(), excess < 0.0, "rotated: {:?}", rotated);
        if let Err(e) = rotated {
            prop_assert!(matches!(e, MassError::TriangleInequality { .. }), "{:?}", e);
        }
    }
}

/// `Shape::mass_properties` dispatches to the formulas above (and a plane has none).
#[test]
fn shapes_use_the_solid_formulas() {
    use crate::body::Shape;
    let rho = 1200.0;
    assert_eq!(Shape::Sphere { radius: 0.3 }.mass_properties(rho), Some(solid_sphere(rho, 0.3)));
    let h = DVec3::new(0.1, 0.2, 0.3);
    assert_eq!(Shape::Box { half_extents: h }.mass_properties(rho), Some(solid_box(rho, h)));
    assert_eq!(
        Shape::Capsule { radius: 0.1, half_height: 0.4 }.mass_properties(rho),
        Some(solid_capsule(rho, 0.1, 0.4))
    );
    assert_eq!(
        Shape::Cylinder { radius: 0.1, half_height: 0.4 }.mass_properties(rho),
        Some(solid_cylinder(rho, 0.1, 0.4))
    );
    assert_eq!(Shape::Plane.mass_properties(rho), None);
    // every solid's moments pass the validation
    for shape in [
        Shape::Sphere { radius: 0.3 },
        Shape::Box { half_extents: h },
        Shape::Capsule { radius: 0.1, half_height: 0.4 },
    ] {
        let (m, i) = shape.mass_properties(rho).unwrap();
        assert!(MassProperties::from_principal(m, i).is_ok(), "{shape:?}");
    }
}

/// The helper used by the docs: `assert_rel` is relative to the larger value.
#[test]
fn inverse_moments_are_reciprocals() {
    let mp = MassProperties::from_principal(1.0, DVec3::new(0.1, 0.2, 0.25)).unwrap();
    assert_rel("I⁻¹ I", mp.inv_inertia_body * mp.inertia_body, DVec3::ONE, EPS);
}

/// Regression: a small body (a 20 g box of 5 × 3 × 1 cm, moments ≈ 1e-6 kg·m²) given as a full tensor
/// in turned axes must get its principal frame back. The eigen-solver treats cross products of columns
/// below an absolute 1e-20 as zero and returned an arbitrary axis for tensors this small.
#[test]
fn from_tensor_small_body_recovers_its_frame() {
    let (mass, moments) = (0.02, DVec3::new(1.6667e-6, 4.3333e-6, 5.6667e-6));
    let world_from_principal = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 2.0) / 3.0, 0.7);
    let tensor = inertia_world(DMat3::from_quat(world_from_principal), moments);
    let mp = MassProperties::from_tensor(mass, tensor).unwrap();
    let big = moments.max_element();
    assert_close("P diag(I_body) Pᵀ vs tensor", mp.inertia_user(), tensor, 1e-12, big);
    assert_close("principal moments", mp.inertia_body, moments, 1e-12, big);
}

/// Regression: an axisymmetric body (a cylinder, `Ix = Iy`) given as a turned tensor must keep its two
/// equal moments equal to round-off. The eigen-solver's closed-form cubic loses half the digits at a
/// double root (errors of `√ε` times the spread), which made a symmetric top slightly asymmetric.
#[test]
fn from_tensor_axisymmetric_keeps_equal_moments() {
    let (mass, moments) = solid_cylinder(2700.0, 0.05, 0.2);
    let big = moments.max_element();
    // the axial moment is the smallest here
    let expected = DVec3::new(moments.z, moments.x, moments.y);
    // a deterministic spread of axes and angles
    for k in 0..64 {
        let t = k as f64;
        let axis = DVec3::new((1.3 * t).sin(), (2.1 * t + 0.5).cos(), 0.7 + (0.9 * t).sin()).normalize();
        let world_from_principal = DQuat::from_axis_angle(axis, 0.1 + 0.37 * t);
        let tensor = inertia_world(DMat3::from_quat(world_from_principal), moments);
        let mp = MassProperties::from_tensor(mass, tensor).unwrap();
        let mut sorted = mp.inertia_body.to_array();
        sorted.sort_by(f64::total_cmp);
        assert_close("principal moments", DVec3::from_array(sorted), expected, 1e-12, big);
        assert_close("P diag(I_body) Pᵀ vs tensor", mp.inertia_user(), tensor, 1e-12, big);
    }
}
