//! The grid's candidate pairs against their definition: every pair of bodies tested, `O(n²)`, on
//! random scenes of spheres, boxes and capsules of mixed sizes, huge boxes (walls, a floor box),
//! planes, fixed bodies, bodies without a shape, far outliers and excluded pairs; and on a lattice
//! of cubes that touch exactly (the closed test's equality).

use super::super::Colliders;
use crate::body::{MassProperties, RigidBody, Shape};
use crate::math::{DQuat, DVec3};
use proptest::prelude::*;

/// A body's description in a random scene.
#[derive(Debug, Clone)]
struct Spec {
    /// 0: no shape, 1: sphere, 2: box, 3: capsule, 4: huge thin box, 5: plane.
    kind: u8,
    /// The shape's size (m): a radius or half extents.
    size: [f64; 3],
    position: [f64; 3],
    /// A rotation vector (rad).
    turn: [f64; 3],
    velocity: [f64; 3],
    omega: [f64; 3],
    fixed: bool,
}

fn body(spec: &Spec) -> RigidBody {
    let mut b = RigidBody::new("b", MassProperties::from_principal(1.0, DVec3::ONE).unwrap());
    let [a, h, c] = spec.size;
    b.shape = match spec.kind {
        1 => Some(Shape::Sphere { radius: a }),
        2 => Some(Shape::Box { half_extents: DVec3::new(a, h, c) }),
        3 => Some(Shape::Capsule { radius: a, half_height: h }),
        // a wall or a floor: 20–30 m across, thin along one axis
        4 => Some(Shape::Box { half_extents: DVec3::new(10.0 + 5.0 * a, 10.0 + 5.0 * h, 0.25 * c) }),
        5 => Some(Shape::Plane),
        _ => None,
    };
    b.fixed = spec.fixed;
    b.state.position = DVec3::from_array(spec.position);
    b.state.orientation = DQuat::from_scaled_axis(DVec3::from_array(spec.turn));
    b.state.velocity = DVec3::from_array(spec.velocity);
    b.state.omega_body = DVec3::from_array(spec.omega);
    b
}

/// The candidate pairs by their definition: every pair of bodies with a box whose boxes (as the
/// broad phase made them) overlap on the three axes, closed, but not two fixed ones; each plane with
/// every free body with a box one of whose eight corners is at most `slop / 2` above the plane;
/// less the excluded pairs; sorted.
fn every_pair(c: &Colliders, bodies: &[RigidBody], slop: f64) -> Pairs {
    every_pair_asleep(c, bodies, &[], slop)
}

/// [`every_pair`] with the bodies `asleep` resting as fixed ones (empty: none).
fn every_pair_asleep(c: &Colliders, bodies: &[RigidBody], asleep: &[bool], slop: f64) -> Pairs {
    let rests = |i: usize| bodies[i].fixed || asleep.get(i).copied().unwrap_or(false);
    let plane = |i: usize| c.planes.contains(&i);
    let boxed = |i: usize| c.shapes[i].is_some() && !plane(i);
    let meet = |i: usize, j: usize| {
        let (a, b) = (&c.aabbs[i], &c.aabbs[j]);
        (0..3).all(|k| a.mins[k] <= b.maxs[k] && b.mins[k] <= a.maxs[k])
    };
    // the height of a corner of body j's box above plane i, along the plane's outward normal
    let reaches = |i: usize, j: usize| {
        let pose = &c.poses[i];
        let normal = pose.rotation * c.shapes[i].as_ref().and_then(|s| s.as_halfspace()).expect("a plane").normal;
        let (lo, hi) = (c.aabbs[j].mins, c.aabbs[j].maxs);
        (0..8).any(|k| {
            let corner = DVec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            normal.dot(corner - pose.translation) <= 0.5 * slop
        })
    };
    let mut pairs = Vec::new();
    for i in 0..bodies.len() {
        for j in 0..bodies.len() {
            if i < j && boxed(i) && boxed(j) && !(rests(i) && rests(j)) && meet(i, j) {
                pairs.push((i, j));
            }
            if i != j && plane(i) && boxed(j) && !rests(j) && reaches(i, j) {
                pairs.push((i, j));
            }
        }
    }
    pairs.retain(|&(i, j)| !c.is_excluded(i, j));
    pairs.sort();
    pairs
}

