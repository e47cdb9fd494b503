//! `hopperflow run`, `check` and `init`: one case from a file (or the paper's base case).

use crate::exit_codes::EXIT_BAD_INPUT;
use std::path::PathBuf;
use std::sync::Arc;

use case::{default_case, load_case, parse_case, template, template_files, Case, CASE_TEMPLATE};
use clap::Args;
use files::write_atomic;
use files::BED_CASE_FILE;
use indicatif::{ProgressBar, ProgressStyle};
use run::{
    check_save_bed, occupant, read_bed, run_case_from, Bed, Occupant, Progress, RunError,
    RunOptions, RunOutcome, Start,
};

#[derive(Args)]
pub struct RunArgs {
    /// Case file (TOML); without it, the paper's base case (α = 90°, D = 30 mm).
    case: Option<PathBuf>,
    /// Override a key, e.g. `--set geometry.outlet_width=0.045` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
    /// Output directory.
    #[arg(long, default_value = "out/run")]
    out: PathBuf,
    /// Continue a killed run from its checkpoint in the output directory. Refused (exit 2,
    /// nothing changed) when the checkpoint or summary there came from other inputs, naming
    /// each key that changed, or when the checkpoint is damaged.
    #[arg(long, conflicts_with = "restart")]
    resume: bool,
    /// Discard whatever run the output directory holds (finished, checkpointed, or of other
    /// inputs) and start the case over.
    #[arg(long)]
    restart: bool,
    /// Worker threads (results are identical for any value). The forces and the kick and
    /// drift run in parallel; list builds and the run's measurements stay on one thread. For
    /// 10^5 spheres and more two threads are nearly twice as fast as one; for the paper's
    /// 3000 spheres they gain about a quarter (docs/performance.md, "Threads"). Several cases
    /// use the cores better side by side: `study --jobs`.
    #[arg(long, default_value_t = 1)]
    threads: usize,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
    /// Skip the plots and the VTU snapshots (faster; the tables and summary.json are written
    /// as ever, and `hopperflow report` does not need the pictures).
    #[arg(long)]
    no_pictures: bool,
    /// Save the settled bed into DIR when the gate opens (bed.bin, the engine's whole state,
    /// and case.toml), for later runs with --from-bed. Refused when DIR holds a bed already,
    /// unless --restart (which replaces it) or --resume of the run that saved it.
    #[arg(long, value_name = "DIR", conflicts_with = "from_bed")]
    save_bed: Option<PathBuf>,
    /// Start from a bed saved by --save-bed: no fill and no settling, the gate opens at
    /// once. The case may differ from the bed's only in the outlet (size and position, flat
    /// bottoms only), the discharge rules and [measure]/[output] keys; without CASE the
    /// bed's own case is the base for --set. Replicas from one bed share its packing.
    #[arg(long, value_name = "DIR", conflicts_with = "packing")]
    from_bed: Option<PathBuf>,
    /// Start from a packing file instead of the fill: CSV with the columns
    /// x,y,z,radius,material (SI units; material may be left out for a case of one component,
    /// and for a mixture names each particle's component) or a VTU with points and a `radius`
    /// array, as hopperflow writes them. The particles are placed at rest, settle with the
    /// gate closed, and the run goes on.
    #[arg(long, value_name = "FILE")]
    packing: Option<PathBuf>,
    /// Print the cost estimate (spheres, time step, steps, particle-steps, wall time on this
    /// machine from a short timed run of the case's spheres, peak memory) and exit without
    /// running; exit 2 if the run would be refused as unable to finish.
    #[arg(long)]
    estimate: bool,
    /// With --estimate: print it as JSON.
    #[arg(long, requires = "estimate")]
    json: bool,
    /// Run even when the estimate says the run could not finish: a predicted wall time over
    /// 30 days, or more memory than the machine has (refused otherwise, exit 2).
    #[arg(long)]
    no_cost_check: bool,
}

#[derive(Args)]
pub struct CheckArgs {
    /// Case file to validate.
    case: PathBuf,
    /// Overrides, as for `run`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
}

