//! Runs the contact scenes in tumble and in Rapier, single-threaded, side by side: wall time per step,
//! the ratio, and the stability of the pyramid (the largest displacement of a body after the run).
//!
//! Usage: `cargo run --release -p rapier-compare -- [STEPS] [SCENE.toml ...]`
//! (default: 1,000 steps of `scenes/pyramid.toml` and `scenes/balls.toml`). A scene with
//! `contacts = false` (`scenes/many.toml`: 10,000 free tumbling bodies) is built in Rapier as bodies
//! without colliders carrying the same mass and principal inertia: a comparison of the free-body
//! integration alone.
//!
//! The Rapier world is built from the tumble world the scene loader produced: same shapes, poses,
//! velocities, masses (Rapier computes the inertia from the shape and the mass, as tumble does for a
//! `mass` with a shape), friction and restitution (equal on every body in these scenes, so the two
//! engines' combine rules agree), `dt` and gravity. Sleeping is off in Rapier, as tumble has none.

use rapier3d_f64::prelude::*;
use std::path::Path;
use std::time::Instant;
use tumble::body::Shape;
use tumble::math::{DQuat, DVec3};

fn rapier_world(world: &tumble::World) -> (PhysicsWorld, Vec<Option<RigidBodyHandle>>) {
    let mut rw = PhysicsWorld { gravity: world.config.gravity, ..PhysicsWorld::default() };
    rw.integration_parameters.dt = world.config.dt;
    let contact = world.config.contact;
    let mut handles = Vec::with_capacity(world.bodies.len());
    for b in &world.bodies {
        if !contact.enabled && !b.fixed {
            // free bodies (contacts off in the scene): no collider, the body's own mass properties
            let mass = MassProperties::with_principal_inertia_frame(
                DVec3::ZERO,
                b.mass.mass,
                b.mass.inertia_body,
                b.mass.user_from_body,
            );
            let body = RigidBodyBuilder::dynamic()
                .pose(Pose::from_parts(b.state.position, b.orientation_user()))
                .linvel(b.state.velocity)
                .angvel(b.state.omega_world())
                .additional_mass_properties(mass)
                .gravity_scale(b.gravity_scale)
                .can_sleep(false);
            handles.push(Some(rw.insert_body(body)));
            continue;
        }
        let Some(shape) = &b.shape else {
            handles.push(None);
            continue;
        };
        let collider = match *shape {
            Shape::Sphere { radius } => ColliderBuilder::ball(radius),
            Shape::Box { half_extents: h } => ColliderBuilder::cuboid(h.x, h.y, h.z),
            Shape::Capsule { radius, half_height } => ColliderBuilder::capsule_z(half_height, radius),
            Shape::Cylinder { radius, half_height } => ColliderBuilder::cylinder(half_height, radius)
                .rotation(DVec3::new(std::f64::consts::FRAC_PI_2, 0.0, 0.0)),
            Shape::Plane => ColliderBuilder::halfspace(rapier3d_f64::na::Unit::new_unchecked(Vector::Z)),
            // meshes (triangles when fixed; convex pieces or the hull when moving), convex hulls and
            // compounds: the very parry shape tumble collides with (Rapier uses the same parry)
            Shape::Mesh(_) | Shape::Convex(_) | Shape::Compound(_) => {
                let (parry, offset) = tumble::collision::parry_shape(shape, b.fixed);
                ColliderBuilder::new(parry).position(offset)
            }
        };
        let friction = b.material.friction.unwrap_or(contact.friction);
        let restitution = b.material.restitution.unwrap_or(contact.restitution);
        let collider = collider
            .friction(friction)
            .restitution(restitution)
            .friction_combine_rule(CoefficientCombineRule::Min)
            .restitution_combine_rule(CoefficientCombineRule::Max)
            .mass(b.mass.mass);
        let rotation: DQuat = b.orientation_user();
        let pose = Pose::from_parts(b.state.position, rotation);
        let body = if b.fixed { RigidBodyBuilder::fixed() } else { RigidBodyBuilder::dynamic() }
            .pose(pose)
            .linvel(b.state.velocity)
            .angvel(b.state.omega_world())
            .gravity_scale(b.gravity_scale)
            .can_sleep(false);
        let (handle, _) = rw.insert(body, collider);
        handles.push(Some(handle));
    }
    (rw, handles)
}

struct Run {
    ms_per_step: f64,
    largest_displacement: f64,
}

fn run_tumble(mut world: tumble::World, steps: usize) -> Run {
    let start: Vec<DVec3> = world.bodies.iter().map(|b| b.state.position).collect();
    let t = Instant::now();
    for _ in 0..steps {
        if let Err(e) = world.step() {
            eprintln!("tumble: {e}");
            break;
        }
    }
    let ms_per_step = t.elapsed().as_secs_f64() * 1e3 / steps as f64;
    let largest_displacement = world
        .bodies
        .iter()
        .zip(&start)
        .filter(|(b, _)| !b.fixed)
        .map(|(b, s)| (b.state.position - *s).length())
        .fold(0.0, f64::max);
    Run { ms_per_step, largest_displacement }
}

fn run_rapier(world: &tumble::World, steps: usize) -> Run {
    let (mut rw, handles) = rapier_world(world);
    let t = Instant::now();
    for _ in 0..steps {
        rw.step();
    }
    let ms_per_step = t.elapsed().as_secs_f64() * 1e3 / steps as f64;
    let largest_displacement = world
        .bodies
        .iter()
        .zip(&handles)
        .filter(|(b, _)| !b.fixed)
        .filter_map(|(b, h)| h.map(|h| (rw.bodies[h].translation() - b.state.position).length()))
        .fold(0.0, f64::max);
    Run { ms_per_step, largest_displacement }
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let steps = match args.first().and_then(|a| a.parse::<usize>().ok()) {
        Some(n) => {
            args.remove(0);
            n
        }
        None => 1000,
    };
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let scenes: Vec<String> = if args.is_empty() {
        ["scenes/pyramid.toml", "scenes/balls.toml"].iter().map(|s| root.join(s).display().to_string()).collect()
    } else {
        args
    };
    println!("{steps} steps each, single-threaded");
    println!("| scene | bodies | tumble ms/step | Rapier ms/step | tumble/Rapier | largest displacement tumble (m) | Rapier (m) |");
    println!("|---|---|---|---|---|---|---|");
    for path in scenes {
        let scene = match tumble::scene::load(Path::new(&path)) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(2);
            }
        };
        let world = scene.world;
        let rapier = run_rapier(&world, steps);
        let n = world.bodies.len();
        let tumble = run_tumble(world, steps);
        let name = Path::new(&path).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or(path.clone());
        println!(
            "| {name} | {n} | {:.3} | {:.3} | {:.2} | {:.4} | {:.4} |",
            tumble.ms_per_step,
            rapier.ms_per_step,
            tumble.ms_per_step / rapier.ms_per_step,
            tumble.largest_displacement,
            rapier.largest_displacement
        );
    }
}