/// The broad phase's pairs of `bodies` (with `excluded` pairs) and those by definition.
/// Candidate pairs, `(i, j)` body indices.
type Pairs = Vec<(usize, usize)>;

fn both(bodies: &[RigidBody], excluded: &[(usize, usize)], slop: f64) -> (Pairs, Pairs) {
    let mut c = Colliders::new(bodies);
    for &(i, j) in excluded {
        c.exclude_pair(i, j);
    }
    c.broad_phase(bodies, &[], 1.0 / 60.0, DVec3::new(0.0, 0.0, -9.81), slop);
    let expected = every_pair(&c, bodies, slop);
    (c.pairs.clone(), expected)
}

fn spec(extent: f64) -> impl Strategy<Value = Spec> {
    let kind =
        prop_oneof![3 => Just(1u8), 3 => Just(2u8), 2 => Just(3u8), 1 => Just(0u8), 1 => Just(4u8), 1 => Just(5u8)];
    let coordinate = prop_oneof![12 => -extent..extent, 1 => -1e4..1e4f64];
    (
        kind,
        prop::array::uniform3(0.05..1.5f64),
        prop::array::uniform3(coordinate),
        prop::array::uniform3(-3.0..3.0f64),
        prop::array::uniform3(prop_oneof![3 => Just(0.0), 2 => -20.0..20.0f64]),
        prop::array::uniform3(prop_oneof![3 => Just(0.0), 1 => -10.0..10.0f64]),
        prop::bool::weighted(0.3),
    )
        .prop_map(|(kind, size, position, turn, velocity, omega, fixed)| Spec {
            kind,
            size,
            position,
            turn,
            velocity,
            omega,
            fixed,
        })
}

fn scene() -> impl Strategy<Value = (Vec<Spec>, Vec<(usize, usize)>)> {
    (1.0..15.0f64, 1usize..250)
        .prop_flat_map(|(extent, n)| {
            (prop::collection::vec(spec(extent), n), prop::collection::vec((0..n, 0..n), 0..30))
        })
        .prop_map(|(specs, excluded)| (specs, excluded.into_iter().filter(|(i, j)| i != j).collect()))
}

/// A pile of `n` spheres and boxes of about one size packed in a cube: every cell full, its
/// neighbours too, every direction of neighbouring cells met.
fn pile() -> impl Strategy<Value = Vec<Spec>> {
    (20usize..400).prop_flat_map(|n| {
        let extent = 0.5 * (n as f64).cbrt();
        let spec = (
            prop_oneof![Just(1u8), Just(2u8)],
            prop::array::uniform3(0.3..0.5f64),
            prop::array::uniform3(-extent..extent),
            prop::array::uniform3(-3.0..3.0f64),
            prop::array::uniform3(-2.0..2.0f64),
            prop::bool::weighted(0.1),
        )
            .prop_map(|(kind, size, position, turn, velocity, fixed)| Spec {
                kind,
                size,
                position,
                turn,
                velocity,
                omega: [0.0; 3],
                fixed,
            });
        prop::collection::vec(spec, n)
    })
}

