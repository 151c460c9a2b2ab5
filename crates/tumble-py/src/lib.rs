//! `tumble` for Python: the extension module `tumble._tumble`, re-exported by the pure-Python
//! package `tumble` (`python/tumble/__init__.py`). The Python API is the contract of
//! `docs/python.md`; the stubs in `python/tumble/_tumble.pyi` describe every name defined here.
//!
//! - [`model`]: `Model`, an immutable scene (frozen, `Sync`, picklable through its scene text);
//! - [`world`]: `World`, the mutable state of one simulation (stepping releases the GIL);
//! - [`rollout`]: batched rollouts on a thread pool sized per call;
//! - [`step_worlds`]: many `World`s stepped in one call (with PD targets), the GIL released;
//! - [`dynamics`]: `rnea`, `crba`, `aba`, `bias` on numpy arrays;
//! - [`arrays`]: checked conversions between numpy arrays and slices (float64 only, no silent casts).

use pyo3::prelude::*;

mod arrays;
mod dynamics;
mod model;
mod rollout;
mod step_worlds;
mod world;

pyo3::create_exception!(
    tumble,
    TumbleError,
    pyo3::exceptions::PyValueError,
    "Bad input to tumble (a scene, a file, an array), or a simulation that diverged; the message names the problem."
);
pyo3::create_exception!(
    tumble,
    DivergedError,
    TumbleError,
    "A step produced a non-finite or absurd state; the world is left at its last finite state. \
The message names the body or robot, the quantity, the step and the time."
);

/// A `TumbleError` with this message.
pub(crate) fn bad(message: impl Into<String>) -> PyErr {
    TumbleError::new_err(message.into())
}

#[pymodule]
fn _tumble(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("TumbleError", py.get_type::<TumbleError>())?;
    m.add("DivergedError", py.get_type::<DivergedError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<model::Model>()?;
    m.add_class::<world::World>()?;
    m.add_function(wrap_pyfunction!(rollout::rollout, m)?)?;
    m.add_function(wrap_pyfunction!(rollout::default_nthread, m)?)?;
    m.add_function(wrap_pyfunction!(step_worlds::step_worlds, m)?)?;
    m.add_function(wrap_pyfunction!(dynamics::rnea, m)?)?;
    m.add_function(wrap_pyfunction!(dynamics::bias, m)?)?;
    m.add_function(wrap_pyfunction!(dynamics::crba, m)?)?;
    m.add_function(wrap_pyfunction!(dynamics::aba, m)?)?;
    Ok(())
}
