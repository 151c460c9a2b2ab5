//! `[[grid]]`: blocks of identical bodies for big scenes.
//!
//! ```toml
//! [[grid]]
//! count = [100, 10, 10]        # copies along world x, y, z
//! spacing = [2.0, 2.0, 2.0]    # m between neighbours, world frame
//! origin = [0.0, 0.0, 0.0]     # m, the position of copy (0, 0, 0) (default: the world origin)
//! [grid.body]                  # a template: every key of [[body]] except `position`
//! name = "rock"                # copy (i, j, k) is named `rock_i_j_k`
//! mass = 1.0
//! ```
//!
//! Copy `(i, j, k)` sits at `origin + (i·spacing[0], j·spacing[1], k·spacing[2])`; copies are
//! appended after the `[[body]]` entries, `i` slowest and `k` fastest. The total count is computed
//! with checked multiplication and refused above [`MAX_BODIES`] before anything is allocated.

use super::body::BodyReader;
use super::error::{nums, SceneError, Source};
use super::schema::{GridDoc, Loc, SceneDoc, Table};
use super::{MAX_BODIES, MAX_POSITION};
use crate::body::RigidBody;
use crate::math::DVec3;

/// Estimated memory per loaded body (bytes): the body, its name and the world's per-body data.
pub(crate) fn bytes_per_body() -> u64 {
    (std::mem::size_of::<RigidBody>() + 32 + std::mem::size_of::<f64>()) as u64
}

fn memory_text(bodies: u64) -> String {
    let bytes = bodies as f64 * bytes_per_body() as f64;
    if bytes >= (1u64 << 30) as f64 {
        format!("{:.1} GiB", bytes / (1u64 << 30) as f64)
    } else {
        format!("{:.1} MiB", bytes / (1u64 << 20) as f64)
    }
}

/// The number of bodies the scene will have, refused above [`MAX_BODIES`].
pub(crate) fn total_bodies(src: &Source, doc: &SceneDoc) -> Result<usize, SceneError> {
    let mut total = doc.body.len() as u64;
    for (g, grid) in doc.grid.iter().enumerate() {
        let count = &grid.value.count;
        let path = format!("grid[{g}].count");
        if count.value.contains(&0) {
            return Err(src
                .error(count.span.as_ref(), path, "every count must be ≥ 1")
                .got(format!("{:?}", count.value))
                .hint("remove the `[[grid]]` entry to generate no bodies"));
        }
        let [nx, ny, nz] = count.value;
        let product = nx.checked_mul(ny).and_then(|n| n.checked_mul(nz));
        let new_total = product.and_then(|n| n.checked_add(total));
        match new_total {
            Some(n) if n <= MAX_BODIES => total = n,
            Some(n) => {
                return Err(src
                    .error(
                        count.span.as_ref(),
                        path,
                        format!("the scene would have {n} bodies, more than the limit of {MAX_BODIES}"),
                    )
                    .got(format!("{:?}", count.value))
                    .hint(format!("{n} bodies would need about {} of memory", memory_text(n))));
            }
            None => {
                return Err(src
                    .error(count.span.as_ref(), path, "the number of bodies overflows a 64-bit integer")
                    .got(format!("{:?}", count.value))
                    .hint(format!("the limit is {MAX_BODIES} bodies")));
            }
        }
    }
    Ok(total as usize)
}

/// Appends the copies of grid `g` to `bodies`. Returns the template's name (the prefix of the copies).
pub(crate) fn expand(
    src: &Source,
    g: usize,
    grid: &Loc<Table<GridDoc>>,
    warnings: &mut Vec<String>,
    bodies: &mut Vec<RigidBody>,
    gravity: DVec3,
) -> Result<String, SceneError> {
    let doc = &grid.value;
    let path = format!("grid[{g}].body");
    let template = &doc.body;
    let Some(name) = &template.value.name else {
        return Err(src
            .error(template.span.as_ref(), format!("{path}.name"), "missing: the template needs a name")
            .hint("copy (i, j, k) of a template named `rock` is named `rock_i_j_k`"));
    };
    if let Some(p) = &template.value.position {
        return Err(src
            .error(p.span.as_ref(), format!("{path}.position"), "a grid's template has no position")
            .hint("the grid places copy (i, j, k) at origin + (i, j, k)·spacing; set `origin` on the grid"));
    }
    let vec3 = |key: &str, loc: &Option<super::schema::Vec3Doc>| -> Result<Option<DVec3>, SceneError> {
        match loc {
            Some(l) if l.value.iter().any(|x| !x.is_finite()) => {
                Err(src.error(l.span.as_ref(), format!("grid[{g}].{key}"), "must be finite").got(nums(&l.value)))
            }
            _ => Ok(loc.as_ref().map(|l| DVec3::from_array(l.value))),
        }
    };
    let Some(spacing) = vec3("spacing", &doc.spacing)? else {
        return Err(src
            .error(grid.span.as_ref(), format!("grid[{g}].spacing"), "missing: the distance between copies (m)")
            .hint("e.g. `spacing = [2.0, 2.0, 2.0]`"));
    };
    let origin = vec3("origin", &doc.origin)?.unwrap_or(DVec3::ZERO);
    let [nx, ny, nz] = doc.count.value;
    // the copies span a box from `origin` to `far`; both ends must be within the position limit
    let far = origin + spacing * DVec3::new((nx - 1) as f64, (ny - 1) as f64, (nz - 1) as f64);
    for (key, p) in [("origin", origin), ("spacing", far)] {
        if p.length() > MAX_POSITION {
            let span =
                if key == "origin" { doc.origin.as_ref() } else { doc.spacing.as_ref() }.and_then(|l| l.span.as_ref());
            return Err(src
                .error(
                    span,
                    format!("grid[{g}].{key}"),
                    format!("places bodies beyond {MAX_POSITION:e} m from the origin"),
                )
                .got(format!("a copy at {}", nums(&p.to_array()))));
        }
    }

    let mut reader = BodyReader { src, path: &path, span: template.span.as_ref(), warnings, gravity };
    let body = reader.read(&template.value, name.value.clone())?;
    for i in 0..nx {
        for j in 0..ny {
            for k in 0..nz {
                let mut copy = body.clone();
                copy.name = format!("{}_{i}_{j}_{k}", name.value);
                copy.state.position = origin + spacing * DVec3::new(i as f64, j as f64, k as f64);
                bodies.push(copy);
            }
        }
    }
    Ok(name.value.clone())
}

/// If `name` has the form of a copy of the grid named `prefix` with counts `count`
/// (`prefix_i_j_k`, indices in range, written without leading zeros), the indices.
pub(crate) fn copy_index(name: &str, prefix: &str, count: [u64; 3]) -> Option<[u64; 3]> {
    let rest = name.strip_prefix(prefix)?.strip_prefix('_')?;
    let parts: Vec<&str> = rest.split('_').collect();
    if parts.len() != 3 {
        return None;
    }
    let mut index = [0u64; 3];
    for (slot, (part, n)) in index.iter_mut().zip(parts.iter().zip(count)) {
        let canonical =
            !part.is_empty() && part.bytes().all(|b| b.is_ascii_digit()) && (part.len() == 1 || !part.starts_with('0'));
        let value: u64 = part.parse().ok().filter(|_| canonical)?;
        if value >= n {
            return None;
        }
        *slot = value;
    }
    Some(index)
}
