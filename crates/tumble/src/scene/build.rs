//! The parsed document → a validated [`Scene`]: the version, `[world]`, unique names, the bodies
//! and the grids.

use super::body::BodyReader;
use super::error::{names_hint, nearest, num, nums, SceneError, Source};
use super::grid;
use super::schema::{Loc, SceneDoc, Table, WorldDoc};
use super::{Format, Scene};
use crate::integrate::{Integrator, Tolerances};
use crate::math::DVec3;
use crate::world::{World, WorldConfig};
use std::collections::HashMap;
use std::ops::Range;

/// The only format version this build reads.
pub const VERSION: i64 = 1;

/// A time step above this (s) is accepted with a warning: few rigid-body motions are resolved by it.
pub const LARGE_DT: f64 = 0.1;

pub(crate) fn build(src: &Source, doc: SceneDoc) -> Result<Scene, SceneError> {
    let mut warnings = Vec::new();
    let origin = src.origin.to_string();
    if doc.is_empty() {
        warnings.push(src.warning(None, "", "the file is empty: a default world with no bodies"));
        return Ok(Scene { world: World::new(WorldConfig::default(), Vec::new()), origin, warnings });
    }
    check_version(src, &doc)?;
    let config = world_config(src, doc.world.as_ref(), &mut warnings)?;
    let total = grid::total_bodies(src, &doc)?;
    let mut bodies = Vec::with_capacity(total);

    // name → (path, span) of the body that took it; `order` keeps the file's order for messages
    let mut names: HashMap<String, (String, Option<Range<usize>>)> = HashMap::with_capacity(doc.body.len());
    let mut order: Vec<String> = Vec::with_capacity(doc.body.len());
    let gravity = config.gravity;
    for (i, entry) in doc.body.iter().enumerate() {
        let path = format!("body[{i}]");
        let name = body_name(src, &path, entry)?;
        if let Some((first_path, first_span)) = names.get(&name.value) {
            return Err(duplicate(src, &path, name, first_path, first_span.as_ref()));
        }
        names.insert(name.value.clone(), (format!("{path}.name"), name.span.clone()));
        order.push(name.value.clone());
        let mut reader = BodyReader { src, path: &path, span: entry.span.as_ref(), warnings: &mut warnings, gravity };
        bodies.push(reader.read(&entry.value, name.value.clone())?);
    }

    let mut prefixes: HashMap<String, (String, Option<Range<usize>>)> = HashMap::new();
    for (g, entry) in doc.grid.iter().enumerate() {
        let prefix = grid::expand(src, g, entry, &mut warnings, &mut bodies, config.gravity)?;
        let name_loc = entry.value.body.value.name.as_ref();
        let span = name_loc.and_then(|l| l.span.clone());
        let path = format!("grid[{g}].body.name");
        if let Some((first_path, first_span)) = prefixes.get(&prefix) {
            let here = Loc { value: prefix.clone(), span: span.clone() };
            return Err(duplicate(src, &format!("grid[{g}].body"), &here, first_path, first_span.as_ref())
                .hint("two grids with the same template name would both name a copy `name_0_0_0`"));
        }
        // an explicit body named like one of the copies
        for name in &order {
            if let Some([i, j, k]) = grid::copy_index(name, &prefix, entry.value.count.value) {
                let Some((first_path, first_span)) = names.get(name) else { continue };
                let here = Loc { value: name.clone(), span: span.clone() };
                return Err(duplicate(src, &format!("grid[{g}].body"), &here, first_path, first_span.as_ref())
                    .hint(format!("copy ({i}, {j}, {k}) of grid[{g}] is named `{name}`")));
            }
        }
        prefixes.insert(prefix, (path, span));
    }

    let (robots, filters) = super::robot::read_robots(src, &doc.robot, &mut names, config.gravity, &mut warnings)?;
    if bodies.is_empty() && robots.is_empty() {
        warnings.push(src.warning(None, "", "the scene has no bodies"));
    }
    let mut world = World::new(config, bodies);
    world.robots = robots;
    super::robot::robot_collisions(src, &doc.robot, &filters, &mut world, &mut warnings)?;
    collision_filters(src, &doc, &mut world)?;
    overlap_warnings(src, &doc, &mut world, &mut warnings)?;
    Ok(Scene { world, origin, warnings })
}

