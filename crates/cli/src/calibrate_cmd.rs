//! `hopperflow calibrate`: finds up to two material parameters from up to two lab targets
//! (docs/physics.md §12) by rounds of studies, in parallel and resumably, and prints the
//! estimate with its uncertainty.
//!
//! Exit status: 0 when the estimate converged and meets the targets; 3 when it did not
//! converge within `max_rounds`, misses a target, or some runs failed (the record is written
//! either way); 2 for bad input; 1 when the calibration
//! could not go on; 75 when stopped by a signal (rerun the same command to continue).

use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};

use calibrate::{
    run_calibration, slurm_step, CalibrationError, CalibrationEvent, CalibrationOptions,
    CalibrationRecord, SlurmStep,
};
use clap::{Args, Parser};

use crate::slurm_cmd::SlurmArgs;
use run::Start;
use study::{SimulationRunner, StudyEvent};

#[derive(Args)]
pub struct CalibrateArgs {
    /// The calibration file (TOML): the parameters to find, their ranges, and the lab's
    /// targets, each a measure of a test case (cases/calibration.toml is an example).
    file: PathBuf,
    /// Output directory (default: `calibration-<name>`). An existing one is continued.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Runs at the same time (default: one per core; each run uses one thread).
    #[arg(long)]
    jobs: Option<usize>,
    /// Check the calibration file and its test cases, then stop.
    #[arg(long)]
    check: bool,
    #[command(flatten)]
    cluster: SlurmArgs,
    /// The round an array task or a collect job belongs to (written into the job scripts).
    #[arg(long, hide = true)]
    round: Option<u32>,
}

/// File in the calibration's folder that keeps the Slurm options of `--slurm`, so that the
/// job that ends one round submits the next with the same.
const SLURM_OPTIONS_FILE: &str = "slurm-options.txt";

/// The Slurm options again, as parsed from the saved words.
#[derive(Parser)]
struct SavedSlurm {
    #[command(flatten)]
    cluster: SlurmArgs,
}

/// The words that give `args` back to [`SavedSlurm`], one a line.
fn slurm_words(args: &SlurmArgs) -> Vec<String> {
    let mut words = vec!["--slurm".to_string()];
    if args.submit {
        words.push("--submit".into());
    }
    let mut pair = |flag: &str, value: Option<String>| {
        if let Some(v) = value {
            words.push(format!("{flag}={v}"));
        }
    };
    pair("--partition", args.partition.clone());
    pair("--time", args.time.clone());
    pair("--mem", args.mem.clone());
    pair("--cpus-per-task", Some(args.cpus_per_task.to_string()));
    pair("--account", args.account.clone());
    pair("--throttle", args.throttle.map(|t| t.to_string()));
    for line in &args.sbatch_lines {
        words.push(format!("--sbatch-line={line}"));
    }
    words
}

/// The hopperflow binary and the calibration's own arguments for the jobs of `round`.
fn task_command(file: &std::path::Path, out: &std::path::Path, round: u32) -> Vec<String> {
    let exe = std::env::current_exe()
        .map(|p| p.display().to_string())
        .unwrap_or_else(|_| "hopperflow".into());
    let absolute = |p: &std::path::Path| {
        std::path::absolute(p)
            .unwrap_or_else(|_| p.to_path_buf())
            .display()
            .to_string()
    };
    vec![
        exe,
        "calibrate".into(),
        absolute(file),
        "--out".into(),
        absolute(out),
        "--round".into(),
        round.to_string(),
    ]
}

/// `--slurm` and the collect job: fits the rounds that have ended and writes (or submits)
/// the jobs of the next, or prints the result when there is none.
fn slurm_advance(
    plan: &case::CalibrationPlan,
    file: &std::path::Path,
    out: &std::path::Path,
    cluster: &SlurmArgs,
) -> i32 {
    let text = match std::fs::read_to_string(file) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: cannot read {}: {e}", file.display());
            return crate::exit_codes::EXIT_BAD_INPUT;
        }
    };
    match slurm_step(plan, out) {
        Err(e) => {
            eprintln!("error: {e}");
            exit_code(&e)
        }
        Ok(SlurmStep::Finished(record)) => print_result(&record, out, None),
        Ok(SlurmStep::Run(round, sweep)) => {
            println!("round {round}: {} runs", sweep.cases.len());
            crate::slurm_cmd::write_jobs(
                &sweep,
                &text,
                &calibrate::round_dir(out, round),
                &task_command(file, out, round),
                cluster,
            )
        }
    }
}

