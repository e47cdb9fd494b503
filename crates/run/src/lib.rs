//! Running one hopper case end to end: protocol, checkpoints, measurements and outputs.

#![warn(missing_docs)]

mod bed;
pub mod bench;
mod checkpoint;
mod composition;
mod container;
pub mod cost;
mod fields;
mod fill;
mod orientations;
mod outputs;
mod packing;
mod pile_outputs;
mod protocol;
mod remaining;
mod residence;
mod simulation;
mod start;
mod time_spent;
mod unclog;
mod wall_forces;
mod wall_pressure;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use case::Case;

use files::CaseSummary;
use files::{remove_stale_temporaries, write_atomic, write_json_atomic, OutputError};
use files::{StartRecord, CASE_FILE, CHECKPOINT_FILE, START_FILE, SUMMARY_FILE};

pub use bed::{
    bed_header, check_bed, check_bed_case, check_save_bed, read_bed, Bed, BedError, BedHeader,
    BedReuse, SaveBedError, BED_MAGIC,
};
pub use checkpoint::{
    case_changes, config_hash, read_checkpoint_header, CheckpointError, CheckpointHeader,
    KeyChange, MAGIC as CHECKPOINT_MAGIC,
};
pub use container::{
    adopt_walls, build_container_walls, build_cuboid_walls, build_cylinder_walls, build_heap_walls,
    build_mesh_walls, build_slab_walls, cuboid_outline, cuboid_wall_polygons, cylinder_outline,
    cylinder_wall_polygons, gate_outline, heap_outline, heap_wall_polygons, mesh_outline,
    mesh_wall_polygons, slab_outline, vertical_cut, wall_names, ContainerWalls, CuboidWalls,
    CylinderWalls, HeapWalls, MeshWalls, SlabWalls, MESH_WALL_INDEX, WALL_NAMES,
};
pub use fill::{
    insert_silo_batch, insert_slab_batch, inside_slab, Draw, FillRegion, Inserted, ParticleDraws,
};
pub use outputs::{fit_radial, write_radial_profiles};
pub use packing::{
    packing_count, read_packing, PackedParticle, Packing, PackingError, PackingPlace,
    PackingProblem, PACKING_COLUMNS, PACKING_OVERLAP_FRACTION, RADIUS_TOLERANCE,
    REQUIRED_PACKING_COLUMNS,
};
pub use protocol::{outlet_geometry, CaseRun, OwnedSnapshot, Phase, RunState};
pub use simulation::{
    case_simulation, case_simulation_by_component, contact_laws, lattice_bed, sample_radius,
    slab_simulation,
};
pub use start::{Start, StartError};
pub use time_spent::{ProtocolTime, TimeSpent};
pub use unclog::{avalanches, lapses, Avalanche, Clog, UnclogRecord, AVALANCHE_COLUMNS};

