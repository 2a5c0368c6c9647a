//! A request to stop, from SIGTERM or SIGINT (issue #68): `whisker trials` registers the
//! signals on [`flag`] (the CLI, through `signal-hook`); a batch then starts no new trial,
//! and the long loops of a run (each whisk of the closed loop, each update of the maze and
//! of navigation, each second of a scripted run) call [`check`], so a running trial stops
//! within one step with [`Error::Interrupted`] and is not journalled. Nothing registers the
//! signals for the other commands, which keep the default (the process ends at once, and
//! their outputs are written atomically).

use crate::error::{Error, Result};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, LazyLock};

/// The signal received (0: none).
static SIGNAL: LazyLock<Arc<AtomicUsize>> = LazyLock::new(|| Arc::new(AtomicUsize::new(0)));

/// The flag a signal handler sets to the signal's number.
pub fn flag() -> Arc<AtomicUsize> {
    SIGNAL.clone()
}

/// The signal that asked to stop, if one did.
pub fn requested() -> Option<i32> {
    match SIGNAL.load(Ordering::SeqCst) {
        0 => None,
        s => Some(s as i32),
    }
}

/// Asks to stop as `signal` would (tests, and callers that stop a batch themselves).
pub fn request(signal: i32) {
    SIGNAL.store(signal as usize, Ordering::SeqCst);
}

/// [`Error::Interrupted`] once a signal asked to stop.
pub fn check() -> Result {
    match requested() {
        Some(s) => Err(Error::interrupted(s)),
        None => Ok(()),
    }
}

/// The signal's name.
pub use crate::error::signal_name as name;