fn exit_code(e: &CalibrationError) -> i32 {
    match e {
        CalibrationError::Stopped => crate::exit_codes::EXIT_STOPPED,
        CalibrationError::DifferentCalibration { .. } | CalibrationError::Case { .. } => {
            crate::exit_codes::EXIT_BAD_INPUT
        }
        CalibrationError::Study { source, .. } => crate::exit_codes::study_exit_code(source),
        _ => 1,
    }
}

pub fn run(args: CalibrateArgs) -> i32 {
    let plan = match case::load_calibration(&args.file) {
        Ok(plan) => plan,
        Err(e) => {
            eprintln!("{e}");
            return crate::exit_codes::EXIT_BAD_INPUT;
        }
    };
    if args.check {
        println!(
            "{}: {} parameter(s), {} target(s) in {} test case(s), {} replicate(s), at most {} rounds",
            args.file.display(),
            plan.parameters.len(),
            plan.targets.len(),
            plan.tests.len(),
            plan.replicates,
            plan.max_rounds
        );
        return 0;
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("calibration-{}", plan.name)));
    let stop = crate::signals::stop_flag();
    let runner = SimulationRunner {
        pictures: false,
        stop: Some(Arc::clone(&stop)),
        threads: args.cluster.cpus_per_task.max(1) as usize,
        start: Arc::new(Start::Fill),
    };
    if let (Some(index), Some(list)) = (args.cluster.task_index, &args.cluster.task_list) {
        // An array task: the round's study, rebuilt from the rounds before it.
        return match slurm_step(&plan, &out) {
            Ok(SlurmStep::Run(round, sweep)) if Some(round) == args.round => {
                let dir = calibrate::round_dir(&out, round);
                crate::slurm_cmd::task(&sweep, &dir, list, index, &runner)
            }
            Ok(_) => {
                eprintln!(
                    "error: round {} of {} is not the round that has runs to do",
                    args.round.unwrap_or(0),
                    out.display()
                );
                1
            }
            Err(e) => {
                eprintln!("error: {e}");
                exit_code(&e)
            }
        };
    }
    if args.cluster.status {
        return match slurm_step(&plan, &out) {
            Ok(SlurmStep::Run(round, _)) => {
                println!("round {round} has runs to do:");
                crate::slurm_cmd::status(&calibrate::round_dir(&out, round))
            }
            Ok(SlurmStep::Finished(record)) => print_result(&record, &out, None),
            Err(e) => {
                eprintln!("error: {e}");
                exit_code(&e)
            }
        };
    }
    if args.cluster.collect {
        // The job after a round's array: the next round, with the options saved by --slurm.
        let saved = std::fs::read_to_string(out.join(SLURM_OPTIONS_FILE)).unwrap_or_default();
        let words = std::iter::once("saved".to_string()).chain(saved.lines().map(String::from));
        let cluster = match SavedSlurm::try_parse_from(words) {
            Ok(s) => s.cluster,
            Err(e) => {
                eprintln!("error: the saved Slurm options of {}: {e}", out.display());
                return crate::exit_codes::EXIT_BAD_INPUT;
            }
        };
        return slurm_advance(&plan, &args.file, &out, &cluster);
    }
    if args.cluster.slurm {
        if let Err(e) = std::fs::create_dir_all(&out).and_then(|()| {
            let mut words = slurm_words(&args.cluster).join("\n");
            words.push('\n');
            files::write_atomic(out.join(SLURM_OPTIONS_FILE), words.as_bytes())
                .map_err(|e| std::io::Error::other(e.to_string()))
        }) {
            eprintln!("error: {}: {e}", out.display());
            return 1;
        }
        return slurm_advance(&plan, &args.file, &out, &args.cluster);
    }
    let keys: Vec<String> = plan.parameters.iter().map(|p| p.key.clone()).collect();
    let printer = Mutex::new(());
    let started = std::time::Instant::now();
    let observer = |event: CalibrationEvent<'_>| {
        let _line = printer.lock().unwrap_or_else(|p| p.into_inner());
        match event {
            CalibrationEvent::RoundStarted {
                round,
                runs,
                lower,
                upper,
            } => {
                let ranges: Vec<String> = keys
                    .iter()
                    .zip(lower.iter().zip(&upper))
                    .map(|(k, (l, u))| format!("{k} in [{l:.4e}, {u:.4e}]"))
                    .collect();
                println!("round {round}: {runs} runs, {}", ranges.join(", "));
            }
            CalibrationEvent::Study(StudyEvent::Started {
                total,
                already_done,
            }) if *already_done > 0 => {
                println!("  resuming: {already_done} of {total} runs already finished");
            }
            CalibrationEvent::Study(StudyEvent::CaseEnded {
                status: files::CaseStatus::Failed,
                id,
                reason,
                ..
            }) => {
                println!(
                    "  {id} FAILED: {}",
                    reason.as_deref().unwrap_or("unknown error")
                );
            }
            CalibrationEvent::Study(_) => {}
            CalibrationEvent::RoundFitted(round) => {
                for e in &round.estimate {
                    println!(
                        "  {} = {:.5e} ± {:.2e}{}",
                        e.key,
                        e.value,
                        e.standard_error,
                        if e.at_range_edge {
                            "  (at the end of its range)"
                        } else {
                            ""
                        }
                    );
                }
            }
        }
    };
    let options = CalibrationOptions {
        jobs: args.jobs.unwrap_or(0),
    };
    let outcome = run_calibration(&plan, &out, &runner, &options, &observer, Some(&stop));
    let record = match outcome {
        Ok(record) => record,
        Err(e) => {
            eprintln!("error: {e}");
            return exit_code(&e);
        }
    };
    if stop.load(Ordering::Relaxed) {
        return crate::exit_codes::EXIT_STOPPED;
    }
    print_result(&record, &out, Some(started.elapsed().as_secs_f64()))
}