#[derive(Args)]
pub struct InitArgs {
    /// Where to write the commented case file (default: print it).
    file: Option<PathBuf>,
    /// The geometry kind of the template: slab (the paper's hopper), cylinder (a silo), box
    /// (a rectangular silo), mesh (STL walls; with FILE, the example STL files it names are
    /// written beside it), or a calibration test: heap (the angle of repose of a lifted
    /// cylinder's heap) or draw-down (a box discharging through a slot).
    #[arg(
        long,
        default_value = "slab",
        value_parser = ["slab", "cylinder", "box", "mesh", "heap", "draw-down"]
    )]
    kind: String,
}

fn load(case: Option<&PathBuf>, sets: &[String]) -> Result<Case, i32> {
    let result = match case {
        Some(path) => load_case(path, sets),
        None => default_case(sets),
    };
    result.map_err(|errors| {
        eprintln!("{errors}");
        EXIT_BAD_INPUT
    })
}

pub fn check(args: CheckArgs) -> i32 {
    match load(Some(&args.case), &args.sets) {
        Ok(case) => {
            print!("{}", case.to_toml_string());
            0
        }
        Err(code) => code,
    }
}

pub fn init(args: InitArgs) -> i32 {
    // clap has checked the kind against the same list.
    let text = template(&args.kind).unwrap_or(CASE_TEMPLATE);
    match args.file {
        None => {
            print!("{text}");
            0
        }
        Some(path) => {
            // The template and the files it names, beside it; nothing is overwritten.
            let dir = path.parent().unwrap_or(std::path::Path::new(""));
            let mut files = vec![(path.clone(), text.to_string())];
            for (name, contents) in template_files(&args.kind) {
                files.push((dir.join(name), contents));
            }
            if let Some((existing, _)) = files.iter().find(|(p, _)| p.exists()) {
                eprintln!("error: {} exists; not overwriting it", existing.display());
                return EXIT_BAD_INPUT;
            }
            for (file, contents) in &files {
                if let Err(e) = write_atomic(file, contents.as_bytes()) {
                    eprintln!("error: {e}");
                    return 1;
                }
                eprintln!("wrote {}", file.display());
            }
            0
        }
    }
}

/// Refuses (exit 2) an output directory that already holds a run, finished or
/// checkpointed, when neither --resume nor --restart says what to do with it.
fn refuse_occupied(out: &std::path::Path) -> Option<i32> {
    match occupant(out)? {
        Occupant::Finished => eprintln!(
            "error: {} already holds a finished run; --resume reads it back, --restart runs the case again, or choose another --out",
            out.display()
        ),
        Occupant::Checkpoint(what) => eprintln!(
            "error: {} holds {what}; --resume continues it, --restart discards it, or choose another --out",
            out.display()
        ),
    }
    Some(EXIT_BAD_INPUT)
}

/// The case and what the run starts from, or the exit code of the refusal: a bed that
/// cannot be read or was settled under other inputs, a packing file with problems.
fn case_and_start(args: &RunArgs) -> Result<(Case, Start), i32> {
    let refuse = |e: &dyn std::fmt::Display| {
        eprintln!("error: {e}");
        EXIT_BAD_INPUT
    };
    let bed = match &args.from_bed {
        Some(dir) => Some(read_bed(dir).map_err(|e| refuse(&e))?),
        None => None,
    };
    let case = match (&bed, &args.case) {
        // Without a case file the bed's own resolved case is the base for --set.
        (Some(bed), None) => {
            let name = bed_case_file(bed).display().to_string();
            parse_case(bed.case_text(), &name, &args.sets).map_err(|errors| {
                eprintln!("{errors}");
                EXIT_BAD_INPUT
            })?
        }
        _ => load(args.case.as_ref(), &args.sets)?,
    };
    let start = Start::choose(&case, bed, args.packing.as_deref()).map_err(|e| refuse(&e))?;
    if let (Start::Bed(bed), None) = (&start, &args.case) {
        note_uncentred(args, bed, &case);
    }
    Ok((case, start))
}

/// What the run's case came from, in words: the case file, the bed's case, or the base case.
fn case_name(args: &RunArgs, start: &Start) -> String {
    match (&args.case, start) {
        (Some(path), _) => path.display().to_string(),
        (None, Start::Bed(bed)) => format!("the bed's case ({})", bed_case_file(bed).display()),
        (None, _) => "paper base case".into(),
    }
}

