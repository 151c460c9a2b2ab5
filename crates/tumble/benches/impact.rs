//! One collision's impulse (`contact::impact::collide`, Mirtich §4.2–4.4: the impact integrated
//! with the normal impulse as the independent variable), per collision, on the committed cases of
//! `tests/fixtures/impact/curved_slides.json` (written by `tools/impact_reference.py`):
//!
//! - `landings`: 80 quadruped feet landing as the trotting scenes meet them (μ = 0.9, e = 0.5);
//! - `random`: 54 random collisions whose slip curves (the hard cases).
//!
//! Criterion reports the time per collision (throughput in elements).
//!
//! `cargo bench -p tumble --bench impact -- --warm-up-time 1 --measurement-time 3`

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use serde::Deserialize;
use std::hint::black_box;
use tumble::contact::impact::{collide, tangent_basis, RestitutionLaw};
use tumble::math::{DMat3, DVec3};

#[derive(Deserialize)]
struct Case {
    kind: String,
    k: [f64; 9],
    u0: [f64; 3],
    mu: f64,
    e: f64,
}

/// The fixture's cases of `kind`, as `collide`'s world-frame inputs (normal +z).
fn cases(kind: &str) -> Vec<(DMat3, DVec3, f64, f64)> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/impact/curved_slides.json");
    let cases: Vec<Case> = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let (t1, t2) = tangent_basis(DVec3::Z);
    let frame = DMat3::from_cols(t1, t2, DVec3::Z);
    cases
        .iter()
        .filter(|c| c.kind == kind)
        .map(|c| {
            // rows in the fixture; glam takes columns
            let k = DMat3::from_cols_array(&c.k).transpose();
            (frame * k * frame.transpose(), frame * DVec3::from_array(c.u0), c.mu, c.e)
        })
        .collect()
}

fn impact(c: &mut Criterion) {
    let mut group = c.benchmark_group("impact");
    for kind in ["landing", "random"] {
        let cases = cases(kind);
        assert!(!cases.is_empty(), "no {kind} cases in the fixture");
        group.throughput(Throughput::Elements(cases.len() as u64));
        group.bench_function(kind, |b| {
            b.iter(|| {
                for &(k, u, mu, e) in &cases {
                    black_box(collide(black_box(k), DVec3::Z, black_box(u), mu, e, RestitutionLaw::Stronge));
                }
            })
        });
    }
    group.finish();
}

criterion_group!(benches, impact);
criterion_main!(benches);
