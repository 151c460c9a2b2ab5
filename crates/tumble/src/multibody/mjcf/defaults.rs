//! `<default>` classes: which value an attribute takes when the element does not write it.
//!
//! MJCF reference, "default": the top-level `<default>` is the class `main`; a nested
//! `<default class="c">` starts from everything its parent class sets. An element takes the class
//! named by its `class` attribute, else the `childclass` of the nearest enclosing `<body>` or
//! `<frame>` that has one, else `main`; attributes written on the element win over the class's.

use super::xml::{Attr, El};
use super::MjcfError;
use super::MjcfErrorKind;
use std::collections::HashMap;

/// The classes of a model.
#[derive(Debug, Default)]
pub struct Defaults {
    classes: HashMap<String, Class>,
}

#[derive(Debug, Default)]
struct Class {
    parent: Option<String>,
    /// Per element tag (`joint`, `geom`, `motor`, …) the attributes the class sets.
    elements: HashMap<String, Vec<Attr>>,
}

/// The elements a `<default>` may set values for (anything else inside is an error, as in MuJoCo).
const DEFAULTABLE: &[&str] = &[
    "mesh",
    "material",
    "joint",
    "geom",
    "site",
    "camera",
    "light",
    "pair",
    "equality",
    "tendon",
    "general",
    "motor",
    "position",
    "velocity",
    "intvelocity",
    "damper",
    "cylinder",
    "muscle",
    "adhesion",
    "flex",
    "texture",
    "hfield",
    "skin",
];

impl Defaults {
    /// The classes declared by the `<default>` elements directly under `<mujoco>`.
    pub fn read(root: &El) -> Result<Self, MjcfError> {
        let mut d = Defaults::default();
        d.classes.insert("main".into(), Class::default());
        for el in root.children.iter().filter(|c| c.tag == "default") {
            d.class(el, None)?;
        }
        Ok(d)
    }

    fn class(&mut self, el: &El, parent: Option<&str>) -> Result<(), MjcfError> {
        let name = match (el.attr("class"), parent) {
            (Some(a), _) => a.value.clone(),
            (None, None) => "main".to_string(),
            (None, Some(_)) => return Err(el.error(MjcfErrorKind::MissingAttribute("class"))),
        };
        if parent.is_some() && self.classes.contains_key(&name) {
            return Err(el.attr_error("class", MjcfErrorKind::Invalid(format!("class '{name}' is defined twice"))));
        }
        let class = self.classes.entry(name.clone()).or_default();
        if parent.is_some() {
            class.parent = parent.map(str::to_string);
        }
        for child in &el.children {
            if child.tag == "default" {
                continue;
            }
            if !DEFAULTABLE.contains(&child.tag.as_str()) {
                return Err(child.error(MjcfErrorKind::Invalid(format!("<{}> cannot appear in <default>", child.tag))));
            }
            let slot =
                self.classes.get_mut(&name).expect("inserted above").elements.entry(child.tag.clone()).or_default();
            for a in &child.attrs {
                match slot.iter_mut().find(|b| b.name == a.name) {
                    Some(b) => *b = a.clone(),
                    None => slot.push(a.clone()),
                }
            }
        }
        for child in el.children.iter().filter(|c| c.tag == "default") {
            self.class(child, Some(&name))?;
        }
        Ok(())
    }

    /// True when `class` is declared.
    pub fn has(&self, class: &str) -> bool {
        self.classes.contains_key(class)
    }

    /// The value class `class` (or an ancestor) gives attribute `name` of a `tag` element.
    pub fn lookup(&self, class: &str, tag: &str, name: &str) -> Option<&Attr> {
        let mut c = Some(class);
        let mut depth = 0;
        while let Some(name_c) = c {
            let class = self.classes.get(name_c)?;
            if let Some(a) = class.elements.get(tag).and_then(|attrs| attrs.iter().find(|a| a.name == name)) {
                return Some(a);
            }
            c = class.parent.as_deref();
            depth += 1;
            if depth > 1000 {
                return None;
            }
        }
        None
    }

    /// Every attribute name a class chain sets for `tag` (for checking them like written ones).
    pub fn names(&self, class: &str, tag: &str) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        let mut c = Some(class);
        while let Some(name_c) = c {
            let Some(class) = self.classes.get(name_c) else { break };
            for a in class.elements.get(tag).map(Vec::as_slice).unwrap_or(&[]) {
                if !out.contains(&a.name) {
                    out.push(a.name.clone());
                }
            }
            c = class.parent.as_deref();
            if out.len() > 10_000 {
                break;
            }
        }
        out
    }
}
