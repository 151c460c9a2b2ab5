//! Shells: the connected pieces of a closed surface, and which way each one faces.
//!
//! A closed, consistently oriented surface may still consist of several *shells* (pieces connected
//! through shared vertices): two separate parts in one file, or a hollow part whose inner surface
//! bounds a cavity. Each shell's signed volume `V_k` (the sum of its tetrahedra, as in
//! [`integrals`](super::integrals)) says which way it faces:
//!
//! - `V_k > 0`: outward, a solid;
//! - `V_k < 0` and the shell's bounding box lies within that of an outward shell: a *cavity*,
//!   subtracted from the solid around it (accepted, with a warning);
//! - `V_k < 0` otherwise: it cannot be a cavity, so its triangles face inward: the shell is
//!   flipped, with a warning (for a single shell: the whole mesh is inside out).
//!
//! Shells of negligible volume (`|V_k| ≤ 1e-12 L³`) are left as they are. The bounding-box test is a
//! necessary condition for a cavity, not a sufficient one: an inside-out part lying within another
//! part's bounding box (but outside the part) is taken for a cavity, and said so in the warning.
//!
//! Cost: a union–find over the vertices (near-linear), one pass over the triangles.

use super::topology::MeshWarning;
use crate::math::DVec3;

/// Per shell: six times the signed volume (m³) and the bounding box (m).
#[derive(Clone, Copy)]
struct Shell {
    six_volume: f64,
    lo: DVec3,
    hi: DVec3,
}

/// Finds the shells of a closed, consistently oriented surface, flips those that face inward and
/// are no cavity, and returns the signed volume of the whole (m³) after the flips.
pub(super) fn orient_shells(
    vertices: &[DVec3],
    triangles: &mut [[u32; 3]],
    reference: DVec3,
    warnings: &mut Vec<MeshWarning>,
) -> f64 {
    // union–find with path halving: vertices of one triangle are in one shell
    let mut parent: Vec<u32> = (0..vertices.len() as u32).collect();
    let find = |parent: &mut Vec<u32>, mut x: u32| {
        while parent[x as usize] != x {
            parent[x as usize] = parent[parent[x as usize] as usize];
            x = parent[x as usize];
        }
        x
    };
    for t in triangles.iter() {
        for (a, b) in [(t[0], t[1]), (t[1], t[2])] {
            let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
            if ra != rb {
                parent[ra.max(rb) as usize] = ra.min(rb);
            }
        }
    }
    // shells numbered in the order of their first triangle; D = a · (b × c) about the reference
    let mut number = vec![u32::MAX; vertices.len()];
    let mut shells: Vec<Shell> = Vec::new();
    let mut shell_of = Vec::with_capacity(triangles.len());
    for t in triangles.iter() {
        let root = find(&mut parent, t[0]) as usize;
        if number[root] == u32::MAX {
            number[root] = shells.len() as u32;
            shells.push(Shell { six_volume: 0.0, lo: DVec3::INFINITY, hi: DVec3::NEG_INFINITY });
        }
        let k = number[root];
        shell_of.push(k);
        let [a, b, c] = t.map(|i| vertices[i as usize]);
        let shell = &mut shells[k as usize];
        shell.six_volume += (a - reference).dot((b - reference).cross(c - reference));
        shell.lo = shell.lo.min(a).min(b).min(c);
        shell.hi = shell.hi.max(a).max(b).max(c);
    }
    let total: f64 = shells.iter().map(|s| s.six_volume).sum::<f64>() / 6.0;
    let size = shells.iter().fold(0.0_f64, |e, s| e.max((s.hi - s.lo).max_element()));
    let negligible = 6e-12 * size.powi(3);
    let within = |inner: &Shell, outer: &Shell| inner.lo.cmpge(outer.lo).all() && inner.hi.cmple(outer.hi).all();
    let mut flip = vec![false; shells.len()];
    let (mut flipped, mut flipped_volume, mut cavities, mut cavity_volume) = (0, 0.0, 0, 0.0);
    for (k, shell) in shells.iter().enumerate() {
        // not clearly negative (a NaN volume included): not turned inside out
        if shell.six_volume.partial_cmp(&-negligible) != Some(std::cmp::Ordering::Less) {
            continue;
        }
        let is_cavity = shells.iter().any(|outer| outer.six_volume > negligible && within(shell, outer));
        if is_cavity {
            cavities += 1;
            cavity_volume += shell.six_volume / 6.0;
        } else {
            flip[k] = true;
            flipped += 1;
            flipped_volume += shell.six_volume / 6.0;
        }
    }
    if flipped == 0 {
        if cavities > 0 {
            warnings.push(MeshWarning::Cavities { shells: cavities, volume: cavity_volume });
        }
        return total;
    }
    for (t, &k) in triangles.iter_mut().zip(&shell_of) {
        if flip[k as usize] {
            t.swap(1, 2);
        }
    }
    warnings.insert(0, MeshWarning::InsideOut { volume: flipped_volume, shells: flipped });
    if cavities > 0 {
        warnings.push(MeshWarning::Cavities { shells: cavities, volume: cavity_volume });
    }
    total - 2.0 * flipped_volume
}
