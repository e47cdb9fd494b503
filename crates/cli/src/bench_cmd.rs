//! `hopperflow bench`: engine timings on the paper's problem.

use clap::{Args, ValueEnum};
use std::path::PathBuf;

use run::bench::{
    bidisperse_benchmark, combine, dumbbell_benchmark, hopper_benchmark, mesh_floor_benchmark,
    scaling_benchmark, settled_bed, silo_benchmark, time_steps, BenchResult, BidisperseBed,
    SiloBench, SiloInputError, SiloRequest, SiloSource, SiloStart,
};

use crate::exit_codes::EXIT_BAD_INPUT;

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
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
    /// The monodisperse bed of `--case bidisperse --ratio 1` with each pair of its spheres
    /// along x joined into a rigid dumbbell (10^4 beads by default): the cost of a clump's
    /// member sphere against a free sphere's.
    Dumbbells,
    /// The benchmark silo of Dosta et al. (2024), M1 and the large orifice, with
    /// `--particles` spheres (default 20 000), timed over 0.05–0.08 s after the gate opens;
    /// `--meshed` for triangle-mesh walls, `--case-file` for any case instead, `--packing`
    /// to start from a packing file.
    Silo,
}

#[derive(Args)]
pub struct BenchArgs {
    /// Which benchmark [default: bed; silo with --case-file or --packing].
    #[arg(long, value_enum)]
    case: Option<BenchCase>,
    /// Worker threads (default: report 1 thread and all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
    /// Particles in the bed (default 3000), the scaling packing (default 10^4, 10^5, 10^6),
    /// the bidisperse bed (default 10^4, rounded to whole blocks), the dumbbell bed's beads
    /// (default 10^4) or the silo (default 20 000;
    /// with --case-file it replaces the file's particles.count and any --set of it).
    #[arg(long, conflicts_with = "packing")]
    particles: Option<usize>,
    /// Steps timed (bed, bidisperse and dumbbells: default 4000; scaling: default 20 per
    /// repetition, repeated from a fresh packing until each size has 2·10^7 particle-steps).
    #[arg(long)]
    steps: Option<u64>,
    /// Bed, bidisperse and dumbbell beds: untimed steps of settling before the timed steps
    /// (2.5 µs each).
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
    /// settled bidisperse beds and silos are cached beside it, a silo as
    /// silo-n{N}-{walls}-{key}.bin with a key of its resolved case (the --set overrides and
    /// the STL files' SHA-256 included) and its packing file's bytes, so that a bed is reused
    /// only for the inputs that made it.
    #[arg(long, default_value = "out/bench-cache/hopper.bin")]
    cache: PathBuf,
    /// Runs of the whole benchmark: the median run is reported, with every run's time and
    /// their spread (median, mean, standard deviation, range). One timing on a shared or
    /// virtual machine can be 15 % off; compare medians, and differences larger than the range.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100))]
    runs: u32,
    /// Silo only: meshed cylinder and cone instead of the exact ones.
    #[arg(long, conflicts_with = "case_file")]
    meshed: bool,
    /// Silo only: time the discharge of this case file instead of the built-in silo, over the
    /// same window (0.05–0.08 s after the gate opens). The file and the --set overrides are
    /// read and checked as `hopperflow run FILE` reads them (exit 2 on any error, nothing
    /// timed); the file says its walls, so not with --meshed.
    #[arg(long, value_name = "FILE")]
    case_file: Option<PathBuf>,
    /// Silo only: start from a packing file instead of the fill, as `hopperflow run --packing`
    /// does (CSV with the columns x,y,z,radius and, for a mixture, material, or VTU): the
    /// particles are placed at rest, settle on the closed gate under the case's settling
    /// criterion, the gate opens and the same window is timed. particles.count is the
    /// packing's, so not with --particles.
    #[arg(long, value_name = "FILE")]
    packing: Option<PathBuf>,
    /// Silo only: override a key of the silo's case (the built-in one or --case-file's), e.g.
    /// `--set seed=2` (repeatable), as for `hopperflow run`; --particles and --meshed are
    /// applied after it.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    sets: Vec<String>,
}

impl BenchArgs {
    /// The benchmark asked for: --case, or the silo where only a silo option names one.
    fn case(&self) -> BenchCase {
        match self.case {
            Some(case) => case,
            None if self.case_file.is_some() || self.packing.is_some() => BenchCase::Silo,
            None => BenchCase::Bed,
        }
    }

    /// The silo's inputs as the options give them.
    fn silo_request(&self) -> SiloRequest {
        SiloRequest {
            source: match &self.case_file {
                Some(file) => SiloSource::File(file.clone()),
                None => SiloSource::Template {
                    meshed: self.meshed,
                },
            },
            sets: self.sets.clone(),
            start: match &self.packing {
                Some(file) => SiloStart::Packing(file.clone()),
                None => SiloStart::Fill {
                    particles: self.particles,
                },
            },
        }
    }
}

