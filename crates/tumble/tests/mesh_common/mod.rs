//! Meshes built in code for the mesh tests, and the tolerance helper.
#![allow(dead_code)]

use std::f64::consts::PI;
use tumble::math::{DMat3, DVec3};
use tumble::mesh::{MeshWarning, TriMesh};

/// Vertices (m) and outward triangles.
pub type Parts = (Vec<DVec3>, Vec<[u32; 3]>);

/// The box `[-h, h]` (half extents `h`, m), 12 outward triangles.
pub fn box_parts(h: DVec3) -> Parts {
    let v = (0..8)
        .map(|i| {
            DVec3::new(
                if i & 1 == 0 { -h.x } else { h.x },
                if i & 2 == 0 { -h.y } else { h.y },
                if i & 4 == 0 { -h.z } else { h.z },
            )
        })
        .collect();
    // corners i = x + 2y + 4z; each face counter-clockwise seen from outside
    let t = vec![
        [0, 2, 3],
        [0, 3, 1], // z = -h
        [4, 5, 7],
        [4, 7, 6], // z = +h
        [0, 1, 5],
        [0, 5, 4], // y = -h
        [2, 6, 7],
        [2, 7, 3], // y = +h
        [0, 4, 6],
        [0, 6, 2], // x = -h
        [1, 3, 7],
        [1, 7, 5], // x = +h
    ];
    (v, t)
}

/// The tetrahedron with corners at the origin and `(a,0,0)`, `(0,b,0)`, `(0,0,c)` (m).
pub fn corner_tetrahedron(a: f64, b: f64, c: f64) -> Parts {
    let v = vec![DVec3::ZERO, DVec3::new(a, 0.0, 0.0), DVec3::new(0.0, b, 0.0), DVec3::new(0.0, 0.0, c)];
    (v, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
}

/// The icosahedron subdivided `level` times, vertices on the sphere of radius `r` (m).
pub fn icosphere(level: u32, r: f64) -> Parts {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<DVec3> = [
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ]
    .iter()
    .map(|p| DVec3::from_array(*p).normalize())
    .collect();
    let mut t: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut midpoints = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, v: &mut Vec<DVec3>| -> u32 {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push((v[a as usize] + v[b as usize]).normalize());
                (v.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(4 * t.len());
        for [a, b, c] in t {
            let (ab, bc, ca) = (mid(a, b, &mut v), mid(b, c, &mut v), mid(c, a, &mut v));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        t = next;
    }
    (v.into_iter().map(|p| p * r).collect(), t)
}

/// A torus of radii `big` and `small` (m) about z, `n × m` quads split in two triangles.
pub fn torus(big: f64, small: f64, n: u32, m: u32) -> Parts {
    let mut v = Vec::new();
    for i in 0..n {
        let u = 2.0 * PI * f64::from(i) / f64::from(n);
        for j in 0..m {
            let w = 2.0 * PI * f64::from(j) / f64::from(m);
            let rho = big + small * w.cos();
            v.push(DVec3::new(rho * u.cos(), rho * u.sin(), small * w.sin()));
        }
    }
    let id = |i: u32, j: u32| (i % n) * m + (j % m);
    let mut t = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    (v, t)
}

/// Checks the parts, expecting no warning.
pub fn mesh(parts: Parts) -> TriMesh {
    let (mesh, warnings) = TriMesh::new(parts.0, parts.1).expect("a valid mesh");
    assert_eq!(warnings, Vec::<MeshWarning>::new());
    mesh
}

/// `|a − b| ≤ tol · scale`, with a message naming `what`.
#[track_caller]
pub fn close(what: &str, a: f64, b: f64, tol: f64, scale: f64) {
    assert!((a - b).abs() <= tol * scale, "{what}: {a} vs {b}, |Δ| = {:e} > {tol:e} × {scale:e}", (a - b).abs());
}

/// The largest absolute entry of a matrix.
pub fn max_abs(m: DMat3) -> f64 {
    m.to_cols_array().iter().fold(0.0_f64, |x, y| x.max(y.abs()))
}
