//! `hopperflow study … --slurm`, `--status`, `--task-index` and `--collect`: a study as a
//! Slurm array job with one case per task, its progress, one task, and the collection of the
//! case folders into `results.csv` and the report.
//!
//! The study crate does the work (`study::write_jobs`, `study::case_statuses`); this module turns the flags into its
//! options and prints what it returns.

use std::path::{Path, PathBuf};

use case::SweepPlan;
use clap::Args;
use study::{
    collect_study, run_task, JobsError, SimulationRunner, SlurmOptions, TaskOutcome, TimeLimit,
};

use crate::exit_codes::EXIT_BAD_INPUT;
use crate::exit_codes::EXIT_STOPPED;

/// Slurm options of `hopperflow study`.
#[derive(Args, Clone, Debug, Default)]
pub struct SlurmArgs {
    /// Write a Slurm array job (one case per task) and a report job into OUT/slurm/ instead
    /// of running the study here. Rerun it to write an array of the unfinished cases only.
    #[arg(long)]
    pub slurm: bool,
    /// With --slurm: submit both jobs with sbatch (the report job after the array) and print
    /// their ids.
    #[arg(long, requires = "slurm")]
    pub submit: bool,
    /// With --slurm: the partition (default: the cluster's default partition).
    #[arg(long, requires = "slurm")]
    pub partition: Option<String>,
    /// With --slurm: time limit of each task, in any format sbatch takes (default 1-00:00:00).
    #[arg(long, requires = "slurm")]
    pub time: Option<String>,
    /// With --slurm: memory per task, e.g. 500M or 2G (default 1G).
    #[arg(long, requires = "slurm")]
    pub mem: Option<String>,
    /// With --slurm: CPUs per task; each case runs on that many threads (same results).
    #[arg(long, requires = "slurm", default_value_t = 1)]
    pub cpus_per_task: u32,
    /// With --slurm: the account to charge.
    #[arg(long, requires = "slurm")]
    pub account: Option<String>,
    /// With --slurm: at most this many tasks at once.
    #[arg(long, requires = "slurm")]
    pub throttle: Option<u32>,
    /// With --slurm: a further sbatch option for both jobs, e.g. `--sbatch-line=--qos=short`
    /// (repeatable).
    #[arg(long = "sbatch-line", requires = "slurm", value_name = "OPTION")]
    pub sbatch_lines: Vec<String>,
    /// Show where each case of the study in OUT stands (finished, failed, running, pending,
    /// checkpointed, not started), asking squeue where it runs. SWEEP may then be the study
    /// folder itself.
    #[arg(long, conflicts_with_all = ["slurm", "collect"])]
    pub status: bool,
    /// Assemble results.csv and failures.json from the case folders and write the report
    /// (what the report job runs).
    #[arg(long, conflicts_with = "slurm")]
    pub collect: bool,
    /// Run only the case on this line (from 0) of --task-list (what an array task runs).
    #[arg(long, requires = "task_list", conflicts_with_all = ["slurm", "collect", "status"])]
    pub task_index: Option<usize>,
    /// The list of case identifiers an array job runs, one a line.
    #[arg(long, requires = "task_index")]
    pub task_list: Option<PathBuf>,
}

/// Parses the Slurm options; the error names the flag and value.
fn slurm_options(args: &SlurmArgs) -> Result<SlurmOptions, String> {
    let mut options = SlurmOptions {
        partition: args.partition.clone(),
        account: args.account.clone(),
        cpus_per_task: args.cpus_per_task,
        throttle: args.throttle,
        extra: args.sbatch_lines.clone(),
        ..SlurmOptions::default()
    };
    if let Some(time) = &args.time {
        options.time = time
            .parse::<TimeLimit>()
            .map_err(|e| format!("--time: {e}"))?;
    }
    if let Some(mem) = &args.mem {
        options.memory = mem.clone();
    }
    Ok(options)
}