/// Why a run failed.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The engine stopped (NaN, excessive overlap, bad set-up).
    #[error("simulation: {0}")]
    Engine(#[from] dem::DemError),
    /// A probe refused its input.
    #[error("measurement: {0}")]
    Measure(#[from] measure::MeasureError),
    /// The analysis of the measurements failed.
    #[error("analysis: {0}")]
    Analysis(#[from] analysis::AnalysisError),
    /// A quantity this kind of container does not measure (yet).
    #[error("not measured: {0}")]
    NotMeasured(&'static str),
    /// Writing an output failed.
    #[error("output: {0}")]
    Output(#[from] OutputError),
    /// A checkpoint to resume from cannot be used: truncated, corrupt, foreign or from
    /// another version. Nothing was written.
    #[error("{path} {error}; nothing was changed")]
    BadCheckpoint {
        /// The checkpoint file.
        path: PathBuf,
        /// What is wrong with it.
        error: CheckpointError,
    },
    /// A summary to resume from cannot be read. Nothing was written.
    #[error("{path} is not a readable hopperflow summary ({reason}); nothing was changed")]
    BadSummary {
        /// The summary file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// The output directory holds a run of other inputs: resuming it would label its
    /// results with inputs that did not produce them. Nothing was written.
    #[error("{} holds a run of other inputs (per its {file}: config hash {found}, this case's is {expected}){}; nothing was changed", .dir.display(), describe_changes(.changes))]
    OtherInputs {
        /// The output directory.
        dir: PathBuf,
        /// The file that records the other inputs: `summary.json`, `checkpoint.bin` or
        /// `case.toml`.
        file: &'static str,
        /// The config hash found there.
        found: String,
        /// This case's config hash.
        expected: String,
        /// The keys that differ, earlier value first.
        changes: Vec<KeyChange>,
    },
    /// The output directory holds a run that started otherwise (from another bed or
    /// packing, or from its own fill): resuming it would mix two starts. Nothing was written.
    #[error("{} holds a run that started from {} (per its {file}); this run starts from {}; nothing was changed", .dir.display(), files::describe_start(.found.as_ref()), files::describe_start(.expected.as_ref()))]
    OtherStart {
        /// The output directory.
        dir: PathBuf,
        /// The file that records the other start.
        file: &'static str,
        /// What that run started from (`None`: its own fill).
        found: Option<StartRecord>,
        /// What this run starts from.
        expected: Option<StartRecord>,
    },
    /// A saved bed cannot be read, or the case may not reuse it. Nothing was written.
    #[error("{0}")]
    Bed(#[from] BedError),
    /// A packing file is not valid for the case. Nothing was written.
    #[error("{0}")]
    Packing(#[from] PackingError),
    /// A run resumed past its gate's opening was asked to save its bed, which it no longer
    /// has. Nothing was written.
    #[error("the run in {} opened its gate before its checkpoint, and {} holds no bed of this case: the bed can no longer be saved from it; --restart runs the case again and saves it", .dir.display(), .bed_dir.display())]
    BedTooLate {
        /// The output directory.
        dir: PathBuf,
        /// Where the bed was to be saved.
        bed_dir: PathBuf,
    },
    /// The hopper could not take all particles.
    #[error("could only insert {inserted} of {total} particles: no free space in the insertion band for 1 s")]
    CannotFill {
        /// Particles inserted.
        inserted: usize,
        /// Particles requested.
        total: usize,
    },
    /// A benchmark's discharge stopped before the end of its timed window
    /// (`hopperflow bench`): a finished run takes no more steps, so the window cannot be timed.
    #[error("the discharge stopped ({reason:?}) {stopped:.4} s after the gate opened, before the end of the benchmark window ({start:.4}-{end:.4} s after the opening): it needs more particles, or a longer protocol.time_limit or clog_timeout")]
    EndedBeforeWindow {
        /// Why the discharge stopped.
        reason: files::StopReason,
        /// When, after the opening [s].
        stopped: f64,
        /// The window's start after the opening [s].
        start: f64,
        /// The window's end after the opening [s].
        end: f64,
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
    /// Wall time left, at most [s]: the particle-steps the protocol still allows
    /// ([`cost::particle_steps_left`]: the fill estimated, the settling and the discharge to
    /// their limits) at this process's speed so far in the current phase. NaN before a
    /// phase's first report. The discharge usually ends well before its limit.
    pub remaining_at_most: f64,
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
    /// Set from outside (a signal handler: SIGTERM from a scheduler, Ctrl-C) to stop the run
    /// after its current protocol chunk, with a checkpoint written.
    pub stop: Option<Arc<AtomicBool>>,
    /// Save the settled bed into this folder when the gate opens ([`BED_FILE`] and
    /// [`BED_CASE_FILE`], each written atomically, replacing a bed there), for runs that
    /// start from it ([`Start::Bed`]).
    pub save_bed: Option<PathBuf>,
}

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            threads: 1,
            resume: true,
            progress: None,
            pictures: false,
            chunk_limit: None,
            stop: None,
            save_bed: None,
        }
    }
}

/// What `run_case` ended with.
#[derive(Debug)]
pub enum RunOutcome {
    /// The case finished; its summary.
    Finished(Box<CaseSummary>),
    /// Stopped early by `chunk_limit` or the `stop` flag; a checkpoint was written, from
    /// which a resumed run continues bit-identically.
    Interrupted,
}

fn phase_name(p: Phase) -> &'static str {
    match p {
        Phase::Fill { .. } => "fill",
        Phase::Settle { .. } | Phase::Resettle { .. } => "settle",
        Phase::Slip { .. } => "slip",
        Phase::Discharge { .. } => "discharge",
        Phase::Pulse { .. } => "pulse",
        Phase::Lift { .. } => "lift",
        Phase::Rest { .. } => "rest",
        Phase::Done { .. } => "done",
    }
}

/// "; changed keys: a: x -> y, …" for a non-empty list.
fn describe_changes(changes: &[KeyChange]) -> String {
    if changes.is_empty() {
        return String::new();
    }
    let list: Vec<String> = changes.iter().map(ToString::to_string).collect();
    format!("; changed keys: {}", list.join(", "))
}

/// The first line of `case.toml` starts with this, then the version and the hash.
const CASE_HEADER: &str = "# Resolved by hopperflow ";

/// What an output directory already holds of a run of this case.
enum Prior {
    /// Nothing to continue.
    Nothing,
    /// The finished run's summary.
    Finished(Box<CaseSummary>),
    /// A checkpointed run to continue.
    Checkpoint(Box<checkpoint::Checkpoint>),
}

/// The resolved case text of a `case.toml`, without its header line.
fn case_text_of(file_text: &str) -> &str {
    match file_text.strip_prefix(CASE_HEADER) {
        Some(rest) => rest.split_once('\n').map_or("", |(_, body)| body),
        None => file_text,
    }
}

/// What `out_dir` holds that a resume of the case with `case_text` (hash `hash`), started
/// from `start`, may continue, or why it must not: a summary, checkpoint or case file of
/// other inputs or of another start, or a damaged summary or checkpoint. Reads only.
fn prior_run(
    out_dir: &Path,
    case_text: &str,
    hash: &str,
    start: Option<&StartRecord>,
) -> Result<Prior, RunError> {
    let other_start = |file: &'static str, found: Option<StartRecord>| RunError::OtherStart {
        dir: out_dir.into(),
        file,
        found,
        expected: start.cloned(),
    };
    let other = |file: &'static str, found: String, old_text: &str| RunError::OtherInputs {
        dir: out_dir.into(),
        file,
        found,
        expected: hash.to_string(),
        changes: case_changes(old_text, case_text),
    };
    let recorded_case = std::fs::read_to_string(out_dir.join(CASE_FILE)).ok();
    let recorded_text = recorded_case.as_deref().map(case_text_of);

    let summary_path = out_dir.join(SUMMARY_FILE);
    if summary_path.exists() {
        let text = std::fs::read_to_string(&summary_path).map_err(|e| RunError::BadSummary {
            path: summary_path.clone(),
            reason: e.to_string(),
        })?;
        let summary: CaseSummary =
            serde_json::from_str(&text).map_err(|e| RunError::BadSummary {
                path: summary_path.clone(),
                reason: e.to_string(),
            })?;
        if summary.config_hash != hash {
            return Err(other(
                SUMMARY_FILE,
                summary.config_hash,
                recorded_text.unwrap_or(""),
            ));
        }
        if summary.start.as_ref() != start {
            return Err(other_start(SUMMARY_FILE, summary.start));
        }
        return Ok(Prior::Finished(Box::new(summary)));
    }
    let checkpoint_path = out_dir.join(CHECKPOINT_FILE);
    if checkpoint_path.exists() {
        let saved = checkpoint::read_checkpoint(&checkpoint_path).map_err(|error| {
            RunError::BadCheckpoint {
                path: checkpoint_path.clone(),
                error,
            }
        })?;
        let header = &saved.header;
        if header.config_hash != hash || header.case_text != case_text {
            return Err(other(
                CHECKPOINT_FILE,
                header.config_hash.clone(),
                &header.case_text,
            ));
        }
        if header.start.as_ref() != start {
            return Err(other_start(CHECKPOINT_FILE, header.start.clone()));
        }
        return Ok(Prior::Checkpoint(Box::new(saved)));
    }
    // A run killed before its first checkpoint: its start file says how it started (none:
    // from its own fill), if it got as far as its case file.
    let recorded_start = read_start_file(out_dir);
    if recorded_text.is_some() && recorded_start.as_ref() != start {
        return Err(other_start(START_FILE, recorded_start));
    }
    // A run killed before its first checkpoint left only its case file: nothing to continue,
    // but a folder of other inputs all the same.
    if let Some(text) = recorded_text {
        let found = config_hash(text);
        if found != hash {
            return Err(other(CASE_FILE, found, text));
        }
    }
    Ok(Prior::Nothing)
}

/// What a run directory holds that a new run must not silently overwrite.
#[derive(Debug, Clone, PartialEq)]
pub enum Occupant {
    /// A finished run (`summary.json`).
    Finished,
    /// A checkpoint, in words: "an unfinished run (checkpoint in the fill at t = … s, config
    /// hash …)", or "a checkpoint that is truncated: …" for a damaged one.
    Checkpoint(String),
}

/// What `dir` already holds of a run, if anything: what a front end names when it refuses
/// to start a run there without being told to resume or restart. Reads only.
pub fn occupant(dir: &Path) -> Option<Occupant> {
    if dir.join(SUMMARY_FILE).exists() {
        return Some(Occupant::Finished);
    }
    let checkpoint = dir.join(CHECKPOINT_FILE);
    if !checkpoint.exists() {
        return None;
    }
    Some(Occupant::Checkpoint(
        match read_checkpoint_header(&checkpoint) {
            Ok(h) => format!(
                "an unfinished run (checkpoint in the {} at t = {:.4} s, config hash {})",
                h.phase,
                h.time,
                &h.config_hash[..h.config_hash.len().min(12)]
            ),
            Err(e) => format!("a checkpoint that {e}"),
        },
    ))
}

/// Checks, reading only, that `dir` holds nothing that a resumed run of `case` must refuse:
/// a summary, checkpoint or case file of other inputs, or a damaged summary or checkpoint
/// (the errors [`run_case`] would return with `resume`). A missing `dir` is fine.
pub fn check_run_dir(case: &Case, dir: &Path) -> Result<(), RunError> {
    check_run_dir_from(case, dir, &Start::Fill)
}

/// [`check_run_dir`] for a run that starts from `start`: also refuses a folder whose run
/// started otherwise.
pub fn check_run_dir_from(case: &Case, dir: &Path, start: &Start) -> Result<(), RunError> {
    check_run_dir_started(case, dir, start.record().as_ref())
}

/// [`check_run_dir_from`] for the start recorded as `start` (`None`: the fill).
pub fn check_run_dir_started(
    case: &Case,
    dir: &Path,
    start: Option<&StartRecord>,
) -> Result<(), RunError> {
    if !dir.is_dir() {
        return Ok(());
    }
    let text = case.to_toml_string();
    prior_run(dir, &text, &config_hash(&text), start).map(|_| ())
}

/// The start recorded in `dir`'s [`START_FILE`]; `None` when there is none (or it cannot be
/// read, which only a damaged folder shows: then the case file decides).
fn read_start_file(dir: &Path) -> Option<StartRecord> {
    let text = std::fs::read_to_string(dir.join(START_FILE)).ok()?;
    let value: serde_json::Value = serde_json::from_str(&text).ok()?;
    serde_json::from_value(value.get("start")?.clone()).ok()
}

/// Removes what a previous run left in `out_dir`, the files that mark its state first
/// (summary, then checkpoint), so that a restart killed part-way leaves no folder that
/// claims a finished or resumable run of other inputs.
fn clear_previous_run(out_dir: &Path) -> Result<(), RunError> {
    let remove = |path: PathBuf| match std::fs::remove_file(&path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(source) => Err(RunError::Directory { path, source }),
    };
    for name in [
        SUMMARY_FILE,
        CHECKPOINT_FILE,
        CASE_FILE,
        START_FILE,
        "timing.json",
    ]
    .iter()
    .chain(outputs::RESULT_FILES)
    {
        remove(out_dir.join(name))?;
    }
    let snapshots = out_dir.join(outputs::SNAPSHOT_DIR);
    match std::fs::remove_dir_all(&snapshots) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(source) => Err(RunError::Directory {
            path: snapshots,
            source,
        }),
    }
}

/// What a checkpoint written now records of the run.
fn checkpoint_header(
    case: &Case,
    case_text: &str,
    hash: &str,
    run: &CaseRun,
    start: Option<&StartRecord>,
) -> CheckpointHeader {
    CheckpointHeader {
        program_version: env!("CARGO_PKG_VERSION").to_string(),
        config_hash: hash.to_string(),
        seed: case.seed,
        case_text: case_text.to_string(),
        phase: phase_name(run.phase()).to_string(),
        time: run.simulation().time(),
        start: start.cloned(),
    }
}

fn write_checkpoint(
    path: &Path,
    header: &CheckpointHeader,
    run: &CaseRun,
    pictures: &outputs::Pictures,
    spent: &TimeSpent,
) -> Result<(), RunError> {
    Ok(checkpoint::write_checkpoint(
        path,
        header,
        run.checkpoint(),
        &pictures.schedule(),
        spent,
    )?)
}

/// Runs `case` into `out_dir`, writing the resolved case, measurements, plots and
/// `summary.json` (last).
///
/// With `resume`, a finished case returns its saved summary and a checkpointed one
/// continues from the checkpoint, bit-identically; a folder whose summary, checkpoint or
/// case file records other inputs is refused ([`RunError::OtherInputs`]), as is a damaged
/// checkpoint or summary, and then nothing in it is changed. Without `resume` the case
/// starts over, and what a previous run left in the folder is removed first.
///
/// Temporary files that a killed write left behind are removed either way.
pub fn run_case(case: &Case, out_dir: &Path, options: &RunOptions) -> Result<RunOutcome, RunError> {
    run_case_from(case, out_dir, options, &Start::Fill)
}

/// [`run_case`] from `start`: its own fill, a saved bed ([`Start::Bed`]: no fill and no
/// settling, the gate opens at once) or a packing ([`Start::Packing`]: no fill, the
/// particles settle from where the file puts them).
///
/// The start is checked against the case before anything is written: a bed settled under
/// other inputs ([`check_bed`]) or a packing that does not fit the case is refused
/// ([`RunError::Bed`], [`RunError::Packing`]). The run folder records the start (the
/// checkpoints, `summary.json` and [`START_FILE`]), and a resume refuses a folder whose run
/// started otherwise ([`RunError::OtherStart`]).
pub fn run_case_from(
    case: &Case,
    out_dir: &Path,
    options: &RunOptions,
    start: &Start,
) -> Result<RunOutcome, RunError> {
    let case_text = case.to_toml_string();
    let hash = config_hash(&case_text);
    let record = start.record();
    let reuse = match start {
        Start::Fill => None,
        Start::Bed(bed) => Some(check_bed(bed, case)?),
        Start::Packing(packing) => {
            packing.check(case)?;
            None
        }
    };
    let prior = if options.resume && out_dir.is_dir() {
        prior_run(out_dir, &case_text, &hash, record.as_ref())?
    } else {
        Prior::Nothing
    };
    if let Prior::Finished(summary) = prior {
        return Ok(RunOutcome::Finished(summary));
    }
    if let (Some(bed_dir), Prior::Checkpoint(saved)) = (&options.save_bed, &prior) {
        let opened = matches!(saved.header.phase.as_str(), "discharge" | "done");
        let saved_bed = bed_header(bed_dir).is_some_and(|h| bed::is_bed_of(&h, &case_text));
        if opened && !saved_bed {
            return Err(RunError::BedTooLate {
                dir: out_dir.into(),
                bed_dir: bed_dir.clone(),
            });
        }
    }
    std::fs::create_dir_all(out_dir).map_err(|source| RunError::Directory {
        path: out_dir.into(),
        source,
    })?;
    remove_stale_temporaries(out_dir)?;
    remove_stale_temporaries(&out_dir.join(outputs::SNAPSHOT_DIR))?;
    if !options.resume {
        clear_previous_run(out_dir)?;
    }
    // The resolved case, headed by the program version; the seed is one of its keys.
    let header = format!(
        "{CASE_HEADER}{}; config hash {hash}\n",
        env!("CARGO_PKG_VERSION")
    );
    let case_file_text = format!("{header}{case_text}");

    let draw = options.pictures && case.output.plots;
    let mut pictures = outputs::Pictures::new(out_dir, case, draw)?;
    let fresh = matches!(prior, Prior::Nothing);
    // The time earlier processes spent on this run, and where this one takes it up.
    let (earlier, resumed_at) = match &prior {
        Prior::Checkpoint(saved) => (
            saved.spent.unwrap_or_else(TimeSpent::unknown),
            Some(saved.header.time),
        ),
        _ => (TimeSpent::default(), None),
    };
    let mut run = match prior {
        Prior::Checkpoint(saved) => {
            let saved = *saved;
            pictures.resume(saved.pictures);
            CaseRun::resume(case, saved.state, options.threads)?
        }
        _ => match start {
            Start::Fill => CaseRun::new(case, options.threads)?,
            Start::Bed(bed) => CaseRun::from_bed(case, bed.state.clone(), options.threads)?,
            Start::Packing(packing) => CaseRun::from_packing(case, packing, options.threads)?,
        },
    };
    // The start file before the case file: a folder with a case file always says how its
    // run started.
    if fresh {
        if let Some(record) = &record {
            write_json_atomic(
                out_dir.join(START_FILE),
                &start_file(record, start, reuse.as_ref(), (case, &run)),
            )?;
        }
    }
    write_atomic(out_dir.join(CASE_FILE), case_file_text.as_bytes())?;
    if options.save_bed.is_some() {
        run.keep_bed();
    }
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
    let checkpoint_path = out_dir.join(CHECKPOINT_FILE);
    let summary_path = out_dir.join(SUMMARY_FILE);
    let mut next_checkpoint = run.simulation().time() + case.output.checkpoint_interval;
    // This process's wall time [s] and particle-steps in the current phase, for the speed
    // that the remaining time is reckoned at.
    let mut phase_speed = (phase_name(run.phase()), 0.0, 0.0);
    let mut chunks = 0u64;
    loop {
        let phase = run.phase();
        if let Phase::Done { .. } = phase {
            break;
        }
        let chunk_started = Instant::now();
        run.advance()?;
        chunks += 1;
        if let (Some(state), Some(dir)) = (run.take_bed(), &options.save_bed) {
            let bed = BedHeader {
                program_version: env!("CARGO_PKG_VERSION").to_string(),
                config_hash: hash.clone(),
                seed: case.seed,
                case_text: case_text.clone(),
                time: run.simulation().time(),
                particles: run.simulation().particles().len(),
                settled: state.record.settled,
            };
            bed::write_bed(dir, &bed, &state, &case_file_text)?;
        }
        let t = run.simulation().time();
        pictures.observe(&run)?;
        if case.output.checkpoint_interval > 0.0 && t >= next_checkpoint {
            next_checkpoint = t + case.output.checkpoint_interval;
            let header = checkpoint_header(case, &case_text, &hash, &run, record.as_ref());
            let spent = earlier.then(started.elapsed().as_secs_f64(), protocol_time);
            write_checkpoint(&checkpoint_path, &header, &run, &pictures, &spent)?;
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
                Phase::Settle { .. } | Phase::Slip { .. } | Phase::Resettle { .. } => 1.0,
                Phase::Discharge { .. }
                | Phase::Pulse { .. }
                | Phase::Lift { .. }
                | Phase::Rest { .. }
                | Phase::Done { .. } => {
                    run.state.discharged_mass / (total_mass(case)).max(f64::MIN_POSITIVE)
                }
            };
            let phase = run.phase();
            if phase_speed.0 != phase_name(phase) {
                phase_speed = (phase_name(phase), 0.0, 0.0);
            } else {
                phase_speed.1 += elapsed;
                phase_speed.2 += psteps;
            }
            let left =
                cost::particle_steps_left(case, phase, t, sim.steps(), sim.particles().len());
            report(&Progress {
                phase: phase_name(phase),
                time: t,
                particles: sim.particles().len(),
                fraction,
                particle_steps_per_second: if elapsed > 0.0 { psteps / elapsed } else { 0.0 },
                remaining_at_most: if phase_speed.2 > 0.0 {
                    left * phase_speed.1 / phase_speed.2
                } else {
                    f64::NAN
                },
            });
            last_report = (Instant::now(), sim.steps(), sim.particles().len());
        }
        protocol_time.add(phase, chunk_started.elapsed().as_secs_f64());
        let stopped = options
            .stop
            .as_ref()
            .is_some_and(|flag| flag.load(Ordering::Relaxed));
        if stopped || options.chunk_limit.is_some_and(|limit| chunks >= limit) {
            let header = checkpoint_header(case, &case_text, &hash, &run, record.as_ref());
            let spent = earlier.then(started.elapsed().as_secs_f64(), protocol_time);
            write_checkpoint(&checkpoint_path, &header, &run, &pictures, &spent)?;
            return Ok(RunOutcome::Interrupted);
        }
    }
    let mut summary = outputs::finish(&run, out_dir, &hash, draw)?;
    summary.start = record;
    let engine = run.simulation().phase_times().unwrap_or_default();
    let wall = started.elapsed().as_secs_f64();
    let whole = earlier.then(wall, protocol_time);
    // This process's time, and the whole run's over every process that worked on it
    // (`TimeSpent`): a resumed run's own figures leave out what came before its checkpoint.
    write_json_atomic(
        out_dir.join("timing.json"),
        &serde_json::json!({
            "wall_time_s": wall,
            "steps": run.simulation().steps(),
            "threads": options.threads,
            "protocol_s": protocol_time,
            "engine_s": engine,
            "resumed_at_s": resumed_at,
            "run": {
                "wall_time_s": whole.wall,
                "protocol_s": whole.protocol,
                "processes": whole.processes,
                "partial": whole.partial,
            },
        }),
    )?;
    write_json_atomic(&summary_path, &summary)?;
    let _ = std::fs::remove_file(&checkpoint_path);
    Ok(RunOutcome::Finished(Box::new(summary)))
}

