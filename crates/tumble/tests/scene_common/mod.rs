//! Helpers shared by the scene tests: write a scene to a temporary file, load it, return the message.
#![allow(dead_code)]

use std::path::PathBuf;
use tumble::scene::{self, Scene};

/// The first lines of most bad TOML scenes: line 2 opens the body, line 3 names it, line 4 is free.
pub const BODY: &str = "version = 1\n[[body]]\nname = \"a\"\n";

/// A scene written to a fresh temporary directory under `name`.
pub struct Written {
    _dir: tempfile::TempDir,
    pub path: PathBuf,
}

pub fn write(name: &str, bytes: &[u8]) -> Written {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).expect("write the scene");
    Written { _dir: dir, path }
}

/// Loads `text` as `bad.toml`.
pub fn load_toml(text: &str) -> Result<Scene, String> {
    let w = write("bad.toml", text.as_bytes());
    scene::load(&w.path).map_err(|e| e.to_string())
}

/// Loads `text` as `bad.json`.
pub fn load_json(text: &str) -> Result<Scene, String> {
    let w = write("bad.json", text.as_bytes());
    scene::load(&w.path).map_err(|e| e.to_string())
}

/// The error message of a TOML scene that must be rejected.
pub fn toml_error(text: &str) -> String {
    match load_toml(text) {
        Ok(_) => panic!("accepted a bad scene:\n{text}"),
        Err(e) => e,
    }
}

/// The error message of a JSON scene that must be rejected.
pub fn json_error(text: &str) -> String {
    match load_json(text) {
        Ok(_) => panic!("accepted a bad scene:\n{text}"),
        Err(e) => e,
    }
}

/// Asserts that `message` contains every part.
#[track_caller]
pub fn assert_has(message: &str, parts: &[&str]) {
    for part in parts {
        assert!(message.contains(part), "expected {part:?} in the message:\n{message}");
    }
}

/// The warnings of a TOML scene that must be accepted.
pub fn toml_warnings(text: &str) -> Vec<String> {
    match load_toml(text) {
        Ok(scene) => scene.warnings,
        Err(e) => panic!("rejected a valid scene:\n{text}\n{e}"),
    }
}
