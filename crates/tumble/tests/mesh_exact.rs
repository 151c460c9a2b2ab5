//! Mass properties of meshes against closed forms: a box and a tetrahedron exact to round-off, a
//! tessellated sphere within bounds that the tessellation itself gives, and invariance under
//! rigid motions (proptest).

mod mesh_common;

use mesh_common::*;
use proptest::prelude::*;
use std::f64::consts::PI;
use tumble::math::{DMat3, DQuat, DVec3};
use tumble::mesh::{MeshWarning, TriMesh};

const EPS: f64 = f64::EPSILON;

#[test]
fn a_box_is_exact_to_round_off() {
    let h = DVec3::new(0.5, 1.25, 2.0);
    let rho = 7.5;
    for offset in [DVec3::ZERO, DVec3::new(10.0, -3.0, 7.0)] {
        let (v, t) = box_parts(h);
        let p = mesh((v.into_iter().map(|x| x + offset).collect(), t)).mass_properties(rho).unwrap();
        let m = 8.0 * h.x * h.y * h.z * rho;
        let s = h * h;
        let expected = DVec3::new(s.y + s.z, s.x + s.z, s.x + s.y) * (m / 3.0);
        close("volume", p.volume, 8.0 * h.x * h.y * h.z, 4.0 * EPS, p.volume);
        close("mass", p.mass, m, 4.0 * EPS, m);
        for k in 0..3 {
            close("centre of mass", p.center_of_mass[k], offset[k], 4.0 * EPS, offset.length().max(1.0));
            close("diagonal", p.inertia.col(k)[k], expected[k], 8.0 * EPS, expected.max_element());
            for j in (0..3).filter(|&j| j != k) {
                close("product of inertia", p.inertia.col(k)[j], 0.0, 8.0 * EPS, expected.max_element());
            }
        }
        // ascending moments: Iz < Iy < Ix for hx < hy < hz, along the mesh axes
        close("I1", p.principal_moments.x, expected.z, 8.0 * EPS, expected.max_element());
        close("I3", p.principal_moments.z, expected.x, 8.0 * EPS, expected.max_element());
        assert!(p.principal_axes.x_axis.z.abs() > 1.0 - 1e-15, "{:?}", p.principal_axes);
        assert!(p.principal_axes.z_axis.x.abs() > 1.0 - 1e-15, "{:?}", p.principal_axes);
    }
}

/// The corner tetrahedron: `V = abc/6`, `c = (a, b, c)/4`, and about the centre of mass
/// `Ixx = 3m(b² + c²)/80`, `Ixy = m ab/80` (the integrals `∫x² dV = V a²/10`, `∫xy dV = V ab/20`
/// about the corner, moved by the parallel-axis theorem).
#[test]
fn a_tetrahedron_is_exact_to_round_off() {
    let (a, b, c) = (1.0, 2.0, 3.0);
    let rho = 2.0;
    let p = mesh(corner_tetrahedron(a, b, c)).mass_properties(rho).unwrap();
    let m = rho * a * b * c / 6.0;
    close("volume", p.volume, a * b * c / 6.0, 4.0 * EPS, 1.0);
    close("mass", p.mass, m, 4.0 * EPS, m);
    let com = DVec3::new(a, b, c) / 4.0;
    for k in 0..3 {
        close("centre of mass", p.center_of_mass[k], com[k], 4.0 * EPS, com.length());
    }
    let expected = DMat3::from_cols(
        DVec3::new(3.0 * m * (b * b + c * c) / 80.0, m * a * b / 80.0, m * a * c / 80.0),
        DVec3::new(m * a * b / 80.0, 3.0 * m * (a * a + c * c) / 80.0, m * b * c / 80.0),
        DVec3::new(m * a * c / 80.0, m * b * c / 80.0, 3.0 * m * (a * a + b * b) / 80.0),
    );
    let scale = max_abs(expected);
    for k in 0..3 {
        for j in 0..3 {
            close("inertia", p.inertia.col(k)[j], expected.col(k)[j], 16.0 * EPS, scale);
        }
    }
    // the principal decomposition reproduces the tensor: A diag(I) Aᵀ = I
    let rebuilt = p.principal_axes * DMat3::from_diagonal(p.principal_moments) * p.principal_axes.transpose();
    assert!(max_abs(rebuilt - p.inertia) <= 1e-14 * scale, "{rebuilt:?} vs {:?}", p.inertia);
    assert!((p.principal_axes.determinant() - 1.0).abs() < 1e-14);
}

