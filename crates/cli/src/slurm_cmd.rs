//! `hopperflow study … --slurm`, `--status`, `--task-index` and `--collect`: a study as a
//! Slurm array job with one case per task, its progress, one task, and the collection of the
//! case folders into `results.csv` and the report.
//!
//! Everything is checked before anything is written: the options, the partition (against
//! `sinfo`, where it runs), `sbatch` (with `--submit`) and the study folder itself.

use std::path::{Path, PathBuf};
use std::process::Command;

use clap::Args;
use serde::{Deserialize, Serialize};
use study::cluster::{array_script, report_script, SlurmOptions, TimeLimit};
use case::SweepPlan;
use files::{write_atomic, write_json_atomic};
use study::sweep::{case_states, collect_study, prepare_study, run_task, CaseState, SimulationRunner, TaskOutcome};

use crate::run_cmd::EXIT_BAD_INPUT;
use crate::signals::EXIT_STOPPED;

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

/// One submission of the array, recorded in `slurm/jobs.json` for `--status`.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Submission {
    /// Job id of the array.
    array_job: String,
    /// Job id of the report job.
    report_job: String,
    /// The task list it runs (task i runs line i).
    task_list: PathBuf,
}

/// Parses and checks the Slurm options; the error names the flag and value.
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
    options.validate()?;
    Ok(options)
}

/// Whether `program` is an executable file on PATH.
fn on_path(program: &str) -> bool {
    std::env::var_os("PATH").is_some_and(|paths| {
        std::env::split_paths(&paths).any(|dir| {
            let path = dir.join(program);
            path.is_file()
                && std::fs::metadata(&path).is_ok_and(|m| {
                    #[cfg(unix)]
                    {
                        use std::os::unix::fs::PermissionsExt;
                        m.permissions().mode() & 0o111 != 0
                    }
                    #[cfg(not(unix))]
                    {
                        let _ = m;
                        true
                    }
                })
        })
    })
}

/// The partitions `sinfo` knows, or `None` where sinfo is missing or fails.
fn known_partitions() -> Option<Vec<String>> {
    if !on_path("sinfo") {
        return None;
    }
    let output = Command::new("sinfo")
        .args(["--noheader", "--format=%R"])
        .output()
        .ok()?;
    if !output.status.success() {
        return None;
    }
    Some(
        String::from_utf8_lossy(&output.stdout)
            .lines()
            .map(|l| l.trim().trim_end_matches('*').to_string())
            .filter(|l| !l.is_empty())
            .collect(),
    )
}

fn absolute(path: &Path) -> PathBuf {
    std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf())
}

