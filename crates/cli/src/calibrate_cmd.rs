//! `hopperflow calibrate`: finds up to two material parameters from up to two lab targets
//! (docs/physics.md §10) by rounds of studies, in parallel and resumably, and prints the
//! estimate with its uncertainty.
//!
//! Exit status: 0 when the estimate converged and meets the targets; 3 when it did not
//! converge within `max_rounds`, misses a target, or some runs failed (the record is written
//! either way); 2 for bad input; 1 when the calibration
//! could not go on; 75 when stopped by a signal (rerun the same command to continue).

use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};

use calibrate::{run_calibration, CalibrationError, CalibrationEvent, CalibrationOptions};
use clap::Args;
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
        threads: 1,
        start: Arc::new(Start::Fill),
    };
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
        Err(CalibrationError::Stopped) => {
            eprintln!("{}", CalibrationError::Stopped);
            return crate::exit_codes::EXIT_STOPPED;
        }
        Err(e) => {
            eprintln!("error: {e}");
            return match e {
                CalibrationError::DifferentCalibration { .. } | CalibrationError::Case { .. } => {
                    crate::exit_codes::EXIT_BAD_INPUT
                }
                CalibrationError::Study { source, .. } => {
                    crate::exit_codes::study_exit_code(&source)
                }
                _ => 1,
            };
        }
    };
    if stop.load(Ordering::Relaxed) {
        return crate::exit_codes::EXIT_STOPPED;
    }
    println!();
    println!(
        "{} after {} round(s), {} runs ({} failed), {:.0} s",
        if record.converged {
            "converged"
        } else {
            "NOT converged"
        },
        record.rounds.len(),
        record.runs,
        record.failed_runs,
        started.elapsed().as_secs_f64()
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
