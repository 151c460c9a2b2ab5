//! The rotational right-hand side in its two forms (seed §3), per evaluation:
//!
//! - `alpha_body`: Euler's equations in the body frame (3.5), `α_body = I_body⁻¹ (τ_body − ω_body × I_body ω_body)`,
//!   with the constant diagonal `I_body` (its inverse is three reciprocals);
//! - `alpha_world`: (3.3) in the world frame, which must first form `R` from the quaternion, then
//!   `I_world = R I_body Rᵀ` (1.2), its inverse, and `ω_world × I_world ω_world`.
//!
//! Both run over the same 1024 random states; criterion reports the time per state (throughput in
//! elements). The ratio of the two is what the body-frame form saves.
//!
//! `cargo bench -p tumble --bench rhs -- --warm-up-time 1 --measurement-time 3`

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;
use tumble::body::dynamics::{alpha_body, alpha_world};
use tumble::math::{DMat3, DQuat, DVec3};

/// One body's inputs to the right-hand side, in both frames.
struct Sample {
    inertia_body: DVec3,
    orientation: DQuat,
    omega_body: DVec3,
    torque_body: DVec3,
    omega_world: DVec3,
    torque_world: DVec3,
}

/// A small deterministic generator (xorshift64*), so that every run measures the same inputs.
fn samples(n: usize) -> Vec<Sample> {
    let mut seed = 0x9E37_79B9_7F4A_7C15_u64;
    let mut next = move || {
        seed ^= seed >> 12;
        seed ^= seed << 25;
        seed ^= seed >> 27;
        (seed.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    (0..n)
        .map(|_| {
            let orientation = DQuat::from_xyzw(next(), next(), next(), next() + 2.0).normalize();
            let inertia_body = DVec3::new(1.0 + 0.5 * next(), 2.0 + 0.5 * next(), 2.5 + 0.5 * next());
            let omega_body = 5.0 * DVec3::new(next(), next(), next());
            let torque_body = DVec3::new(next(), next(), next());
            Sample {
                inertia_body,
                orientation,
                omega_body,
                torque_body,
                omega_world: orientation * omega_body,
                torque_world: orientation * torque_body,
            }
        })
        .collect()
}

fn rhs(c: &mut Criterion) {
    let samples = samples(1024);
    let mut group = c.benchmark_group("rhs");
    group.throughput(Throughput::Elements(samples.len() as u64));
    group.bench_function("alpha_body", |b| {
        b.iter(|| {
            for s in black_box(&samples) {
                black_box(alpha_body(s.inertia_body, s.omega_body, s.torque_body));
            }
        })
    });
    group.bench_function("alpha_world", |b| {
        b.iter(|| {
            for s in black_box(&samples) {
                let world_from_body = DMat3::from_quat(s.orientation);
                black_box(alpha_world(world_from_body, s.inertia_body, s.omega_world, s.torque_world));
            }
        })
    });
    group.finish();
}

criterion_group!(benches, rhs);
criterion_main!(benches);