/// Mass of all particles of a case, estimated from the mean sphere volume [kg].
fn total_mass(case: &Case) -> f64 {
    case.particles.total_mass()
}

/// The content of [`START_FILE`]: the start's identity (what a resume compares), where it
/// was read from, and for a bed what the reuse changed and what it kept.
fn start_file(
    record: &StartRecord,
    start: &Start,
    reuse: Option<&BedReuse>,
    (case, run): (&Case, &CaseRun),
) -> serde_json::Value {
    let mut value = serde_json::json!({ "start": record });
    match start {
        Start::Fill => {}
        Start::Bed(bed) => {
            let changes: Vec<String> = reuse
                .map(|r| r.changes.iter().map(ToString::to_string).collect())
                .unwrap_or_default();
            value["source"] = bed.path().display().to_string().into();
            value["bed"] = serde_json::json!({
                "config_hash": bed.header().config_hash,
                "time_s": bed.header().time,
                "particles": bed.header().particles,
                "settled": bed.header().settled,
            });
            value["changed_keys"] = changes.into();
            value["walls_rebuilt"] = run.rebuilt_walls().to_vec().into();
            value["kept"] = "positions, velocities, spins and forces of every particle; every \
                particle-particle contact history; the histories of contacts with the walls \
                not rebuilt; the time and step count"
                .into();
        }
        Start::Packing(packing) => {
            value["source"] = packing.source().display().to_string().into();
            value["particles"] = packing.particles().len().into();
            if let Some(material) = packing.material() {
                value["material"] = material.into();
            }
            // A mixture's packing: how many particles of each component it placed.
            if !packing.components().is_empty() {
                let mut counts = serde_json::Map::new();
                for (k, component) in case.particles.components.iter().enumerate() {
                    let n = packing
                        .components()
                        .iter()
                        .filter(|&&c| usize::from(c) == k)
                        .count();
                    counts.insert(component.name.clone(), n.into());
                }
                value["components"] = counts.into();
            }
        }
    }
    value
}
