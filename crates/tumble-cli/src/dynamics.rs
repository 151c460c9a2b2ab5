//! `tumble dynamics ROBOT.urdf [--floating] --input IN.jsonl --out OUT.jsonl [--gravity GX GY GZ]`
//! and `tumble dynamics ROBOT.urdf [--floating] --bench`.
//!
//! Each input line `{"q": [..], "v": [..], "tau": [..]?, "a": [..]?}` gives one output line with
//! `"mass_matrix"` (CRBA, row by row), `"bias"` (RNEA with zero acceleration), `"qdd"` (ABA, when
//! `tau` is given) and `"tau"` (RNEA, when `a` is given). The model's joint damping and springs
//! (MJCF's `damping`, `stiffness`; none in URDF) act beside `tau`: `qdd = ABA(τ + τ_passive)`, and
//! the `tau` written is `M a + b − τ_passive`. An MJCF model's state is tumble's (`q = qpos − ref`
//! for hinges and slides, a free joint's linear velocity in the body frame: `docs/mjcf.md`). Bad input (a line that is not such an
//! object, wrong lengths, a quaternion that is not of unit length) stops with exit 2 naming the
//! line, and the output is not written.
//!
//! `--bench` times the three algorithms on random states (seeded): the states are swept ten times
//! in timed chunks of 20 consecutive calls, and the median chunk gives the time per call. Parsing
//! and I/O are outside the timed loops.

use crate::cli::DynamicsArgs;
use crate::error::{Failure, Status};
use crate::model::load_robot;
use crate::output::OutputFile;
use crate::report::Stdout;
use serde_json::{json, Map, Value};
use std::io::{BufWriter, Write};
use std::time::Instant;
use tumble::math::DVec3;
use tumble::multibody::{aba, add_passive_forces, bias_forces, crba, rnea, MultibodyModel, Workspace};

/// Input files larger than this are refused before reading (bytes).
const MAX_INPUT_BYTES: u64 = 512 << 20;

/// Runs `tumble dynamics`.
pub fn dynamics(args: &DynamicsArgs) -> Result<Status, Failure> {
    let mut model = load_robot(&args.robot)?;
    if let Some(g) = &args.gravity {
        if g.len() != 3 || g.iter().any(|x| !x.is_finite()) {
            return Err(Failure::bad_input(format!("--gravity: three finite numbers are needed (got {g:?})")));
        }
        model.gravity = DVec3::new(g[0], g[1], g[2]);
    }
    for w in &model.warnings {
        eprintln!("warning: {w}");
    }
    if args.bench {
        return bench(&model, args.bench_states);
    }
    let (Some(input), Some(out)) = (&args.input, &args.out) else {
        return Err(Failure::bad_input("--input and --out are required (or --bench)"));
    };
    if same_file(input, out) {
        return Err(Failure::bad_input(format!(
            "refusing to overwrite the input '{}' with the output",
            input.display()
        )));
    }
    let text = read_input(input)?;
    // compute everything first: bad input writes nothing
    let mut ws = Workspace::new(&model);
    let mut lines = Vec::new();
    for (index, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let at = |message: String| Failure::bad_input(format!("{}:{}: {message}", input.display(), index + 1));
        let result = evaluate(&model, &mut ws, line).map_err(at)?;
        lines.push(result);
    }
    let (output, file) =
        OutputFile::create(out).map_err(|e| Failure::output(format!("cannot write '{}': {e}", out.display())))?;
    let mut writer = BufWriter::new(file);
    let written = lines
        .iter()
        .try_for_each(|l| writeln!(writer, "{l}"))
        .and_then(|()| writer.flush())
        .and_then(|()| writer.get_ref().sync_all());
    drop(writer);
    match written {
        Ok(()) => output.commit().map_err(|e| Failure::output(format!("cannot write '{}': {e}", out.display())))?,
        Err(e) => {
            output.discard();
            return Err(Failure::output(format!("cannot write '{}': {e}", out.display())));
        }
    }
    Ok(Status::Success)
}