/// A polyhedron inscribed in the sphere of radius `r` contains the ball of radius `r_in` (the
/// smallest distance from the centre to a face plane): its volume and its moments of inertia about
/// the centre lie between those of the two balls. The gap closes like `h²` as the faces shrink.
#[test]
fn a_tessellated_sphere_lies_between_its_inner_and_outer_balls() {
    let (r, rho) = (0.7, 3.0);
    let mut previous_gap = f64::INFINITY;
    for level in 2..=5 {
        let (v, t) = icosphere(level, r);
        let r_in = t
            .iter()
            .map(|f| {
                let [a, b, c] = f.map(|i| v[i as usize]);
                (b - a).cross(c - a).normalize().dot(a).abs()
            })
            .fold(f64::INFINITY, f64::min);
        let p = mesh((v, t)).mass_properties(rho).unwrap();
        let ball = |radius: f64| (4.0 / 3.0 * PI * radius.powi(3), 8.0 / 15.0 * PI * rho * radius.powi(5));
        let ((v_in, i_in), (v_out, i_out)) = (ball(r_in), ball(r));
        assert!(v_in <= p.volume && p.volume <= v_out, "level {level}: {v_in} ≤ {} ≤ {v_out}", p.volume);
        for k in 0..3 {
            let moment = p.principal_moments[k];
            assert!(i_in <= moment && moment <= i_out, "level {level}: {i_in} ≤ {moment} ≤ {i_out}");
        }
        assert!(p.center_of_mass.length() < 1e-15 * r, "{:?}", p.center_of_mass);
        // an icosphere is not isotropic exactly, but nearly: moments agree to the tessellation error
        let spread = p.principal_moments.z - p.principal_moments.x;
        assert!(spread <= (i_out - i_in), "level {level}: spread {spread:e}");
        let gap = (v_out - p.volume) / v_out;
        assert!(gap < previous_gap / 3.5, "level {level}: gap {gap:e} after {previous_gap:e}: not O(h²)");
        previous_gap = gap;
    }
    assert!(previous_gap < 1e-3);
}

#[test]
fn an_inside_out_mesh_is_flipped_with_a_warning_and_gives_the_same_result() {
    let (v, t) = torus(1.0, 0.3, 24, 12);
    let inward: Vec<[u32; 3]> = t.iter().map(|&[a, b, c]| [a, c, b]).collect();
    let right = mesh((v.clone(), t)).mass_properties(1.0).unwrap();
    let (flipped, warnings) = TriMesh::new(v, inward).unwrap();
    assert!(matches!(warnings[..], [MeshWarning::InsideOut { volume, shells: 1 }] if volume < 0.0), "{warnings:?}");
    assert_eq!(flipped.mass_properties(1.0).unwrap(), right);
}

/// The torus about z: volume `2π² R r²`, and the closed forms approached as the tessellation refines.
#[test]
fn a_torus_converges_to_its_closed_form() {
    let (big, small) = (1.0, 0.25);
    let p = mesh(torus(big, small, 256, 128)).mass_properties(1.0).unwrap();
    let volume = 2.0 * PI * PI * big * small * small;
    let iz = volume * (big * big + 0.75 * small * small);
    // the inscribed polygon of n sides has area (n/2π) sin(2π/n) of the circle's: O(1/n²) short
    let relative = 1.0 - 128.0 / (2.0 * PI) * (2.0 * PI / 128.0f64).sin();
    assert!((p.volume - volume).abs() / volume < 2.0 * relative + 2.0 * (1.0 - (PI / 256.0).cos()), "{}", p.volume);
    assert!((p.inertia.z_axis.z - iz).abs() / iz < 1e-3, "{} vs {iz}", p.inertia.z_axis.z);
}

fn transformed(mesh: &TriMesh, rotation: DQuat, translation: DVec3) -> TriMesh {
    mesh.map_vertices(|v| rotation * v + translation)
}

proptest! {
    /// Moving the mesh by `x ↦ R x + t` moves the centre of mass the same way, turns the inertia
    /// into `R I Rᵀ` and keeps the volume and principal moments, to 1e-10 relative even 10 km from
    /// the origin (where integrals taken about the origin would lose eight digits).
    #[test]
    fn mass_properties_move_with_the_mesh(
        q in prop::array::uniform4(-1.0f64..1.0),
        t in prop::array::uniform3(-1e4f64..1e4),
        which in 0usize..3,
    ) {
        prop_assume!(q.iter().map(|x| x * x).sum::<f64>() > 1e-3);
        let rotation = DQuat::from_xyzw(q[0], q[1], q[2], q[3]).normalize();
        let translation = DVec3::from_array(t);
        let base = match which {
            0 => mesh(corner_tetrahedron(1.0, 2.0, 3.0)),
            1 => mesh(torus(1.0, 0.3, 24, 12)),
            _ => mesh(box_parts(DVec3::new(0.1, 0.2, 0.3))),
        };
        let a = base.mass_properties(2.5).unwrap();
        let b = transformed(&base, rotation, translation).mass_properties(2.5).unwrap();
        let size = 3.0;
        let tol = 1e-10;
        prop_assert!((a.volume - b.volume).abs() <= tol * a.volume, "{} vs {}", a.volume, b.volume);
        let moved = rotation * a.center_of_mass + translation;
        prop_assert!((moved - b.center_of_mass).length() <= tol * size, "{moved:?} vs {:?}", b.center_of_mass);
        let r = DMat3::from_quat(rotation);
        let turned = r * a.inertia * r.transpose();
        let scale = max_abs(a.inertia);
        prop_assert!(max_abs(turned - b.inertia) <= tol * scale, "{turned:?} vs {:?}", b.inertia);
        prop_assert!((a.principal_moments - b.principal_moments).abs().max_element() <= tol * scale);
    }
}