/// The options that only the silo takes, as given on the command line.
fn silo_options(args: &BenchArgs) -> Vec<&'static str> {
    let mut given = Vec::new();
    if args.case_file.is_some() {
        given.push("--case-file");
    }
    if args.packing.is_some() {
        given.push("--packing");
    }
    if !args.sets.is_empty() {
        given.push("--set");
    }
    if args.meshed {
        given.push("--meshed");
    }
    given
}

/// The silo's inputs read and checked, or the exit code of the refusal (its message printed):
/// each error names the option and the file it came from.
fn resolve_cylinder(args: &BenchArgs) -> Result<SiloBench, i32> {
    args.silo_request().resolve().map_err(|e| {
        match &e {
            SiloInputError::Case {
                file: Some(file), ..
            } => eprintln!(
                "error: --case-file {}: not a usable case; nothing was timed\n{e}",
                file.display()
            ),
            SiloInputError::Case { file: None, .. } => eprintln!(
                "error: the built-in silo with these options is not a valid case; nothing was \
                 timed\n{e}"
            ),
            SiloInputError::Packing(p) => eprintln!(
                "error: --packing {}: not a usable packing; nothing was timed\n{}",
                p.file.display(),
                error_lines(&e)
            ),
        }
        EXIT_BAD_INPUT
    })
}

/// Every line of an error as an `error:` line (a packing error has one per problem).
fn error_lines(e: &SiloInputError) -> String {
    e.to_string()
        .lines()
        .map(|l| format!("error: {l}"))
        .collect::<Vec<_>>()
        .join("\n")
}

fn one(
    args: &BenchArgs,
    silo: Option<&SiloBench>,
    threads: usize,
) -> anyhow::Result<Vec<BenchResult>> {
    match args.case() {
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
            let silo = silo.ok_or_else(|| anyhow::anyhow!("the silo's inputs were not read"))?;
            let cache = args.cache.with_file_name(silo.cache_name());
            Ok(vec![silo_benchmark(silo, threads, Some(&cache))?])
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
        BenchCase::Dumbbells => {
            let beads = args.particles.unwrap_or(10_000);
            let (settle, steps) = (
                args.settle_steps.unwrap_or(160_000),
                args.steps.unwrap_or(4000),
            );
            let cache = args
                .cache
                .with_file_name(format!("dumbbells-n{beads}-s{settle}.bin"));
            Ok(vec![dumbbell_benchmark(
                beads,
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
fn repeated(
    args: &BenchArgs,
    silo: Option<&SiloBench>,
    threads: usize,
) -> anyhow::Result<Vec<BenchResult>> {
    let mut runs = Vec::new();
    for _ in 0..args.runs {
        runs.push(one(args, silo, threads)?);
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
    // Refuse inputs before anything is timed: silo options on another benchmark, then the
    // silo's case and packing, read once for every run and thread count.
    let case = args.case();
    let given = silo_options(&args);
    if case != BenchCase::Silo && !given.is_empty() {
        let name = case
            .to_possible_value()
            .map_or_else(String::new, |v| v.get_name().to_string());
        let verb = if given.len() == 1 { "applies" } else { "apply" };
        eprintln!(
            "error: {} {verb} to --case silo only, not to --case {name}",
            given.join(", ")
        );
        return EXIT_BAD_INPUT;
    }
    let silo = if case == BenchCase::Silo {
        match resolve_cylinder(&args) {
            Ok(silo) => Some(silo),
            Err(code) => return code,
        }
    } else {
        None
    };
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
        match repeated(&args, silo.as_ref(), t) {
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
        // Where the time went, as LAMMPS' timing table after a run, each phase with the part
        // of it that one thread ran while the others waited (in brackets), and the serial
        // share of the whole.
        println!(
            "\n{:<8} {:>7} {:>17} {:>17} {:>17} {:>7} {:>8}   (ns per particle-step; serial in brackets)",
            "case", "threads", "forces", "integrate", "neighbour", "other", "serial"
        );
        let split = |whole: f64, serial: f64| format!("{whole:.1} ({serial:.1})");
        for r in &results {
            let p = &r.phases;
            println!(
                "{:<8} {:>7} {:>17} {:>17} {:>17} {:>7.1} {:>7.1}%",
                r.case,
                r.threads,
                split(p.forces_ns, p.forces_serial_ns),
                split(p.integrate_ns, p.integrate_serial_ns),
                split(p.neighbour_ns, p.neighbour_serial_ns),
                p.other_ns,
                100.0 * p.serial_share
            );
        }
        // Amdahl's law from the one-thread run and each run on more threads.
        for r in results.iter().filter(|r| r.threads > 1) {
            let Some(one) = results
                .iter()
                .find(|o| o.threads == 1 && o.case == r.case && o.particles == r.particles)
            else {
                continue;
            };
            let measured = (r.ns_per_particle_step, r.phases.serial_ns, r.threads);
            let predict = |q| run::bench::amdahl_speedup(one.ns_per_particle_step, measured, q);
            println!(
                "\n{}: {:.2}× on {} threads; Amdahl's law from its serial part predicts {:.1}× on 16 and {:.1}× on 64 (an upper bound: docs/performance.md, Scaling model)",
                r.case,
                one.ns_per_particle_step / r.ns_per_particle_step,
                r.threads,
                predict(16),
                predict(64)
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
