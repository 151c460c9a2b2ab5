//! The pure-Rust loop that `tumble.rollout` (Python) is measured against: `B` rows, each a clone of
//! the scene's world set to the scene's initial state, stepped `NSTEP` times on one thread, the
//! state written after every step into one `(B, NSTEP, nstate)` buffer — exactly the work of a
//! one-thread rollout, without Python.
//!
//! ```sh
//! cargo run --release -p tumble --example rollout_loop -- scenes/double_pendulum.toml 64 1000 [THREADS]
//! ```
//!
//! Prints one JSON line: `{"rows", "nstep", "nstate", "threads", "seconds", "steps_per_s"}` (the best
//! of 5 runs; a step is one world step of one row). With `THREADS` > 1 the rows are split into that
//! many contiguous blocks, one scoped thread each: the two-thread figure of the Rust loop, against
//! which the rollout's thread scaling can be told apart from the machine's.

use std::path::PathBuf;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (scene, rows, nstep, threads) = match args.as_slice() {
        [scene, rows, nstep] => (scene, rows, nstep, "1"),
        [scene, rows, nstep, threads] => (scene, rows, nstep, threads.as_str()),
        _ => {
            eprintln!("usage: rollout_loop SCENE ROWS NSTEP [THREADS]");
            std::process::exit(2);
        }
    };
    let threads: usize = threads.parse().ok().filter(|&n| n > 0).expect("THREADS: a positive number");
    let rows: usize = rows.parse().expect("ROWS: a number");
    let nstep: usize = nstep.parse().expect("NSTEP: a number");
    let base = match tumble::scene::load(&PathBuf::from(scene)) {
        Ok(scene) => scene.world,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    };
    let s = base.state_len();
    let mut x0 = vec![0.0; s];
    base.write_state(&mut x0).expect("length");
    let mut out = vec![0.0; rows * nstep * s];
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let start = Instant::now();
        let row_len = (nstep * s).max(1);
        let block = rows.div_ceil(threads).max(1) * row_len;
        std::thread::scope(|scope| {
            for rows_out in out.chunks_mut(block) {
                let (base, x0) = (&base, &x0);
                scope.spawn(move || {
                    for row in rows_out.chunks_mut(row_len) {
                        let mut world = base.clone();
                        world.set_state(x0).expect("the scene's own state");
                        for t in 0..nstep {
                            world.step().expect("the benchmark scenes do not diverge");
                            world.write_state(&mut row[t * s..(t + 1) * s]).expect("length");
                        }
                    }
                });
            }
        });
        best = best.min(start.elapsed().as_secs_f64());
    }
    std::hint::black_box(&out);
    let steps = (rows * nstep) as f64;
    println!(
        "{{\"rows\": {rows}, \"nstep\": {nstep}, \"nstate\": {s}, \"threads\": {threads}, \"seconds\": {best}, \"steps_per_s\": {}}}",
        steps / best
    );
}
