//! SIGINT and SIGTERM: the first one asks the run to stop after the current step (it then flushes,
//! closes its files, writes the summary and exits with 130); a second one ends the process at once
//! with status 130.

use signal_hook::consts::{SIGINT, SIGTERM};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Installs the handlers; the flag turns true at the first SIGINT or SIGTERM.
pub fn install() -> std::io::Result<Arc<AtomicBool>> {
    let stop = Arc::new(AtomicBool::new(false));
    for signal in [SIGINT, SIGTERM] {
        // registered first, so it sees the flag as it was before this signal: set means a second signal
        signal_hook::flag::register_conditional_shutdown(signal, 130, Arc::clone(&stop))?;
        signal_hook::flag::register(signal, Arc::clone(&stop))?;
    }
    Ok(stop)
}
