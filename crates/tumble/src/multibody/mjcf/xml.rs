//! The MJCF document as an owned tree: every `<include file>` replaced by the children of the
//! included file's `<mujoco>` (as MuJoCo does, before anything else is read), each element and
//! attribute keeping the file, line and column it came from.
//!
//! Paths of included files are relative to the directory of the main model file (MuJoCo's rule);
//! an include that repeats a file already on the include path is a cycle and refused, as is a
//! depth beyond [`MAX_INCLUDE_DEPTH`].

use super::{MjcfError, MjcfErrorKind};
use roxmltree::{Document, Node};
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// Files larger than this are refused before reading (bytes).
pub const MAX_MJCF_BYTES: u64 = 64 << 20;
/// Includes nested deeper than this are refused.
pub const MAX_INCLUDE_DEPTH: usize = 16;
/// Elements nested deeper than this are refused (the reader recurses over the tree; MuJoCo models
/// are a few tens deep).
pub const MAX_ELEMENT_DEPTH: usize = 1000;

/// Where a piece of text came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Pos {
    pub file: Rc<str>,
    pub line: u32,
    pub column: u32,
}

/// One attribute, with its position.
#[derive(Debug, Clone)]
pub struct Attr {
    pub name: String,
    pub value: String,
    pub pos: Pos,
}

/// One element, its attributes in file order and its element children (text and comments dropped).
#[derive(Debug, Clone)]
pub struct El {
    pub tag: String,
    pub attrs: Vec<Attr>,
    pub children: Vec<El>,
    pub pos: Pos,
}

impl El {
    /// The attribute `name`, as written on this element.
    pub fn attr(&self, name: &str) -> Option<&Attr> {
        self.attrs.iter().find(|a| a.name == name)
    }

    /// `tag name="…"` (or the tag alone), for messages.
    pub fn describe(&self) -> String {
        match self.attr("name") {
            Some(a) => format!("{} name=\"{}\"", self.tag, a.value),
            None => self.tag.clone(),
        }
    }

    /// An error at this element.
    pub fn error(&self, kind: MjcfErrorKind) -> MjcfError {
        MjcfError::at(&self.pos, self.describe(), kind)
    }

    /// An error at attribute `attr` of this element (`<tag attr>`), at the attribute's position
    /// when it is written on the element.
    pub fn attr_error(&self, attr: &str, kind: MjcfErrorKind) -> MjcfError {
        let pos = self.attr(attr).map(|a| &a.pos).unwrap_or(&self.pos);
        MjcfError::at(pos, format!("{} {}", self.tag, attr), kind)
    }
}

/// Reads `path` and expands its includes.
pub fn load(path: &Path) -> Result<El, MjcfError> {
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut stack = Vec::new();
    read_file(path, &dir, &mut stack, None)
}

/// Parses `text` (named `file` in errors) and expands its includes relative to `dir`.
pub fn parse(text: &str, file: &str, dir: &Path) -> Result<El, MjcfError> {
    let mut stack = vec![PathBuf::from(file)];
    convert_document(text, Rc::from(file), dir, &mut stack)
}

fn whole_file(file: &str, kind: MjcfErrorKind) -> MjcfError {
    MjcfError { file: file.into(), line: 0, column: 0, element: "mujoco".into(), kind: Box::new(kind) }
}

fn read_file(path: &Path, dir: &Path, stack: &mut Vec<PathBuf>, from: Option<&El>) -> Result<El, MjcfError> {
    let file = path.display().to_string();
    let fail = |kind: MjcfErrorKind| match from {
        Some(include) => include.attr_error("file", kind),
        None => whole_file(&file, kind),
    };
    let meta = std::fs::metadata(path).map_err(|e| fail(MjcfErrorKind::Io(format!("{}: {e}", path.display()))))?;
    if meta.len() > MAX_MJCF_BYTES {
        return Err(fail(MjcfErrorKind::Invalid(format!(
            "{} is {} bytes, more than the limit of {MAX_MJCF_BYTES}",
            path.display(),
            meta.len()
        ))));
    }
    let text =
        std::fs::read_to_string(path).map_err(|e| fail(MjcfErrorKind::Io(format!("{}: {e}", path.display()))))?;
    stack.push(path.to_path_buf());
    let el = convert_document(&text, Rc::from(file.as_str()), dir, stack);
    stack.pop();
    el
}

fn convert_document(text: &str, file: Rc<str>, dir: &Path, stack: &mut Vec<PathBuf>) -> Result<El, MjcfError> {
    let doc = Document::parse(text).map_err(|e| {
        let pos = e.pos();
        MjcfError {
            file: file.to_string(),
            line: pos.row,
            column: pos.col,
            element: "xml".into(),
            kind: Box::new(MjcfErrorKind::Xml(e.to_string())),
        }
    })?;
    let root = doc.root_element();
    if let Some(deep) = root.descendants().find(|n| n.is_element() && n.ancestors().count() > MAX_ELEMENT_DEPTH + 1) {
        let pos = pos_of(&doc, deep.range().start, &file);
        return Err(MjcfError::at(
            &pos,
            deep.tag_name().name().to_string(),
            MjcfErrorKind::Invalid(format!("elements nested deeper than {MAX_ELEMENT_DEPTH}")),
        ));
    }
    let el = convert(&doc, root, &file);
    if el.tag != "mujoco" {
        return Err(el.error(MjcfErrorKind::Invalid(format!("the root element must be <mujoco>, found <{}>", el.tag))));
    }
    expand(el, dir, stack)
}

fn pos_of(doc: &Document, offset: usize, file: &Rc<str>) -> Pos {
    let p = doc.text_pos_at(offset);
    Pos { file: file.clone(), line: p.row, column: p.col }
}

fn convert(doc: &Document, node: Node, file: &Rc<str>) -> El {
    let attrs = node
        .attributes()
        .map(|a| Attr {
            name: a.name().to_string(),
            value: a.value().to_string(),
            pos: pos_of(doc, a.range().start, file),
        })
        .collect();
    let children = node.children().filter(|n| n.is_element()).map(|n| convert(doc, n, file)).collect();
    El { tag: node.tag_name().name().to_string(), attrs, children, pos: pos_of(doc, node.range().start, file) }
}

/// Replaces each `<include>` below `el` by the children of its file's `<mujoco>`.
fn expand(mut el: El, dir: &Path, stack: &mut Vec<PathBuf>) -> Result<El, MjcfError> {
    let mut children = Vec::with_capacity(el.children.len());
    for child in std::mem::take(&mut el.children) {
        if child.tag != "include" {
            children.push(expand(child, dir, stack)?);
            continue;
        }
        let Some(file) = child.attr("file") else {
            return Err(child.error(MjcfErrorKind::MissingAttribute("file")));
        };
        let path = dir.join(&file.value);
        if stack.iter().any(|p| p == &path) {
            return Err(child.attr_error("file", MjcfErrorKind::Invalid(format!("{} includes itself", path.display()))));
        }
        if stack.len() > MAX_INCLUDE_DEPTH {
            return Err(child.attr_error(
                "file",
                MjcfErrorKind::Invalid(format!("includes nested deeper than {MAX_INCLUDE_DEPTH}")),
            ));
        }
        let included = read_file(&path, dir, stack, Some(&child))?;
        children.extend(included.children);
    }
    el.children = children;
    Ok(el)
}
