//! An element seen through its default class: typed attribute values with errors at the attribute
//! (on the element, or in the `<default>` that gave it).

use super::defaults::Defaults;
use super::xml::{Attr, El};
use super::{MjcfError, MjcfErrorKind};

/// An element with the class its attributes fall back to.
pub struct View<'a> {
    pub el: &'a El,
    defaults: Option<(&'a Defaults, String)>,
    /// The element name the defaults are stored under (the tag, but `tendon` for `<fixed>`).
    default_tag: Option<&'static str>,
}

impl<'a> View<'a> {
    /// `el` resolved against `class` of `defaults` (`None`: the element takes no defaults, as
    /// `<freejoint>` and `<body>`).
    pub fn new(el: &'a El, defaults: Option<(&'a Defaults, String)>) -> Self {
        Self { el, defaults, default_tag: None }
    }

    /// Looks defaults up under `tag` instead of the element's own tag.
    pub fn set_default_tag(&mut self, tag: &'static str) {
        self.default_tag = Some(tag);
    }

    fn tag(&self) -> &str {
        self.default_tag.unwrap_or(&self.el.tag)
    }

    /// The attribute as written on the element, else as its class gives it.
    pub fn get(&self, name: &str) -> Option<&'a Attr> {
        self.el.attr(name).or_else(|| self.defaults.as_ref().and_then(|(d, c)| d.lookup(c, self.tag(), name)))
    }

    /// True when the element itself writes `name`.
    pub fn written(&self, name: &str) -> bool {
        self.el.attr(name).is_some()
    }

    /// An error about attribute `name` (`<tag name>`), at its position.
    pub fn err(&self, name: &str, kind: MjcfErrorKind) -> MjcfError {
        match self.get(name) {
            Some(a) => MjcfError::at(&a.pos, format!("{} {}", self.el.tag, name), kind),
            None => self.el.attr_error(name, kind),
        }
    }

    fn bad(&self, name: &str, expected: &str) -> MjcfError {
        let value = self.get(name).map(|a| a.value.clone()).unwrap_or_default();
        self.err(name, MjcfErrorKind::BadValue { value, expected: expected.to_string() })
    }

    pub fn str(&self, name: &str) -> Option<&'a str> {
        self.get(name).map(|a| a.value.as_str())
    }

    /// The numbers of `name` (finite), `None` when absent.
    pub fn numbers(&self, name: &str) -> Result<Option<Vec<f64>>, MjcfError> {
        let Some(a) = self.get(name) else { return Ok(None) };
        let mut out = Vec::new();
        for part in a.value.split_whitespace() {
            match part.parse::<f64>() {
                Ok(x) if x.is_finite() => out.push(x),
                _ => return Err(self.bad(name, "finite numbers")),
            }
        }
        Ok(Some(out))
    }

    /// Exactly `n` numbers, `None` when absent.
    pub fn vec(&self, name: &str, n: usize) -> Result<Option<Vec<f64>>, MjcfError> {
        match self.numbers(name)? {
            Some(v) if v.len() == n => Ok(Some(v)),
            Some(_) => Err(self.bad(name, &format!("{n} finite numbers"))),
            None => Ok(None),
        }
    }

    /// One number, `default` when absent.
    pub fn f64(&self, name: &str, default: f64) -> Result<f64, MjcfError> {
        Ok(self.vec(name, 1)?.map(|v| v[0]).unwrap_or(default))
    }

    /// One number ≥ 0, `default` when absent.
    pub fn nonneg(&self, name: &str, default: f64) -> Result<f64, MjcfError> {
        let x = self.f64(name, default)?;
        if x < 0.0 {
            return Err(self.bad(name, "a finite number ≥ 0"));
        }
        Ok(x)
    }

    /// A non-negative integer, `default` when absent.
    pub fn int(&self, name: &str, default: i64) -> Result<i64, MjcfError> {
        match self.str(name) {
            None => Ok(default),
            Some(t) => t.trim().parse::<i64>().map_err(|_| self.bad(name, "an integer")),
        }
    }

    /// One of `allowed`, `None` when absent.
    pub fn keyword(&self, name: &str, allowed: &[&str]) -> Result<Option<&'a str>, MjcfError> {
        match self.str(name) {
            None => Ok(None),
            Some(t) if allowed.contains(&t.trim()) => Ok(Some(t.trim())),
            Some(_) => Err(self.bad(name, &format!("one of {}", allowed.join(", ")))),
        }
    }

    /// `true` or `false`, `None` when absent.
    pub fn bool(&self, name: &str) -> Result<Option<bool>, MjcfError> {
        Ok(self.keyword(name, &["true", "false"])?.map(|t| t == "true"))
    }

    /// Every attribute the element writes or its class gives must be in `known` (MuJoCo refuses
    /// unknown attributes too).
    pub fn check_known(&self, known: &[&str]) -> Result<(), MjcfError> {
        for a in &self.el.attrs {
            if !known.contains(&a.name.as_str()) {
                return Err(MjcfError::at(
                    &a.pos,
                    format!("{} {}", self.el.tag, a.name),
                    MjcfErrorKind::Invalid(format!("unknown attribute '{}'", a.name)),
                ));
            }
        }
        if let Some((d, c)) = &self.defaults {
            for name in d.names(c, self.tag()) {
                if !known.contains(&name.as_str()) {
                    return Err(self.err(&name, MjcfErrorKind::Invalid(format!("unknown attribute '{name}'"))));
                }
            }
        }
        Ok(())
    }

    /// Refuses `name` when it is set to anything but what `harmless` accepts.
    pub fn refuse_unless(&self, name: &str, harmless: impl Fn(&str) -> bool, why: &str) -> Result<(), MjcfError> {
        match self.str(name) {
            Some(v) if !harmless(v.trim()) => Err(self.err(name, MjcfErrorKind::Unsupported(why.to_string()))),
            _ => Ok(()),
        }
    }
}

/// True for a list of numbers that are all zero (or empty).
pub fn all_zero(text: &str) -> bool {
    text.split_whitespace().all(|p| p.parse::<f64>().is_ok_and(|x| x == 0.0))
}
