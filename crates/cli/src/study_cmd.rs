//! `hopperflow study`: runs a parametric study (the built-in fan2023 programme or a sweep
//! file) in parallel and resumably, then writes its report (`report/` in the output
//! folder, as `hopperflow report` does) unless `--no-report`, and prints where both are.
//!
//! Exit status: 0 when every case finished and the report is written; 3 when a case failed
//! (the report of what finished is still written); 1 when the study or its report could
//! not be written; 2 for bad input.

use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use clap::Args;

use crate::slurm_cmd::SlurmArgs;
use case::{
    builtin_sweep, load_sweep, parse_sweep, sweep_with_replicas, SweepPlan, BUILTIN_SWEEP_NAMES,
};
use indicatif::{ProgressBar, ProgressStyle};
use run::Start;
use study::{run_study, SimulationRunner, StudyEvent, StudyOptions};

#[derive(Args)]
pub struct StudyArgs {
    /// A built-in sweep (`fan2023`, `fan2023-sensitivity`, `fan2023-quick`) or a sweep file (TOML).
    sweep: String,
    /// Output directory (default: `study-<sweep name>`). An existing one is resumed.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Independent fills per grid point (overrides the sweep's `replicas`).
    #[arg(long)]
    replicas: Option<u32>,
    /// Cases run at the same time (default: one per core; each case uses one thread).
    #[arg(long)]
    jobs: Option<usize>,
    /// Run the reduced preset of a built-in sweep (fan2023-quick: 600 spheres, 6 cases).
    #[arg(long)]
    quick: bool,
    /// Print the sweep file (built-in or given) instead of running it.
    #[arg(long)]
    print: bool,
    /// Override a key of the base case, e.g. `--set protocol.time_limit=10` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Skip the per-case plots and frames (faster; the report does not need them).
    #[arg(long)]
    no_pictures: bool,
    /// Worker threads of each case (results do not depend on it). With --slurm it is
    /// --cpus-per-task.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1024))]
    case_threads: u32,
    #[command(flatten)]
    cluster: SlurmArgs,
    /// Do not write the report at the end (build it later with `hopperflow report DIR`).
    #[arg(long)]
    no_report: bool,
    /// Start every case from one bed saved by `hopperflow run --save-bed DIR` instead of its
    /// own fill: the same settled packing through each outlet of the sweep. The cases may
    /// differ from the bed's only in the outlet, the discharge rules and [measure]/[output]
    /// keys; each takes the bed's seed, and replicas are refused (they would repeat one run).
    #[arg(long, value_name = "DIR")]
    from_bed: Option<PathBuf>,
    /// Print the cost estimate of the cases still to run, summed (particle-steps, wall time
    /// on this machine at --jobs cases at a time, peak memory), and exit without running;
    /// exit 2 if the study would be refused as unable to finish.
    #[arg(long)]
    estimate: bool,
    /// Run even when the estimate says the study could not finish: a predicted wall time
    /// over 30 days, or more memory than the machine has (refused otherwise, exit 2).
    #[arg(long)]
    no_cost_check: bool,
}

