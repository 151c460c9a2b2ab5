//! The URDF vocabulary inside `<link>` and `<joint>`: an attribute or a child element that the
//! specification does not define is ignored with a warning (file:line:column, the link or joint,
//! and the nearest known name), once per element and name in a file.
//!
//! Reference: the URDF XML specification (ROS wiki, `urdf/XML/link`, `urdf/XML/joint`,
//! `urdf/XML/robot`). URDF is an open format, so an unknown name is never an error; but a typo
//! inside an element that is read turns into a silent default (`<origin xzy="0 0 1"/>` is the
//! identity, `<axis xzy=…>` is x, a misspelt `<inertail>` leaves the link massless), which is why
//! it is reported. Names in an XML namespace (`xacro:…`, vendor extensions) are extensions by
//! construction and stay silent, and so does the content of an unknown element.

use roxmltree::{Document, Node};
use std::collections::HashSet;

/// Each element of a link or joint subtree: its attributes and its child elements.
const VOCABULARY: &[(&str, &[&str], &[&str])] = &[
    ("link", &["name"], &["inertial", "visual", "collision"]),
    ("inertial", &[], &["origin", "mass", "inertia"]),
    ("origin", &["xyz", "rpy"], &[]),
    ("mass", &["value"], &[]),
    ("inertia", &["ixx", "ixy", "ixz", "iyy", "iyz", "izz"], &[]),
    ("visual", &["name"], &["origin", "geometry", "material"]),
    ("collision", &["name"], &["origin", "geometry"]),
    ("geometry", &[], &["box", "cylinder", "sphere", "mesh"]),
    ("box", &["size"], &[]),
    ("cylinder", &["radius", "length"], &[]),
    ("sphere", &["radius"], &[]),
    ("mesh", &["filename", "scale"], &[]),
    ("material", &["name"], &["color", "texture"]),
    ("color", &["rgba"], &[]),
    ("texture", &["filename"], &[]),
    (
        "joint",
        &["name", "type"],
        &["origin", "parent", "child", "axis", "calibration", "dynamics", "limit", "mimic", "safety_controller"],
    ),
    ("parent", &["link"], &[]),
    ("child", &["link"], &[]),
    ("axis", &["xyz"], &[]),
    // `reference_position` is read by urdfdom beside the specification's `rising` and `falling`
    ("calibration", &["rising", "falling", "reference_position"], &[]),
    ("dynamics", &["damping", "friction"], &[]),
    ("limit", &["lower", "upper", "effort", "velocity"], &[]),
    ("mimic", &["joint", "multiplier", "offset"], &[]),
    ("safety_controller", &["soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"], &[]),
];

/// The attributes and children of `tag`, if it is an element of the vocabulary.
fn entry(tag: &str) -> Option<(&'static [&'static str], &'static [&'static str])> {
    VOCABULARY.iter().find(|(t, _, _)| *t == tag).map(|(_, attributes, children)| (*attributes, *children))
}

/// Warns about every unknown attribute and child element in the subtree of `top` (a `<link>` or
/// `<joint>`), once per `(element, name)` pair recorded in `seen`: one warning for an element's new
/// unknown attributes, one for its new unknown children, at the first of them.
pub(super) fn check(
    doc: &Document,
    file: &str,
    top: Node,
    seen: &mut HashSet<(String, String)>,
    warnings: &mut Vec<String>,
) {
    let owner = format!("{} '{}'", top.tag_name().name(), top.attribute("name").unwrap_or(""));
    let mut stack = vec![top];
    while let Some(node) = stack.pop() {
        let tag = node.tag_name().name();
        let Some((attributes, children)) = entry(tag) else { continue };
        // (offset, name) of the unknown names not reported yet
        let mut new_attributes: Vec<(usize, &str)> = Vec::new();
        for a in node.attributes().filter(|a| a.namespace().is_none()) {
            if !attributes.contains(&a.name()) && seen.insert((tag.to_string(), a.name().to_string())) {
                new_attributes.push((a.range_qname().start, a.name()));
            }
        }
        let elements: Vec<Node> =
            node.children().filter(|n| n.is_element() && n.tag_name().namespace().is_none()).collect();
        let mut new_elements: Vec<(usize, &str)> = Vec::new();
        for n in &elements {
            let name = n.tag_name().name();
            if !children.contains(&name) && seen.insert((tag.to_string(), format!("<{name}>"))) {
                new_elements.push((n.range().start, name));
            }
        }
        let mut warn = |found: &[(usize, &str)], element: bool, known: &[&str]| {
            let Some(&(at, _)) = found.first() else { return };
            let pos = doc.text_pos_at(at);
            // each name, with the nearest known one when it is close (a likely typo)
            let names: Vec<String> = found
                .iter()
                .map(|(_, name)| {
                    let shown = if element { format!("<{name}>") } else { format!("'{name}'") };
                    match (crate::scene::error::nearest(name, known), element) {
                        (Some(best), false) => format!("{shown} (did you mean '{best}'?)"),
                        (Some(best), true) => format!("{shown} (did you mean <{best}>?)"),
                        (None, _) => shown,
                    }
                })
                .collect();
            let (list, plural) = (names.join(", "), found.len() > 1);
            let text = match (element, plural) {
                (false, false) => format!("unknown attribute {list} on <{tag}>, ignored"),
                (false, true) => format!("unknown attributes {list} on <{tag}>, ignored"),
                (true, false) => format!("ignored {list} in <{tag}>: not a URDF element there"),
                (true, true) => format!("ignored {list} in <{tag}>: not URDF elements there"),
            };
            warnings.push(format!("{file}:{}:{}: {owner}: {text}", pos.row, pos.col));
        };
        warn(&new_attributes, false, attributes);
        warn(&new_elements, true, children);
        // known children pushed in reverse so that they are visited in file order
        stack.extend(elements.into_iter().rev().filter(|n| children.contains(&n.tag_name().name())));
    }
}
