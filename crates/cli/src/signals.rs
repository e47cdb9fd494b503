//! SIGTERM and Ctrl-C stop a run or a study cleanly: the running cases write a checkpoint
//! after their current protocol chunk and the process exits with [`crate::exit_codes::EXIT_STOPPED`].
//!
//! Slurm sends SIGTERM at a job's time limit and on `scancel`, then SIGKILL after its
//! `KillWait` (30 s by default); a protocol chunk takes milliseconds, so the checkpoint is
//! written well inside that grace. A second Ctrl-C ends the process at once.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// A flag that SIGTERM and SIGINT set. Where the handlers cannot be installed the flag
/// stays false and the signals keep their default action (end the process), which loses
/// at most the work since the last periodic checkpoint.
pub fn stop_flag() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    #[cfg(unix)]
    {
        use signal_hook::consts::{SIGINT, SIGTERM};
        use signal_hook::flag;
        // Registered first, so it sees the flag before the second handler sets it: a
        // second Ctrl-C after the first ends the process with 130 (128 + SIGINT).
        let _ = flag::register_conditional_shutdown(SIGINT, 130, Arc::clone(&flag));
        for signal in [SIGTERM, SIGINT] {
            if let Err(e) = flag::register(signal, Arc::clone(&flag)) {
                tracing::warn!("cannot handle signal {signal}: {e}");
            }
        }
    }
    flag
}

/// Ends the process quietly, as other command-line tools do, when what it prints goes to a
/// pipe whose reader has gone (`hopperflow check CASE | head`). Rust ignores SIGPIPE, so a
/// print would fail and panic instead; this restores the signal's default action (end the
/// process) through a handler that emulates it. Every output file is written before the
/// summary lines are printed, so nothing is lost.
pub fn quiet_broken_pipe() {
    #[cfg(unix)]
    {
        let always = Arc::new(AtomicBool::new(true));
        if let Err(e) =
            signal_hook::flag::register_conditional_default(signal_hook::consts::SIGPIPE, always)
        {
            tracing::warn!("cannot handle SIGPIPE: {e}");
        }
    }
}