fn check_version(src: &Source, doc: &SceneDoc) -> Result<(), SceneError> {
    match &doc.version {
        None => {
            let at = (src.format == Format::Toml).then_some(0..0);
            Err(src
                .error(at.as_ref(), "version", "missing: the format version is required")
                .hint(format!("start the file with `version = {VERSION}`")))
        }
        Some(v) if v.value != VERSION => Err(src
            .error(v.span.as_ref(), "version", format!("unsupported version: this tumble reads version {VERSION}"))
            .got(v.value.to_string())),
        Some(_) => Ok(()),
    }
}

fn body_name<'d>(
    src: &Source,
    path: &str,
    entry: &'d Loc<Table<super::schema::BodyDoc>>,
) -> Result<&'d Loc<String>, SceneError> {
    match &entry.value.name {
        Some(n) if !n.value.trim().is_empty() => Ok(n),
        Some(n) => {
            Err(src.error(n.span.as_ref(), format!("{path}.name"), "must not be empty").got(format!("{:?}", n.value)))
        }
        None => Err(src
            .error(entry.span.as_ref(), format!("{path}.name"), "missing: every body needs a unique name")
            .hint(format!("e.g. `name = \"body{}\"`", path.trim_start_matches("body[").trim_end_matches(']')))),
    }
}

pub(crate) fn duplicate(
    src: &Source,
    path: &str,
    name: &Loc<String>,
    first_path: &str,
    first_span: Option<&Range<usize>>,
) -> SceneError {
    let first = match first_span {
        Some(s) => {
            let p = src.line_col(s.start);
            format!("{first_path} at {}:{}:{}", src.origin, p.line, p.column)
        }
        None => first_path.to_string(),
    };
    src.error(name.span.as_ref(), format!("{path}.name"), format!("duplicate name: already used by {first}"))
        .got(format!("\"{}\"", name.value))
}

