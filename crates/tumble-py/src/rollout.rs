//! `tumble.rollout`: many simulations of one model, one per row, on a thread pool.
//!
//! Each row is exactly what a `World` does when stepped from Python: a clone of the model's world at
//! `t = 0`, `set_state(x0[b])`, then per step the row's controls added to the scene's joint forces
//! (`set_torque`), one `step()` and the state written out. Rows share nothing, so the numbers do not
//! depend on the thread count or on how the rows are split (between threads, calls or machines).
//!
//! A row that diverges stops there: its remaining states are NaN and its status (steps done) is
//! below `nstep`; the other rows run on.
//!
//! Threads: `nthread`, else `OMP_NUM_THREADS` (what Ray and batch schedulers set per task), else the
//! machine's cores. Pools are built once per size and kept. The GIL is released for the whole batch;
//! a row allocates once (its world), never per step.

use crate::arrays::{check_finite, check_shape, f64_array, out_array, values};
use crate::bad;
use crate::model::{Model, RobotInfo};
use crate::world::{apply_torque, check_rows};
use numpy::{PyArray1, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use rayon::prelude::*;
use std::sync::{Arc, Mutex};

/// The thread pools built so far, by size.
static POOLS: Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>> = Mutex::new(Vec::new());

pub(crate) fn pool(nthread: usize) -> PyResult<Arc<rayon::ThreadPool>> {
    let mut pools = POOLS.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, p)) = pools.iter().find(|(n, _)| *n == nthread) {
        return Ok(p.clone());
    }
    let built = rayon::ThreadPoolBuilder::new()
        .num_threads(nthread)
        .thread_name(|i| format!("tumble-rollout-{i}"))
        .build()
        .map_err(|e| bad(format!("cannot start {nthread} threads: {e}")))?;
    let built = Arc::new(built);
    pools.push((nthread, built.clone()));
    Ok(built)
}

/// The thread count used when `nthread` is not given: `OMP_NUM_THREADS` when set to a positive
/// integer (Ray sets it to a task's CPUs), else the number of cores.
#[pyfunction]
pub fn default_nthread() -> usize {
    std::env::var("OMP_NUM_THREADS")
        .ok()
        .and_then(|s| s.trim().parse::<usize>().ok())
        .filter(|&n| n > 0)
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}

/// Steps one row: `x0` (nstate), `control` (nstep · nu) or none, into `out` (nstep · nstate).
/// Returns the number of steps done (`nstep` unless the row diverged; then the rest is NaN).
fn run_row(model: &Model, x0: &[f64], control: Option<&[f64]>, nstep: usize, out: &mut [f64]) -> (u64, Option<String>) {
    let mut world = model.world.clone();
    if let Err(e) = world.set_state(x0) {
        out.fill(f64::NAN);
        return (0, Some(e.to_string())); // the rows were checked before: not reached
    }
    let s = x0.len();
    let nu = model.nu();
    for t in 0..nstep {
        if let Some(u) = control {
            apply_controls(&mut world, &model.robots, &u[t * nu..(t + 1) * nu]);
        }
        if let Err(e) = world.step() {
            out[t * s..].fill(f64::NAN);
            return (t as u64, Some(e.to_string()));
        }
        // lengths match by construction
        let _ = world.write_state(&mut out[t * s..(t + 1) * s]);
    }
    (nstep as u64, None)
}

/// Each robot's slice of one step's controls `u` (nu), added to its scene torques.
fn apply_controls(world: &mut tumble::World, robots: &[RobotInfo], u: &[f64]) {
    let mut k = 0;
    for (r, info) in robots.iter().enumerate() {
        apply_torque(world, &info.base_tau, r, &u[k..k + info.nv]);
        k += info.nv;
    }
}

/// Simulates a batch: `x0` (B, nstate) initial states → the state after every step,
/// (B, nstep, nstate). `control` (B, nstep, nu): robot joint forces per step (robot order), added
/// to the scene's. `nthread`: threads (default `default_nthread()`). `out`: write there instead of
/// allocating. `return_status`: also return the steps each row completed (B,) int64, below `nstep`
/// for a row that diverged (its later states are NaN). The GIL is released while it runs.
#[pyfunction]
#[pyo3(signature = (model, x0, nstep, control = None, nthread = None, *, out = None, return_status = false))]
#[allow(clippy::too_many_arguments)]
pub fn rollout<'py>(
    py: Python<'py>,
    model: Bound<'py, Model>,
    x0: &Bound<'py, PyAny>,
    nstep: usize,
    control: Option<&Bound<'py, PyAny>>,
    nthread: Option<usize>,
    out: Option<&Bound<'py, PyAny>>,
    return_status: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let m = model.get();
    let s = m.world.state_len();
    let nu = m.nu();
    let x0 = f64_array(x0, "x0")?;
    check_shape("x0", x0.shape(), &[None, Some(s)], "(B, nstate)")?;
    let batch = x0.shape()[0];
    let x0 = x0.try_readonly().map_err(|e| bad(format!("x0: {e}")))?;
    let x0 = values(&x0);
    check_rows(&mut m.world.clone(), &x0, s)?;
    let control = match control {
        None => None,
        Some(c) => {
            let c = f64_array(c, "control")?;
            check_shape("control", c.shape(), &[Some(batch), Some(nstep), Some(nu)], "(B, nstep, nu)")?;
            Some(c.try_readonly().map_err(|e| bad(format!("control: {e}")))?)
        }
    };
    let control = control.as_ref().map(values);
    if let Some(c) = &control {
        check_finite("control", c)?;
    }
    let nthread = nthread.unwrap_or_else(default_nthread);
    if nthread == 0 {
        return Err(bad("nthread: must be at least 1"));
    }
    let pool = pool(nthread)?;
    let states = match out {
        Some(o) => out_array(o, &[batch, nstep, s])?,
        None => PyArrayDyn::<f64>::zeros(py, numpy::IxDyn(&[batch, nstep, s]), false),
    };
    let mut done = vec![nstep as u64; batch];
    {
        let mut rw = states.try_readwrite().map_err(|e| bad(format!("out: {e}")))?;
        let out_slice = rw.as_slice_mut().map_err(|e| bad(format!("out: {e}")))?;
        let row_len = nstep * s;
        let x0 = &x0[..];
        let control = control.as_deref();
        if row_len > 0 {
            py.detach(|| {
                pool.install(|| {
                    out_slice.par_chunks_mut(row_len).zip(done.par_iter_mut()).enumerate().for_each(
                        |(b, (row, done))| {
                            let u = control.map(|c| &c[b * nstep * nu..(b + 1) * nstep * nu]);
                            *done = run_row(m, &x0[b * s..(b + 1) * s], u, nstep, row).0;
                        },
                    )
                })
            });
        }
    }
    if return_status {
        let status = PyArray1::from_iter(py, done.iter().map(|&d| d as i64));
        Ok((states, status).into_pyobject(py)?.into_any())
    } else {
        Ok(states.into_any())
    }
}