/// The `case.toml` beside a bed's `bed.bin`.
fn bed_case_file(bed: &Bed) -> PathBuf {
    bed.path().with_file_name(BED_CASE_FILE)
}

/// A note when a slab outlet centred in the bed's case is no longer centred because only
/// its width was set: the bed's resolved case names the outlet's position (`outlet_gap`),
/// which a new width keeps.
fn note_uncentred(args: &RunArgs, bed: &Bed, case: &Case) {
    let placed = args.sets.iter().any(|s| {
        let key = s.split('=').next().unwrap_or("").trim();
        key == "geometry.outlet_gap" || key == "geometry.outlet_offset"
    });
    let Ok(old) = parse_case(bed.case_text(), "bed", &[]) else {
        return;
    };
    if let (false, Some(was), Some(now)) = (placed, old.slab(), case.slab()) {
        if was.outlet_offset() == 0.0 && now.outlet_offset() != 0.0 {
            eprintln!(
                "note: the outlet is no longer centred: the bed's case places its left edge at \
                 outlet_gap = {} m, which the new width keeps; --set geometry.outlet_offset=0 \
                 centres it",
                now.outlet_gap
            );
        }
    }
}

/// Refuses (exit 2) a bed folder for --save-bed that holds a bed already, unless --restart
/// replaces it or --resume continues the run of the same case that saved it.
fn refuse_saved_bed(args: &RunArgs, case: &Case) -> Option<i32> {
    let dir = args.save_bed.as_ref()?;
    match check_save_bed(dir, case, args.resume, args.restart) {
        Ok(()) => None,
        Err(e) => {
            eprintln!("error: {e}");
            Some(EXIT_BAD_INPUT)
        }
    }
}

/// Estimates the run's cost, prints it (to standard output with --estimate, standard error
/// else, nothing with --quiet) and refuses a run that could not finish unless
/// --no-cost-check: `Some(exit code)` to stop with, `None` to go on and run.
fn check_cost(args: &RunArgs, case: &Case, start: &Start) -> Option<i32> {
    // A short run is not timed (`run::cost::SHORT_RUN_PARTICLE_STEPS`); --estimate always is.
    let timing = if args.estimate {
        run::cost::Timing::Always
    } else {
        run::cost::Timing::UnlessShort
    };
    let estimate = match run::cost::estimate_cost(case, start, args.threads, timing) {
        Ok(e) => e,
        Err(e) if args.estimate => {
            eprintln!("error: the cost could not be estimated: {e}");
            return Some(1);
        }
        Err(e) => {
            eprintln!("warning: no cost estimate: {e}");
            return None;
        }
    };
    let physical = run::cost::physical_memory();
    let refusal = run::cost::cost_refusal(case, &estimate, physical);
    if args.estimate && args.json {
        let value = crate::cost_report::estimate_json(&estimate, physical, refusal.as_deref());
        println!("{value:#}");
    } else if args.estimate {
        for line in crate::cost_report::estimate_lines(&estimate, physical) {
            println!("{line}");
        }
    } else if !args.quiet {
        for line in crate::cost_report::estimate_lines(&estimate, physical) {
            eprintln!("{line}");
        }
    }
    match refusal {
        Some(why) if !args.no_cost_check => {
            eprintln!("error: {why}");
            eprintln!("hint: --no-cost-check runs it anyway");
            Some(EXIT_BAD_INPUT)
        }
        _ if args.estimate => Some(0),
        _ => None,
    }
}

