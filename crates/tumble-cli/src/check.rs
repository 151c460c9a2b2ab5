//! `tumble check SCENE`: load and validate a scene and print what was understood.

use crate::cli::CheckArgs;
use crate::error::{Failure, Status};
use crate::report::Stdout;

/// Prints the scene's description (stdout); exit 0, or 2 with the loader's message.
pub fn check(args: &CheckArgs) -> Result<Status, Failure> {
    let scene = tumble::scene::load(&args.scene).map_err(Failure::bad_input)?;
    let mut text = scene.describe();
    if !text.ends_with('\n') {
        text.push('\n');
    }
    // the description lists the warnings; any it leaves out are added
    let missing: Vec<&String> = scene.warnings.iter().filter(|w| !text.contains(w.as_str())).collect();
    for warning in missing {
        text.push_str(&format!("warning: {warning}\n"));
    }
    Stdout::default().write(&text).map_err(|e| Failure::output(format!("cannot write to standard output: {e}")))?;
    Ok(Status::Success)
}
