//! Scene files (TOML or JSON, `version = 1`) → [`World`], with precise errors.
//!
//! The format is specified key by key in `docs/scene-format.md`. In short: `version = 1`, a `[world]`
//! table of settings, `[[body]]` entries (mass properties, shape, initial state, loads),
//! `[[grid]]` entries that generate blocks of identical bodies and `[[robot]]` entries (URDF trees,
//! module `robot`). Every float is checked to be finite, every physical quantity to be in range, unknown keys are rejected with the nearest valid key, and
//! every error names the file, the line and column (TOML) or the field path (JSON), and the field.
//!
//! Modules: [`schema`] (the file as written), `build` (scene and world), `body` (one body), `shape`
//! (its shape or compound), `grid`
//! (the generator), [`error`] (messages), `describe` (the account printed by `tumble check`).

mod body;
mod build;
mod describe;
pub mod error;
mod grid;
mod mjcf_world;
mod robot;
pub mod schema;
mod shape;

pub use error::{ErrorDetail, LineCol, SceneError};
pub use mjcf_world::mjcf_world_text;

use crate::world::World;
use std::io::Read;
use std::path::Path;

/// Largest TOML scene file read (bytes): parsing TOML costs 30–50× the file size in memory.
pub const MAX_TOML_BYTES: u64 = 64 << 20;
/// Largest JSON scene file read (bytes).
pub const MAX_JSON_BYTES: u64 = 512 << 20;
/// Largest number of bodies a scene may have (explicit plus generated).
pub const MAX_BODIES: u64 = 10_000_000;
/// Largest initial distance of a centre of mass from the world origin (m).
pub const MAX_POSITION: f64 = 1e10;
/// Largest initial speed (m/s).
pub const MAX_SPEED: f64 = 1e8;
/// Largest gravitational acceleration of a body, `|gravity_scale · g|` (m/s²): the bound on `[world]`'s gravity.
pub const MAX_GRAVITY: f64 = 1e6;
/// Largest initial angular speed (rad/s).
pub const MAX_ANGULAR_SPEED: f64 = 1e8;
/// Quaternions with `| |q| − 1 |` up to this are normalised silently (round-off in the file).
pub const QUAT_SILENT_TOLERANCE: f64 = 1e-9;
/// Quaternions with `| |q| − 1 |` up to this are normalised with a warning; beyond it, an error.
pub const QUAT_WARN_TOLERANCE: f64 = 1e-3;

/// The built-in demo scene's text (`scenes/demo.toml`).
pub const DEMO_TOML: &str = include_str!("../../../../scenes/demo.toml");

/// The syntax of a scene file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Toml,
    Json,
}

impl Format {
    /// The format a path's extension names (`.toml`, `.json`, any case).
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "toml" => Some(Format::Toml),
            "json" => Some(Format::Json),
            _ => None,
        }
    }

    /// The largest file of this format that is read (bytes).
    pub fn max_bytes(self) -> u64 {
        match self {
            Format::Toml => MAX_TOML_BYTES,
            Format::Json => MAX_JSON_BYTES,
        }
    }
}

/// A loaded, validated scene.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The world, ready to step.
    pub world: World,
    /// Where it came from: the file path as given, or `<built-in demo>`.
    pub origin: String,
    /// Things the loader noticed but accepted (an empty scene, a quaternion normalised, ...),
    /// each formatted like an error message: `<file>:<line>:<col>: <field path>: <text>`.
    pub warnings: Vec<String>,
}

/// Loads a scene file (`.toml` or `.json`, by extension).
///
/// The size is checked before reading ([`MAX_TOML_BYTES`], [`MAX_JSON_BYTES`]); the text must be
/// UTF-8 (a leading byte-order mark is stripped).
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let origin = path.display().to_string();
    if path.extension().is_some_and(|e| e == "xml" || e == "mjcf") {
        return load_mjcf_world(path);
    }
    let Some(format) = Format::from_path(path) else {
        let ext = path.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_default();
        return Err(SceneError::file(&origin, "cannot tell the format from the file name")
            .got(if ext.is_empty() { "no extension".to_string() } else { format!(".{ext}") })
            .hint("scene files end in .toml or .json"));
    };
    let cannot_read = |e: std::io::Error| SceneError::file(&origin, format!("cannot read: {e}"));
    let meta = std::fs::metadata(path).map_err(cannot_read)?;
    if meta.is_dir() {
        return Err(SceneError::file(&origin, "cannot read: is a directory"));
    }
    let cap = format.max_bytes();
    if meta.len() > cap {
        return Err(too_large(&origin, format, meta.len()));
    }
    let mut bytes = Vec::new();
    // `take` guards against a file that grows between the metadata and the read
    std::fs::File::open(path).and_then(|f| f.take(cap + 1).read_to_end(&mut bytes)).map_err(cannot_read)?;
    if bytes.len() as u64 > cap {
        return Err(too_large(&origin, format, bytes.len() as u64));
    }
    let text = decode_utf8(&origin, bytes)?;
    from_str(&text, &origin, format)
}

