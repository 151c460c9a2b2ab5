//! Property tests: no input makes the loader panic, and whatever it accepts is finite and sane.

use proptest::prelude::*;
use tumble::scene::{self, Format};

const SEEDS: [&str; 3] = [
    include_str!("../../../scenes/demo.toml"),
    include_str!("../../../scenes/asymmetric_top.toml"),
    include_str!("../../../scenes/projectile.toml"),
];

/// Whatever loads has finite state, positive masses and unit quaternions.
fn check_accepted(text: &str, format: Format) {
    if let Ok(s) = scene::from_str(text, "fuzz", format) {
        let c = s.world.config;
        assert!(c.dt > 0.0 && c.dt.is_finite() && c.gravity.is_finite() && c.duration.is_finite());
        for b in &s.world.bodies {
            assert!(b.state.is_finite(), "{}", b.name);
            assert!(b.mass.mass > 0.0 && b.mass.mass.is_finite());
            assert!(b.mass.inertia_body.min_element() > 0.0 && b.mass.inertia_body.is_finite());
            assert!((b.state.orientation.length() - 1.0).abs() < 1e-12);
        }
        let _ = s.describe();
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// A shipped scene with some bytes replaced, inserted or removed.
    #[test]
    fn mutated_scenes_never_panic(
        seed in 0usize..SEEDS.len(),
        edits in prop::collection::vec((any::<prop::sample::Index>(), 0u8..3, any::<u8>()), 1..8),
    ) {
        let mut bytes = SEEDS[seed].as_bytes().to_vec();
        for (at, kind, byte) in edits {
            if bytes.is_empty() {
                break;
            }
            let i = at.index(bytes.len());
            match kind {
                0 => bytes[i] = byte,
                1 => bytes.insert(i, byte),
                _ => {
                    bytes.remove(i);
                }
            }
        }
        let text = String::from_utf8_lossy(&bytes);
        check_accepted(&text, Format::Toml);
    }

    /// Random numbers (any bit pattern, so NaN, infinities and subnormals too) in every numeric slot.
    #[test]
    fn any_numbers_are_checked(values in prop::collection::vec(any::<f64>(), 12)) {
        let v: Vec<String> = values.iter().map(|x| {
            if x.is_nan() { "nan".into() } else if x.is_infinite() { if *x > 0.0 { "inf".into() } else { "-inf".into() } } else { format!("{x:e}") }
        }).collect();
        let text = format!(
            "version = 1\n[world]\ndt = {}\n[[body]]\nname = \"b\"\nmass = {}\ninertia = [{}, {}, {}]\n\
             orientation = [{}, {}, {}, {}]\nvelocity = [{}, {}, {}]\n",
            v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9], v[10], v[11]
        );
        check_accepted(&text, Format::Toml);
    }

    /// Arbitrary text as JSON.
    #[test]
    fn arbitrary_json_never_panics(text in "\\PC{0,200}") {
        check_accepted(&text, Format::Json);
        check_accepted(&text, Format::Toml);
    }
}

/// R02: a million bodies load (about 0.5 GB in memory: run by hand with `--ignored`).
#[test]
#[ignore]
fn r02_a_million_bodies_load() {
    let text = "version = 1\n[[grid]]\ncount = [100, 100, 100]\nspacing = [2.0, 2.0, 2.0]\n\
        [grid.body]\nname = \"b\"\ndensity = 1000.0\nshape = { type = \"sphere\", radius = 0.5 }\n";
    let s = scene::from_str(text, "million.toml", Format::Toml).expect("loads");
    assert_eq!(s.world.bodies.len(), 1_000_000);
    assert_eq!(s.world.bodies[999_999].name, "b_99_99_99");
}
