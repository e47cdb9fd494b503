//! The real case runner: one DEM simulation per case, single-threaded (cases run side by
//! side instead, which scales better than threads inside a 3000-particle run).

use std::path::Path;

use super::runner::CaseRunner;
use crate::config::SweepCase;
use crate::run::{run_case, RunOptions, RunOutcome};
use crate::summary::CaseSummary;

/// Runs each case with [`run_case`], resuming its own checkpoints.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SimulationRunner {
    /// Write each case's plots and frames too (slower; the study's report does not need them).
    pub pictures: bool,
}

impl Default for SimulationRunner {
    fn default() -> Self {
        Self { pictures: true }
    }
}

impl CaseRunner for SimulationRunner {
    fn run(&self, case: &SweepCase, dir: &Path) -> Result<CaseSummary, String> {
        let options = RunOptions {
            threads: 1,
            resume: true,
            pictures: self.pictures,
            ..RunOptions::default()
        };
        match run_case(&case.case, dir, &options) {
            Ok(RunOutcome::Finished(summary)) => Ok(*summary),
            Ok(RunOutcome::Interrupted) => {
                Err("the run stopped early; its checkpoint will be resumed".to_string())
            }
            Err(e) => Err(e.to_string()),
        }
    }
}
