//! Mass properties of a mesh of 1 000 000 triangles (a torus of 1000 × 500 quads), in three stages:
//!
//! - `integrals`: the volume integrals alone, on a checked mesh (two passes over the triangles);
//! - `check_and_integrals`: from a triangle soup with every corner repeated, as STL writes it:
//!   welding, the edge checks, then the integrals;
//! - `binary_stl_file`: everything `tumble mass` does with a 50 MB binary STL: read the file, decode,
//!   weld, check, integrate.
//!
//! Criterion reports the time per mesh and the throughput in triangles per second.
//!
//! `cargo bench -p tumble --bench mesh -- --warm-up-time 1 --measurement-time 5`

#[path = "../tests/mesh_common/mod.rs"]
mod mesh_common;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;
use tumble::math::DVec3;
use tumble::mesh::{self, MeshLimits, TriMesh};

/// The torus as a binary STL: 84-byte header, then 50 bytes per triangle.
fn binary_stl(vertices: &[DVec3], triangles: &[[u32; 3]]) -> Vec<u8> {
    let mut bytes = vec![0u8; 80];
    bytes.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
    for t in triangles {
        bytes.extend_from_slice(&[0u8; 12]);
        for &i in t {
            for x in vertices[i as usize].to_array() {
                bytes.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        bytes.extend_from_slice(&[0u8; 2]);
    }
    bytes
}

fn bench(c: &mut Criterion) {
    let (vertices, triangles) = mesh_common::torus(1.0, 0.3, 1000, 500);
    assert_eq!(triangles.len(), 1_000_000);
    let (checked, _) = TriMesh::new(vertices.clone(), triangles.clone()).expect("a closed torus");
    // the soup: three corners of their own per triangle
    let soup_vertices: Vec<DVec3> = triangles.iter().flat_map(|t| t.map(|i| vertices[i as usize])).collect();
    let soup_triangles: Vec<[u32; 3]> = (0..triangles.len() as u32).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
    let dir = tempfile::tempdir().expect("a temporary directory");
    let stl = dir.path().join("torus.stl");
    std::fs::write(&stl, binary_stl(&vertices, &triangles)).expect("the STL is written");

    let mut group = c.benchmark_group("mesh_1M_triangles");
    group.sample_size(10);
    group.throughput(Throughput::Elements(triangles.len() as u64));
    group.bench_function("integrals", |b| b.iter(|| black_box(&checked).mass_properties(1000.0).unwrap()));
    group.bench_function("check_and_integrals", |b| {
        b.iter(|| {
            let (mesh, _) = TriMesh::new(soup_vertices.clone(), soup_triangles.clone()).unwrap();
            mesh.mass_properties(1000.0).unwrap()
        })
    });
    group.bench_function("binary_stl_file", |b| {
        b.iter(|| mesh::mass_properties_of_file(black_box(&stl), [1.0; 3], 1000.0, &MeshLimits::default()).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
