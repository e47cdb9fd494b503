//! `hopperflow run`, `check` and `init`: one case from a file (or the paper's base case).

use std::path::PathBuf;
use std::sync::Arc;

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use study::config::{default_case, load_case, template, Case, CASE_TEMPLATE};
use study::output::write_atomic;
use study::run::{occupant, run_case, Occupant, Progress, RunError, RunOptions, RunOutcome};

/// Exit code for bad input (a malformed case file or override).
pub const EXIT_BAD_INPUT: i32 = 2;

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
    /// 3000 spheres a whole run is only 1-7 % faster (docs/performance.md). Several cases use
    /// the cores better side by side: `study --jobs`.
    #[arg(long, default_value_t = 1)]
    threads: usize,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
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
    /// The geometry kind of the template: slab (the paper's hopper) or cylinder (a silo).
    #[arg(long, default_value = "slab", value_parser = ["slab", "cylinder"])]
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
            if path.exists() {
                eprintln!("error: {} exists; not overwriting it", path.display());
                return EXIT_BAD_INPUT;
            }
            match write_atomic(&path, text.as_bytes()) {
                Ok(()) => {
                    eprintln!("wrote {}", path.display());
                    0
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    1
                }
            }
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

pub fn run(args: RunArgs) -> i32 {
    // Validate everything before touching the output directory: bad input leaves nothing.
    let case = match load(args.case.as_ref(), &args.sets) {
        Ok(c) => c,
        Err(code) => return code,
    };
    if !args.resume && !args.restart {
        if let Some(code) = refuse_occupied(&args.out) {
            return code;
        }
    }
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::new(1000);
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} {prefix:>9} [{bar:30}] {msg} (elapsed {elapsed}, eta {eta})",
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
        b.set_message(format!(
            "t = {:.3} s, {} particles, {:.2e} particle-steps/s",
            p.time, p.particles, p.particle_steps_per_second
        ));
    });
    let options = RunOptions {
        threads: args.threads,
        // A plain run reaches here only with an empty folder; --restart starts over.
        resume: !args.restart,
        progress: Some(progress),
        pictures: true,
        chunk_limit: None,
        stop: Some(crate::signals::stop_flag()),
    };
    let started = std::time::Instant::now();
    let outcome = run_case(&case, &args.out, &options);
    bar.finish_and_clear();
    match outcome {
        Ok(RunOutcome::Finished(s)) => {
            println!(
                "case      {}",
                args.case
                    .as_ref()
                    .map_or("paper base case".into(), |p| p.display().to_string())
            );
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
            crate::signals::EXIT_STOPPED
        }
        Err(
            e @ (RunError::OtherInputs { .. }
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
