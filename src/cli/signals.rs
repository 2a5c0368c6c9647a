//! SIGTERM and SIGINT during `whisker trials` (issue #68): what Slurm sends at a time
//! limit or on preemption (`KillWait`, 30 s by default, before SIGKILL), and Ctrl-C.
//!
//! The signal sets `whisker_scenario::stop`'s flag: the batch starts no new trial, and
//! each running trial stops at its next whisk (closed loop), update (maze, navigation) or
//! simulated step (scripted run) without being journalled. The batch then exits with 143
//! (SIGTERM) or 130 (SIGINT), printing the command that resumes it. Should a running trial
//! not stop within the grace (`--grace`, default [`GRACE_S`]), a watchdog ends the process
//! with the same code: the journal is consistent either way (each line is appended whole
//! and synced; a line cut short by an exit is dropped on reading), and `--resume` clears
//! and reruns the trials that were running.

use std::time::Duration;
use whisker_scenario::{Error, Result, stop};

/// The default grace (s): within Slurm's default `KillWait` of 30 s.
pub const GRACE_S: f64 = 20.0;

/// Routes SIGTERM and SIGINT to the stop flag and starts the watchdog.
pub fn stop_on_signals(grace: f64) -> Result {
    if !(grace.is_finite() && grace >= 0.0) {
        return Err(Error::Input(format!(
            "--grace: expected a number of seconds ≥ 0, got {grace}"
        )));
    }
    for signal in [signal_hook::consts::SIGTERM, signal_hook::consts::SIGINT] {
        signal_hook::flag::register_usize(signal, stop::flag(), signal as usize)
            .map_err(|e| Error::Failure(format!("cannot handle {}: {e}", stop::name(signal))))?;
    }
    std::thread::spawn(move || {
        let signal = loop {
            if let Some(s) = stop::requested() {
                break s;
            }
            std::thread::sleep(Duration::from_millis(50));
        };
        eprintln!(
            "trials     {} received: no new trial starts; the running ones stop at their next step (within {grace} s)",
            stop::name(signal)
        );
        std::thread::sleep(Duration::from_secs_f64(grace));
        eprintln!(
            "error: the running trials did not stop within {grace} s of {}: leaving them unjournalled (--resume reruns them)",
            stop::name(signal)
        );
        std::process::exit(128 + signal);
    });
    Ok(())
}
