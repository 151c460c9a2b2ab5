//! `tumble model ROBOT.urdf [--floating] [--json]`: the joint layout of a robot (URDF, or MJCF for
//! a `.xml` file: each MJCF joint a joint of its own, a body with several joints split into one
//! body per joint, named `BODY/JOINT` but for the last).

use crate::cli::{ModelArgs, RobotArgs};
use crate::error::{Failure, Status};
use crate::report::Stdout;
use serde_json::{json, Value};
use tumble::multibody::mjcf::{load_mjcf, MjcfOptions};
use tumble::multibody::{
    load_urdf, reduced_model, ChildOrder, FrameOrigin, LockError, Massless, MultibodyModel, UrdfOptions,
};

/// Loads the robot named on the command line (exit 2 with the reader's message), reduced by
/// `--lock` when it is given.
pub fn load_robot(args: &RobotArgs) -> Result<MultibodyModel, Failure> {
    if is_mjcf(&args.urdf) {
        let urdf_only = [
            ("--floating", args.floating),
            ("--joint-order name", args.joint_order == "name"),
            ("--balance-inertia", args.balance_inertia),
            ("--massless fuse", args.massless == "fuse"),
        ];
        if let Some((flag, _)) = urdf_only.iter().find(|(_, on)| *on) {
            return Err(Failure::bad_input(format!(
                "{flag} applies to URDF files; {} is MJCF (its free joints and joint order are its own)",
                args.urdf.display()
            )));
        }
        let options = MjcfOptions { drop_frictionloss: args.drop_frictionloss };
        let model = load_mjcf(&args.urdf, options).map_err(Failure::bad_input)?.model;
        return if args.lock.is_empty() { Ok(model) } else { lock(&model, &args.lock) };
    }
    if args.drop_frictionloss {
        return Err(Failure::bad_input("--drop-frictionloss applies to MJCF files"));
    }
    let order = if args.joint_order == "name" { ChildOrder::JointName } else { ChildOrder::File };
    let massless = match (args.massless.as_str(), args.lock.is_empty()) {
        ("fuse", _) => Massless::Fuse,
        // with `--lock`, massless joints are allowed until the model is reduced (then checked)
        (_, false) => Massless::Allow,
        (_, true) => Massless::Error,
    };
    let model = load_urdf(
        &args.urdf,
        UrdfOptions {
            floating: args.floating,
            order,
            balance_inertia: args.balance_inertia,
            massless,
            ..UrdfOptions::default()
        },
    )
    .map_err(Failure::bad_input)?;
    if args.lock.is_empty() {
        return Ok(model);
    }
    lock(&model, &args.lock)
}

/// An MJCF file: `.xml` or `.mjcf` (URDF files end in `.urdf`).
pub fn is_mjcf(path: &std::path::Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("xml") || e.eq_ignore_ascii_case("mjcf"))
}

/// `--lock NAME[=VALUE],…`: the model with those joints held at `VALUE` (0 when omitted), every
/// other joint at its neutral value for the reduction (only the locked ones' values matter).
fn lock(model: &MultibodyModel, entries: &[String]) -> Result<MultibodyModel, Failure> {
    let movable: Vec<&str> = model.bodies.iter().map(|b| b.joint.name.as_str()).collect();
    let mut q_full = model.neutral_configuration();
    let mut names: Vec<&str> = Vec::with_capacity(entries.len());
    for entry in entries {
        let (name, value) = match entry.split_once('=') {
            Some((name, value)) => (name.trim(), Some(value.trim())),
            None => (entry.trim(), None),
        };
        let Some(j) = model.joint_index(name) else {
            let fixed =
                model.frames.iter().any(|f| matches!(&f.origin, FrameOrigin::Fixed { joint, .. } if joint == name));
            return Err(Failure::bad_input(if fixed {
                format!("--lock: joint `{name}` is fixed already: there is nothing to lock")
            } else {
                format!("--lock: unknown joint `{name}` (movable joints: {})", movable.join(", "))
            }));
        };
        let joint = &model.bodies[j].joint;
        if let Some(text) = value {
            let x: f64 = text.parse().ok().filter(|x: &f64| x.is_finite()).ok_or_else(|| {
                Failure::bad_input(format!(
                    "--lock {entry}: the value must be a finite number (rad or m), got `{text}`"
                ))
            })?;
            if joint.kind.nq() != 1 {
                return Err(Failure::bad_input(format!(
                    "--lock {entry}: a {} joint has {} coordinates; lock it without a value (held at its neutral \
                     configuration)",
                    joint.kind.name(),
                    joint.kind.nq()
                )));
            }
            q_full[joint.q_index] = x;
        }
        names.push(name);
    }
    reduced_model(model, &names, &q_full).map_err(|e| match &e {
        LockError::Massless { joints } => Failure::bad_input(format!(
            "--lock: {e}; lock them too: --lock {}",
            names.iter().copied().chain(joints.iter().map(String::as_str)).collect::<Vec<_>>().join(",")
        )),
        _ => Failure::bad_input(format!("--lock: {e}")),
    })
}