/// `[world]` → a validated [`WorldConfig`]; missing keys take `WorldConfig::default()`.
fn world_config(
    src: &Source,
    doc: Option<&Loc<Table<WorldDoc>>>,
    warnings: &mut Vec<String>,
) -> Result<WorldConfig, SceneError> {
    let mut config = WorldConfig::default();
    let Some(table) = doc else { return Ok(config) };
    let w = &table.value;
    let finite = |key: &str, l: &Loc<f64>| -> Result<f64, SceneError> {
        if l.value.is_finite() {
            Ok(l.value)
        } else {
            Err(src.error(l.span.as_ref(), format!("world.{key}"), "must be finite").got(num(l.value)))
        }
    };
    if let Some(g) = &w.gravity {
        if g.value.iter().any(|x| !x.is_finite()) {
            return Err(src.error(g.span.as_ref(), "world.gravity", "must be finite").got(nums(&g.value)));
        }
        config.gravity = DVec3::from_array(g.value);
    }
    if let Some(l) = &w.dt {
        config.dt = finite("dt", l)?;
    }
    if let Some(l) = &w.duration {
        config.duration = finite("duration", l)?;
    }
    let mut tolerances = Tolerances::default();
    if let Some(l) = &w.rtol {
        tolerances.rtol = finite("rtol", l)?;
    }
    if let Some(l) = &w.atol {
        tolerances.atol = finite("atol", l)?;
    }
    config.tolerances = tolerances;
    if let Some(l) = &w.sample_every {
        config.sample_every = l.value;
    }
    if let Some(l) = &w.threads {
        config.threads = usize::try_from(l.value).map_err(|_| {
            src.error(l.span.as_ref(), "world.threads", "must be an integer ≥ 0 (0: one thread per core)")
                .got(l.value.to_string())
        })?;
    }
    contact_settings(src, w, &mut config)?;
    if let Some(l) = &w.integrator {
        config.integrator = l.value.parse::<Integrator>().map_err(|_| {
            let names: Vec<&str> = Integrator::ALL.iter().map(|i| i.name()).collect();
            let e = src
                .error(
                    l.span.as_ref(),
                    "world.integrator",
                    format!("unknown integrator (expected one of: {})", Integrator::names()),
                )
                .got(format!("\"{}\"", l.value));
            match nearest(&l.value, &names) {
                Some(best) => e.hint(format!("did you mean `{best}`?")),
                None => e,
            }
        })?;
    }
    config.validate().map_err(|e| {
        let span = |l: Option<Range<usize>>| l.or_else(|| table.span.clone());
        let at = match e.field {
            "gravity" => span(w.gravity.as_ref().and_then(|l| l.span.clone())),
            "dt" => span(w.dt.as_ref().and_then(|l| l.span.clone())),
            // the step cap concerns duration/dt: point at whichever was given
            "duration" => span(w.duration.as_ref().or(w.dt.as_ref()).and_then(|l| l.span.clone())),
            "rtol" => span(w.rtol.as_ref().and_then(|l| l.span.clone())),
            "atol" => span(w.atol.as_ref().and_then(|l| l.span.clone())),
            "sample_every" => span(w.sample_every.as_ref().and_then(|l| l.span.clone())),
            "threads" => span(w.threads.as_ref().and_then(|l| l.span.clone())),
            "restitution" => span(w.restitution.as_ref().and_then(|l| l.span.clone())),
            "friction" => span(w.friction.as_ref().and_then(|l| l.span.clone())),
            "impact_speed" => span(w.impact_speed.as_ref().and_then(|l| l.span.clone())),
            "slop" => span(w.contact_slop.as_ref().and_then(|l| l.span.clone())),
            "contact_hertz" => span(w.contact_hertz.as_ref().and_then(|l| l.span.clone())),
            "contact_damping_ratio" => span(w.contact_damping_ratio.as_ref().and_then(|l| l.span.clone())),
            "contact_substeps" => span(w.contact_substeps.as_ref().and_then(|l| l.span.clone())),
            "max_correction_speed" => span(w.max_correction_speed.as_ref().and_then(|l| l.span.clone())),
            "contact_iterations" => span(w.contact_iterations.as_ref().and_then(|l| l.span.clone())),
            "sleep_speed" => span(w.sleep_speed.as_ref().and_then(|l| l.span.clone())),
            "sleep_time" => span(w.sleep_time.as_ref().and_then(|l| l.span.clone())),
            "max_pairs" => span(w.max_pairs.as_ref().and_then(|l| l.span.clone())),
            "manifold_reuse" => span(w.manifold_reuse.as_ref().and_then(|l| l.span.clone())),
            _ => table.span.clone(),
        };
        let field = if e.field == "slop" { "contact_slop" } else { e.field };
        src.error(at.as_ref(), format!("world.{field}"), e.problem).got(e.value)
    })?;
    if config.dt > LARGE_DT {
        let span = w.dt.as_ref().and_then(|l| l.span.as_ref());
        let text = format!("dt = {} s is larger than {LARGE_DT} s: fast rotations will not be resolved", config.dt);
        warnings.push(src.warning(span, "world.dt", &text));
    }
    Ok(config)
}