/// Writes (and with --submit submits) the array job of the unfinished cases and the report
/// job. `command` is the hopperflow binary and the study's own arguments, as each task and
/// the report job must repeat them.
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
    if let Some(partition) = &options.partition {
        if let Some(known) = known_partitions() {
            let wanted: Vec<&str> = partition.split(',').collect();
            if let Some(unknown) = wanted.iter().find(|p| !known.iter().any(|k| k == *p)) {
                eprintln!(
                    "error: --partition '{unknown}': sinfo knows {}",
                    if known.is_empty() {
                        "no partitions".to_string()
                    } else {
                        known.join(", ")
                    }
                );
                return EXIT_BAD_INPUT;
            }
        }
    }
    if args.submit && !on_path("sbatch") {
        eprintln!("error: --submit needs sbatch, which is not on PATH; drop --submit to write the scripts only");
        return EXIT_BAD_INPUT;
    }
    if let Err(e) = prepare_study(plan, out) {
        eprintln!("error: {e}");
        return crate::study_cmd::exit_code_of(&e);
    }
    if let Err(e) = write_atomic(out.join("sweep.toml"), sweep_text.as_bytes()) {
        eprintln!("error: {e}");
        return 1;
    }
    let out = absolute(out);
    let slurm = out.join("slurm");
    let logs = slurm.join("logs");
    if let Err(e) = std::fs::create_dir_all(&logs) {
        eprintln!("error: cannot create {}: {e}", logs.display());
        return 1;
    }
    let states = match case_states(&out) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return 1;
        }
    };
    let queued = queued_cases(&out);
    let todo: Vec<&str> = states
        .iter()
        .filter(|(id, state)| state.is_unfinished() && !queued.contains_key(id))
        .map(|(id, _)| id.as_str())
        .collect();
    let report = report_script(&plan.name, &logs, command, &options);
    let report_path = slurm.join("report.sh");
    if let Err(e) = write_atomic(&report_path, report.as_bytes()) {
        eprintln!("error: {e}");
        return 1;
    }
    if todo.is_empty() {
        println!(
            "no case left to run ({} finished, {} queued); report script: {}",
            states.iter().filter(|(_, s)| !s.is_unfinished()).count(),
            queued.len(),
            report_path.display()
        );
        return 0;
    }
    let serial = (1..)
        .find(|k| !slurm.join(format!("tasks-{k}.txt")).exists())
        .unwrap_or(1);
    let task_list = slurm.join(format!("tasks-{serial}.txt"));
    let array_path = slurm.join(format!("array-{serial}.sh"));
    let mut list = todo.join("\n");
    list.push('\n');
    let array = array_script(&plan.name, todo.len(), &task_list, &logs, command, &options);
    if let Err(e) = write_atomic(&task_list, list.as_bytes())
        .and_then(|()| write_atomic(&array_path, array.as_bytes()))
    {
        eprintln!("error: {e}");
        return 1;
    }
    println!(
        "{} of {} cases to run: {}",
        todo.len(),
        states.len(),
        array_path.display()
    );
    println!("report script: {}", report_path.display());
    if !args.submit {
        println!(
            "submit with: sbatch --parsable {} and then sbatch --dependency=afterany:<array id> {}",
            array_path.display(),
            report_path.display()
        );
        return 0;
    }
    let array_job = match sbatch(&[array_path.as_os_str().to_string_lossy().as_ref()]) {
        Ok(id) => id,
        Err(e) => {
            eprintln!("error: {e}");
            return 1;
        }
    };
    let dependency = format!("--dependency=afterany:{array_job}");
    let report_job = match sbatch(&[&dependency, report_path.to_string_lossy().as_ref()]) {
        Ok(id) => id,
        Err(e) => {
            eprintln!("error: the array {array_job} was submitted, the report job not: {e}");
            return 1;
        }
    };
    let mut submissions = read_submissions(&slurm);
    submissions.push(Submission {
        array_job: array_job.clone(),
        report_job: report_job.clone(),
        task_list,
    });
    if let Err(e) = write_json_atomic(slurm.join("jobs.json"), &submissions) {
        eprintln!("error: {e}");
        return 1;
    }
    println!("submitted array job {array_job}");
    println!("submitted report job {report_job}");
    0
}

/// Submits a script with `sbatch --parsable` and returns the job id.
fn sbatch(args: &[&str]) -> Result<String, String> {
    let output = Command::new("sbatch")
        .arg("--parsable")
        .args(args)
        .output()
        .map_err(|e| format!("cannot run sbatch: {e}"))?;
    if !output.status.success() {
        return Err(format!(
            "sbatch {} failed: {}",
            args.join(" "),
            String::from_utf8_lossy(&output.stderr).trim()
        ));
    }
    // `--parsable` prints "id" or "id;cluster".
    let text = String::from_utf8_lossy(&output.stdout);
    let id = text.trim().split(';').next().unwrap_or("").to_string();
    if id.is_empty() || !id.bytes().all(|b| b.is_ascii_digit()) {
        return Err(format!("sbatch printed no job id: '{}'", text.trim()));
    }
    Ok(id)
}

fn read_submissions(slurm: &Path) -> Vec<Submission> {
    std::fs::read_to_string(slurm.join("jobs.json"))
        .ok()
        .and_then(|text| serde_json::from_str(&text).ok())
        .unwrap_or_default()
}

