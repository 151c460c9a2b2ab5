//! `tumble.rnea`, `bias`, `crba`, `aba`: Pinocchio's functions on a model's robot, on float64 arrays.
//!
//! The robot is the model's (as placed in the scene: a fixed base's pose folded in, the scene's
//! gravity). Vectors are 1-D (`q` nq, `v`, `a`, `tau` nv); the results are new arrays. Each call
//! allocates its workspace (a few kB): fine at the µs scale of these functions from Python.

use crate::arrays::finite_vector;
use crate::bad;
use crate::model::Model;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use tumble::multibody::{aba as aba_fn, bias_forces, crba as crba_fn, rnea as rnea_fn, Workspace};

struct Args<'m> {
    model: &'m tumble::multibody::MultibodyModel,
    q: Vec<f64>,
    v: Vec<f64>,
}

fn args<'m>(
    m: &'m Model,
    robot: Option<&Bound<'_, PyAny>>,
    q: &Bound<'_, PyAny>,
    v: Option<&Bound<'_, PyAny>>,
) -> PyResult<Args<'m>> {
    let r = m.robot_index(robot)?;
    let model = &m.world.robots[r].model;
    let q = finite_vector(q, "q", model.nq(), "(nq,) joint positions")?;
    let v = match v {
        Some(v) => finite_vector(v, "v", model.nv(), "(nv,) joint velocities")?,
        None => Vec::new(),
    };
    Ok(Args { model, q, v })
}

/// Inverse dynamics `τ = M(q) a + C(q, v) v + g(q)` (nv) of the model's robot.
#[pyfunction]
#[pyo3(signature = (model, q, v, a, robot = None))]
pub fn rnea<'py>(
    py: Python<'py>,
    model: &Bound<'py, Model>,
    q: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
    a: &Bound<'py, PyAny>,
    robot: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let x = args(model.get(), robot, q, Some(v))?;
    let a = finite_vector(a, "a", x.model.nv(), "(nv,) joint accelerations")?;
    let mut tau = vec![0.0; x.model.nv()];
    rnea_fn(x.model, &mut Workspace::new(x.model), &x.q, &x.v, &a, &mut tau).map_err(|e| bad(e.to_string()))?;
    Ok(PyArray1::from_vec(py, tau))
}

/// Bias forces `C(q, v) v + g(q)` (nv): RNEA with zero acceleration.
#[pyfunction]
#[pyo3(signature = (model, q, v, robot = None))]
pub fn bias<'py>(
    py: Python<'py>,
    model: &Bound<'py, Model>,
    q: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
    robot: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let x = args(model.get(), robot, q, Some(v))?;
    let mut b = vec![0.0; x.model.nv()];
    bias_forces(x.model, &mut Workspace::new(x.model), &x.q, &x.v, &mut b).map_err(|e| bad(e.to_string()))?;
    Ok(PyArray1::from_vec(py, b))
}

/// The joint-space mass matrix `M(q)` (nv, nv), symmetric (both triangles filled).
#[pyfunction]
#[pyo3(signature = (model, q, robot = None))]
pub fn crba<'py>(
    py: Python<'py>,
    model: &Bound<'py, Model>,
    q: &Bound<'py, PyAny>,
    robot: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let x = args(model.get(), robot, q, None)?;
    let mut ws = Workspace::new(x.model);
    let m = crba_fn(x.model, &mut ws, &x.q).map_err(|e| bad(e.to_string()))?;
    let n = x.model.nv();
    let rows: Vec<Vec<f64>> = (0..n).map(|i| (0..n).map(|j| m[(i, j)]).collect()).collect();
    if n == 0 {
        return Ok(PyArray2::zeros(py, [0, 0], false));
    }
    PyArray2::from_vec2(py, &rows).map_err(|e| bad(e.to_string()))
}

/// Forward dynamics `a = M(q)⁻¹ (τ − C(q, v) v − g(q))` (nv) by the articulated-body algorithm.
#[pyfunction]
#[pyo3(signature = (model, q, v, tau, robot = None))]
pub fn aba<'py>(
    py: Python<'py>,
    model: &Bound<'py, Model>,
    q: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
    tau: &Bound<'py, PyAny>,
    robot: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let x = args(model.get(), robot, q, Some(v))?;
    let tau = finite_vector(tau, "tau", x.model.nv(), "(nv,) joint forces")?;
    let mut qdd = vec![0.0; x.model.nv()];
    aba_fn(x.model, &mut Workspace::new(x.model), &x.q, &x.v, &tau, &mut qdd).map_err(|e| bad(e.to_string()))?;
    Ok(PyArray1::from_vec(py, qdd))
}
