//! Running one hopper case end to end: protocol, checkpoints, measurements and outputs.

mod outputs;
mod protocol;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use crate::config::Case;
use crate::output::{write_atomic, write_json_atomic, OutputError};
use crate::summary::CaseSummary;

pub use protocol::{outlet_geometry, CaseRun, Frame, Phase, RunState};

/// Name of the checkpoint file inside a run directory.
pub const CHECKPOINT_FILE: &str = "checkpoint.bin";
/// Name of the summary; its presence marks a finished case.
pub const SUMMARY_FILE: &str = "summary.json";

/// Why a run failed.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The engine stopped (NaN, excessive overlap, bad set-up).
    #[error("simulation: {0}")]
    Engine(#[from] dem::DemError),
    /// A probe refused its input.
    #[error("measurement: {0}")]
    Measure(#[from] crate::measure::MeasureError),
    /// The analysis of the measurements failed.
    #[error("analysis: {0}")]
    Analysis(#[from] analysis::AnalysisError),
    /// Writing an output failed.
    #[error("output: {0}")]
    Output(#[from] OutputError),
    /// A checkpoint could not be read or written.
    #[error("checkpoint {path}: {reason}")]
    Checkpoint {
        /// The checkpoint file.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
    /// The hopper could not take all particles.
    #[error("could only insert {inserted} of {total} particles: no free space in the insertion band for 1 s")]
    CannotFill {
        /// Particles inserted.
        inserted: usize,
        /// Particles requested.
        total: usize,
    },
    /// The output directory could not be created.
    #[error("cannot create output directory {path}: {source}")]
    Directory {
        /// The directory.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
}

/// Progress of a run, for progress bars.
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    /// "fill", "settle", "discharge" or "done".
    pub phase: &'static str,
    /// Simulated time [s].
    pub time: f64,
    /// Particles in the simulation.
    pub particles: usize,
    /// Particles inserted or discharged so far, out of the case's count.
    pub fraction: f64,
    /// Particle-steps per second of wall time since the last report.
    pub particle_steps_per_second: f64,
}

/// A progress callback, shared with the thread that draws the bar.
pub type ProgressSink = Arc<dyn Fn(&Progress) + Send + Sync>;

/// How to run a case.
#[derive(Clone)]
pub struct RunOptions {
    /// Worker threads of the engine (results do not depend on it).
    pub threads: usize,
    /// Continue from a checkpoint or a finished summary in the output directory.
    pub resume: bool,
    /// Called after every protocol chunk.
    pub progress: Option<ProgressSink>,
    /// Write pictures and snapshots (plots, frames, VTU). Studies may turn them off.
    pub pictures: bool,
    /// Stop after this many protocol chunks (testing interruptions); `None` runs to the end.
    pub chunk_limit: Option<u64>,
}

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            threads: 1,
            resume: true,
            progress: None,
            pictures: false,
            chunk_limit: None,
        }
    }
}

/// What `run_case` ended with.
#[derive(Debug)]
pub enum RunOutcome {
    /// The case finished; its summary.
    Finished(Box<CaseSummary>),
    /// Stopped early by `chunk_limit`; a checkpoint was written.
    Interrupted,
}

fn phase_name(p: Phase) -> &'static str {
    match p {
        Phase::Fill { .. } => "fill",
        Phase::Settle { .. } => "settle",
        Phase::Discharge { .. } => "discharge",
        Phase::Done { .. } => "done",
    }
}

fn read_checkpoint(path: &Path) -> Result<RunState, RunError> {
    let bytes = std::fs::read(path).map_err(|e| RunError::Checkpoint {
        path: path.into(),
        reason: e.to_string(),
    })?;
    postcard::from_bytes(&bytes).map_err(|e| RunError::Checkpoint {
        path: path.into(),
        reason: format!("unreadable ({e}); delete it to start the case afresh"),
    })
}

fn write_checkpoint(path: &Path, run: &mut CaseRun) -> Result<(), RunError> {
    let bytes = postcard::to_allocvec(run.checkpoint()).map_err(|e| RunError::Checkpoint {
        path: path.into(),
        reason: e.to_string(),
    })?;
    Ok(write_atomic(path, &bytes)?)
}

