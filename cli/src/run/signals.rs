//! Signals and exit statuses of `geopid run`.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use signal_hook::consts::{SIGINT, SIGTERM};

/// The exit status of a run stopped by a signal: 128 + its number, as a
/// shell reports it.
pub const EXIT_SIGINT: u8 = 130;
/// See [`EXIT_SIGINT`].
pub const EXIT_SIGTERM: u8 = 143;
/// The status of a run whose output pipe was closed by its reader (128 +
/// SIGPIPE), as `yes | head` reports it.
pub const EXIT_SIGPIPE: u8 = 141;

/// The flags SIGINT and SIGTERM set: `cancel` (either), and which one.
pub type SignalFlags = (Arc<AtomicBool>, Arc<AtomicBool>, Arc<AtomicBool>);

/// SIGINT and SIGTERM set `cancel` (and say which); the loop stops at the
/// current step and the files are closed. A second signal while the first
/// is being handled ends the process at once.
pub fn install_signal_flags() -> std::io::Result<SignalFlags> {
    let cancel = Arc::new(AtomicBool::new(false));
    let by_int = Arc::new(AtomicBool::new(false));
    let by_term = Arc::new(AtomicBool::new(false));
    for (sig, which) in [(SIGINT, &by_int), (SIGTERM, &by_term)] {
        let reg = |r: std::io::Result<signal_hook::SigId>| r.map(|_| ());
        reg(signal_hook::flag::register_conditional_shutdown(
            sig,
            128 + sig,
            Arc::clone(&cancel),
        ))?;
        reg(signal_hook::flag::register(sig, Arc::clone(&cancel)))?;
        reg(signal_hook::flag::register(sig, Arc::clone(which)))?;
    }
    Ok((cancel, by_int, by_term))
}