/// An MJCF file as a whole world, as MuJoCo's `simulate` runs it (`tumble run X.xml`): its
/// `<option>` as `[world]`, the geometry fixed to the world as fixed bodies, the free bodies
/// without child bodies as moving bodies, and the rest of the tree as one robot (`[[robot]]
/// mjcf`), its actuators at `ctrl = 0` (module `mjcf_world`).
pub fn load_mjcf_world(path: &Path) -> Result<Scene, SceneError> {
    load_mjcf_world_from(path, None)
}

/// [`load_mjcf_world`] from the state and controls of the file's `<keyframe><key>` named
/// `keyframe` (or an unnamed key's index), `None`: from `qpos0` at rest (`tumble run X.xml
/// --keyframe NAME`).
pub fn load_mjcf_world_from(path: &Path, keyframe: Option<&str>) -> Result<Scene, SceneError> {
    let origin = path.display().to_string();
    let (text, mut warnings) = mjcf_world_text(path, keyframe)?;
    let mut scene = from_str(&text, &origin, Format::Json)?;
    warnings.append(&mut scene.warnings);
    scene.warnings = warnings;
    Ok(scene)
}

fn too_large(origin: &str, format: Format, len: u64) -> SceneError {
    let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
    let (name, why) = match format {
        Format::Toml => {
            ("TOML", "parsing TOML takes 30–50× the file's size in memory; use JSON or `[[grid]]` for big scenes")
        }
        Format::Json => ("JSON", "a scene this large would not fit in memory once loaded"),
    };
    SceneError::file(
        origin,
        format!("file too large: the limit for {name} scenes is {:.0} MiB", mib(format.max_bytes())),
    )
    .got(format!("{len} bytes = {:.1} MiB", mib(len)))
    .hint(why)
}

/// The file's text; invalid UTF-8 is reported with the line and column of the first bad byte.
fn decode_utf8(origin: &str, bytes: Vec<u8>) -> Result<String, SceneError> {
    String::from_utf8(bytes).map_err(|e| {
        let valid = e.utf8_error().valid_up_to();
        let bytes = e.as_bytes();
        let prefix = std::str::from_utf8(&bytes[..valid]).unwrap_or("");
        let src = error::Source { origin, text: prefix, format: Format::Json };
        SceneError::file(origin, "the file is not valid UTF-8 text")
            .got(format!("byte 0x{:02x} at offset {valid}", bytes.get(valid).copied().unwrap_or(0)))
            .hint("save the scene as UTF-8")
            .at(src.line_col(valid))
    })
}

/// Parses and validates a scene from text. `origin` names it in messages (a path, or `<stdin>`).
/// A leading UTF-8 byte-order mark is stripped.
pub fn from_str(text: &str, origin: &str, format: Format) -> Result<Scene, SceneError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let src = error::Source { origin, text, format };
    let doc = match format {
        Format::Toml => parse_toml(&src)?,
        Format::Json => parse_json(&src)?,
    };
    build::build(&src, doc)
}

fn parse_toml(src: &error::Source) -> Result<schema::SceneDoc, SceneError> {
    let de = toml::Deserializer::parse(src.text).map_err(|e| src.toml_error(&e, String::new()))?;
    let _spans = schema::SpanGuard::enable();
    let doc: schema::Table<schema::SceneDoc> =
        serde_path_to_error::deserialize(de).map_err(|e| src.toml_error(e.inner(), error::path_text(e.path())))?;
    Ok(doc.0)
}

fn parse_json(src: &error::Source) -> Result<schema::SceneDoc, SceneError> {
    if src.text.trim().is_empty() {
        return Ok(schema::SceneDoc::default());
    }
    let mut de = serde_json::Deserializer::from_str(src.text);
    let doc: schema::Table<schema::SceneDoc> =
        serde_path_to_error::deserialize(&mut de).map_err(|e| src.json_error(e.inner(), error::path_text(e.path())))?;
    de.end().map_err(|e| src.json_error(&e, String::new()))?;
    Ok(doc.0)
}

/// The built-in demo scene (`scenes/demo.toml`): a box with principal moments 1, 2, 2.6 kg·m² spun
/// near its intermediate axis, which flips every few seconds (the Dzhanibekov effect), beside the
/// same box spun about its stable major axis, both held in place by `gravity_scale = 0`; below
/// them a floor, onto which a box, a capsule, a cylinder and a ball are thrown and come to rest.
pub fn demo() -> Scene {
    // the embedded text is fixed at compile time and loaded by the tests
    from_str(DEMO_TOML, "<built-in demo>", Format::Toml).expect("the embedded demo scene is valid")
}

impl Scene {
    /// A human-readable account of what was understood (for `tumble check`).
    pub fn describe(&self) -> String {
        describe::describe(self)
    }
}

#[cfg(test)]
mod tests;