/// The layout as JSON: movable joints with their coordinates, fixed joints with `null` indices,
/// and the fixed tendons (`L = offset + Σ coef q[q_index]`) when there are any.
pub fn layout(model: &MultibodyModel) -> Value {
    let mut joints = Vec::new();
    for frame in &model.frames {
        match &frame.origin {
            FrameOrigin::Root => {}
            FrameOrigin::Body(b) => {
                let j = &model.bodies[*b].joint;
                joints.push(json!({
                    "name": j.name, "type": j.kind.name(), "parent": j.parent_link, "child": frame.name,
                    "q_index": j.q_index, "v_index": j.v_index, "nq": j.kind.nq(), "nv": j.kind.nv(),
                }));
            }
            FrameOrigin::Fixed { joint, parent_link } => joints.push(json!({
                "name": joint, "type": "fixed", "parent": parent_link, "child": frame.name,
                "q_index": null, "v_index": null, "nq": 0, "nv": 0,
            })),
        }
    }
    let mut layout = json!({
        "name": model.name, "nq": model.nq(), "nv": model.nv(), "total_mass": model.total_mass, "joints": joints,
    });
    if !model.locked.is_empty() {
        let locked: Vec<Value> = model.locked.iter().map(|(name, q)| json!({"name": name, "q": q})).collect();
        layout["locked"] = Value::Array(locked);
    }
    if !model.tendons.is_empty() {
        // L = offset + Σ coef q[q_index]
        let tendons: Vec<Value> = model
            .tendons
            .iter()
            .map(|t| {
                let terms: Vec<Value> = t
                    .terms
                    .iter()
                    .map(|term| {
                        json!({"joint": model.bodies[term.body].joint.name, "q_index": term.q_index,
                               "v_index": term.v_index, "coef": term.coef})
                    })
                    .collect();
                json!({
                    "name": t.name, "offset": t.offset, "terms": terms, "stiffness": t.stiffness,
                    "spring_length": [t.spring_length.0, t.spring_length.1], "damping": t.damping,
                    "range": t.range.map(|(lo, hi)| [lo, hi]),
                })
            })
            .collect();
        layout["tendons"] = Value::Array(tendons);
    }
    layout
}

fn table(model: &MultibodyModel, layout: &Value) -> String {
    let mut text = format!(
        "robot '{}': nq = {}, nv = {}, total mass {} kg, {} base\n",
        model.name,
        model.nq(),
        model.nv(),
        model.total_mass,
        if model.bodies.first().is_some_and(|b| b.joint.kind.name() == "floating") { "floating" } else { "fixed" },
    );
    let rows: Vec<[String; 6]> = layout["joints"]
        .as_array()
        .map(|a| a.as_slice())
        .unwrap_or(&[])
        .iter()
        .map(|j| {
            let index = |k: &str| j[k].as_u64().map_or("-".to_string(), |i| i.to_string());
            [
                j["name"].as_str().unwrap_or("").to_string(),
                j["type"].as_str().unwrap_or("").to_string(),
                format!("{} → {}", j["parent"].as_str().unwrap_or(""), j["child"].as_str().unwrap_or("")),
                index("q_index"),
                index("v_index"),
                format!("{}/{}", j["nq"], j["nv"]),
            ]
        })
        .collect();
    let header = ["joint", "type", "parent → child", "q", "v", "nq/nv"];
    let mut widths: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for r in &rows {
        for (w, c) in widths.iter_mut().zip(r) {
            *w = (*w).max(c.chars().count());
        }
    }
    let line = |cells: &[String]| -> String {
        let mut l = String::new();
        for (c, w) in cells.iter().zip(&widths) {
            l.push_str(c);
            l.push_str(&" ".repeat(w - c.chars().count() + 2));
        }
        l.trim_end().to_string() + "\n"
    };
    text.push_str(&line(&header.map(String::from)));
    for r in &rows {
        text.push_str(&line(r));
    }
    if !model.locked.is_empty() {
        let list: Vec<String> = model.locked.iter().map(|(name, q)| format!("{name} at {q:?}")).collect();
        text.push_str(&format!("locked: {}\n", list.join(", ")));
    }
    let meshes = model.meshes();
    if !meshes.is_empty() {
        let resolved = meshes.iter().filter(|m| m.path.is_some()).count();
        text.push_str(&format!("meshes: {} named, {resolved} resolved (not needed for dynamics)\n", meshes.len()));
    }
    for t in &model.tendons {
        // L = L₀ + Σ c q, and what acts along it
        let terms: Vec<String> =
            t.terms.iter().map(|term| format!("{} {}", term.coef, model.bodies[term.body].joint.name)).collect();
        let mut acts = Vec::new();
        if t.stiffness != 0.0 {
            acts.push(format!("stiffness {} to {}..{}", t.stiffness, t.spring_length.0, t.spring_length.1));
        }
        if t.damping != 0.0 {
            acts.push(format!("damping {}", t.damping));
        }
        if let Some((lo, hi)) = t.range {
            acts.push(format!("limited to {lo}..{hi}"));
        }
        text.push_str(&format!(
            "tendon {}: L = {} + {}{}\n",
            t.name,
            t.offset,
            terms.join(" + "),
            if acts.is_empty() { String::new() } else { format!("; {}", acts.join(", ")) }
        ));
    }
    for w in &model.warnings {
        text.push_str(&format!("warning: {w}\n"));
    }
    text
}

/// Prints the layout (a table, or JSON with `--json`); exit 0, or 2 with the reader's message.
pub fn model(args: &ModelArgs) -> Result<Status, Failure> {
    let model = load_robot(&args.robot)?;
    let layout = layout(&model);
    let text = if args.json {
        for w in &model.warnings {
            eprintln!("warning: {w}");
        }
        format!("{layout}\n")
    } else {
        table(&model, &layout)
    };
    Stdout::default().write(&text).map_err(|e| Failure::output(format!("cannot write to standard output: {e}")))?;
    Ok(Status::Success)
}
