//! Slurm's own commands, asked from here: the partitions `sinfo` knows, `sbatch` to submit a
//! script, and `squeue` for the array tasks of a study that are pending or running. Where a
//! command is missing, the answer says so (`None`, or nothing queued) instead of failing, so
//! that scripts can be written on a machine without Slurm.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use serde::{Deserialize, Serialize};

/// One submission of a study's array job, recorded in `slurm/jobs.json` so that the study's
/// status can ask `squeue` about its tasks.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Submission {
    /// Job id of the array.
    pub array_job: String,
    /// Job id of the report job.
    pub report_job: String,
    /// The task list it runs (task i runs line i).
    pub task_list: PathBuf,
}

/// Name of the submissions' record inside a study's `slurm/` folder.
pub const SUBMISSIONS_FILE: &str = "jobs.json";

/// Whether `program` is an executable file on PATH.
pub fn on_path(program: &str) -> bool {
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
pub fn known_partitions() -> Option<Vec<String>> {
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

/// Checks a `--partition` value (one partition or a comma-separated list) against the
/// partitions `sinfo` knows; accepted where sinfo is missing. The error names the unknown
/// partition and lists the known ones.
pub fn check_partition(partition: &str) -> Result<(), String> {
    let Some(known) = known_partitions() else {
        return Ok(());
    };
    match partition.split(',').find(|p| !known.iter().any(|k| k == p)) {
        None => Ok(()),
        Some(unknown) => Err(format!(
            "--partition '{unknown}': sinfo knows {}",
            if known.is_empty() {
                "no partitions".to_string()
            } else {
                known.join(", ")
            }
        )),
    }
}

/// Submits a script with `sbatch --parsable` and returns the job id.
pub fn sbatch(args: &[&str]) -> Result<String, String> {
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

/// The submissions recorded in the study's `slurm/` folder; none where the record is
/// missing or unreadable.
pub fn read_submissions(slurm: &Path) -> Vec<Submission> {
    std::fs::read_to_string(slurm.join(SUBMISSIONS_FILE))
        .ok()
        .and_then(|text| serde_json::from_str(&text).ok())
        .unwrap_or_default()
}

/// The cases of the study in `out` whose array task squeue shows, with its state
/// (PENDING, RUNNING, …). Empty where squeue is missing or nothing was submitted.
pub fn queued_cases(out: &Path) -> BTreeMap<String, String> {
    let mut queued = BTreeMap::new();
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
    let lists: BTreeMap<&str, Vec<String>> = submissions
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
