//! `tumble model ROBOT.urdf [--floating] [--json]`: the joint layout of a robot.

use crate::cli::{ModelArgs, RobotArgs};
use crate::error::{Failure, Status};
use crate::report::Stdout;
use serde_json::{json, Value};
use tumble::multibody::{load_urdf, ChildOrder, FrameOrigin, Massless, MultibodyModel, UrdfOptions};

/// Loads the robot named on the command line (exit 2 with the reader's message).
pub fn load_robot(args: &RobotArgs) -> Result<MultibodyModel, Failure> {
    let order = if args.joint_order == "name" { ChildOrder::JointName } else { ChildOrder::File };
    load_urdf(
        &args.urdf,
        UrdfOptions {
            floating: args.floating,
            order,
            balance_inertia: args.balance_inertia,
            massless: if args.massless == "fuse" { Massless::Fuse } else { Massless::Error },
            ..UrdfOptions::default()
        },
    )
    .map_err(Failure::bad_input)
}

/// The layout as JSON: movable joints with their coordinates, fixed joints with `null` indices.
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
    json!({
        "name": model.name, "nq": model.nq(), "nv": model.nv(), "total_mass": model.total_mass, "joints": joints,
    })
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
    let meshes = model.meshes();
    if !meshes.is_empty() {
        let resolved = meshes.iter().filter(|m| m.path.is_some()).count();
        text.push_str(&format!("meshes: {} named, {resolved} resolved (not needed for dynamics)\n", meshes.len()));
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
