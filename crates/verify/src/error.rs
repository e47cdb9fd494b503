//! Errors of the verification suite: an engine refusal, a run that never produced the event it
//! waited for, or a state from which a measurement could not be read.

use dem::wall::WallError;
use dem::DemError;

/// Why a verification case could not produce its measurements.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum VerifyError {
    /// The engine refused the set-up or stopped the run.
    #[error("engine: {0}")]
    Engine(#[from] DemError),
    /// A wall could not be built.
    #[error("wall: {0}")]
    Wall(#[from] WallError),
    /// The awaited event (separation, stop, end of sliding) did not happen within the step budget.
    #[error("{what} did not happen within {steps} steps")]
    NoEvent {
        /// What was awaited.
        what: &'static str,
        /// Steps taken before giving up.
        steps: u64,
    },
    /// A measured quantity could not be read from the engine's state.
    #[error("{what} could not be read: {reason}")]
    Measurement {
        /// What was to be read.
        what: &'static str,
        /// Why it could not.
        reason: String,
    },
}