/// The cases of the study in `out` whose array task squeue shows, with its state
/// (PENDING, RUNNING, …). Empty where squeue is missing or nothing was submitted.
fn queued_cases(out: &Path) -> std::collections::BTreeMap<String, String> {
    let mut queued = std::collections::BTreeMap::new();
    let submissions = read_submissions(&out.join("slurm"));
    if submissions.is_empty() || !on_path("squeue") {
        return queued;
    }
    let jobs: Vec<&str> = submissions.iter().map(|s| s.array_job.as_str()).collect();
    let Ok(output) = Command::new("squeue")
        .args(["--noheader", "--array", "--format=%i %T", "--jobs"])
        .arg(jobs.join(","))
        .output()
    else {
        return queued;
    };
    let lists: std::collections::BTreeMap<&str, Vec<String>> = submissions
        .iter()
        .map(|s| {
            let ids = std::fs::read_to_string(&s.task_list)
                .map(|t| t.lines().map(String::from).collect())
                .unwrap_or_default();
            (s.array_job.as_str(), ids)
        })
        .collect();
    for line in String::from_utf8_lossy(&output.stdout).lines() {
        let mut words = line.split_whitespace();
        let (Some(job), Some(state)) = (words.next(), words.next()) else {
            continue;
        };
        // "123_4" is task 4 of array 123; a pending remainder shows as "123_[5-9%2]".
        let Some((array, task)) = job.split_once('_') else {
            continue;
        };
        let Some(ids) = lists.get(array) else {
            continue;
        };
        for index in task_indices(task) {
            if let Some(id) = ids.get(index) {
                queued.insert(id.clone(), state.to_string());
            }
        }
    }
    queued
}

/// The task indices of squeue's `%i` suffix: `4`, or `[5-9]`, `[1,3,5-7%2]`.
fn task_indices(task: &str) -> Vec<usize> {
    let inner = task.trim_start_matches('[').trim_end_matches(']');
    let inner = inner.split('%').next().unwrap_or("");
    let mut out = Vec::new();
    for part in inner.split(',') {
        match part.split_once('-') {
            Some((a, b)) => {
                if let (Ok(a), Ok(b)) = (a.parse::<usize>(), b.parse::<usize>()) {
                    out.extend(a..=b.min(a + 1_000_000));
                }
            }
            None => out.extend(part.parse::<usize>().ok()),
        }
    }
    out
}

/// `--status`: every case's state, and the counts.
pub fn status(out: &Path) -> i32 {
    let states = match case_states(out) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return EXIT_BAD_INPUT;
        }
    };
    let queued = queued_cases(out);
    let mut counts = std::collections::BTreeMap::<String, usize>::new();
    for (id, state) in &states {
        let shown = match (state, queued.get(id)) {
            (CaseState::Finished, _) => "finished".to_string(),
            (_, Some(q)) if q == "RUNNING" => "running".to_string(),
            (_, Some(q)) if q == "PENDING" => "pending".to_string(),
            (_, Some(q)) => q.to_lowercase(),
            (other, None) => other.label().to_string(),
        };
        let detail = match state {
            CaseState::Failed(reason) => format!("  ({reason})"),
            _ => String::new(),
        };
        println!("{id:<32} {shown}{detail}");
        *counts.entry(shown).or_default() += 1;
    }
    let summary: Vec<String> = counts.iter().map(|(k, n)| format!("{n} {k}")).collect();
    println!("{} cases: {}", states.len(), summary.join(", "));
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
            crate::study_cmd::exit_code_of(&e)
        }
    }
}

/// `--collect`: results.csv and failures.json from the case folders, then the report.
pub fn collect(plan: &SweepPlan, out: &Path) -> i32 {
    let collected = match collect_study(plan, out) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return crate::study_cmd::exit_code_of(&e);
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

#[cfg(test)]
mod tests {
    use super::task_indices;

    #[test]
    fn squeue_task_suffixes_expand_to_indices() {
        assert_eq!(task_indices("4"), vec![4]);
        assert_eq!(task_indices("[5-7]"), vec![5, 6, 7]);
        assert_eq!(task_indices("[1,3,5-6%2]"), vec![1, 3, 5, 6]);
        assert!(task_indices("[x]").is_empty());
    }
}
