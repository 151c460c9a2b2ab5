//! Quadrupeds of example-robot-data on the floor (issue "Legged robots at MuJoCo's speed"):
//! `scenes/{solo12,go1,anymal_c}_stand.toml` (the URDFs' own collision geometry: Solo-12's STL
//! meshes, Go1's and ANYmal C's primitives; PD at the SRDF's standing pose, semi-implicit Euler,
//! `dt = 1e-3`, friction 0.9).
//!
//! - standing, after the first second: the base drifts under 1 mm, no foot sinks 1 mm (over the
//!   whole run, landing included), the normal forces sum to the weight within 0.5 % at every step,
//!   no foot slides 0.1 mm;
//! - the same standing step with rk4;
//! - trotting (`*_trot.toml`: periodic PD targets, the feet lift and land): the robot stays up and
//!   its state is the same bit for bit on 1 and 2 threads.

use std::path::{Path, PathBuf};
use tumble::collision::links::Side;
use tumble::math::DVec3;
use tumble::{Integrator, World};

fn scene(name: &str) -> World {
    let path: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(format!("{name}.toml"));
    tumble::scene::load(&path).unwrap_or_else(|e| panic!("{name}: {e}")).world
}

/// Worst figures over `[1, duration]` s: (|Σ f_n − W| / W, depth over the whole run (m), foot slide
/// (m), base drift (m)).
fn standing(name: &str, integrator: Integrator, duration: f64) -> (f64, f64, f64, f64) {
    let mut world = scene(name);
    world.config.integrator = integrator;
    world.config.duration = duration;
    let robot = 0;
    let mass: f64 = world.robots[robot].model.bodies.iter().map(|b| b.inertia.mass).sum();
    let weight = mass * world.config.gravity.length();
    let names = world.robots[robot].link_names().to_vec();
    let feet: Vec<usize> = (0..names.len()).filter(|&k| names[k].to_lowercase().ends_with("_foot")).collect();
    assert_eq!(feet.len(), 4, "{name}: feet among {names:?}");
    // the first moving frame is the floating base's
    let base = 0;
    let steps = world.config.step_count();
    let settle = (1.0 / world.config.dt).round() as u64;
    let (mut force, mut depth, mut slide, mut drift) = (0.0_f64, 0.0_f64, 0.0_f64, 0.0_f64);
    let (mut anchors, mut base_anchor) = (Vec::new(), DVec3::ZERO);
    for step in 1..=steps {
        world.step().unwrap_or_else(|e| panic!("{name}: {e}"));
        depth = world.contacts().links.active().map(|(c, _)| -c.gap).fold(depth, f64::max);
        if step < settle {
            continue;
        }
        let r = &world.robots[robot];
        let positions: Vec<DVec3> = feet.iter().map(|&k| r.link_state(k).position).collect();
        let base_position = r.link_state(base).position;
        if step == settle {
            anchors = positions;
            base_anchor = base_position;
            continue;
        }
        let normal: f64 = world
            .contacts()
            .links
            .active()
            .filter(|(c, _)| matches!(c.a, Side::Body(_)))
            .map(|(c, p)| p.dot(c.normal_world) / world.config.dt)
            .sum();
        force = force.max((normal - weight).abs() / weight);
        for (p, a) in positions.iter().zip(&anchors) {
            slide = slide.max(((*p - *a) * DVec3::new(1.0, 1.0, 0.0)).length());
        }
        drift = drift.max((base_position - base_anchor).length());
    }
    println!(
        "{name}, {integrator}, {duration} s: normal forces within {:.4} % of the weight ({weight:.3} N), depth {:.3} mm, \
         feet slide {:.2e} m, base drifts {:.2e} m",
        100.0 * force,
        1e3 * depth,
        slide,
        drift
    );
    (force, depth, slide, drift)
}

fn check_standing(name: &str, integrator: Integrator) {
    let (force, depth, slide, drift) = standing(name, integrator, 3.0);
    assert!(force <= 0.005, "{name}: normal forces off the weight by {:.3} %", 100.0 * force);
    assert!(depth < 1e-3, "{name}: a foot sank {depth} m");
    assert!(slide <= 1e-4, "{name}: a foot slid {slide} m after the first second");
    assert!(drift <= 1e-3, "{name}: the base drifted {drift} m after the first second");
}

#[test]
fn solo12_stands_without_sinking_sliding_or_drifting() {
    check_standing("solo12_stand", Integrator::SemiImplicitEuler);
}

#[test]
fn go1_stands_without_sinking_sliding_or_drifting() {
    check_standing("go1_stand", Integrator::SemiImplicitEuler);
}

#[test]
fn anymal_c_stands_without_sinking_sliding_or_drifting() {
    check_standing("anymal_c_stand", Integrator::SemiImplicitEuler);
}

#[test]
fn the_quadrupeds_stand_as_well_under_rk4() {
    for name in ["solo12_stand", "go1_stand", "anymal_c_stand"] {
        check_standing(name, Integrator::Rk4);
    }
}

/// Trotting: the base stays above 80 % of its standing height, the feet lift off the floor
/// (some step has fewer than four feet in contact) and land again; the states on 1 and 2 threads
/// are the same bit for bit.
#[test]
fn the_quadrupeds_trot_without_falling_and_the_same_on_two_threads() {
    for name in ["solo12_trot", "go1_trot", "anymal_c_trot"] {
        let mut hashes = Vec::new();
        for threads in [1, 2] {
            let mut world = scene(name);
            world.set_threads(threads);
            world.set_parallel_min_pairs(0);
            let z0 = world.robots[0].link_state(0).position.z;
            let steps = (2.0 / world.config.dt).round() as u64;
            let (mut lowest, mut fewest, mut most) = (f64::INFINITY, usize::MAX, 0);
            for step in 1..=steps {
                world.step().unwrap_or_else(|e| panic!("{name}: {e}"));
                lowest = lowest.min(world.robots[0].link_state(0).position.z);
                if step > 500 {
                    let mut touching: Vec<String> = world
                        .contacts()
                        .links
                        .active()
                        .filter(|(c, p)| matches!(c.a, Side::Body(_)) && p.length() > 0.0)
                        .map(|(c, _)| format!("{:?}", c.b))
                        .collect();
                    touching.sort();
                    touching.dedup();
                    fewest = fewest.min(touching.len());
                    most = most.max(touching.len());
                }
            }
            println!(
                "{name}, {threads} threads: base lowest {lowest:.4} m (start {z0:.4}), links touching {fewest}..{most}"
            );
            assert!(lowest > 0.8 * z0, "{name}: the base fell to {lowest} m");
            assert!(fewest < most, "{name}: the feet never lifted ({fewest}..{most} links touching)");
            hashes.push(world.state_hash());
        }
        assert_eq!(hashes[0], hashes[1], "{name}: 1 and 2 threads differ");
    }
}