/// The contact keys of `[world]` → `config.contact` (ranges are checked by `WorldConfig::validate`).
fn contact_settings(src: &Source, w: &WorldDoc, config: &mut WorldConfig) -> Result<(), SceneError> {
    use crate::contact::{FrictionModel, RestitutionLaw};
    let finite = |key: &str, l: &Loc<f64>| -> Result<f64, SceneError> {
        if l.value.is_finite() {
            Ok(l.value)
        } else {
            Err(src.error(l.span.as_ref(), format!("world.{key}"), "must be finite").got(num(l.value)))
        }
    };
    let c = &mut config.contact;
    if let Some(l) = &w.contacts {
        c.enabled = l.value;
    }
    if let Some(l) = &w.sleep {
        c.sleep = l.value;
    }
    let scalars = [
        ("restitution", &w.restitution, &mut c.restitution),
        ("friction", &w.friction, &mut c.friction),
        ("impact_speed", &w.impact_speed, &mut c.impact_speed),
        ("contact_slop", &w.contact_slop, &mut c.slop),
        ("contact_hertz", &w.contact_hertz, &mut c.hertz),
        ("contact_damping_ratio", &w.contact_damping_ratio, &mut c.damping_ratio),
        ("max_correction_speed", &w.max_correction_speed, &mut c.max_correction_speed),
        ("sleep_speed", &w.sleep_speed, &mut c.sleep_speed),
        ("sleep_time", &w.sleep_time, &mut c.sleep_time),
        ("manifold_reuse", &w.manifold_reuse, &mut c.manifold_reuse),
    ];
    for (key, loc, target) in scalars {
        if let Some(l) = loc {
            *target = finite(key, l)?;
        }
    }
    if let Some(l) = &w.contact_iterations {
        c.iterations = l.value;
    }
    if let Some(l) = &w.contact_substeps {
        c.substeps = l.value;
    }
    if let Some(l) = &w.max_pairs {
        c.max_pairs = Some(l.value);
    }
    if let Some(l) = &w.friction_model {
        c.friction_model =
            one_of(src, l, "world.friction_model", "friction model", &FrictionModel::NAMES, FrictionModel::from_name)?;
    }
    if let Some(l) = &w.restitution_law {
        c.law = one_of(
            src,
            l,
            "world.restitution_law",
            "restitution law",
            &RestitutionLaw::NAMES,
            RestitutionLaw::from_name,
        )?;
    }
    Ok(())
}

/// The value a scene names, `parse(name)`, one of `names`; else an error at the name's place in
/// the file naming `field`, what it is (`what`) and the names, with the nearest as a hint.
fn one_of<T>(
    src: &Source,
    l: &Loc<String>,
    field: &str,
    what: &str,
    names: &[&str],
    parse: impl Fn(&str) -> Option<T>,
) -> Result<T, SceneError> {
    parse(&l.value).ok_or_else(|| {
        let e = src
            .error(l.span.as_ref(), field, format!("unknown {what} (expected one of: {})", names.join(", ")))
            .got(format!("\"{}\"", l.value));
        match nearest(&l.value, names) {
            Some(best) => e.hint(format!("did you mean `{best}`?")),
            None => e,
        }
    })
}

/// `no_collide = ["name", ...]` of each `[[body]]` → pairs excluded from collision.
fn collision_filters(src: &Source, doc: &SceneDoc, world: &mut World) -> Result<(), SceneError> {
    for (i, entry) in doc.body.iter().enumerate() {
        let Some(list) = &entry.value.no_collide else { continue };
        for name in &list.value {
            if let Some(links) = world.link_shapes_named(name) {
                for l in links {
                    world.contact_stage().links.colliders.exclude_body(l, i);
                }
                continue;
            }
            let Some(j) = world.body_index(name) else {
                // the bodies, then the robots' links with collision geometry (`robot/link`)
                let colliders = world.contacts().links.colliders.links();
                let mut names: Vec<&str> = world.bodies.iter().map(|b| b.name.as_str()).collect();
                for c in colliders {
                    if !names.contains(&c.name.as_str()) {
                        names.push(c.name.as_str());
                    }
                }
                let e = src
                    .error(list.span.as_ref(), format!("body[{i}].no_collide"), "names no body of the scene")
                    .got(format!("\"{name}\""));
                let what = if colliders.is_empty() { "the bodies" } else { "the bodies and robot links" };
                return Err(match names_hint(name, what, &names) {
                    Some(hint) => e.hint(hint),
                    None => e,
                });
            };
            world.contact_stage().exclude_pair(i, j);
        }
    }
    for (g, entry) in doc.grid.iter().enumerate() {
        if let Some(list) = &entry.value.body.value.no_collide {
            return Err(src
                .error(list.span.as_ref(), format!("grid[{g}].body.no_collide"), "not available in a grid template")
                .hint("list the pair on an explicit `[[body]]`"));
        }
    }
    Ok(())
}

