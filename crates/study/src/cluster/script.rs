//! The batch scripts of a study on Slurm: an array job with one case per task, and a report
//! job that collects the case folders once the array has ended.

use std::fmt::Write as _;
use std::path::Path;

use super::time_limit::TimeLimit;

/// Resources and placement of the jobs, as sbatch options.
#[derive(Debug, Clone, PartialEq)]
pub struct SlurmOptions {
    /// Partition (`--partition`); `None` takes the cluster's default.
    pub partition: Option<String>,
    /// Time limit of each array task (`--time`).
    pub time: TimeLimit,
    /// Memory per task (`--mem`), as sbatch writes it: a whole number with an optional
    /// K, M, G or T suffix (megabytes without one).
    pub memory: String,
    /// CPUs per task (`--cpus-per-task`); each case runs on this many threads, which
    /// changes no result.
    pub cpus_per_task: u32,
    /// Account to charge (`--account`).
    pub account: Option<String>,
    /// At most this many tasks at once (`--array=…%N`).
    pub throttle: Option<u32>,
    /// Further `#SBATCH` lines, as given (without the `#SBATCH` prefix).
    pub extra: Vec<String>,
}

impl Default for SlurmOptions {
    /// One CPU and 1 GB for a day: a paper-sized case needs minutes and tens of megabytes,
    /// a 10⁵-sphere silo hours; both fit, and small requests schedule sooner.
    fn default() -> Self {
        Self {
            partition: None,
            time: TimeLimit { seconds: 86_400 },
            memory: "1G".into(),
            cpus_per_task: 1,
            account: None,
            throttle: None,
            extra: Vec::new(),
        }
    }
}

/// Whether `name` can stand in a partition or account name without quoting (Slurm's names
/// are letters, digits, `_`, `-` and `.`; a comma separates several partitions).
fn plain_name(name: &str) -> bool {
    !name.is_empty()
        && name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-' | b'.' | b','))
}

impl SlurmOptions {
    /// Checks every option; the error names the flag, the value and what is allowed.
    pub fn validate(&self) -> Result<(), String> {
        if let Some(p) = &self.partition {
            if !plain_name(p) {
                return Err(format!(
                    "--partition '{p}': a partition name has letters, digits, '_', '-' and '.' (',' between several)"
                ));
            }
        }
        if let Some(a) = &self.account {
            if !plain_name(a) {
                return Err(format!(
                    "--account '{a}': an account name has letters, digits, '_', '-' and '.'"
                ));
            }
        }
        let digits = self.memory.trim_end_matches(['K', 'M', 'G', 'T']);
        let suffixes = self.memory.len() - digits.len();
        if suffixes > 1
            || digits.is_empty()
            || !digits.bytes().all(|b| b.is_ascii_digit())
            || digits.bytes().all(|b| b == b'0')
        {
            return Err(format!(
                "--mem '{}': a positive whole number with an optional K, M, G or T suffix, e.g. 1G or 500M",
                self.memory
            ));
        }
        if self.cpus_per_task == 0 {
            return Err("--cpus-per-task 0: at least 1".into());
        }
        if self.throttle == Some(0) {
            return Err("--throttle 0: at least 1 task at a time".into());
        }
        for line in &self.extra {
            if line.contains(['\n', '\r']) {
                return Err(format!(
                    "--sbatch-line '{line}': one line, without line breaks"
                ));
            }
            if !line.trim_start().starts_with('-') {
                return Err(format!(
                    "--sbatch-line '{line}': an sbatch option such as '--qos=short' (without '#SBATCH')"
                ));
            }
        }
        Ok(())
    }
}

/// Quotes `word` for a POSIX shell: as is where it is plainly safe, else in single quotes.
pub fn shell_quote(word: &str) -> String {
    let safe = !word.is_empty()
        && word
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"_-./=:,+@%".contains(&b));
    if safe {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', "'\\''"))
    }
}

fn command_line(words: &[String]) -> String {
    words
        .iter()
        .map(|w| shell_quote(w))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The `#SBATCH` lines both jobs share.
fn common_lines(out: &mut String, options: &SlurmOptions) {
    if let Some(p) = &options.partition {
        let _ = writeln!(out, "#SBATCH --partition={p}");
    }
    if let Some(a) = &options.account {
        let _ = writeln!(out, "#SBATCH --account={a}");
    }
    for line in &options.extra {
        let _ = writeln!(out, "#SBATCH {}", line.trim());
    }
}

/// A batch script: the shebang, a comment saying what it is, its own `#SBATCH` options,
/// those both jobs share, then its one command (`exec`, so that Slurm's SIGTERM reaches
/// hopperflow itself). sbatch reads `#SBATCH` lines only before the first command.
fn script(comment: &str, sbatch: &[String], options: &SlurmOptions, command: &str) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "#!/bin/bash");
    let _ = writeln!(out, "# {comment}");
    for line in sbatch {
        let _ = writeln!(out, "#SBATCH {line}");
    }
    common_lines(&mut out, options);
    let _ = writeln!(out, "exec {command}");
    out
}