/// Estimates the cases of `plan` that `out` does not hold finished, prints the sum (to
/// standard output with --estimate, standard error else) and refuses a study that could
/// not finish unless --no-cost-check: `Some(exit code)` to stop with, `None` to go on.
/// The engine's speed is timed once for each set of spheres and laws among the cases.
fn check_cost(
    args: &StudyArgs,
    plan: &case::SweepPlan,
    out: &std::path::Path,
    start: &Start,
) -> Option<i32> {
    let paths = files::StudyPaths::new(out);
    let threads = args.case_threads as usize;
    let mut speeds: Vec<(String, run::cost::MeasuredSpeed)> = Vec::new();
    let mut estimates = Vec::new();
    // Short cases are not timed (`run::cost::SHORT_RUN_PARTICLE_STEPS`); --estimate always is.
    let timing = if args.estimate {
        run::cost::Timing::Always
    } else {
        run::cost::Timing::UnlessShort
    };
    for sweep_case in &plan.cases {
        if paths
            .case_dir(&sweep_case.id)
            .join(files::SUMMARY_FILE)
            .exists()
        {
            continue;
        }
        let case = &sweep_case.case;
        // The cases' spheres and laws, which set the engine's speed.
        let key =
            serde_json::to_string(&(&case.particles, &case.materials, &case.contact, &case.wall))
                .unwrap_or_default();
        let estimate = match speeds.iter().find(|(k, _)| *k == key) {
            Some((_, speed)) => run::cost::estimate_cost_at(case, start, *speed),
            None => run::cost::estimate_cost(case, start, threads, timing),
        };
        match estimate {
            Ok(e) => {
                if let Some(speed) = e.speed.filter(|_| !speeds.iter().any(|(k, _)| *k == key)) {
                    speeds.push((key, speed));
                }
                estimates.push(e);
            }
            Err(e) => {
                eprintln!("warning: no cost estimate of {}: {e}", sweep_case.id);
                return if args.estimate { Some(1) } else { None };
            }
        }
    }
    let available = std::thread::available_parallelism().map_or(1, |n| n.get());
    let jobs = args.jobs.filter(|&j| j > 0).unwrap_or(available);
    let cost = crate::cost_report::StudyCost::of(&estimates, jobs.min(estimates.len()));
    let physical = run::cost::physical_memory();
    for line in cost.lines(physical) {
        if args.estimate {
            println!("{line}");
        } else {
            eprintln!("{line}");
        }
    }
    // The likely wall time is checked, as for a run (`run::cost::cost_refusal`).
    let excesses =
        run::cost::CostExcess::of(cost.likely_study_wall_time, cost.peak_memory, physical);
    if !excesses.is_empty() && !args.no_cost_check {
        let list: Vec<String> = excesses.iter().map(ToString::to_string).collect();
        eprintln!("error: this study could not finish: {}", list.join("; "));
        // The costliest case, by its own estimate's keys and values.
        if let Some((e, c)) = estimates
            .iter()
            .zip(
                plan.cases
                    .iter()
                    .filter(|c| !paths.case_dir(&c.id).join(files::SUMMARY_FILE).exists()),
            )
            .max_by(|a, b| {
                a.0.likely
                    .wall_time
                    .total()
                    .total_cmp(&b.0.likely.wall_time.total())
            })
        {
            if let Some(why) = run::cost::cost_refusal(&c.case, e, physical) {
                eprintln!("the costliest case, {}: {why}", c.id);
            } else {
                eprintln!(
                    "the costliest case, {}, likely takes {}: the cases together are too many",
                    c.id,
                    run::cost::duration_in_words(e.likely.wall_time.total())
                );
            }
        }
        eprintln!("hint: --no-cost-check runs it anyway");
        return Some(crate::exit_codes::EXIT_BAD_INPUT);
    }
    args.estimate.then_some(0)
}

/// The hopperflow binary and this study's own arguments, as an array task or the report
/// job must repeat them to plan the same study (the sweep file by its absolute path).
fn task_command(args: &StudyArgs, out: &std::path::Path, threads: u32) -> Vec<String> {
    let exe = std::env::current_exe()
        .map(|p| p.display().to_string())
        .unwrap_or_else(|_| "hopperflow".into());
    let sweep = if builtin_sweep(&args.sweep).is_some() {
        args.sweep.clone()
    } else {
        std::path::absolute(&args.sweep)
            .map(|p| p.display().to_string())
            .unwrap_or_else(|_| args.sweep.clone())
    };
    let mut words = vec![exe, "study".into(), sweep];
    let out = std::path::absolute(out).unwrap_or_else(|_| out.to_path_buf());
    words.extend(["--out".into(), out.display().to_string()]);
    if args.quick {
        words.push("--quick".into());
    }
    if let Some(r) = args.replicas {
        words.extend(["--replicas".into(), r.to_string()]);
    }
    for set in &args.sets {
        words.extend(["--set".into(), set.clone()]);
    }
    if args.no_pictures {
        words.push("--no-pictures".into());
    }
    if let Some(bed) = &args.from_bed {
        let bed = std::path::absolute(bed).unwrap_or_else(|_| bed.clone());
        words.extend(["--from-bed".into(), bed.display().to_string()]);
    }
    words.extend(["--case-threads".into(), threads.to_string()]);
    words
}

