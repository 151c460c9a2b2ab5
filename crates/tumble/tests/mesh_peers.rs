//! tumble against trimesh on the meshes of `fixtures/meshes/` (written and measured by
//! `tools/mesh_fixtures.py`): volume, centre of mass, inertia, principal moments and axes agree to
//! 1e-10 relative. trimesh read the same files, so both see the same coordinates.

mod mesh_common;

use mesh_common::max_abs;
use std::path::PathBuf;
use tumble::math::{DMat3, DVec3};
use tumble::mesh::{self, Format, MeshLimits};

const TOLERANCE: f64 = 1e-10;

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/meshes")
}

fn vec3(v: &serde_json::Value) -> DVec3 {
    DVec3::new(v[0].as_f64().unwrap(), v[1].as_f64().unwrap(), v[2].as_f64().unwrap())
}

/// A 3×3 matrix from its rows.
fn rows(v: &serde_json::Value) -> DMat3 {
    DMat3::from_cols(vec3(&v[0]), vec3(&v[1]), vec3(&v[2])).transpose()
}

#[test]
fn mass_properties_agree_with_trimesh() {
    let text = std::fs::read_to_string(fixtures().join("trimesh_expected.json")).unwrap();
    let expected: serde_json::Value = serde_json::from_str(&text).unwrap();
    let meshes = expected["meshes"].as_object().unwrap();
    assert!(meshes.len() >= 5);
    let mut formats = Vec::new();
    let mut worst = 0.0_f64;
    for (name, e) in meshes {
        let loaded = mesh::load(&fixtures().join(name), [1.0; 3], &MeshLimits::default()).unwrap();
        assert!(loaded.warnings.is_empty(), "{name}: {:?}", loaded.warnings);
        formats.push(loaded.format);
        assert_eq!(loaded.mesh.triangles().len() as u64, e["triangles"].as_u64().unwrap(), "{name}");
        let p = loaded.mesh.mass_properties(1.0).unwrap();
        let mut check = |what: &str, ours: f64, theirs: f64, scale: f64| {
            let relative = (ours - theirs).abs() / scale;
            worst = worst.max(relative);
            assert!(relative <= TOLERANCE, "{name} {what}: {ours} vs trimesh {theirs} ({relative:e} relative)");
        };
        let volume = e["volume"].as_f64().unwrap();
        check("volume", p.volume, volume, volume);
        // the centre of mass relative to the mesh's size and distance from the origin
        let com = vec3(&e["center_of_mass"]);
        let size = p.volume.cbrt().max(com.length());
        for k in 0..3 {
            check("centre of mass", p.center_of_mass[k], com[k], size);
        }
        let inertia = rows(&e["inertia"]);
        let scale = max_abs(inertia);
        for k in 0..3 {
            for j in 0..3 {
                check("inertia", p.inertia.col(k)[j], inertia.col(k)[j], scale);
            }
        }
        let moments = vec3(&e["principal_moments"]);
        for k in 0..3 {
            check("principal moment", p.principal_moments[k], moments[k], scale);
        }
        // an axis is defined (up to sign) where its moment is apart from the others
        let axes = rows(&e["principal_axes"]).transpose();
        for k in 0..3 {
            let gap = (0..3).filter(|&j| j != k).map(|j| (moments[k] - moments[j]).abs()).fold(f64::INFINITY, f64::min);
            if gap > 1e-3 * scale {
                let ours = p.principal_axes.col(k);
                check("principal axis", ours.dot(axes.col(k)).abs(), 1.0, 1.0);
            }
        }
    }
    for format in [Format::Obj, Format::StlBinary, Format::StlAscii] {
        assert!(formats.contains(&format), "no {format} fixture");
    }
    println!("largest relative difference from trimesh over {} meshes: {worst:e}", meshes.len());
}