fn same_file(a: &std::path::Path, b: &std::path::Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

fn read_input(path: &std::path::Path) -> Result<String, Failure> {
    let cannot = |e: std::io::Error| Failure::bad_input(format!("cannot read '{}': {e}", path.display()));
    let meta = std::fs::metadata(path).map_err(cannot)?;
    if meta.is_dir() {
        return Err(Failure::bad_input(format!("cannot read '{}': it is a directory", path.display())));
    }
    if meta.len() > MAX_INPUT_BYTES {
        return Err(Failure::bad_input(format!(
            "'{}' is {} bytes, more than the limit of {MAX_INPUT_BYTES}",
            path.display(),
            meta.len()
        )));
    }
    std::fs::read_to_string(path).map_err(cannot)
}

/// A vector field of an input line, checked for length.
fn field(object: &Map<String, Value>, key: &str, len: usize) -> Result<Option<Vec<f64>>, String> {
    let Some(value) = object.get(key) else { return Ok(None) };
    let array = value.as_array().ok_or_else(|| format!("\"{key}\" must be an array of numbers"))?;
    let numbers: Option<Vec<f64>> = array.iter().map(Value::as_f64).collect();
    let numbers = numbers.ok_or_else(|| format!("\"{key}\" must be an array of numbers"))?;
    if numbers.len() != len {
        return Err(format!("\"{key}\" has {} numbers, the model needs {len}", numbers.len()));
    }
    Ok(Some(numbers))
}

/// The output object of one input line.
fn evaluate(model: &MultibodyModel, ws: &mut Workspace, line: &str) -> Result<Value, String> {
    let value: Value = serde_json::from_str(line).map_err(|e| format!("not JSON: {e}"))?;
    let object = value.as_object().ok_or("each line must be a JSON object")?;
    if let Some(key) = object.keys().find(|k| !["q", "v", "tau", "a"].contains(&k.as_str())) {
        return Err(format!("unknown key \"{key}\" (expected q, v, tau, a)"));
    }
    let (nq, nv) = (model.nq(), model.nv());
    let q = field(object, "q", nq)?.ok_or("\"q\" is required")?;
    let v = field(object, "v", nv)?.ok_or("\"v\" is required")?;
    check_quaternions(model, &q)?;
    let mut out = Map::new();
    let m = crba(model, ws, &q).map_err(|e| e.to_string())?;
    let rows: Vec<Vec<f64>> = (0..nv).map(|r| (0..nv).map(|c| m[(r, c)]).collect()).collect();
    out.insert("mass_matrix".into(), json!(rows));
    let mut result = vec![0.0; nv];
    bias_forces(model, ws, &q, &v, &mut result).map_err(|e| e.to_string())?;
    out.insert("bias".into(), finite("bias", &result)?);
    if let Some(mut tau) = field(object, "tau", nv)? {
        // the model's joint damping and springs act beside τ (none in URDF models)
        add_passive_forces(model, ws, &q, &v, &mut tau).map_err(|e| e.to_string())?;
        aba(model, ws, &q, &v, &tau, &mut result).map_err(|e| e.to_string())?;
        out.insert("qdd".into(), finite("qdd", &result)?);
    }
    if let Some(a) = field(object, "a", nv)? {
        rnea(model, ws, &q, &v, &a, &mut result).map_err(|e| e.to_string())?;
        // τ = M a + b − τ_passive: what must be applied beside the model's damping and springs
        let mut passive = vec![0.0; nv];
        add_passive_forces(model, ws, &q, &v, &mut passive).map_err(|e| e.to_string())?;
        for (t, p) in result.iter_mut().zip(&passive).filter(|(_, p)| **p != 0.0) {
            *t -= p;
        }
        out.insert("tau".into(), finite("tau", &result)?);
    }
    if rows.iter().flatten().any(|x| !x.is_finite()) {
        return Err("the mass matrix is not finite for this state".into());
    }
    Ok(Value::Object(out))
}

/// A result as JSON, refusing non-finite numbers (which JSON cannot hold).
fn finite(what: &str, x: &[f64]) -> Result<Value, String> {
    if x.iter().all(|v| v.is_finite()) {
        Ok(json!(x))
    } else {
        Err(format!("\"{what}\" is not finite for this state"))
    }
}

/// The quaternions of spherical and floating joints must have unit length (to 1e-6).
fn check_quaternions(model: &MultibodyModel, q: &[f64]) -> Result<(), String> {
    for (j, start) in tumble::multibody::simulate::quaternion_slots(model) {
        let norm = q[start..start + 4].iter().map(|x| x * x).sum::<f64>().sqrt();
        if (norm - 1.0).abs() > 1e-6 {
            return Err(format!(
                "joint '{}': the quaternion q[{}..{}] has norm {norm}, not 1",
                j.name,
                start,
                start + 4
            ));
        }
    }
    Ok(())
}

/// SplitMix64, for reproducible random states.
struct SplitMix(u64);

impl SplitMix {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        lo + (hi - lo) * ((z >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// A random configuration: angles and displacements in [−1, 1], unit quaternions.
fn random_q(model: &MultibodyModel, rng: &mut SplitMix) -> Vec<f64> {
    let mut q: Vec<f64> = (0..model.nq()).map(|_| rng.uniform(-1.0, 1.0)).collect();
    tumble::multibody::simulate::normalize_quaternions(model, &mut q);
    q
}

/// The median time per call of `f` (µs) over timed chunks of [`CHUNK`] consecutive states, after a
/// warm-up pass; the states are swept `passes` times. Short chunks (tens of µs) keep most timings
/// free of preemption on a busy machine, and the median discards the ones that are not.
fn median_time(states: usize, passes: usize, mut f: impl FnMut(usize)) -> f64 {
    for s in 0..states {
        f(s); // warm-up pass
    }
    let mut times = Vec::with_capacity(passes * states.div_ceil(CHUNK));
    for _ in 0..passes {
        for start in (0..states).step_by(CHUNK) {
            let end = (start + CHUNK).min(states);
            let clock = Instant::now();
            for s in start..end {
                f(s);
            }
            times.push(clock.elapsed().as_secs_f64() * 1e6 / (end - start) as f64);
        }
    }
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// States per timed chunk of [`median_time`].
const CHUNK: usize = 20;

/// Prints `{"nv", "rnea_us", "crba_us", "aba_us"}`.
fn bench(model: &MultibodyModel, states: usize) -> Result<Status, Failure> {
    if states == 0 {
        return Err(Failure::bad_input("--bench-states must be at least 1"));
    }
    let nv = model.nv();
    let mut rng = SplitMix(0x7475_6d62_6c65);
    let qs: Vec<Vec<f64>> = (0..states).map(|_| random_q(model, &mut rng)).collect();
    let vs: Vec<Vec<f64>> = (0..states).map(|_| (0..nv).map(|_| rng.uniform(-1.0, 1.0)).collect()).collect();
    let taus: Vec<Vec<f64>> = (0..states).map(|_| (0..nv).map(|_| rng.uniform(-1.0, 1.0)).collect()).collect();
    let mut ws = Workspace::new(model);
    let mut out = vec![0.0; nv];
    let passes = 10;
    // any error shows on the first call; the timed loops then cannot fail
    rnea(model, &mut ws, &qs[0], &vs[0], &taus[0], &mut out).map_err(Failure::bad_input)?;
    crba(model, &mut ws, &qs[0]).map_err(Failure::bad_input)?;
    aba(model, &mut ws, &qs[0], &vs[0], &taus[0], &mut out).map_err(Failure::bad_input)?;
    let mut checksum = 0.0;
    let rnea_us = median_time(states, passes, |s| {
        let _ = rnea(model, &mut ws, &qs[s], &vs[s], &taus[s], &mut out);
        checksum += out.first().copied().unwrap_or(0.0);
    });
    let crba_us = median_time(states, passes, |s| {
        if let Ok(m) = crba(model, &mut ws, &qs[s]) {
            checksum += m.iter().next().copied().unwrap_or(0.0);
        }
    });
    let aba_us = median_time(states, passes, |s| {
        let _ = aba(model, &mut ws, &qs[s], &vs[s], &taus[s], &mut out);
        checksum += out.first().copied().unwrap_or(0.0);
    });
    std::hint::black_box(checksum);
    let text = format!("{}\n", json!({"nv": nv, "rnea_us": rnea_us, "crba_us": crba_us, "aba_us": aba_us}));
    Stdout::default().write(&text).map_err(|e| Failure::output(format!("cannot write to standard output: {e}")))?;
    Ok(Status::Success)
}
