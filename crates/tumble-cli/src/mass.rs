//! `tumble mass MESH [--density RHO] [--scale S]`: the mass properties of the solid a mesh bounds,
//! as JSON on stdout (the contract):
//!
//! ```text
//! {"volume": m³, "mass": kg, "center_of_mass": [x, y, z] (m, mesh axes),
//!  "inertia": [[..], [..], [..]] (kg·m², about the centre of mass, mesh axes, rows),
//!  "principal_moments": [I1, I2, I3] (kg·m², ascending),
//!  "principal_axes": [[..], [..], [..]] (unit vectors in mesh axes; axis i belongs to moment i)}
//! ```
//!
//! Warnings (an inside-out mesh flipped, degenerate triangles skipped) go to stderr; a mesh that
//! cannot be read or does not bound a solid is bad input (exit 2) with the file and the problem.

use crate::cli::MassArgs;
use crate::error::{Failure, Status};
use crate::report::Stdout;
use std::io::Write;
use tumble::math::{DMat3, DVec3};
use tumble::mesh::{MeshLimits, MeshMassProperties};

/// The density used when `--density` is not given (kg/m³): that of water.
pub const DEFAULT_DENSITY: f64 = 1000.0;

/// Computes and prints the mass properties; exit 0, or 2 with the file and the problem.
pub fn mass(args: &MassArgs) -> Result<Status, Failure> {
    let density = args.density.unwrap_or(DEFAULT_DENSITY);
    if !(density.is_finite() && density > 0.0) {
        return Err(Failure::bad_input(format!("--density: must be finite and > 0 kg/m³ (got {density})")));
    }
    if !(args.scale.is_finite() && args.scale > 0.0) {
        return Err(Failure::bad_input(format!("--scale: must be finite and > 0 (got {})", args.scale)));
    }
    let mut limits = MeshLimits::default();
    if let Some(n) = args.max_triangles {
        limits.max_triangles = n;
    }
    let scale = [args.scale; 3];
    let (props, warnings) =
        tumble::mesh::mass_properties_of_file(&args.mesh, scale, density, &limits).map_err(Failure::bad_input)?;
    let file = args.mesh.display();
    for warning in &warnings {
        // a closed stderr must not stop the result from being printed
        let _ = writeln!(std::io::stderr().lock(), "warning: {file}: {warning}");
    }
    Stdout::default()
        .write(&to_json(&props))
        .map_err(|e| Failure::output(format!("cannot write to standard output: {e}")))?;
    Ok(Status::Success)
}

/// The contract's JSON, keys in the contract's order, numbers as the shortest text that reads back
/// to the same `f64`.
pub fn to_json(p: &MeshMassProperties) -> String {
    let num = |x: f64| serde_json::Value::from(x).to_string();
    let vec = |v: DVec3| format!("[{}, {}, {}]", num(v.x), num(v.y), num(v.z));
    let rows = |m: DMat3| {
        let r = m.transpose();
        format!("[{}, {}, {}]", vec(r.x_axis), vec(r.y_axis), vec(r.z_axis))
    };
    // principal axes are the columns of the rotation: written as a list of vectors, they are its rows transposed
    let axes = |m: DMat3| format!("[{}, {}, {}]", vec(m.x_axis), vec(m.y_axis), vec(m.z_axis));
    format!(
        "{{\n  \"volume\": {},\n  \"mass\": {},\n  \"center_of_mass\": {},\n  \"inertia\": {},\n  \
         \"principal_moments\": {},\n  \"principal_axes\": {}\n}}\n",
        num(p.volume),
        num(p.mass),
        vec(p.center_of_mass),
        rows(p.inertia),
        vec(p.principal_moments),
        axes(p.principal_axes)
    )
}
