//! The `hopperflow` binary: parses arguments, runs a subcommand, maps errors to exit codes.

use clap::{Parser, Subcommand};

mod bench_cmd;

#[derive(Parser)]
#[command(name = "hopperflow", version, about = "DEM simulation and analysis of granular discharge from hoppers")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Time the engine (ns per particle-step).
    Bench(bench_cmd::BenchArgs),
}

fn main() {
    let cli = Cli::parse();
    let code = match cli.command {
        Command::Bench(args) => bench_cmd::run(args),
    };
    std::process::exit(code);
}
