//! RNEA, CRBA (and its LTDL factorisation) and ABA on Panda (fixed base, nv = 9) and Talos (floating
//! base, nv = 38), per call, over 256 random states (criterion's throughput is per state).
//!
//! `cargo bench -p tumble --bench multibody -- --warm-up-time 1 --measurement-time 3`
//!
//! The same quantities, timed the way Pinocchio's own benchmarks time them, come from
//! `tumble dynamics ROBOT.urdf [--floating] --bench`; `tools/pinocchio_bench.cpp` times Pinocchio
//! identically (see docs/multibody.md for the side-by-side figures).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::hint::black_box;
use std::path::PathBuf;
use tumble::multibody::{
    aba, crba, load_urdf, ltdl_factor, rnea, ChildOrder, JointKind, MultibodyModel, UrdfOptions, Workspace,
};

const STATES: usize = 256;

/// SplitMix64 in [−1, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        2.0 * ((z >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    }
}

struct Case {
    name: &'static str,
    model: MultibodyModel,
    q: Vec<Vec<f64>>,
    v: Vec<Vec<f64>>,
    tau: Vec<Vec<f64>>,
}

fn case(name: &'static str, file: &str, floating: bool) -> Case {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/robots").join(file);
    let model = load_urdf(&path, UrdfOptions { floating, order: ChildOrder::File, ..Default::default() })
        .expect("fixture URDF");
    let mut rng = Rng(42);
    let mut q = Vec::new();
    let (mut v, mut tau) = (Vec::new(), Vec::new());
    for _ in 0..STATES {
        let mut qs: Vec<f64> = (0..model.nq()).map(|_| rng.next()).collect();
        for b in &model.bodies {
            if b.joint.kind == JointKind::Floating {
                let s = b.joint.q_index + 3;
                let n = qs[s..s + 4].iter().map(|x| x * x).sum::<f64>().sqrt();
                qs[s..s + 4].iter_mut().for_each(|x| *x /= n);
            }
        }
        q.push(qs);
        v.push((0..model.nv()).map(|_| rng.next()).collect());
        tau.push((0..model.nv()).map(|_| rng.next()).collect());
    }
    Case { name, model, q, v, tau }
}

fn bench(c: &mut Criterion) {
    let cases = [case("panda", "panda.urdf", false), case("talos_floating", "talos_reduced.urdf", true)];
    let mut group = c.benchmark_group("multibody");
    group.throughput(Throughput::Elements(STATES as u64));
    for case in &cases {
        let m = &case.model;
        let mut ws = Workspace::new(m);
        let mut out = vec![0.0; m.nv()];
        group.bench_function(BenchmarkId::new("rnea", case.name), |b| {
            b.iter(|| {
                for s in 0..STATES {
                    rnea(m, &mut ws, &case.q[s], &case.v[s], &case.tau[s], &mut out).unwrap();
                    black_box(&out);
                }
            })
        });
        group.bench_function(BenchmarkId::new("crba", case.name), |b| {
            b.iter(|| {
                for s in 0..STATES {
                    black_box(crba(m, &mut ws, &case.q[s]).unwrap());
                }
            })
        });
        group.bench_function(BenchmarkId::new("crba_ltdl", case.name), |b| {
            b.iter(|| {
                for s in 0..STATES {
                    crba(m, &mut ws, &case.q[s]).unwrap();
                    ltdl_factor(m, &mut ws).unwrap();
                    black_box(&ws.ltdl);
                }
            })
        });
        group.bench_function(BenchmarkId::new("aba", case.name), |b| {
            b.iter(|| {
                for s in 0..STATES {
                    aba(m, &mut ws, &case.q[s], &case.v[s], &case.tau[s], &mut out).unwrap();
                    black_box(&out);
                }
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