/// A warning for each pair of bodies that overlaps deeply at the start (`World::deep_overlaps`),
/// placed at the second body's `position` (or its table, or its grid). An error when the starting
/// poses give more candidate pairs than the pair budget (bodies heaped at one spot).
fn overlap_warnings(
    src: &Source,
    doc: &SceneDoc,
    world: &mut World,
    warnings: &mut Vec<String>,
) -> Result<(), SceneError> {
    let max_speed = world.config.contact.max_correction_speed;
    let overlaps = match world.deep_overlaps() {
        Ok(overlaps) => overlaps,
        Err(e) => return Err(over_budget(src, doc, world, &e)),
    };
    for o in overlaps {
        let (path, span) = body_location(doc, o.b);
        let text = format!(
            "overlaps body `{}` by {} m at the start (deeper than {} m): the contacts push them apart at up to \
             max_correction_speed = {} m/s",
            world.bodies[o.a].name,
            super::describe::g(o.depth),
            super::describe::g(o.threshold),
            super::describe::g(max_speed)
        );
        let text = format!("body `{}` {text}", world.bodies[o.b].name);
        warnings.push(src.warning(span.as_ref(), &path, &text));
    }
    Ok(())
}

/// The error for starting poses over the pair budget: at the first grid of moving bodies whose
/// copies are closer than their size along an axis (they all overlap), else at `world.max_pairs`.
fn over_budget(src: &Source, doc: &SceneDoc, world: &mut World, e: &crate::world::ContactBudget) -> SceneError {
    let problem =
        format!("the bodies start with {} candidate contact pairs or more, over the budget of {}", e.pairs, e.budget);
    let raise = "or raise `max_pairs` in [world] (default: 32 per body + 10,000)";
    let mut first = doc.body.len();
    for (g, grid) in doc.grid.iter().enumerate() {
        let count = grid.value.count.value;
        let copies: u64 = count.iter().product();
        let size = 2.0 * world.bounding_radius(first);
        first += copies as usize;
        let (Some(spacing), Some(body)) = (&grid.value.spacing, world.bodies.get(first - copies as usize)) else {
            continue;
        };
        let close = (0..3).filter(|&k| count[k] > 1 && spacing.value[k].abs() < size).count();
        if body.fixed || size == 0.0 || close == 0 {
            continue;
        }
        let one_spot = (0..3).all(|k| count[k] == 1 || spacing.value[k] == 0.0);
        let placed = if one_spot { "all at one spot" } else { "closer than their size" };
        return src.error(spacing.span.as_ref(), format!("grid[{g}].spacing"), problem).got(nums(&spacing.value)).hint(
            format!(
                "the {copies} copies of `{}` (bounding diameter {} m) are {placed}: every copy overlaps its \
                 neighbours; space them at least {} m apart along each axis with more than one copy, {raise}",
                grid.value.body.value.name.as_ref().map_or("", |n| n.value.as_str()),
                super::describe::g(size),
                super::describe::g(size),
            ),
        );
    }
    let w = doc.world.as_ref();
    let span = w.and_then(|t| t.value.max_pairs.as_ref().and_then(|l| l.span.clone()).or_else(|| t.span.clone()));
    src.error(span.as_ref(), "world.max_pairs", problem)
        .got(e.budget.to_string())
        .hint(format!("bodies heaped at one spot pair with each other (n²/2 pairs for n bodies): spread them, {raise}"))
}

/// The field path and span that place body `index`: `body[i].position` (or `body[i]`), or the
/// `grid[g].body` that made it.
fn body_location(doc: &SceneDoc, index: usize) -> (String, Option<Range<usize>>) {
    if let Some(entry) = doc.body.get(index) {
        return match &entry.value.position {
            Some(p) => (format!("body[{index}].position"), p.span.clone()),
            None => (format!("body[{index}]"), entry.span.clone()),
        };
    }
    let mut first = doc.body.len();
    for (g, grid) in doc.grid.iter().enumerate() {
        let count: u64 = grid.value.count.value.iter().product();
        if ((index - first) as u64) < count {
            return (format!("grid[{g}].body"), grid.value.body.span.clone());
        }
        first += count as usize;
    }
    (String::new(), None)
}
