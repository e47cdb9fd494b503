//! `hopperflow bench`: engine timings on the paper's problem.

use clap::{Args, ValueEnum};
use std::path::PathBuf;

use study::bench::{
    bidisperse_benchmark, combine, hopper_benchmark, mesh_floor_benchmark, scaling_benchmark,
    settled_bed, silo_benchmark, time_steps, BenchResult, BidisperseBed,
};

#[derive(Clone, Copy, ValueEnum)]
pub enum BenchCase {
    /// A settled bed of 3000 Table-1 spheres in the slab, gate closed.
    Bed,
    /// The paper's base case, timed over 0.1–0.3 s after the gate opens.
    Hopper,
    /// Dense 3D packings (jittered lattices in contact) of 10^4, 10^5 and 10^6 spheres, or of
    /// `--particles`: cost per particle-step and peak memory as N grows.
    Scaling,
    /// A settled 3D bed of spheres of diameters d and `--ratio`·d (d = 3 mm) in equal volumes,
    /// 10^4 spheres by default; `--ratio 1` is the monodisperse bed at the same solid fraction.
    Bidisperse,
    /// The monodisperse 3D bed (2·10^4 spheres by default) timed on its floor plane and then
    /// on a floor of `--triangles` triangles (10^5 by default) in its place.
    MeshFloor,
    /// The benchmark silo of Dosta et al. (2024), M1 and the large orifice, with
    /// `--particles` spheres (default 20 000), timed over 0.05–0.08 s after the gate opens;
    /// `--meshed` for triangle-mesh walls.
    Silo,
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
    /// Particles in the bed (default 3000), the scaling packing (default 10^4, 10^5, 10^6) or
    /// the bidisperse bed (default 10^4, rounded to whole blocks).
    #[arg(long)]
    particles: Option<usize>,
    /// Steps timed (bed and bidisperse: default 4000; scaling: default 20 per
    /// repetition, repeated from a fresh packing until each size has 2·10^7 particle-steps).
    #[arg(long)]
    steps: Option<u64>,
    /// Bed and bidisperse bed: untimed steps of settling before the timed steps (2.5 µs each).
    /// The bed's default, 0.3 s, lets it compact: contacts per particle are 3.6 after 0.05 s,
    /// 4.22 after 0.3 s and 4.26 after 0.6 s, and the cost per particle-step follows them. The
    /// bidisperse bed's default is 0.4 s: its contacts per particle (1:3, 2000 spheres) are
    /// 2.97 after 0.1 s, 4.17 after 0.2 s and 4.32 after 0.4 s.
    #[arg(long)]
    settle_steps: Option<u64>,
    /// Mesh floor only: triangles of the floor (rounded up to 2n²).
    #[arg(long, default_value_t = 100_000, value_parser = clap::value_parser!(usize))]
    triangles: usize,
    /// Bidisperse only: large over small diameter.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=10))]
    ratio: u32,
    /// Checkpoint of the filled, settled hopper, reused between hopper benchmarks; the
    /// settled bidisperse beds are cached beside it.
    #[arg(long, default_value = "out/bench-cache/hopper.bin")]
    cache: PathBuf,
    /// Runs of the whole benchmark: the median run is reported, with every run's time and
    /// their spread (median, mean, standard deviation, range). One timing on a shared or
    /// virtual machine can be 15 % off; compare medians, and differences larger than the range.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100))]
    runs: u32,
    /// Silo only: meshed cylinder and cone instead of the exact ones.
    #[arg(long)]
    meshed: bool,
}

fn one(args: &BenchArgs, threads: usize) -> anyhow::Result<Vec<BenchResult>> {
    match args.case {
        BenchCase::Bed => {
            let settle = args.settle_steps.unwrap_or(120_000);
            let mut sim = settled_bed(args.particles.unwrap_or(3000), threads, settle)?;
            Ok(vec![time_steps(
                &mut sim,
                args.steps.unwrap_or(4000),
                "bed",
                threads,
            )?])
        }
        BenchCase::Hopper => Ok(vec![hopper_benchmark(threads, Some(&args.cache))?]),
        BenchCase::Silo => {
            let particles = args.particles.unwrap_or(20_000);
            let walls = if args.meshed { "meshed" } else { "smooth" };
            let cache = args
                .cache
                .with_file_name(format!("silo-n{particles}-{walls}.bin"));
            Ok(vec![silo_benchmark(
                particles,
                args.meshed,
                threads,
                Some(&cache),
            )?])
        }
        BenchCase::Scaling => {
            let sizes = match args.particles {
                Some(n) => vec![n],
                None => vec![10_000, 100_000, 1_000_000],
            };
            // Sizes in increasing order, so the process's peak memory belongs to the current one.
            let mut out = Vec::new();
            for n in sizes {
                let steps = args.steps.unwrap_or(20).max(1);
                let repeats = (20_000_000 / (n.max(1) as u64 * steps)).clamp(1, 1000) as u32;
                out.push(scaling_benchmark(n, steps, repeats, threads)?);
            }
            Ok(out)
        }
        BenchCase::Bidisperse => {
            let bed = BidisperseBed {
                ratio: args.ratio,
                particles: args.particles.unwrap_or(10_000),
            };
            let (settle, steps) = (
                args.settle_steps.unwrap_or(160_000),
                args.steps.unwrap_or(4000),
            );
            let name = format!("bidisperse-r{}-n{}-s{settle}.bin", bed.ratio, bed.particles);
            let cache = args.cache.with_file_name(name);
            Ok(vec![bidisperse_benchmark(
                bed,
                threads,
                settle,
                steps,
                Some(&cache),
            )?])
        }
        BenchCase::MeshFloor => {
            let particles = args.particles.unwrap_or(20_000);
            let (settle, steps) = (
                args.settle_steps.unwrap_or(160_000),
                args.steps.unwrap_or(2000),
            );
            let name = format!("bidisperse-r1-n{particles}-s{settle}.bin");
            let cache = args.cache.with_file_name(name);
            Ok(mesh_floor_benchmark(
                particles,
                args.triangles,
                threads,
                (settle, steps),
                Some(&cache),
            )?)
        }
    }
}