/// The sweep text and its plan.
fn plan(args: &StudyArgs) -> Result<(String, SweepPlan), String> {
    let name = if args.quick && args.sweep == "fan2023" {
        "fan2023-quick"
    } else {
        args.sweep.as_str()
    };
    let (text, mut plan) = if let Some(text) = builtin_sweep(name) {
        let plan = parse_sweep(text, name, None, &args.sets).map_err(|e| e.to_string())?;
        (text.to_string(), plan)
    } else {
        if args.quick {
            return Err(format!(
                "--quick applies to the built-in fan2023 sweep only; reduce '{}' in the file",
                args.sweep
            ));
        }
        let path = PathBuf::from(&args.sweep);
        if !path.exists() {
            return Err(format!(
                "'{}' is neither a built-in sweep ({}) nor a file",
                args.sweep,
                BUILTIN_SWEEP_NAMES.join(", ")
            ));
        }
        let text = std::fs::read_to_string(&path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let plan = load_sweep(&path, &args.sets).map_err(|e| e.to_string())?;
        (text, plan)
    };
    if let Some(replicas) = args.replicas {
        if replicas == 0 {
            return Err("--replicas must be at least 1".into());
        }
        if replicas != plan.replicas {
            // Replicas are expanded by the sweep reader (each with its own seed), so the
            // file is re-read with the count replaced.
            let text = sweep_with_replicas(&text, replicas);
            plan = if builtin_sweep(name).is_some() {
                parse_sweep(&text, name, None, &args.sets)
            } else {
                let path = PathBuf::from(&args.sweep);
                parse_sweep(&text, &args.sweep, path.parent(), &args.sets)
            }
            .map_err(|e| e.to_string())?;
            return Ok((text, plan));
        }
    }
    Ok((text, plan))
}

pub fn run(args: StudyArgs) -> i32 {
    if args.print {
        let name = if args.quick && args.sweep == "fan2023" {
            "fan2023-quick"
        } else {
            args.sweep.as_str()
        };
        match builtin_sweep(name) {
            Some(text) => print!("{text}"),
            None => match std::fs::read_to_string(&args.sweep) {
                Ok(text) => print!("{text}"),
                Err(e) => {
                    eprintln!("error: cannot read {}: {e}", args.sweep);
                    return 2;
                }
            },
        }
        return 0;
    }
    if args.cluster.status {
        let dir = args
            .out
            .clone()
            .unwrap_or_else(|| PathBuf::from(&args.sweep));
        return crate::slurm_cmd::status(&dir);
    }
    let (text, plan) = match plan(&args) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    // A study from one bed: every case checked against it before anything is written.
    let (plan, start) = match &args.from_bed {
        None => (plan, Start::Fill),
        Some(dir) => match study::plan_from_bed_dir(plan, dir) {
            Ok(planned) => planned,
            Err(e) => {
                eprintln!("error: {e}");
                return crate::exit_codes::study_exit_code(&e);
            }
        },
    };
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("study-{}", plan.name)));
    let stop = crate::signals::stop_flag();
    let runner = SimulationRunner {
        pictures: !args.no_pictures,
        stop: Some(Arc::clone(&stop)),
        threads: args.case_threads as usize,
        start: Arc::new(start),
    };
    if let (Some(index), Some(list)) = (args.cluster.task_index, &args.cluster.task_list) {
        return crate::slurm_cmd::task(&plan, &out, list, index, &runner);
    }
    if args.cluster.collect {
        return crate::slurm_cmd::collect(&plan, &out);
    }
    if args.cluster.slurm {
        let command = task_command(&args, &out, args.cluster.cpus_per_task);
        return crate::slurm_cmd::write_jobs(&plan, &text, &out, &command, &args.cluster);
    }
    // A folder of another sweep, or a case folder of other inputs, is refused before
    // anything in it changes.
    if let Err(e) = study::check_study_dir(&plan, &out) {
        eprintln!("error: {e}");
        return crate::exit_codes::study_exit_code(&e);
    }
    if let Some(code) = check_cost(&args, &plan, &out, &runner.start) {
        return code;
    }
    if let Err(e) = std::fs::create_dir_all(&out) {
        eprintln!("error: cannot create {}: {e}", out.display());
        return 1;
    }
    // Keep the sweep as run beside its results, so the study can be rerun or edited.
    if let Err(e) = files::write_atomic(out.join("sweep.toml"), text.as_bytes()) {
        eprintln!("error: {e}");
        return 1;
    }
    for skipped in &plan.skipped {
        eprintln!("skipped {}: {}", skipped.id, skipped.reasons.join("; "));
    }
    let bar = ProgressBar::new(plan.cases.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} cases  elapsed {elapsed}  eta {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let bar = Mutex::new(bar);
    let observer = |event: &StudyEvent| {
        let bar = bar.lock().unwrap_or_else(|p| p.into_inner());
        match event {
            StudyEvent::Started {
                total,
                already_done,
            } => {
                bar.set_position(*already_done as u64);
                if *already_done > 0 {
                    bar.println(format!(
                        "resuming: {already_done} of {total} cases already finished"
                    ));
                }
            }
            StudyEvent::CaseEnded {
                id,
                outlet_width,
                discharge_rate,
                status,
                wall_time,
                reason,
                done,
                ..
            } => {
                bar.set_position(*done as u64);
                let what = status.outcome_words(*discharge_rate, reason.as_deref());
                bar.println(format!(
                    "{id:<28} D = {:>4.1} mm  {what}  ({wall_time:.0} s)",
                    outlet_width * 1e3
                ));
            }
        }
    };
    let options = StudyOptions {
        jobs: args.jobs.unwrap_or(0),
    };
    let outcome = run_study(&plan, &out, &runner, &options, &observer);
    bar.lock().unwrap_or_else(|p| p.into_inner()).finish();
    match outcome {
        Ok(outcome) => {
            println!(
                "{} cases: {} run now, {} from earlier runs, {} failed",
                outcome.rows.len(),
                outcome.ran,
                outcome.reused,
                outcome.failures.len()
            );
            println!("results: {}", out.join("results.csv").display());
            if stop.load(std::sync::atomic::Ordering::Relaxed) {
                // Stopped cases are unfinished, not failed: no report of a partial study.
                eprintln!(
                    "stopped by a signal: running cases wrote checkpoints; rerun the same command to continue"
                );
                return crate::exit_codes::EXIT_STOPPED;
            }
            // The report covers what finished; failed cases are left out of its fits
            // and counted in it.
            let report_ok = if args.no_report {
                println!("report:  hopperflow report {}", out.display());
                true
            } else {
                match report::build_report(&out) {
                    Ok(files) => {
                        println!("report:  {}", files.markdown.display());
                        println!("html:    {}", files.html.display());
                        println!("comparison: {}", files.comparison.display());
                        true
                    }
                    Err(e) => {
                        eprintln!("error: the report could not be written: {e}");
                        false
                    }
                }
            };
            if !outcome.failures.is_empty() {
                eprintln!(
                    "{} case(s) failed (see {}); rerun the same command to retry them",
                    outcome.failures.len(),
                    out.join("failures.json").display()
                );
                3
            } else if report_ok {
                0
            } else {
                1
            }
        }
        Err(e) => {
            eprintln!("error: {e}");
            1
        }
    }
}