/// Prints the estimate and how the targets are met; the exit status.
fn print_result(record: &CalibrationRecord, out: &std::path::Path, seconds: Option<f64>) -> i32 {
    println!();
    println!(
        "{} after {} round(s), {} runs ({} failed){}",
        if record.converged {
            "converged"
        } else {
            "NOT converged"
        },
        record.rounds.len(),
        record.runs,
        record.failed_runs,
        seconds.map_or(String::new(), |s| format!(", {s:.0} s"))
    );
    for e in &record.estimate {
        println!(
            "{:<36} {:>12.5e} ± {:.2e}   95 %: [{:.4e}, {:.4e}]{}",
            e.key,
            e.value,
            e.standard_error,
            e.lower_95,
            e.upper_95,
            if e.at_range_edge {
                "  at the end of its range: widen it"
            } else {
                ""
            }
        );
    }
    if let Some(r) = record.correlation {
        println!("correlation of the two estimates: {r:.3}");
    }
    for m in &record.matches {
        println!(
            "{}:{:<28} lab {:.5e} ± {:.2e}   simulated {:.5e} ± {:.2e} (one run scatters by {:.2e})",
            m.test, m.measure, m.lab, m.lab_uncertainty, m.predicted, m.predicted_error, m.run_scatter
        );
    }
    if !record.targets_met {
        println!(
            "the targets are NOT met within the ranges searched: the parameters cannot reach them, \
             or the targets contradict each other; widen the ranges or check the targets"
        );
    }
    println!(
        "record: {}",
        out.join(calibrate::CALIBRATION_FILE).display()
    );
    println!("runs:   {}", out.join(calibrate::RUNS_FILE).display());
    if record.converged && record.targets_met && record.failed_runs == 0 {
        0
    } else {
        3
    }
}
