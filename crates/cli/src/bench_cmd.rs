//! `hopperflow bench`: engine timings on the paper's problem.

use clap::{Args, ValueEnum};
use std::path::PathBuf;

use study::bench::{hopper_benchmark, settled_bed, time_steps, BenchResult};

#[derive(Clone, Copy, ValueEnum)]
pub enum BenchCase {
    /// A settled bed of 3000 Table-1 spheres in the slab, gate closed.
    Bed,
    /// The paper's base case, timed over 0.1–0.3 s after the gate opens.
    Hopper,
}

#[derive(Args)]
pub struct BenchArgs {
    /// Which benchmark.
    #[arg(long, value_enum, default_value = "bed")]
    case: BenchCase,
    /// Worker threads (default: report 1 thread and all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
    /// Particles in the bed.
    #[arg(long, default_value_t = 3000)]
    particles: usize,
    /// Steps timed (bed only).
    #[arg(long, default_value_t = 4000)]
    steps: u64,
    /// Checkpoint of the filled, settled hopper, reused between hopper benchmarks.
    #[arg(long, default_value = "out/bench-cache/hopper.bin")]
    cache: PathBuf,
}

fn one(args: &BenchArgs, threads: usize) -> anyhow::Result<BenchResult> {
    match args.case {
        BenchCase::Bed => {
            let mut sim = settled_bed(args.particles, threads, 20_000)?;
            Ok(time_steps(&mut sim, args.steps, "bed", threads)?)
        }
        BenchCase::Hopper => Ok(hopper_benchmark(threads, Some(&args.cache))?),
    }
}

pub fn run(args: BenchArgs) -> i32 {
    let all = std::thread::available_parallelism().map_or(1, |n| n.get());
    let list: Vec<usize> = match args.threads {
        Some(t) => vec![if t == 0 { all } else { t }],
        None => {
            let mut v = vec![1];
            if all > 1 {
                v.push(all);
            }
            v
        }
    };
    let mut results = Vec::new();
    for t in list {
        match one(&args, t) {
            Ok(r) => results.push(r),
            Err(e) => {
                eprintln!("error: {e:#}");
                return 1;
            }
        }
    }
    if args.json {
        let out = if results.len() == 1 {
            serde_json::to_string_pretty(&results[0])
        } else {
            serde_json::to_string_pretty(&results)
        };
        println!("{}", out.unwrap_or_default());
    } else {
        println!("{:<8} {:>7} {:>9} {:>12} {:>16} {:>10}", "case", "threads", "particles", "ns/p-step", "p-steps/s", "contacts/p");
        for r in &results {
            println!(
                "{:<8} {:>7} {:>9} {:>12.1} {:>16.3e} {:>10.2}",
                r.case, r.threads, r.particles, r.ns_per_particle_step, r.particle_steps_per_second, r.contacts_per_particle
            );
        }
    }
    0
}
