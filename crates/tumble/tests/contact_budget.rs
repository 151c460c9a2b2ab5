//! The contact pair budget (R04 and S16 of the reliability catalogue): bodies heaped at one spot
//! pair with each other, `n²/2` candidate pairs for `n` bodies. A scene that starts so is refused at
//! load, naming the grid whose copies overlap; a world whose bodies come together during the run
//! stops at the step that goes over the budget, undone, with a `StepError::ContactBudget`.

mod scene_common;
use scene_common::{assert_has, load_toml, toml_error};
use tumble::world::StepError;

/// 20,000 balls of radius 0.5 m at one spot over a floor: 2·10⁸ candidate pairs (a load that ran
/// out of memory or time before the budget).
const HEAP: &str = "version = 1\n[[body]]\nname = \"floor\"\nfixed = true\nshape = { type = \"plane\" }\n\
                    [[grid]]\ncount = [20, 20, 50]\nspacing = [0.0, 0.0, 0.0]\norigin = [0.0, 0.0, 1.0]\n\
                    [grid.body]\nname = \"ball\"\nmass = 1.0\nshape = { type = \"sphere\", radius = 0.5 }\n";

#[test]
fn a_grid_at_one_spot_is_refused_at_load_naming_its_spacing() {
    let m = toml_error(HEAP);
    assert_has(
        &m,
        &[
            "bad.toml:8:11: grid[0].spacing",
            "candidate contact pairs or more, over the budget of 650032",
            "(got [0, 0, 0])",
            "the 20000 copies of `ball` (bounding diameter 1 m) are all at one spot",
            "max_pairs",
        ],
    );
    // copies closer than their size along one axis only: columns of 200 balls 1 cm apart, each
    // ball overlapping the 100 above and below it: ~1.5·10⁶ pairs, over the budget too
    let columns = HEAP.replace("count = [20, 20, 50]", "count = [10, 10, 200]");
    let m = toml_error(&columns.replace("spacing = [0.0, 0.0, 0.0]", "spacing = [2.0, 2.0, 0.01]"));
    assert_has(&m, &["grid[0].spacing", "closer than their size", "at least 1 m apart"]);
    // a raised budget lets the 500 balls of a smaller heap load (500·499/2 + 500 = 125,250 pairs),
    // with their overlaps reported
    let small = HEAP.replace("count = [20, 20, 50]", "count = [5, 5, 20]");
    assert_has(&toml_error(&small), &["grid[0].spacing", "over the budget of 26032"]);
    let raised = small.replace("version = 1\n", "version = 1\n[world]\nmax_pairs = 125250\n");
    let scene = load_toml(&raised).unwrap();
    assert!(scene.warnings.iter().any(|w| w.contains("overlaps")), "{:?}", scene.warnings);
    // a sparse grid of overlapping neighbours keeps within the budget: warnings, as for bodies
    let sparse = HEAP.replace("spacing = [0.0, 0.0, 0.0]", "spacing = [0.9, 0.9, 0.9]");
    assert!(load_toml(&sparse).unwrap().warnings.iter().any(|w| w.contains("overlaps")));
}

#[test]
fn the_budget_must_be_positive() {
    let m = toml_error("version = 1\n[world]\nmax_pairs = 0\n");
    assert_has(&m, &["bad.toml:3:13: world.max_pairs", "must be ≥ 1", "(got 0)"]);
    let m = toml_error("version = 1\n[world]\nmax_pairs = -5\n");
    assert_has(&m, &["world.max_pairs"]);
}

/// Four balls of radius 0.5 m, 3 m from the origin on ±x and ±y, each moving towards it at 1 m/s,
/// without gravity: no candidate pair at the start, then (at t ≈ 2 s, when their boxes meet) four at
/// once.
const CONVERGING: &str = "version = 1\n[world]\ngravity = [0.0, 0.0, 0.0]\ndt = 0.01\nduration = 4.0\n\
                          max_pairs = 3\n\
                          [[body]]\nname = \"east\"\nmass = 1.0\nshape = { type = \"sphere\", radius = 0.5 }\n\
                          position = [3.0, 0.0, 0.0]\nvelocity = [-1.0, 0.0, 0.0]\n\
                          [[body]]\nname = \"west\"\nmass = 1.0\nshape = { type = \"sphere\", radius = 0.5 }\n\
                          position = [-3.0, 0.0, 0.0]\nvelocity = [1.0, 0.0, 0.0]\n\
                          [[body]]\nname = \"north\"\nmass = 1.0\nshape = { type = \"sphere\", radius = 0.5 }\n\
                          position = [0.0, 3.0, 0.0]\nvelocity = [0.0, -1.0, 0.0]\n\
                          [[body]]\nname = \"south\"\nmass = 1.0\nshape = { type = \"sphere\", radius = 0.5 }\n\
                          position = [0.0, -3.0, 0.0]\nvelocity = [0.0, 1.0, 0.0]\n";

#[test]
fn bodies_that_come_together_stop_the_step_that_goes_over_the_budget() {
    let mut world = load_toml(CONVERGING).unwrap().world;
    let error = loop {
        let before: Vec<_> = world.bodies.iter().map(|b| b.state).collect();
        match world.step() {
            Ok(()) => assert!(world.steps() < 400, "the budget was never exceeded"),
            Err(e) => {
                let after: Vec<_> = world.bodies.iter().map(|b| b.state).collect();
                assert_eq!(after, before, "the step is undone");
                break e;
            }
        }
    };
    let StepError::ContactBudget(budget) = &error else { panic!("{error}") };
    assert_eq!((budget.pairs, budget.budget), (4, 3), "{error}");
    assert_eq!(budget.step, world.steps() + 1);
    assert_eq!(budget.time, budget.step as f64 * 0.01);
    // the boxes (radius plus the step's sweep and margin) meet a little before the balls' surfaces
    // would, 2·(3 − t) − 1 ≈ 1.4 m apart on the diagonal at t = 2 s
    let x = world.bodies[0].state.position.x;
    assert!((0.95..=1.05).contains(&x), "the boxes of east and north meet at x + 0.5 ≈ 1.5: {x}");
    assert!(error.to_string().starts_with(&format!(
        "contact budget exceeded at step {} (t = {} s): 4 candidate pairs, more than the budget of 3",
        budget.step, budget.time
    )));
    // the step fails again, the same way, and the default budget lets the run go on
    assert_eq!(world.step().unwrap_err(), error);
    world.config.contact.max_pairs = None;
    for _ in 0..200 {
        world.step().unwrap();
    }
}
