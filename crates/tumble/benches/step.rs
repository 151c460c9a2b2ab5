//! The cost of a step.
//!
//! - `advance_body/<integrator>`: one step (`dt = 1 ms`) of one torque-free tumbling body
//!   (`I_body = diag(1, 2, 3)` kg·m², spun near its intermediate axis), for every integrator;
//! - `world_step_10000/<integrator>`: one `World::step` of 10,000 such bodies under gravity, for
//!   `semi_implicit_euler` and `rk4`; the throughput criterion prints is body-steps per second.
//!
//! `cargo bench -p tumble --bench step -- --warm-up-time 1 --measurement-time 3`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::hint::black_box;
use tumble::body::{Loads, MassProperties, RigidBody};
use tumble::integrate::{advance_body, BodyRhs, Integrator, Tolerances};
use tumble::math::{quat_exp, DVec3};
use tumble::{World, WorldConfig};

const DT: f64 = 1e-3;

fn tumbler() -> RigidBody {
    let mut body = RigidBody::new("tumbler", MassProperties::from_principal(1.0, DVec3::new(1.0, 2.0, 3.0)).unwrap());
    body.state.omega_body = DVec3::new(0.01, 5.0, 0.01);
    body
}

fn advance(c: &mut Criterion) {
    let mut group = c.benchmark_group("advance_body");
    for integrator in Integrator::ALL {
        let body = tumbler();
        let loads = Loads::default();
        let rhs = BodyRhs { mass: &body.mass, loads: &loads, gravity_world: DVec3::ZERO };
        let mut state = body.state;
        let mut hint = 0.0;
        group.bench_function(BenchmarkId::from_parameter(integrator.name()), |b| {
            // the body keeps tumbling from one iteration to the next
            b.iter(|| {
                advance_body(integrator, Tolerances::default(), &rhs, black_box(&mut state), DT, &mut hint).unwrap()
            })
        });
    }
    group.finish();
}

fn world_of(n: usize, integrator: Integrator) -> World {
    let bodies = (0..n)
        .map(|i| {
            let mut body = tumbler();
            body.name = format!("b{i}");
            let k = i as f64;
            body.state.position = DVec3::new(k % 100.0, (k / 100.0).floor(), 10.0);
            body.state.orientation = quat_exp(DVec3::new((0.7 * k).sin(), (1.3 * k).cos(), 0.5) * 2.0);
            body.state.omega_body = DVec3::new((0.3 * k).sin(), 5.0, (0.9 * k).cos());
            body
        })
        .collect();
    World::new(WorldConfig { dt: DT, integrator, ..Default::default() }, bodies)
}

fn world_step(c: &mut Criterion) {
    const N: usize = 10_000;
    let mut group = c.benchmark_group("world_step_10000");
    group.throughput(Throughput::Elements(N as u64));
    for integrator in [Integrator::SemiImplicitEuler, Integrator::Rk4] {
        let mut world = world_of(N, integrator);
        group.bench_function(BenchmarkId::from_parameter(integrator.name()), |b| {
            b.iter(|| black_box(&mut world).step().unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, advance, world_step);
criterion_main!(benches);