pub fn run(args: RunArgs) -> i32 {
    // Validate everything before touching the output directory: bad input leaves nothing.
    let (case, start) = match case_and_start(&args) {
        Ok(c) => c,
        Err(code) => return code,
    };
    if args.estimate {
        return check_cost(&args, &case, &start).unwrap_or(0);
    }
    if !args.resume && !args.restart {
        if let Some(code) = refuse_occupied(&args.out) {
            return code;
        }
    }
    if let Some(code) = refuse_saved_bed(&args, &case) {
        return code;
    }
    if let Some(code) = check_cost(&args, &case, &start) {
        return code;
    }
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::new(1000);
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} {prefix:>9} [{bar:30}] {msg} (elapsed {elapsed})",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
        );
        bar
    };
    let b = bar.clone();
    let progress = Arc::new(move |p: &Progress| {
        b.set_prefix(p.phase);
        b.set_position((p.fraction.clamp(0.0, 1.0) * 1000.0) as u64);
        let left = if p.remaining_at_most.is_finite() {
            format!(
                ", ≤ {} left",
                run::cost::duration_in_words(p.remaining_at_most)
            )
        } else {
            String::new()
        };
        b.set_message(format!(
            "t = {:.3} s, {} particles, {:.2e} particle-steps/s{left}",
            p.time, p.particles, p.particle_steps_per_second
        ));
    });
    let options = RunOptions {
        threads: args.threads,
        // A plain run reaches here only with an empty folder; --restart starts over.
        resume: !args.restart,
        progress: Some(progress),
        pictures: !args.no_pictures,
        chunk_limit: None,
        stop: Some(crate::signals::stop_flag()),
        save_bed: args.save_bed.clone(),
    };
    let started = std::time::Instant::now();
    let outcome = run_case_from(&case, &args.out, &options, &start);
    bar.finish_and_clear();
    match outcome {
        Ok(RunOutcome::Finished(s)) => {
            println!("case      {}", case_name(&args, &start));
            match &start {
                Start::Fill => {}
                Start::Bed(bed) => println!("start     bed {}", bed.header()),
                Start::Packing(p) => println!(
                    "start     packing {} ({} particles)",
                    p.source().display(),
                    p.particles().len()
                ),
            }
            if let Some(dir) = &args.save_bed {
                println!("bed       {}", dir.display());
            }
            println!("output    {}", args.out.display());
            println!(
                "W         {:.2} ± {:.2} g/s (steady window {:.3}–{:.3} s after opening{})",
                s.discharge_rate * 1e3,
                s.discharge_rate_error * 1e3,
                s.steady_window[0],
                s.steady_window[1],
                if s.plateau_found {
                    ""
                } else {
                    ", no clear plateau"
                }
            );
            println!(
                "flux      {:.2} g/s from ⟨φv⟩, {:.2} g/s from φ(x)·v(x)",
                s.flux_check_rate * 1e3,
                s.flux_check_rate_profiles * 1e3
            );
            println!(
                "v_c       {:.3} m/s, φ_c {:.3}, φ_max {:.3}",
                s.centre_velocity, s.centre_area_fraction, s.max_area_fraction
            );
            println!(
                "φ_B       {:.3} (bed height {:.1} mm)",
                s.bulk_volume_fraction,
                s.bed_height * 1e3
            );
            if let Some(j) = &s.janssen {
                println!(
                    "Janssen   K {:.2} ± {:.2}, μ_w {:.3} ± {:.3}, p_sat {:.0} ± {:.0} Pa \
                     ({} zones of the settled bed)",
                    j.stress_ratio[0],
                    j.stress_ratio[1],
                    j.wall_friction[0],
                    j.wall_friction[1],
                    j.saturation_pressure[0],
                    j.saturation_pressure[1],
                    j.zones
                );
            } else if let Some(why) = &s.janssen_not_fitted {
                println!("Janssen   no fit: {why}");
            }
            println!(
                "stopped   {:?} after {:.2} s of discharge{}",
                s.stop_reason,
                s.discharge_time,
                if s.clogged { " (clogged)" } else { "" }
            );
            println!("wall time {:.1} s", started.elapsed().as_secs_f64());
            0
        }
        Ok(RunOutcome::Interrupted) => {
            eprintln!(
                "stopped by a signal; the checkpoint in {} continues with --resume",
                args.out.display()
            );
            crate::exit_codes::EXIT_STOPPED
        }
        Err(e @ (RunError::Bed(_) | RunError::Packing(_) | RunError::BedTooLate { .. })) => {
            eprintln!("error: {e}");
            EXIT_BAD_INPUT
        }
        Err(
            e @ (RunError::OtherInputs { .. }
            | RunError::OtherStart { .. }
            | RunError::BadCheckpoint { .. }
            | RunError::BadSummary { .. }),
        ) => {
            eprintln!("error: {e}");
            eprintln!(
                "hint: --restart discards what {} holds and starts the case over; or choose another --out",
                args.out.display()
            );
            EXIT_BAD_INPUT
        }
        Err(e) => {
            eprintln!("error: {e}");
            1
        }
    }
}