/// The broad phase over steps of a run, each step `(kind, seed)`: 0 nothing moves; 1 every awake
/// body moves by up to 1 mm (most stay inside their fat boxes); 2 one to twelve awake bodies jump
/// by up to 1 m (their fat boxes made again, their pairs found against every other); 3 every awake
/// body moves by up to 1 m (every fat box made again, then the grid alone while the back-off lasts)
/// and a few bodies fall asleep or wake. The pairs at every step are every pair's test.
fn pairs_over_steps(specs: &[Spec], excluded: &[(usize, usize)], steps: &[(u8, u64)]) -> Result<(), TestCaseError> {
    let mut bodies: Vec<RigidBody> = specs.iter().map(body).collect();
    let mut c = Colliders::new(&bodies);
    for &(i, j) in excluded {
        c.exclude_pair(i, j);
    }
    let (dt, g, slop) = (1.0 / 60.0, DVec3::new(0.0, 0.0, -9.81), 0.01);
    let mut asleep = vec![false; bodies.len()];
    for &(kind, seed) in steps {
        // xorshift64: a step's moves from its seed
        let mut state = seed | 1;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let n = bodies.len();
        let shift = |b: &mut RigidBody, reach: f64, u: &mut dyn FnMut() -> f64| {
            b.state.position += reach * DVec3::new(2.0 * u() - 1.0, 2.0 * u() - 1.0, 2.0 * u() - 1.0);
        };
        let awake = |i: usize, bodies: &[RigidBody], asleep: &[bool]| !bodies[i].fixed && !asleep[i];
        match kind {
            1 | 3 => {
                let reach = if kind == 1 { 1e-3 } else { 1.0 };
                for i in 0..n {
                    if awake(i, &bodies, &asleep) {
                        shift(&mut bodies[i], reach, &mut uniform);
                    }
                }
                if kind == 3 {
                    for _ in 0..3 {
                        let i = (uniform() * n as f64) as usize % n;
                        asleep[i] = !asleep[i] && !bodies[i].fixed;
                    }
                }
            }
            2 => {
                for _ in 0..1 + (uniform() * 12.0) as usize {
                    let i = (uniform() * n as f64) as usize % n;
                    if awake(i, &bodies, &asleep) {
                        shift(&mut bodies[i], 1.0, &mut uniform);
                    }
                }
            }
            _ => {}
        }
        c.broad_phase(&bodies, &asleep, dt, g, slop);
        prop_assert_eq!(&c.pairs, &every_pair_asleep(&c, &bodies, &asleep, slop), "step kind {}", kind);
    }
    Ok(())
}

