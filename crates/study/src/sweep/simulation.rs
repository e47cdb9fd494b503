//! The real case runner: one DEM simulation per case, single-threaded (cases run side by
//! side instead, which scales better than threads inside a 3000-particle run).

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use super::runner::CaseRunner;
use case::SweepCase;
use files::CaseSummary;
use run::{run_case_from, RunOptions, RunOutcome, Start};

/// What a case stopped by the `stop` flag reports as its error.
pub const STOPPED: &str = "stopped by a signal; its checkpoint will be resumed";

/// Runs each case with [`run_case_from`], resuming its own checkpoints.
#[derive(Debug, Clone)]
pub struct SimulationRunner {
    /// Write each case's plots and frames too (slower; the study's report does not need them).
    pub pictures: bool,
    /// When set (by a signal handler), running cases checkpoint and stop after their current
    /// protocol chunk, and cases not yet started are not started.
    pub stop: Option<Arc<AtomicBool>>,
    /// Worker threads of each case (1 by default: cases side by side use the cores better;
    /// results do not depend on it).
    pub threads: usize,
    /// What every case starts from: its fill (the default), or one saved bed for all
    /// ([`super::plan_from_bed`] must have made the plan from the same bed).
    pub start: Arc<Start>,
}

impl Default for SimulationRunner {
    fn default() -> Self {
        Self {
            pictures: true,
            stop: None,
            threads: 1,
            start: Arc::new(Start::Fill),
        }
    }
}

impl CaseRunner for SimulationRunner {
    fn run(&self, case: &SweepCase, dir: &Path) -> Result<CaseSummary, String> {
        if self
            .stop
            .as_ref()
            .is_some_and(|flag| flag.load(Ordering::Relaxed))
        {
            return Err(STOPPED.to_string());
        }
        let options = RunOptions {
            threads: self.threads.max(1),
            resume: true,
            pictures: self.pictures,
            stop: self.stop.clone(),
            ..RunOptions::default()
        };
        match run_case_from(&case.case, dir, &options, &self.start) {
            Ok(RunOutcome::Finished(summary)) => Ok(*summary),
            Ok(RunOutcome::Interrupted) => Err(STOPPED.to_string()),
            Err(e) => Err(e.to_string()),
        }
    }
}