/// Runs `case` into `out_dir`, writing the resolved case, measurements, plots and
/// `summary.json` (last). With `resume`, a finished case returns its saved summary and a
/// checkpointed one continues from the checkpoint, bit-identically.
pub fn run_case(case: &Case, out_dir: &Path, options: &RunOptions) -> Result<RunOutcome, RunError> {
    std::fs::create_dir_all(out_dir).map_err(|source| RunError::Directory {
        path: out_dir.into(),
        source,
    })?;
    let case_text = case.to_toml_string();
    let hash = outputs::config_hash(&case_text);
    let summary_path = out_dir.join(SUMMARY_FILE);
    let checkpoint_path = out_dir.join(CHECKPOINT_FILE);
    if options.resume && summary_path.exists() {
        if let Ok(text) = std::fs::read_to_string(&summary_path) {
            if let Ok(s) = serde_json::from_str::<CaseSummary>(&text) {
                if s.config_hash == hash {
                    return Ok(RunOutcome::Finished(Box::new(s)));
                }
            }
        }
    }
    // The resolved case, headed by the program version; the seed is one of its keys.
    let header = format!(
        "# Resolved by hopperflow {}; config hash {hash}\n",
        env!("CARGO_PKG_VERSION")
    );
    write_atomic(
        out_dir.join("case.toml"),
        format!("{header}{case_text}").as_bytes(),
    )?;

    let mut run = match (options.resume, checkpoint_path.exists()) {
        (true, true) => {
            let state = read_checkpoint(&checkpoint_path)?;
            CaseRun::resume(case, state, options.threads)?
        }
        _ => CaseRun::new(case, options.threads)?,
    };
    let started = Instant::now();
    // Where this process's time goes, for timing.json: by protocol phase here, by phase of
    // the step in the engine (which only reads the clock for it, changing no bit).
    let mut protocol_time = ProtocolTime::default();
    run.time_phases(true);
    let mut last_report = (
        Instant::now(),
        run.simulation().steps(),
        run.simulation().particles().len(),
    );
    let mut next_checkpoint = run.simulation().time() + case.output.checkpoint_interval;
    let draw = options.pictures && case.output.plots;
    let mut pictures = outputs::Pictures::new(out_dir, case, draw)?;
    let mut chunks = 0u64;
    loop {
        let phase = run.phase();
        if let Phase::Done { .. } = phase {
            break;
        }
        let chunk_started = Instant::now();
        run.advance()?;
        chunks += 1;
        let t = run.simulation().time();
        pictures.observe(&run)?;
        if case.output.checkpoint_interval > 0.0 && t >= next_checkpoint {
            next_checkpoint = t + case.output.checkpoint_interval;
            write_checkpoint(&checkpoint_path, &mut run)?;
        }
        if let Some(report) = &options.progress {
            let sim = run.simulation();
            let elapsed = last_report.0.elapsed().as_secs_f64();
            let psteps = (sim.steps() - last_report.1) as f64
                * 0.5
                * (sim.particles().len() + last_report.2) as f64;
            let total = case.particles.count as f64;
            let fraction = match run.phase() {
                Phase::Fill { inserted, .. } => inserted as f64 / total,
                Phase::Settle { .. } => 1.0,
                Phase::Discharge { .. } | Phase::Done { .. } => {
                    run.state.discharged_mass / (total_mass(case)).max(f64::MIN_POSITIVE)
                }
            };
            report(&Progress {
                phase: phase_name(run.phase()),
                time: t,
                particles: sim.particles().len(),
                fraction,
                particle_steps_per_second: if elapsed > 0.0 { psteps / elapsed } else { 0.0 },
            });
            last_report = (Instant::now(), sim.steps(), sim.particles().len());
        }
        protocol_time.add(phase, chunk_started.elapsed().as_secs_f64());
        if options.chunk_limit.is_some_and(|limit| chunks >= limit) {
            write_checkpoint(&checkpoint_path, &mut run)?;
            return Ok(RunOutcome::Interrupted);
        }
    }
    let summary = outputs::finish(&run, out_dir, &hash, draw)?;
    let engine = run.simulation().phase_times().unwrap_or_default();
    write_json_atomic(
        out_dir.join("timing.json"),
        &serde_json::json!({
            "wall_time_s": started.elapsed().as_secs_f64(),
            "steps": run.simulation().steps(),
            "threads": options.threads,
            "protocol_s": protocol_time,
            "engine_s": engine,
        }),
    )?;
    write_json_atomic(&summary_path, &summary)?;
    let _ = std::fs::remove_file(&checkpoint_path);
    Ok(RunOutcome::Finished(Box::new(summary)))
}

/// Wall-clock time of this process in each phase of the protocol, the probes, pictures and
/// checkpoints of each chunk included [s]. A resumed run counts only its own part.
#[derive(Debug, Default, Clone, Copy, serde::Serialize)]
struct ProtocolTime {
    /// Pouring the particles in [s].
    fill: f64,
    /// Waiting for the bed to come to rest [s].
    settle: f64,
    /// From the gate's opening to the stop [s].
    discharge: f64,
}

impl ProtocolTime {
    /// Adds `secs` [s] spent in a chunk that started in `phase`.
    fn add(&mut self, phase: Phase, secs: f64) {
        match phase {
            Phase::Fill { .. } => self.fill += secs,
            Phase::Settle { .. } => self.settle += secs,
            Phase::Discharge { .. } | Phase::Done { .. } => self.discharge += secs,
        }
    }
}

/// Mass of all particles of a case, estimated from the mean sphere volume [kg].
fn total_mass(case: &Case) -> f64 {
    case.particles.total_volume() * case.particles.material.density
}
