//! The `hopperflow` binary: parses arguments, runs a subcommand, maps errors to exit codes.

use clap::{Parser, Subcommand};

mod bench_cmd;
mod calibrate_cmd;
mod cost_report;
mod exit_codes;
mod report_cmd;
mod run_cmd;
mod signals;
mod slurm_cmd;
mod study_cmd;
mod verify_cmd;

#[derive(Parser)]
#[command(
    name = "hopperflow",
    version,
    about = "DEM simulation and analysis of granular discharge from hoppers"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run one hopper case (default: the paper's base case).
    Run(run_cmd::RunArgs),
    /// Validate a case file without running it.
    Check(run_cmd::CheckArgs),
    /// Write a commented case file with every key, its unit and default.
    Init(run_cmd::InitArgs),
    /// Run a parametric study: the paper's (`fan2023`) or a sweep file.
    Study(study_cmd::StudyArgs),
    /// Find material parameters (e.g. rolling friction, cohesion) from lab targets.
    Calibrate(calibrate_cmd::CalibrateArgs),
    /// Build the report of a finished study from its saved results.
    Report(report_cmd::ReportArgs),
    /// Time the engine (ns per particle-step).
    Bench(bench_cmd::BenchArgs),
    /// Run the verification suite (impact benchmarks and closed-form tests).
    Verify(verify_cmd::VerifyArgs),
}

/// Sends the warnings of every part of the program to standard error, as `warning: …` lines;
/// `HOPPERFLOW_LOG` set to a level (`error`, `warn`, `info`, `debug`, `trace` or `off`) shows
/// more or less. An unknown level is named on standard error and the default, `warn`, kept.
fn install_warnings() {
    use tracing_subscriber::filter::LevelFilter;
    let level = match std::env::var("HOPPERFLOW_LOG") {
        Ok(text) => text.trim().parse::<LevelFilter>().unwrap_or_else(|_| {
            eprintln!(
                "warning: HOPPERFLOW_LOG = {text:?} is not a level (error, warn, info, debug, trace, off); using warn"
            );
            LevelFilter::WARN
        }),
        Err(_) => LevelFilter::WARN,
    };
    tracing_subscriber::fmt()
        .with_max_level(level)
        .with_writer(std::io::stderr)
        .without_time()
        .with_target(false)
        .init();
}

fn main() {
    install_warnings();
    signals::quiet_broken_pipe();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() {
                exit_codes::EXIT_BAD_INPUT
            } else {
                0
            };
            let _ = e.print();
            std::process::exit(code);
        }
    };
    let code = match cli.command {
        Command::Run(args) => run_cmd::run(args),
        Command::Check(args) => run_cmd::check(args),
        Command::Init(args) => run_cmd::init(args),
        Command::Study(args) => study_cmd::run(args),
        Command::Calibrate(args) => calibrate_cmd::run(args),
        Command::Report(args) => report_cmd::run(args),
        Command::Bench(args) => bench_cmd::run(args),
        Command::Verify(args) => verify_cmd::run(args),
    };
    std::process::exit(code);
}
