//! Scene errors: `<file>:<line>:<col>: <field path>: <problem> (got <value>)`, then an optional
//! `hint:` line.
//!
//! TOML errors carry the line and column of the offending value (from the spans kept by
//! [`Loc`](super::schema::Loc)) and a snippet of the line; JSON errors carry serde_json's line and
//! column for syntax and type errors, and the field path (`body[3].mass`) for the rest.

use super::Format;
use std::fmt::Write as _;
use std::ops::Range;

/// A position in a text file, both 1-based; the column counts characters, not bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineCol {
    pub line: usize,
    pub column: usize,
}

/// Why a scene could not be loaded. `Display` gives the whole message, e.g.
/// `scenes/x.toml:12:8: body[2].mass: must be finite and > 0 (got -1)`, with a `hint:` line where useful.
/// The parts of the message are in [`SceneError::detail`] (boxed: errors are rare, results stay small).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct SceneError {
    /// The whole message, as displayed.
    pub message: String,
    /// Its parts.
    pub detail: Box<ErrorDetail>,
}

/// The parts of a [`SceneError`] message.
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorDetail {
    /// The file as given (or `<built-in demo>`).
    pub origin: String,
    /// Where in the file, when known (always for TOML values; for JSON syntax and type errors).
    pub position: Option<LineCol>,
    /// The field path, e.g. `body[2].mass`; empty for errors about the whole file.
    pub path: String,
    /// What is wrong.
    pub problem: String,
    /// The offending value, as text.
    pub got: Option<String>,
    /// A suggestion.
    pub hint: Option<String>,
    /// The source line and a caret under the column (TOML).
    pub snippet: Option<String>,
}

impl SceneError {
    /// An error about the file as a whole (cannot read it, too large, not UTF-8, ...).
    pub(crate) fn file(origin: &str, problem: impl Into<String>) -> Self {
        Self::bare(origin, None, String::new(), problem.into())
    }

    fn bare(origin: &str, position: Option<LineCol>, path: String, problem: String) -> Self {
        let detail =
            ErrorDetail { origin: origin.to_string(), position, path, problem, got: None, hint: None, snippet: None };
        let mut e = Self { message: String::new(), detail: Box::new(detail) };
        e.render();
        e
    }

    /// Where in the file, when known.
    pub fn position(&self) -> Option<LineCol> {
        self.detail.position
    }

    /// The field path, e.g. `body[2].mass` (empty for errors about the whole file).
    pub fn path(&self) -> &str {
        &self.detail.path
    }

    /// Adds the offending value.
    pub(crate) fn got(mut self, value: impl Into<String>) -> Self {
        self.detail.got = Some(value.into());
        self.render();
        self
    }

    /// Adds a `hint:` line.
    pub(crate) fn hint(mut self, hint: impl Into<String>) -> Self {
        self.detail.hint = Some(hint.into());
        self.render();
        self
    }

    /// Sets the position (for errors found before the text is parsed).
    pub(crate) fn at(mut self, position: LineCol) -> Self {
        self.detail.position = Some(position);
        self.render();
        self
    }

    fn render(&mut self) {
        let d = &self.detail;
        let mut m = d.origin.clone();
        if let Some(p) = d.position {
            let _ = write!(m, ":{}:{}", p.line, p.column);
        }
        if !d.path.is_empty() {
            let _ = write!(m, ": {}", d.path);
        }
        let _ = write!(m, ": {}", d.problem);
        if let Some(got) = &d.got {
            let _ = write!(m, " (got {got})");
        }
        if let Some(snippet) = &d.snippet {
            m.push('\n');
            m.push_str(snippet);
        }
        if let Some(hint) = &d.hint {
            let _ = write!(m, "\nhint: {hint}");
        }
        self.message = m;
    }
}

/// The text being loaded and where it came from: turns spans into positions and builds messages.
pub(crate) struct Source<'a> {
    pub origin: &'a str,
    pub text: &'a str,
    pub format: Format,
}