/// `args.runs` runs of the benchmark on `threads` threads, each entry (one per size for the
/// scaling benchmark) combined over the runs into its median run.
fn repeated(args: &BenchArgs, threads: usize) -> anyhow::Result<Vec<BenchResult>> {
    let mut runs = Vec::new();
    for _ in 0..args.runs {
        runs.push(one(args, threads)?);
    }
    if runs.len() == 1 {
        return Ok(runs.pop().unwrap_or_default());
    }
    let entries = runs[0].len();
    (0..entries)
        .map(|k| {
            let of_entry: Vec<BenchResult> = runs.iter().map(|r| r[k].clone()).collect();
            let mut c = combine(of_entry).ok_or_else(|| {
                anyhow::anyhow!(
                    "the {} runs of benchmark entry {k} are not comparable",
                    args.runs
                )
            })?;
            // Peak memory is the process's: after the first run it holds the largest size
            // already, so only the first run's memory figures belong to their size.
            c.peak_memory_bytes = runs[0][k].peak_memory_bytes;
            c.bytes_per_particle = runs[0][k].bytes_per_particle;
            Ok(c)
        })
        .collect()
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
        match repeated(&args, t) {
            Ok(r) => results.extend(r),
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
        println!(
            "{:<8} {:>7} {:>9} {:>10} {:>12} {:>12} {:>10} {:>9} {:>10} {:>8}",
            "case",
            "threads",
            "particles",
            "ns/p-step",
            "cpu ns/p-st",
            "p-steps/s",
            "contacts/p",
            "bytes/p",
            "ns/contact",
            "cands/p"
        );
        let or_dash = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.1}"));
        for r in &results {
            println!(
                "{:<8} {:>7} {:>9} {:>10.1} {:>12} {:>12.3e} {:>10.2} {:>9} {:>10.1} {:>8.2}",
                r.case,
                r.threads,
                r.particles,
                r.ns_per_particle_step,
                or_dash(r.cpu_ns_per_particle_step),
                r.particle_steps_per_second,
                r.contacts_per_particle,
                or_dash(r.bytes_per_particle),
                r.ns_per_contact,
                r.candidates_per_particle
            );
        }
        // Where the time went, as LAMMPS' timing table after a run.
        println!(
            "\n{:<8} {:>7} {:>10} {:>10} {:>10} {:>10}   (ns per particle-step)",
            "case", "threads", "forces", "integrate", "neighbour", "other"
        );
        for r in &results {
            let p = &r.phases;
            println!(
                "{:<8} {:>7} {:>10.1} {:>10.1} {:>10.1} {:>10.1}",
                r.case, r.threads, p.forces_ns, p.integrate_ns, p.neighbour_ns, p.other_ns
            );
        }
        // With repeated runs, their spread, as hyperfine reports a command's runs.
        if results.iter().any(|r| r.runs.is_some()) {
            println!(
                "\n{:<8} {:>7} {:>5} {:>8} {:>8} {:>8} {:>8} {:>8} {:>7}   (ns per particle-step)",
                "case", "threads", "runs", "median", "mean", "std dev", "min", "max", "range"
            );
            for r in &results {
                let Some(s) = &r.runs else { continue };
                println!(
                    "{:<8} {:>7} {:>5} {:>8.1} {:>8.1} {:>8.1} {:>8.1} {:>8.1} {:>6.1}%",
                    r.case,
                    r.threads,
                    s.ns_per_particle_step.len(),
                    s.median_ns,
                    s.mean_ns,
                    s.std_dev_ns,
                    s.min_ns,
                    s.max_ns,
                    100.0 * s.relative_range()
                );
            }
        }
    }
    0
}