/// The array job: task i runs the case on line i (from 0) of `task_list` by `command`
/// followed by `--task-list LIST --task-index i`. `command` is the hopperflow binary and
/// the study's arguments.
pub fn array_script(
    study: &str,
    tasks: usize,
    task_list: &Path,
    logs: &Path,
    command: &[String],
    options: &SlurmOptions,
) -> String {
    let throttle = options
        .throttle
        .map(|t| format!("%{t}"))
        .unwrap_or_default();
    let mut words = command.to_vec();
    words.push("--task-list".into());
    words.push(task_list.display().to_string());
    script(
        &format!(
            "hopperflow study '{study}': one case per array task; each task writes only its case folder."
        ),
        &[
            format!("--job-name={}", job_name(study)),
            format!("--array=0-{}{throttle}", tasks.saturating_sub(1)),
            "--ntasks=1".into(),
            format!("--cpus-per-task={}", options.cpus_per_task),
            format!("--mem={}", options.memory),
            format!("--time={}", options.time),
            format!("--output={}/%A_%a.out", logs.display()),
        ],
        options,
        &format!(
            "{} --task-index \"$SLURM_ARRAY_TASK_ID\"",
            command_line(&words)
        ),
    )
}

/// The report job: once the array has ended (however its tasks ended), `command` followed
/// by `--collect` assembles `results.csv` and writes the report.
pub fn report_script(
    study: &str,
    logs: &Path,
    command: &[String],
    options: &SlurmOptions,
) -> String {
    let mut words = command.to_vec();
    words.push("--collect".into());
    script(
        &format!(
            "hopperflow study '{study}': collects the case folders into results.csv and the report."
        ),
        &[
            format!("--job-name={}-report", job_name(study)),
            "--ntasks=1".into(),
            "--cpus-per-task=1".into(),
            format!("--mem={}", options.memory),
            "--time=1:00:00".into(),
            format!("--output={}/report_%j.out", logs.display()),
        ],
        options,
        &command_line(&words),
    )
}

/// The jobs' name: `hf-` and the study's name, with anything but letters, digits, `-`, `_`
/// and `.` replaced.
pub fn job_name(study: &str) -> String {
    let clean: String = study
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("hf-{clean}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoting_survives_the_shell() {
        let words = [
            "plain",
            "two words",
            "it's",
            "$HOME",
            "",
            "a;b",
            "--set=x.y=1",
        ];
        let line = words.map(shell_quote).join(" ");
        // `printf '%s\n'` prints each argument the shell received on its own line.
        let output = std::process::Command::new("sh")
            .arg("-c")
            .arg(format!("printf '%s\\n' {line}"))
            .output()
            .expect("sh runs");
        let got: Vec<String> = String::from_utf8_lossy(&output.stdout)
            .lines()
            .map(String::from)
            .collect();
        assert_eq!(got, words.map(String::from).to_vec());
    }

    #[test]
    fn array_script_carries_the_options_and_one_task_per_case() {
        let options = SlurmOptions {
            partition: Some("short".into()),
            account: Some("granular".into()),
            throttle: Some(4),
            extra: vec!["--qos=low".into()],
            ..SlurmOptions::default()
        };
        options.validate().expect("valid");
        let command = vec![
            "/opt/hf/hopperflow".to_string(),
            "study".into(),
            "my sweep.toml".into(),
        ];
        let text = array_script(
            "demo study",
            44,
            Path::new("/data/s/slurm/tasks-1.txt"),
            Path::new("/data/s/slurm/logs"),
            &command,
            &options,
        );
        for line in [
            "#SBATCH --job-name=hf-demo_study",
            "#SBATCH --array=0-43%4",
            "#SBATCH --cpus-per-task=1",
            "#SBATCH --mem=1G",
            "#SBATCH --time=1-00:00:00",
            "#SBATCH --partition=short",
            "#SBATCH --account=granular",
            "#SBATCH --qos=low",
            "#SBATCH --output=/data/s/slurm/logs/%A_%a.out",
            "exec /opt/hf/hopperflow study 'my sweep.toml' --task-list /data/s/slurm/tasks-1.txt --task-index \"$SLURM_ARRAY_TASK_ID\"",
        ] {
            assert!(text.lines().any(|l| l == line), "missing {line}:\n{text}");
        }
        // sbatch reads #SBATCH lines only before the first command.
        let first_command = text
            .lines()
            .position(|l| !l.starts_with('#'))
            .expect("a command");
        assert!(text
            .lines()
            .skip(first_command)
            .all(|l| !l.starts_with("#SBATCH")));
    }

    #[test]
    fn bad_options_name_the_flag_and_value() {
        let bad = |change: fn(&mut SlurmOptions), needle: &str| {
            let mut options = SlurmOptions::default();
            change(&mut options);
            let err = options.validate().unwrap_err();
            assert!(err.contains(needle), "{err}");
        };
        bad(|o| o.partition = Some("a b".into()), "--partition 'a b'");
        bad(|o| o.account = Some("x;y".into()), "--account 'x;y'");
        bad(|o| o.memory = "lots".into(), "--mem 'lots'");
        bad(|o| o.memory = "0G".into(), "--mem '0G'");
        bad(|o| o.memory = "1GG".into(), "--mem '1GG'");
        bad(|o| o.cpus_per_task = 0, "--cpus-per-task 0");
        bad(|o| o.throttle = Some(0), "--throttle 0");
        bad(
            |o| o.extra = vec!["--qos=a\n#SBATCH --x".into()],
            "one line",
        );
        bad(|o| o.extra = vec!["qos=a".into()], "an sbatch option");
        assert!(SlurmOptions::default().validate().is_ok());
    }
}
