//! `tumble.step_worlds`: many `World`s advanced in one call, each by the same number of steps, on
//! a thread pool with the GIL released — the step of a vector environment.
//!
//! Each world does exactly what `world.set_pd_target(robot, q_target[b])` then `world.step(n)`
//! then `world.state(out=out[b])` would do from Python: the worlds share nothing, so the numbers do
//! not depend on the thread count or on which worlds are stepped together (bit for bit).
//!
//! Everything is checked before anything changes: the worlds (each one borrowed once: the same
//! world twice is an error), the targets' shape and values, each robot's gains, `out`'s shape.

use crate::arrays::{check_finite, check_shape, f64_array, out_array, values};
use crate::bad;
use crate::rollout::{default_nthread, pool};
use crate::world::World;
use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use rayon::prelude::*;

/// Advances every world of `worlds` by `n` steps, on `nthread` threads (default
/// `default_nthread()`) with the GIL released. `q_target` (B, nq): first sets each world's PD
/// position targets of `robot` (name or index; default the only robot), as `World.set_pd_target`
/// does without gains. `out` (B, nstate): the states after the steps are written there. Returns the
/// steps each world completed, (B,) int64: `n`, or fewer for a world whose step diverged (it is left
/// at its last finite state, as `World.step` leaves it; step it alone to read the message).
#[pyfunction]
#[pyo3(signature = (worlds, n = 1, *, robot = None, q_target = None, out = None, nthread = None))]
pub fn step_worlds<'py>(
    py: Python<'py>,
    worlds: Vec<Bound<'py, World>>,
    n: u64,
    robot: Option<&Bound<'py, PyAny>>,
    q_target: Option<&Bound<'py, PyAny>>,
    out: Option<&Bound<'py, PyAny>>,
    nthread: Option<usize>,
) -> PyResult<Bound<'py, PyArray1<i64>>> {
    let batch = worlds.len();
    let mut guards = Vec::with_capacity(batch);
    for (b, w) in worlds.iter().enumerate() {
        let g = w.try_borrow_mut().map_err(|e| bad(format!("worlds[{b}]: {e} (the same World twice?)")))?;
        guards.push(g);
    }
    // the targets: (B, nq), every robot with gains, all checked before any is written
    let mut targets = Vec::new();
    if let Some(q) = q_target {
        let mut rows = Vec::with_capacity(batch);
        for (b, g) in guards.iter().enumerate() {
            let (r, nq) = g.pd_robot(robot, None, None).map_err(|e| bad(format!("worlds[{b}]: {e}")))?;
            if let Some(&(_, first)) = rows.first() {
                if first != nq {
                    return Err(bad(format!("worlds[{b}]: the robot has nq = {nq}, worlds[0]'s {first}")));
                }
            }
            rows.push((r, nq));
        }
        let nq = rows.first().map_or(0, |&(_, nq)| nq);
        let a = f64_array(q, "q_target")?;
        check_shape("q_target", a.shape(), &[Some(batch), Some(nq)], "(B, nq) joint positions")?;
        let ro = a.try_readonly().map_err(|e| bad(format!("q_target: {e}")))?;
        let v = values(&ro).into_owned();
        check_finite("q_target", &v)?;
        // (nq = 0, a robot without coordinates: nothing to write)
        targets = rows.into_iter().zip(v.chunks_exact(nq.max(1)).map(<[f64]>::to_vec)).collect::<Vec<_>>();
    }
    let states = match out {
        None => None,
        Some(o) => {
            let s = guards.first().map_or(0, |g| g.inner().state_len());
            if let Some(b) = guards.iter().position(|g| g.inner().state_len() != s) {
                let sb = guards[b].inner().state_len();
                return Err(bad(format!("out: worlds[{b}] has nstate = {sb}, worlds[0] {s}")));
            }
            let array = out_array(o, &[batch, s])?;
            // nothing to write when the worlds have no state (only fixed bodies)
            (s > 0).then_some((array, s))
        }
    };
    let nthread = nthread.unwrap_or_else(default_nthread);
    if nthread == 0 {
        return Err(bad("nthread: must be at least 1"));
    }
    let pool = pool(nthread)?;
    for (g, ((r, _), q)) in guards.iter_mut().zip(&targets) {
        g.inner_mut().robots[*r].control.q_target.copy_from_slice(q);
    }
    let mut engines: Vec<&mut tumble::World> = guards.iter_mut().map(|g| g.inner_mut()).collect();
    let mut done = vec![n; batch];
    let run = |w: &mut tumble::World, done: &mut u64| {
        if let Some(k) = (0..n).find(|_| w.step().is_err()) {
            *done = k;
        }
    };
    match &states {
        None => {
            py.detach(|| pool.install(|| engines.par_iter_mut().zip(done.par_iter_mut()).for_each(|(w, d)| run(w, d))))
        }
        Some((array, s)) => {
            let mut rw = array.try_readwrite().map_err(|e| bad(format!("out: {e}")))?;
            let slice = rw.as_slice_mut().map_err(|e| bad(format!("out: {e}")))?;
            py.detach(|| {
                pool.install(|| {
                    engines.par_iter_mut().zip(done.par_iter_mut()).zip(slice.par_chunks_mut(*s)).for_each(
                        |((w, d), row)| {
                            run(w, d);
                            // lengths match by construction
                            let _ = w.write_state(row);
                        },
                    )
                })
            });
        }
    }
    Ok(PyArray1::from_iter(py, done.iter().map(|&d| d as i64)))
}
