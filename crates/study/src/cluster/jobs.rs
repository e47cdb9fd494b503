//! A study as Slurm jobs: the array job of its unfinished cases (one case per task) and the
//! report job after it, written into the study's `slurm/` folder and, on request, submitted;
//! and where each case of a study stands, with what the queue says of it.

use std::path::{Path, PathBuf};

use case::SweepPlan;
use files::{write_atomic, write_json_atomic};

use super::queue::{
    check_partition, on_path, queued_cases, read_submissions, sbatch, Submission, SUBMISSIONS_FILE,
};
use super::script::{array_script, report_script, SlurmOptions};
use crate::sweep::{case_states, prepare_study, CaseState, StudyError};

/// Why a study's jobs could not be written or submitted.
#[derive(Debug, thiserror::Error)]
pub enum JobsError {
    /// An option is wrong (the message names it); nothing was written.
    #[error("{0}")]
    BadOption(String),
    /// The study folder could not be prepared or read.
    #[error(transparent)]
    Study(#[from] StudyError),
    /// A script, the task list or the record of submissions could not be written.
    #[error(transparent)]
    Output(#[from] files::OutputError),
    /// A folder could not be created.
    #[error("cannot create {path}: {source}")]
    Io {
        /// The folder.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// `sbatch` refused a job or could not be run; `submitted` holds the array job's id when
    /// the array went in and the report job did not.
    #[error("{}{reason}", .submitted.as_ref().map_or(String::new(), |id| format!("the array {id} was submitted, the report job not: ")))]
    Submit {
        /// The array job's id, when only the report job failed.
        submitted: Option<String>,
        /// sbatch's message.
        reason: String,
    },
}

/// What [`write_jobs`] wrote and submitted.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Jobs {
    /// Cases in the study.
    pub cases: usize,
    /// Cases already finished.
    pub finished: usize,
    /// Unfinished cases left out because the queue already holds their task.
    pub queued: usize,
    /// The cases of the new array, in task order; empty when no case is left to run.
    pub todo: Vec<String>,
    /// The array job's script (`slurm/array-K.sh`), when there are cases to run.
    pub array_script: Option<PathBuf>,
    /// The report job's script (`slurm/report.sh`).
    pub report_script: PathBuf,
    /// The ids of the array and report jobs, when they were submitted.
    pub submitted: Option<(String, String)>,
}

/// Writes the array job of the study's unfinished cases that the queue does not already
/// hold, its task list and the report job into `out/slurm/`, after preparing the study folder
/// (`study.json`) and saving the sweep's text as `out/sweep.toml`; with `submit`, submits
/// both (the report job after the array) and records the submission for
/// [`case_statuses`]. `command` is the hopperflow binary and the study's own arguments, as
/// each task and the report job must repeat them.
///
/// Everything is checked before anything is written: the options, the partition (against
/// `sinfo`, where it runs), `sbatch` (with `submit`) and the study folder itself.
pub fn write_jobs(
    plan: &SweepPlan,
    sweep_text: &str,
    out: &Path,
    command: &[String],
    options: &SlurmOptions,
    submit: bool,
) -> Result<Jobs, JobsError> {
    options.validate().map_err(JobsError::BadOption)?;
    if let Some(partition) = &options.partition {
        check_partition(partition).map_err(JobsError::BadOption)?;
    }
    if submit && !on_path("sbatch") {
        return Err(JobsError::BadOption(
            "--submit needs sbatch, which is not on PATH; drop --submit to write the scripts only"
                .into(),
        ));
    }
    prepare_study(plan, out)?;
    write_atomic(out.join("sweep.toml"), sweep_text.as_bytes())?;
    let out = std::path::absolute(out).unwrap_or_else(|_| out.to_path_buf());
    let slurm = out.join("slurm");
    let logs = slurm.join("logs");
    std::fs::create_dir_all(&logs).map_err(|source| JobsError::Io {
        path: logs.clone(),
        source,
    })?;
    let states = case_states(&out)?;
    let queued = queued_cases(&out);
    let todo: Vec<String> = states
        .iter()
        .filter(|(id, state)| state.is_unfinished() && !queued.contains_key(id))
        .map(|(id, _)| id.clone())
        .collect();
    let report_path = slurm.join("report.sh");
    write_atomic(
        &report_path,
        report_script(&plan.name, &logs, command, options).as_bytes(),
    )?;
    let mut jobs = Jobs {
        cases: states.len(),
        finished: states.iter().filter(|(_, s)| !s.is_unfinished()).count(),
        queued: queued.len(),
        todo,
        array_script: None,
        report_script: report_path.clone(),
        submitted: None,
    };
    if jobs.todo.is_empty() {
        return Ok(jobs);
    }
    let serial = (1..)
        .find(|k| !slurm.join(format!("tasks-{k}.txt")).exists())
        .unwrap_or(1);
    let task_list = slurm.join(format!("tasks-{serial}.txt"));
    let array_path = slurm.join(format!("array-{serial}.sh"));
    let mut list = jobs.todo.join("\n");
    list.push('\n');
    let array = array_script(
        &plan.name,
        jobs.todo.len(),
        &task_list,
        &logs,
        command,
        options,
    );
    write_atomic(&task_list, list.as_bytes())?;
    write_atomic(&array_path, array.as_bytes())?;
    jobs.array_script = Some(array_path.clone());
    if !submit {
        return Ok(jobs);
    }
    let array_job =
        sbatch(&[array_path.to_string_lossy().as_ref()]).map_err(|reason| JobsError::Submit {
            submitted: None,
            reason,
        })?;
    let dependency = format!("--dependency=afterany:{array_job}");
    let report_job =
        sbatch(&[&dependency, report_path.to_string_lossy().as_ref()]).map_err(|reason| {
            JobsError::Submit {
                submitted: Some(array_job.clone()),
                reason,
            }
        })?;
    let mut submissions = read_submissions(&slurm);
    submissions.push(Submission {
        array_job: array_job.clone(),
        report_job: report_job.clone(),
        task_list,
    });
    write_json_atomic(slurm.join(SUBMISSIONS_FILE), &submissions)?;
    jobs.submitted = Some((array_job, report_job));
    Ok(jobs)
}

/// Where one case of a study stands.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CaseStanding {
    /// The case's identifier.
    pub id: String,
    /// Its state in words: finished, running, pending (or another queue state in lower
    /// case), failed, checkpointed, started, not started.
    pub shown: String,
    /// The reason of a failed case.
    pub failure: Option<String>,
}

/// Every case of the study in `out` with its state, the queue's word taking precedence over
/// the folder's for a case that is not finished.
pub fn case_statuses(out: &Path) -> Result<Vec<CaseStanding>, StudyError> {
    let states = case_states(out)?;
    let queued = queued_cases(out);
    Ok(states
        .into_iter()
        .map(|(id, state)| {
            let shown = match (&state, queued.get(&id)) {
                (CaseState::Finished, _) => "finished".to_string(),
                (_, Some(q)) if q == "RUNNING" => "running".to_string(),
                (_, Some(q)) if q == "PENDING" => "pending".to_string(),
                (_, Some(q)) => q.to_lowercase(),
                (other, None) => other.label().to_string(),
            };
            let failure = match state {
                CaseState::Failed(reason) => Some(reason),
                _ => None,
            };
            CaseStanding { id, shown, failure }
        })
        .collect())
}