fn steps() -> impl Strategy<Value = Vec<(u8, u64)>> {
    prop::collection::vec(
        (prop_oneof![2 => Just(0u8), 4 => Just(1u8), 3 => Just(2u8), 1 => Just(3u8)], any::<u64>()),
        40,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// The pairs kept from fat boxes (module `fat`) are every pair's test at every step of a run.
    #[test]
    fn pairs_from_fat_boxes_are_every_pair_tested((specs, excluded) in scene(), steps in steps()) {
        pairs_over_steps(&specs, &excluded, &steps)?;
    }

    /// The same in a dense pile, where most steps keep the fat boxes.
    #[test]
    fn pairs_from_fat_boxes_in_a_pile_are_every_pair_tested(specs in pile(), steps in steps()) {
        pairs_over_steps(&specs, &[], &steps)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    /// The grid's pairs are every pair's test, pair for pair and in the same order.
    #[test]
    fn grid_pairs_are_every_pair_tested((specs, excluded) in scene(), slop in 0.0..0.05f64) {
        let bodies: Vec<RigidBody> = specs.iter().map(body).collect();
        let (grid, expected) = both(&bodies, &excluded, slop);
        prop_assert_eq!(grid, expected);
    }

    /// The same in a dense pile of boxes of one size.
    #[test]
    fn grid_pairs_in_a_pile_are_every_pair_tested(specs in pile()) {
        let bodies: Vec<RigidBody> = specs.iter().map(body).collect();
        let (grid, expected) = both(&bodies, &[], 0.01);
        prop_assert_eq!(grid, expected);
    }
}

/// Cubes of side 0.5 m at rest on a 0.5 m lattice, no margin: each touches its 26 neighbours on a
/// face, an edge or a corner with bounds exactly equal, and the closed test pairs them all;
/// a far cube and a huge box make the grid grow its cells and test a large box.
#[test]
fn touching_lattice_pairs_every_neighbour() {
    let k = 6;
    let mut bodies = Vec::new();
    for x in 0..k {
        for y in 0..k {
            for z in 0..k {
                let mut b = RigidBody::new("cube", MassProperties::from_principal(1.0, DVec3::ONE).unwrap());
                b.shape = Some(Shape::Box { half_extents: DVec3::splat(0.25) });
                b.state.position = 0.5 * DVec3::new(x as f64, y as f64, z as f64);
                bodies.push(b);
            }
        }
    }
    let mut c = Colliders::new(&bodies);
    c.broad_phase(&bodies, &[], 1.0 / 60.0, DVec3::ZERO, 0.0);
    // neighbours along a direction d: k²(k − 1) pairs per face direction (3), k(k − 1)² per edge
    // direction (6), (k − 1)³ per corner direction (4)
    let per_lattice = 3 * k * k * (k - 1) + 6 * k * (k - 1) * (k - 1) + 4 * (k - 1) * (k - 1) * (k - 1);
    assert_eq!(c.pairs.len(), per_lattice);
    assert_eq!(c.pairs, every_pair(&c, &bodies, 0.0));

    let mut far = bodies[0].clone();
    far.state.position = DVec3::new(1e6, -3e5, 7.0);
    let mut floor = bodies[0].clone();
    floor.shape = Some(Shape::Box { half_extents: DVec3::new(20.0, 20.0, 0.5) });
    floor.state.position = DVec3::new(0.0, 0.0, -0.75);
    floor.fixed = true;
    bodies.extend([far, floor]);
    let mut c = Colliders::new(&bodies);
    c.broad_phase(&bodies, &[], 1.0 / 60.0, DVec3::ZERO, 0.0);
    // the floor's top touches the lowest layer's bottom
    assert_eq!(c.pairs.len(), per_lattice + k * k);
    assert_eq!(c.pairs, every_pair(&c, &bodies, 0.0));
}

/// A thousand balls packed in a box of four fixed walls above a plane, some moving fast: the walls
/// are large boxes tested against the cells they cover.
#[test]
fn packed_balls_in_walls() {
    let mut bodies = Vec::new();
    let wall = |half: DVec3, position: DVec3| {
        let mut b = RigidBody::new("wall", MassProperties::from_principal(1.0, DVec3::ONE).unwrap());
        b.shape = Some(Shape::Box { half_extents: half });
        b.state.position = position;
        b.fixed = true;
        b
    };
    let mut ground = wall(DVec3::ONE, DVec3::ZERO);
    ground.shape = Some(Shape::Plane);
    bodies.push(ground);
    bodies.push(wall(DVec3::new(0.25, 7.0, 10.0), DVec3::new(-6.75, 0.0, 10.0)));
    bodies.push(wall(DVec3::new(0.25, 7.0, 10.0), DVec3::new(6.75, 0.0, 10.0)));
    bodies.push(wall(DVec3::new(7.0, 0.25, 10.0), DVec3::new(0.0, -6.75, 10.0)));
    bodies.push(wall(DVec3::new(7.0, 0.25, 10.0), DVec3::new(0.0, 6.75, 10.0)));
    for n in 0..1000 {
        let (x, y, z) = (n % 13, (n / 13) % 13, n / 169);
        let mut b = RigidBody::new("ball", MassProperties::from_principal(1.0, DVec3::ONE).unwrap());
        b.shape = Some(Shape::Sphere { radius: 0.5 });
        // a little off the lattice, pseudo-randomly, and every seventh ball falling fast
        let jitter = 0.01 * DVec3::new((n as f64 * 0.7).sin(), (n as f64 * 1.3).cos(), (n as f64 * 2.9).sin());
        b.state.position = DVec3::new(x as f64 - 6.0, y as f64 - 6.0, z as f64 + 0.5) + jitter;
        if n % 7 == 0 {
            b.state.velocity = DVec3::new(0.0, 0.0, -12.0);
        }
        bodies.push(b);
    }
    let (grid, expected) = both(&bodies, &[(0, 7), (12, 13), (100, 2)], 0.01);
    assert!(expected.len() > 5000, "{} pairs", expected.len());
    assert_eq!(grid, expected);
}

/// Bodies asleep pair as fixed ones: the pairs are those of the awake world without the pairs of
/// two bodies each asleep or fixed, planes included.
#[test]
fn sleeping_bodies_pair_only_with_awake_ones() {
    let mut bodies = Vec::new();
    let mut ground = RigidBody::new("ground", MassProperties::from_principal(1.0, DVec3::ONE).unwrap());
    ground.shape = Some(Shape::Plane);
    ground.fixed = true;
    bodies.push(ground);
    for x in 0..6 {
        for z in 0..4 {
            let mut b = RigidBody::new("cube", MassProperties::from_principal(1.0, DVec3::ONE).unwrap());
            b.shape = Some(Shape::Box { half_extents: DVec3::splat(0.25) });
            b.state.position = DVec3::new(0.5 * x as f64, 0.0, 0.25 + 0.5 * z as f64);
            bodies.push(b);
        }
    }
    // the lower three layers asleep, the top one awake
    let asleep: Vec<bool> = bodies.iter().map(|b| !b.fixed && b.state.position.z < 1.5).collect();
    let mut c = Colliders::new(&bodies);
    c.broad_phase(&bodies, &[], 1.0 / 60.0, DVec3::new(0.0, 0.0, -9.81), 0.0);
    let rests = |i: usize| bodies[i].fixed || asleep[i];
    let mut expected = c.pairs.clone();
    expected.retain(|&(i, j)| !(rests(i) && rests(j)));
    assert!(expected.len() < c.pairs.len() && !expected.is_empty());
    c.broad_phase(&bodies, &asleep, 1.0 / 60.0, DVec3::new(0.0, 0.0, -9.81), 0.0);
    assert_eq!(c.pairs, expected);
}

/// Bodies heaped at one spot: every pair is a candidate. With a budget below that count the search
/// stops, leaves no pair and says how many it had found (more than the budget, at most all of
/// them); with a budget of exactly that count it finds them all, sorted (a body's list of 299
/// partners is past the insertion sort).
#[test]
fn a_heap_at_one_spot_stops_at_the_pair_budget() {
    let n = 300;
    let mut bodies: Vec<RigidBody> = (0..n)
        .map(|_| {
            body(&Spec {
                kind: 1,
                size: [0.5; 3],
                position: [0.0; 3],
                turn: [0.0; 3],
                velocity: [0.0; 3],
                omega: [0.0; 3],
                fixed: false,
            })
        })
        .collect();
    bodies[0].shape = Some(Shape::Plane);
    bodies[0].fixed = true;
    // 299 balls: 299·298/2 ball pairs and 299 with the plane
    let all = 299 * 298 / 2 + 299;
    let mut c = Colliders::new(&bodies);
    c.set_pair_budget(all);
    c.broad_phase(&bodies, &[], 1.0 / 60.0, DVec3::ZERO, 0.0);
    assert_eq!(c.pairs_over_budget(), None);
    assert_eq!(c.pairs, every_pair(&c, &bodies, 0.0));
    assert_eq!(c.pairs.len(), all);
    for budget in [0, 298, 299, 1000, all - 1] {
        c.set_pair_budget(budget);
        c.broad_phase(&bodies, &[], 1.0 / 60.0, DVec3::ZERO, 0.0);
        let found = c.pairs_over_budget().unwrap_or_else(|| panic!("budget {budget}: not exceeded"));
        assert!(found > budget && found <= all, "budget {budget}: {found} found");
        assert!(c.pairs.is_empty(), "budget {budget}");
    }
    // the next broad phase within the budget forgets it
    c.set_pair_budget(usize::MAX);
    c.broad_phase(&bodies, &[], 1.0 / 60.0, DVec3::ZERO, 0.0);
    assert_eq!((c.pairs_over_budget(), c.pairs.len()), (None, all));
}

/// The budget counts the plane pairs the broad phase gives, not one per plane and free body: ten
/// balls apart in a row, the lowest resting on the ground plane and the others high above it, make
/// one pair with a budget of one; two on the ground make two, over a budget of one.
#[test]
fn the_budget_counts_only_the_plane_pairs_made() {
    let ball = |x: f64, z: f64| {
        body(&Spec {
            kind: 1,
            size: [0.5; 3],
            position: [x, 0.0, z],
            turn: [0.0; 3],
            velocity: [0.0; 3],
            omega: [0.0; 3],
            fixed: false,
        })
    };
    let mut bodies: Vec<RigidBody> = (0..10).map(|k| ball(3.0 * k as f64, if k == 0 { 0.5 } else { 5.0 })).collect();
    bodies[0].shape = Some(Shape::Plane);
    bodies[0].fixed = true;
    bodies[0].state.position = DVec3::ZERO;
    bodies[1].state.position.z = 0.5;
    let mut c = Colliders::new(&bodies);
    c.set_pair_budget(1);
    c.broad_phase(&bodies, &[], 1.0 / 60.0, DVec3::new(0.0, 0.0, -9.81), 0.01);
    assert_eq!(c.pairs_over_budget(), None, "nine balls, one on the ground: one pair");
    assert_eq!(c.pairs, [(0, 1)]);
    assert_eq!(c.pairs, every_pair(&c, &bodies, 0.01));
    bodies[2].state.position.z = 0.5;
    c.broad_phase(&bodies, &[], 1.0 / 60.0, DVec3::new(0.0, 0.0, -9.81), 0.01);
    assert_eq!(c.pairs_over_budget(), Some(2), "two on the ground: two pairs, over a budget of one");
    assert!(c.pairs.is_empty());
}

/// A body asleep at two broad phases in a row keeps the box it had (no pose, no box made: its
/// state cannot have changed, `contact::sleep` wakes a body the caller changed), and gets a new one
/// when it wakes or when the step's settings change. Seen here by moving the body behind the
/// sleep module's back, which the world never lets happen.
#[test]
fn a_sleeping_body_keeps_its_box() {
    let cube = |x: f64| {
        let mut b = RigidBody::new("cube", MassProperties::from_principal(1.0, DVec3::ONE).unwrap());
        b.shape = Some(Shape::Box { half_extents: DVec3::splat(0.5) });
        b.state.position = DVec3::new(x, 0.0, 0.0);
        b
    };
    let mut bodies = vec![cube(0.0), cube(1.0)];
    let mut c = Colliders::new(&bodies);
    let (dt, g) = (1.0 / 60.0, DVec3::new(0.0, 0.0, -9.81));
    let asleep = [true, false];
    let x_min = |c: &Colliders| c.aabbs[0].mins.x;
    c.broad_phase(&bodies, &asleep, dt, g, 0.001);
    let made = x_min(&c);
    assert!((made + 0.5).abs() < 0.01);
    // asleep before and now: the box is kept, though the body moved
    bodies[0].state.position.x = -3.0;
    c.broad_phase(&bodies, &asleep, dt, g, 0.001);
    assert_eq!(x_min(&c).to_bits(), made.to_bits());
    // the pair with its awake neighbour is still found from the kept box
    assert_eq!(c.pairs, vec![(0, 1)]);
    // other step settings: made again
    c.broad_phase(&bodies, &asleep, dt / 2.0, g, 0.001);
    assert!((x_min(&c) + 3.5).abs() < 0.01);
    // awake: made again at every broad phase
    bodies[0].state.position.x = 0.0;
    c.broad_phase(&bodies, &[false, false], dt, g, 0.001);
    assert!((x_min(&c) + 0.5).abs() < 0.01);
    bodies[0].state.position.x = -3.0;
    c.broad_phase(&bodies, &[false, false], dt, g, 0.001);
    assert!((x_min(&c) + 3.5).abs() < 0.01);
}