impl Source<'_> {
    /// Line and column of a byte offset.
    pub fn line_col(&self, offset: usize) -> LineCol {
        let mut offset = offset.min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        let before = &self.text[..offset];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = before[line_start..].chars().count() + 1;
        LineCol { line, column }
    }

    /// An error at `span` (TOML) about the field `path`.
    pub fn error(
        &self,
        span: Option<&Range<usize>>,
        path: impl Into<String>,
        problem: impl Into<String>,
    ) -> SceneError {
        let position = span.map(|s| self.line_col(s.start));
        let mut e = SceneError::bare(self.origin, position, path.into(), problem.into());
        if let Some(span) = span {
            e.detail.snippet = self.snippet(span.start);
            e.render();
        }
        e
    }

    /// A warning at `span` about `path`, formatted like an error.
    pub fn warning(&self, span: Option<&Range<usize>>, path: &str, text: &str) -> String {
        let mut w = self.origin.to_string();
        if let Some(span) = span {
            let p = self.line_col(span.start);
            let _ = write!(w, ":{}:{}", p.line, p.column);
        }
        if !path.is_empty() {
            let _ = write!(w, ": {path}");
        }
        let _ = write!(w, ": {text}");
        w
    }

    /// `   12 | mass = -1` and a caret under the column.
    fn snippet(&self, offset: usize) -> Option<String> {
        if self.format != Format::Toml {
            return None;
        }
        let p = self.line_col(offset);
        let line = self.text.lines().nth(p.line - 1)?;
        // long lines (a 10 MB string) are cut so that the message stays readable
        let shown: String = line.chars().take(200).collect();
        let caret = " ".repeat(p.column.saturating_sub(1).min(200));
        let width = p.line.to_string().len();
        Some(format!("{:width$} | {shown}\n{:width$} | {caret}^", p.line, ""))
    }

    /// A TOML syntax error, or a TOML type/unknown-key error found while deserializing.
    pub fn toml_error(&self, err: &toml::de::Error, path: String) -> SceneError {
        let span = err.span();
        let (problem, hint) = reword_serde(err.message().trim());
        let mut e = self.error(span.as_ref(), path, problem);
        if let Some(h) = hint {
            e = e.hint(h);
        }
        e
    }

    /// A JSON syntax or type error (serde_json gives line and column).
    pub fn json_error(&self, err: &serde_json::Error, path: String) -> SceneError {
        let text = err.to_string();
        let message = match text.rfind(" at line ") {
            Some(i) => &text[..i],
            None => &text,
        };
        let (problem, hint) = reword_serde(message);
        let position = (err.line() > 0).then(|| LineCol { line: err.line(), column: err.column().max(1) });
        let e = SceneError::bare(self.origin, position, path, problem);
        match hint {
            Some(h) => e.hint(h),
            None => e,
        }
    }
}

/// The field path of a `serde_path_to_error` path, without `toml`'s private span keys.
pub(crate) fn path_text(path: &serde_path_to_error::Path) -> String {
    use serde_path_to_error::Segment;
    let mut out = String::new();
    for segment in path.iter() {
        match segment {
            Segment::Seq { index } => {
                let _ = write!(out, "[{index}]");
            }
            Segment::Map { key } if key.starts_with("$__") => {}
            Segment::Map { key } | Segment::Enum { variant: key } => {
                if !out.is_empty() {
                    out.push('.');
                }
                out.push_str(key);
            }
            Segment::Unknown => {}
        }
    }
    out
}

/// Serde's messages, with a "did you mean" hint for unknown keys.
fn reword_serde(message: &str) -> (String, Option<String>) {
    if let Some(rest) = message.strip_prefix("unknown field `") {
        let unknown = rest.split('`').next().unwrap_or("");
        let valid: Vec<&str> =
            rest.split('`').skip(1).enumerate().filter(|(i, _)| i % 2 == 1).map(|(_, s)| s).collect();
        let problem = format!("unknown key `{unknown}`");
        let list = valid.iter().map(|v| format!("`{v}`")).collect::<Vec<_>>().join(", ");
        let hint = match nearest(unknown, &valid) {
            Some(best) => format!("did you mean `{best}`? (valid keys: {list})"),
            None if valid.is_empty() => "this table takes no keys".to_string(),
            None => format!("valid keys: {list}"),
        };
        return (problem, Some(hint));
    }
    (message.to_string(), None)
}

/// The candidate closest to `word`, if it is close enough to be a likely typo.
pub(crate) fn nearest<'c>(word: &str, candidates: &[&'c str]) -> Option<&'c str> {
    // a small edit distance catches typos (`mas`, `gravtiy`); Jaro–Winkler catches other forms
    // of the same word (`bodies` for `body`)
    let limit = (word.chars().count() / 3).max(2);
    candidates
        .iter()
        .map(|c| (strsim::damerau_levenshtein(word, c), strsim::jaro_winkler(word, c), *c))
        .filter(|(d, jw, _)| *d <= limit || *jw >= 0.8)
        .min_by(|a, b| a.0.cmp(&b.0).then(b.1.total_cmp(&a.1)))
        .map(|(_, _, c)| c)
}

/// How many names a hint lists when none is close to the one given.
pub(crate) const LISTED_NAMES: usize = 8;

/// The hint for a name that matches none of `candidates`: the nearest one when it is close
/// (`did you mean `b`?`), else the first [`LISTED_NAMES`] of them and how many more, introduced by
/// `what` (e.g. "the bodies"); `None` when there is no candidate.
pub(crate) fn names_hint(word: &str, what: &str, candidates: &[&str]) -> Option<String> {
    if let Some(best) = nearest(word, candidates) {
        return Some(format!("did you mean `{best}`?"));
    }
    if candidates.is_empty() {
        return None;
    }
    let shown: Vec<String> = candidates.iter().take(LISTED_NAMES).map(|n| format!("`{n}`")).collect();
    let more = candidates.len().saturating_sub(LISTED_NAMES);
    let tail = if more > 0 { format!(", … and {more} more") } else { String::new() };
    Some(format!("{what}: {}{tail}", shown.join(", ")))
}

/// A float as written in messages (`NaN`, `inf`, `-1`, `0.25`).
pub(crate) fn num(x: f64) -> String {
    format!("{x}")
}

/// A list of floats as written in messages: `[1, NaN, 0.5]`.
pub(crate) fn nums(xs: &[f64]) -> String {
    let items: Vec<String> = xs.iter().map(|x| num(*x)).collect();
    format!("[{}]", items.join(", "))
}