/// Writes (and with --submit submits) the array job of the unfinished cases and the report
/// job, and says what it did. `command` is the hopperflow binary and the study's own
/// arguments, as each task and the report job must repeat them.
pub fn write_jobs(
    plan: &SweepPlan,
    sweep_text: &str,
    out: &Path,
    command: &[String],
    args: &SlurmArgs,
) -> i32 {
    let options = match slurm_options(args) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("error: {e}");
            return EXIT_BAD_INPUT;
        }
    };
    let jobs = match study::write_jobs(plan, sweep_text, out, command, &options, args.submit) {
        Ok(jobs) => jobs,
        Err(e) => {
            eprintln!("error: {e}");
            return match &e {
                JobsError::BadOption(_) => EXIT_BAD_INPUT,
                JobsError::Study(e) => crate::exit_codes::study_exit_code(e),
                _ => 1,
            };
        }
    };
    let report = jobs.report_script.display();
    let Some(array) = &jobs.array_script else {
        println!(
            "no case left to run ({} finished, {} queued); report script: {report}",
            jobs.finished, jobs.queued
        );
        return 0;
    };
    println!(
        "{} of {} cases to run: {}",
        jobs.todo.len(),
        jobs.cases,
        array.display()
    );
    println!("report script: {report}");
    match &jobs.submitted {
        None => println!(
            "submit with: sbatch --parsable {} and then sbatch --dependency=afterany:<array id> {report}",
            array.display()
        ),
        Some((array_job, report_job)) => {
            println!("submitted array job {array_job}");
            println!("submitted report job {report_job}");
        }
    }
    0
}

/// `--status`: every case's state, and the counts.
pub fn status(out: &Path) -> i32 {
    let cases = match study::case_statuses(out) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return EXIT_BAD_INPUT;
        }
    };
    let mut counts = std::collections::BTreeMap::<&str, usize>::new();
    for case in &cases {
        let detail = case
            .failure
            .as_ref()
            .map_or(String::new(), |reason| format!("  ({reason})"));
        println!("{:<32} {}{detail}", case.id, case.shown);
        *counts.entry(case.shown.as_str()).or_default() += 1;
    }
    let summary: Vec<String> = counts.iter().map(|(k, n)| format!("{n} {k}")).collect();
    println!("{} cases: {}", cases.len(), summary.join(", "));
    0
}

/// `--task-index`: runs the one case on that line of the task list.
pub fn task(
    plan: &SweepPlan,
    out: &Path,
    list: &Path,
    index: usize,
    runner: &SimulationRunner,
) -> i32 {
    let ids = match std::fs::read_to_string(list) {
        Ok(text) => text.lines().map(String::from).collect::<Vec<_>>(),
        Err(e) => {
            eprintln!("error: cannot read the task list {}: {e}", list.display());
            return EXIT_BAD_INPUT;
        }
    };
    let Some(id) = ids.get(index) else {
        eprintln!(
            "error: --task-index {index}: the task list {} has {} lines (0–{})",
            list.display(),
            ids.len(),
            ids.len().saturating_sub(1)
        );
        return EXIT_BAD_INPUT;
    };
    let checkpoint = out.join("cases").join(id).join(files::CHECKPOINT_FILE);
    if let Ok(header) = run::read_checkpoint_header(&checkpoint) {
        println!(
            "{id}: continuing from its checkpoint in the {} at t = {:.4} s",
            header.phase, header.time
        );
    }
    match run_task(plan, out, id, runner) {
        Ok(TaskOutcome::Finished(summary)) => {
            println!(
                "{id}: finished, W = {:.3} g/s",
                summary.discharge_rate * 1e3
            );
            0
        }
        Ok(TaskOutcome::Failed(reason)) => {
            eprintln!("{id}: failed: {reason}");
            3
        }
        Ok(TaskOutcome::Stopped) => {
            eprintln!(
                "{id}: stopped by a signal after writing its checkpoint; resubmit to continue"
            );
            EXIT_STOPPED
        }
        Err(e) => {
            eprintln!("error: {id}: {e}");
            crate::exit_codes::study_exit_code(&e)
        }
    }
}

/// `--collect`: results.csv and failures.json from the case folders, then the report.
pub fn collect(plan: &SweepPlan, out: &Path) -> i32 {
    let collected = match collect_study(plan, out) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return crate::exit_codes::study_exit_code(&e);
        }
    };
    println!(
        "{} cases: {} in results.csv ({} failed), {} unfinished",
        plan.cases.len(),
        collected.rows.len(),
        collected.failures.len(),
        collected.unfinished.len()
    );
    for id in &collected.unfinished {
        println!("unfinished: {id}");
    }
    match report::build_report(out) {
        Ok(files) => println!("report: {}", files.markdown.display()),
        Err(e) => {
            eprintln!("error: the report: {e}");
            return 1;
        }
    }
    if collected.failures.is_empty() && collected.unfinished.is_empty() {
        0
    } else {
        3
    }
}
