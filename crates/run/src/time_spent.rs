//! The wall-clock time a run has cost, by phase of the protocol and over every process that
//! worked on it: a run killed and resumed is timed whole (`timing.json`'s `run`), each
//! checkpoint carrying the time spent up to it.

use super::protocol::Phase;

/// Wall-clock time a run has spent up to a checkpoint, over every process that worked on it:
/// each earlier process's share up to the checkpoint it left, this process's up to now.
/// Work redone after a kill (from the last checkpoint to the kill) is counted once.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TimeSpent {
    /// Wall-clock time from each process's start to the checkpoint, summed [s].
    pub wall: f64,
    /// The same by protocol phase [s].
    pub protocol: ProtocolTime,
    /// Processes whose time is counted, this one included [-].
    pub processes: u32,
    /// Whether some earlier process's time is missing: it left a checkpoint written before
    /// checkpoints recorded the time spent.
    pub partial: bool,
}

impl TimeSpent {
    /// This record followed by a process that spent `wall` [s], `protocol` by phase.
    pub fn then(self, wall: f64, protocol: ProtocolTime) -> Self {
        Self {
            wall: self.wall + wall,
            protocol: self.protocol.plus(protocol),
            processes: self.processes + 1,
            partial: self.partial,
        }
    }

    /// What is known before a process resumed from a checkpoint that did not record it.
    pub fn unknown() -> Self {
        Self {
            partial: true,
            ..Self::default()
        }
    }
}

/// Wall-clock time in each phase of the protocol, the probes, pictures and checkpoints of
/// each chunk included [s].
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ProtocolTime {
    /// Pouring the particles in [s].
    pub fill: f64,
    /// Waiting for the bed to come to rest [s].
    pub settle: f64,
    /// From the gate's opening to the stop [s].
    pub discharge: f64,
}

impl ProtocolTime {
    /// Adds `secs` [s] spent in a chunk that started in `phase`.
    pub(crate) fn add(&mut self, phase: Phase, secs: f64) {
        match phase {
            Phase::Fill { .. } => self.fill += secs,
            Phase::Settle { .. } | Phase::Slip { .. } | Phase::Resettle { .. } => {
                self.settle += secs
            }
            Phase::Discharge { .. }
            | Phase::Pulse { .. }
            | Phase::Lift { .. }
            | Phase::Rest { .. }
            | Phase::Done { .. } => self.discharge += secs,
        }
    }

    /// The sum of two records, phase by phase.
    pub fn plus(self, other: Self) -> Self {
        Self {
            fill: self.fill + other.fill,
            settle: self.settle + other.settle,
            discharge: self.discharge + other.discharge,
        }
    }
}
