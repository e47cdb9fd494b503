//! Engine benchmarks on the paper's problem: a settled bed in the slab, and the hopper's
//! discharge. Wall-clock timing lives here, never in tests.

use std::time::Instant;

use dem::{DemError, PhaseTimes, Simulation};
use rand::SeedableRng;
use serde::Serialize;

use crate::{lattice_bed, slab_simulation};
use case::Case;

mod bidisperse;
mod dumbbell_bed;
mod mesh_floor;
mod repeat;
mod silo_inputs;
pub use bidisperse::{bidisperse_bed, bidisperse_benchmark, BidisperseBed};
use bidisperse::{settled_bidisperse_bed, SMALL_DIAMETER};
pub use dumbbell_bed::{dumbbell_bed, dumbbell_benchmark};
pub use mesh_floor::mesh_floor_benchmark;
pub use repeat::{combine, RunSpread};
pub use silo_inputs::{
    SiloBench, SiloInputError, SiloRequest, SiloSource, SiloStart, SILO_PARTICLES,
};

/// One timing.
#[derive(Debug, Clone, Serialize)]
pub struct BenchResult {
    /// Which benchmark ("bed", "hopper").
    pub case: String,
    /// Worker threads.
    pub threads: usize,
    /// Particles in the timed window (mean).
    pub particles: usize,
    /// Steps timed.
    pub steps: u64,
    /// Wall time per particle and step [ns].
    pub ns_per_particle_step: f64,
    /// Particle-steps per second of wall time.
    pub particle_steps_per_second: f64,
    /// Contacts per particle (particle–particle counted for both partners, plus walls).
    pub contacts_per_particle: f64,
    /// Particle–wall contacts per particle (included in `contacts_per_particle`).
    pub wall_contacts_per_particle: f64,
    /// Wall time per contact and step [ns]: each touching pair and each particle–wall
    /// contact counted once.
    pub ns_per_contact: f64,
    /// Particle–particle candidates in the neighbour list per particle, each counted for
    /// both partners (sampled as the contacts are).
    pub candidates_per_particle: f64,
    /// Neighbour-list rebuilds during the window.
    pub rebuilds: u64,
    /// CPU time of the calling thread per particle and step [ns], where the OS reports it
    /// (Linux schedstat); less sensitive than wall time to other load on the machine.
    pub cpu_ns_per_particle_step: Option<f64>,
    /// Peak resident memory of the process so far (Linux VmHWM) [bytes], where reported.
    pub peak_memory_bytes: Option<u64>,
    /// Peak memory above what the process held before the set-up, per particle [bytes].
    pub bytes_per_particle: Option<f64>,
    /// Where the wall time went, per particle-step.
    pub phases: PhaseBreakdown,
    /// With repeated runs ([`combine`]): every run's timing and their spread; this result
    /// is then the median run. Absent for a single run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub runs: Option<RunSpread>,
}

/// A benchmark's wall time per particle-step split by phase of the step [ns]. The four add up
/// to `ns_per_particle_step`.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct PhaseBreakdown {
    /// Contact detection and forces, pairs and walls [ns].
    pub forces_ns: f64,
    /// Half kicks and drift [ns].
    pub integrate_ns: f64,
    /// Neighbour-list rebuilds [ns].
    pub neighbour_ns: f64,
    /// The rest: the benchmark's own loop and, for the hopper, the run protocol's outlet
    /// probes, deletion below the outlet and measurements [ns].
    pub other_ns: f64,
    /// The part of `forces_ns` outside the pool's parallel regions, run by one thread while
    /// the others wait [ns]; all of it on one thread.
    pub forces_serial_ns: f64,
    /// The part of `integrate_ns` outside parallel regions [ns].
    pub integrate_serial_ns: f64,
    /// The part of `neighbour_ns` outside parallel regions [ns].
    pub neighbour_serial_ns: f64,
    /// Everything outside parallel regions, `other_ns` included [ns].
    pub serial_ns: f64,
    /// `serial_ns` over the whole time per particle-step [-]: the serial share of
    /// Amdahl's law at this thread count.
    pub serial_share: f64,
}

impl PhaseBreakdown {
    /// Splits `secs` [s] of wall time over `particle_steps` by the engine's phase times.
    fn of(times: Option<PhaseTimes>, secs: f64, particle_steps: f64) -> Self {
        let t = times.unwrap_or_default();
        let ns = |s: f64| s * 1e9 / particle_steps;
        let serial = secs - t.parallel();
        Self {
            forces_ns: ns(t.forces),
            integrate_ns: ns(t.integrate),
            neighbour_ns: ns(t.neighbour),
            other_ns: ns(secs - t.total()),
            forces_serial_ns: ns(t.forces - t.forces_parallel),
            integrate_serial_ns: ns(t.integrate - t.integrate_parallel),
            neighbour_serial_ns: ns(t.neighbour - t.neighbour_parallel),
            serial_ns: ns(serial),
            serial_share: if secs > 0.0 { serial / secs } else { 1.0 },
        }
    }
}

/// Amdahl's law from two measurements of one benchmark: `one` ns per particle-step on one
/// thread, and `many` ns on `threads` threads of which `serial` ns ran outside the parallel
/// regions ([`PhaseBreakdown::serial_ns`]). The parallel part measured on `threads` threads
/// carries whatever extra work the split costs (pairs resolved twice at range boundaries,
/// the joins); it is assumed to divide evenly over more threads while the serial part stays
/// as it is. Returns the predicted speed-up over one thread on `target` threads, which is
/// an upper bound wherever memory bandwidth or the joins' cost grow with the thread count
/// (docs/performance.md, *Scaling model*).
pub fn amdahl_speedup(one: f64, (many, serial, threads): (f64, f64, usize), target: usize) -> f64 {
    let parallel = (many - serial).max(0.0);
    let predicted = serial + parallel * threads as f64 / target.max(1) as f64;
    one / predicted
}

/// CPU time consumed by the calling thread [ns], from Linux's schedstat.
fn thread_cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

/// Times `steps` steps of `sim` and reports per particle-step.
pub fn time_steps(
    sim: &mut Simulation,
    steps: u64,
    case: &str,
    threads: usize,
) -> Result<BenchResult, DemError> {
    let n = sim.particles().len();
    let rebuilds = sim.rebuilds();
    sim.time_phases(true);
    let cpu0 = thread_cpu_ns();
    let start = Instant::now();
    let (mut contacts, mut wall_contacts, mut candidates) = (0.0, 0.0, 0.0);
    // Steps in runs of up to 10, as a case runs them (`Simulation::run` fuses the half kicks
    // of consecutive steps); contacts are sampled at the end of each run.
    let mut done = 0;
    while done < steps {
        let n = (steps - done).min(10);
        sim.run(n)?;
        done += n;
        let c = sim.contacts();
        contacts += n as f64 * (2 * c.particle_particle + c.particle_wall) as f64;
        wall_contacts += n as f64 * c.particle_wall as f64;
        candidates += n as f64 * (2 * sim.candidate_pairs()) as f64;
    }
    let secs = start.elapsed().as_secs_f64();
    let cpu = match (cpu0, thread_cpu_ns()) {
        (Some(a), Some(b)) if threads == 1 => Some((b - a) as f64),
        _ => None,
    };
    let ps = (n as u64 * steps) as f64;
    Ok(BenchResult {
        case: case.into(),
        threads,
        particles: n,
        steps,
        ns_per_particle_step: secs * 1e9 / ps,
        particle_steps_per_second: ps / secs,
        contacts_per_particle: contacts / (steps as f64 * n.max(1) as f64),
        wall_contacts_per_particle: wall_contacts / (steps as f64 * n.max(1) as f64),
        ns_per_contact: secs * 1e9 / (0.5 * (contacts + wall_contacts)),
        candidates_per_particle: candidates / (steps as f64 * n.max(1) as f64),
        rebuilds: sim.rebuilds() - rebuilds,
        cpu_ns_per_particle_step: cpu.map(|c| c / ps),
        peak_memory_bytes: None,
        bytes_per_particle: None,
        phases: PhaseBreakdown::of(sim.phase_times(), secs, ps),
        runs: None,
    })
}

/// A memory figure of this process from Linux's /proc/self/status (`VmHWM`, `VmRSS`) [bytes].
pub(crate) fn process_memory(key: &str) -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with(key))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Lattice spacing of the scaling packing as a fraction of the diameter: 0.5 % overlap.
const PACKING_SPACING: f64 = 0.995;
/// Random displacement of each lattice site, as a fraction of the diameter, up to ±.
const PACKING_JITTER: f64 = 0.002;

/// A dense 3D packing for the scaling benchmark: `count` Table-1 spheres (d = 3 mm) on a simple
/// cubic lattice 0.995 d apart, each site jittered by up to ±0.002 d, so every interior sphere
/// touches its six neighbours; six planes close the box tightly and gravity is off. Returns the
/// simulation and the resident memory before it was built [bytes].
pub fn dense_packing(count: usize, threads: usize) -> Result<(Simulation, Option<u64>), DemError> {
    use dem::{DVec3, Interaction, Material, ParticleInit, SimulationConfig};
    use rand::Rng;
    let before = process_memory("VmRSS:");
    let case = Case::paper_base();
    let diameter = 3.0e-3;
    let mut config = SimulationConfig::new(case.time_step);
    config.gravity = DVec3::ZERO;
    config.threads = threads;
    // The hopper's skin (crates/study hopper set-up) for comparable lists.
    config.skin = 0.1 * diameter;
    let mut sim = Simulation::new(config)?;
    let material = Material::fan2023();
    let id = sim.add_material(material, Interaction::fan2023())?;
    let side = (count as f64).cbrt().ceil() as usize;
    let spacing = PACKING_SPACING * diameter;
    // Walls on the lattice's outer faces: the outer spheres press on them as hard as on their
    // neighbours, so the packing stays compressed instead of relaxing into free space.
    let edge = side as f64 * spacing;
    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
        for (point, normal) in [(DVec3::ZERO, axis), (edge * axis, -axis)] {
            add_plane(&mut sim, point, normal, material)?;
        }
    }
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(case.seed);
    let mut placed = 0;
    'fill: for z in 0..side {
        for y in 0..side {
            for x in 0..side {
                if placed == count {
                    break 'fill;
                }
                let site = (DVec3::new(x as f64, y as f64, z as f64) + DVec3::splat(0.5)) * spacing;
                let jitter = DVec3::new(rng.gen::<f64>(), rng.gen::<f64>(), rng.gen::<f64>()) * 2.0
                    - DVec3::ONE;
                sim.add_particle(ParticleInit::at_rest(
                    site + PACKING_JITTER * diameter * jitter,
                    0.5 * diameter,
                    id,
                ))?;
                placed += 1;
            }
        }
    }
    Ok((sim, before))
}

/// Times `steps` steps of a [`dense_packing`] of `count` spheres (after 10 untimed steps that
/// build the lists), `repeats` times from a fresh packing, and reports the mean figures and
/// the peak memory of the process.
///
/// Every size is timed over the same stretch of simulated time (the same steps after the
/// packing is made), so all sizes are compared in the same physical state: a packing left to
/// run longer relaxes and loses contacts, which would make small sizes look cheaper. Small
/// sizes repeat the stretch instead of running longer.
pub fn scaling_benchmark(
    count: usize,
    steps: u64,
    repeats: u32,
    threads: usize,
) -> Result<BenchResult, DemError> {
    let repeats = repeats.max(1);
    let mut runs = Vec::with_capacity(repeats as usize);
    let mut first_before = None;
    for k in 0..repeats {
        let (mut sim, before) = dense_packing(count, threads)?;
        if k == 0 {
            first_before = before;
        }
        sim.run(10)?;
        runs.push(time_steps(&mut sim, steps, "scaling", threads)?);
    }
    let mean =
        |f: &dyn Fn(&BenchResult) -> f64| runs.iter().map(f).sum::<f64>() / runs.len() as f64;
    let mut r = runs[0].clone();
    r.steps = steps * repeats as u64;
    r.ns_per_particle_step = mean(&|r| r.ns_per_particle_step);
    r.particle_steps_per_second = 1e9 / r.ns_per_particle_step;
    r.contacts_per_particle = mean(&|r| r.contacts_per_particle);
    r.wall_contacts_per_particle = mean(&|r| r.wall_contacts_per_particle);
    r.ns_per_contact = mean(&|r| r.ns_per_contact);
    r.candidates_per_particle = mean(&|r| r.candidates_per_particle);
    r.phases = PhaseBreakdown {
        forces_ns: mean(&|r| r.phases.forces_ns),
        integrate_ns: mean(&|r| r.phases.integrate_ns),
        neighbour_ns: mean(&|r| r.phases.neighbour_ns),
        other_ns: mean(&|r| r.phases.other_ns),
        forces_serial_ns: mean(&|r| r.phases.forces_serial_ns),
        integrate_serial_ns: mean(&|r| r.phases.integrate_serial_ns),
        neighbour_serial_ns: mean(&|r| r.phases.neighbour_serial_ns),
        serial_ns: mean(&|r| r.phases.serial_ns),
        serial_share: mean(&|r| r.phases.serial_share),
    };
    r.rebuilds = runs.iter().map(|r| r.rebuilds).sum();
    r.cpu_ns_per_particle_step = runs
        .iter()
        .map(|r| r.cpu_ns_per_particle_step)
        .sum::<Option<f64>>()
        .map(|total| total / runs.len() as f64);
    r.peak_memory_bytes = process_memory("VmHWM:");
    r.bytes_per_particle = match (r.peak_memory_bytes, first_before) {
        (Some(peak), Some(before)) => {
            Some(peak.saturating_sub(before) as f64 / count.max(1) as f64)
        }
        _ => None,
    };
    Ok(r)
}

/// A settled bed of `count` Table-1 spheres in the paper's slab under gravity, gate closed.
/// Returns the simulation after `settle_steps` untimed steps.
pub fn settled_bed(
    count: usize,
    threads: usize,
    settle_steps: u64,
) -> Result<Simulation, DemError> {
    let case = Case::paper_base();
    let (mut sim, _walls, material) = slab_simulation(&case, threads)?;
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(case.seed);
    lattice_bed(&mut sim, &case, material, count, &mut rng)?;
    sim.run(settle_steps)?;
    Ok(sim)
}

/// Simulated time after the gate opens at which the hopper benchmark's window starts [s].
pub const HOPPER_WINDOW_START: f64 = 0.1;
/// Length of the hopper benchmark's window [s] (80 000 steps of 2.5 µs), the same window
/// as the LIGGGHTS side-by-side input.
pub const HOPPER_WINDOW: f64 = 0.2;

/// Times the paper's base case over a fixed window of the discharge, probes and particle
/// deletion included. The filled, settled hopper is cached in `cache` (a checkpoint file) so
/// that repeated benchmarks skip the fill.
pub fn hopper_benchmark(
    threads: usize,
    cache: Option<&std::path::Path>,
) -> Result<BenchResult, crate::RunError> {
    let window = (HOPPER_WINDOW_START, HOPPER_WINDOW);
    discharge_benchmark(&Case::paper_base(), None, "hopper", window, threads, cache)
}

/// Simulated time after the gate opens at which the silo benchmark's window starts [s],
/// past the first surge of the opening.
pub const SILO_WINDOW_START: f64 = 0.05;
/// Length of the silo benchmark's window [s]: 20 000 steps of 1.5 µs, the window of the
/// LIGGGHTS side-by-side input (`bench/liggghts/silo`).
pub const SILO_WINDOW: f64 = 0.03;

/// Times the silo benchmark's case ([`SiloRequest::resolve`]; by default the benchmark silo of
/// Dosta et al. (2024), reduced to [`SILO_PARTICLES`] spheres of its material M1 with the large
/// orifice, `hopperflow init --kind cylinder`) over [`SILO_WINDOW`] from [`SILO_WINDOW_START`]
/// after the opening, from its fill or its packing; the settled silo is cached in `cache`,
/// which should be named by [`SiloBench::cache_name`].
pub fn silo_benchmark(
    bench: &SiloBench,
    threads: usize,
    cache: Option<&std::path::Path>,
) -> Result<BenchResult, crate::RunError> {
    let window = (SILO_WINDOW_START, SILO_WINDOW);
    discharge_benchmark(
        &bench.case,
        bench.packing.as_ref(),
        &bench.label,
        window,
        threads,
        cache,
    )
}

/// Times `case` over the window (`start` after the gate opens, `length` long) [s], probes and
/// particle deletion included. The bed is the protocol's fill, or `packing` placed at rest
/// (as `hopperflow run --packing`); either settles on the closed gate under the case's
/// criterion. The settled case is cached in `cache`, whose name must stand for all of these
/// inputs: a cached state is taken as it is.
pub fn discharge_benchmark(
    case: &Case,
    packing: Option<&crate::Packing>,
    label: &str,
    (window_start, window_length): (f64, f64),
    threads: usize,
    cache: Option<&std::path::Path>,
) -> Result<BenchResult, crate::RunError> {
    use crate::{CaseRun, Phase, RunState};
    let case = case.clone();
    let cached: Option<RunState> = cache
        .and_then(|p| std::fs::read(p).ok())
        .and_then(|bytes| postcard::from_bytes(&bytes).ok());
    let mut run = match cached {
        Some(state) => CaseRun::resume(&case, state, threads)?,
        None => {
            let mut run = match packing {
                Some(p) => CaseRun::from_packing(&case, p, threads)?,
                None => CaseRun::new(&case, threads)?,
            };
            while !matches!(
                run.phase(),
                Phase::Discharge { .. } | Phase::Lift { .. } | Phase::Done { .. }
            ) {
                run.advance()?;
            }
            if let Some(path) = cache {
                if let Some(dir) = path.parent() {
                    let _ = std::fs::create_dir_all(dir);
                }
                if let Ok(bytes) = postcard::to_allocvec(&run.checkpoint()) {
                    files::write_atomic(path, &bytes)?;
                }
            }
            run
        }
    };
    // The window after the opening, and in simulated time.
    let after = (window_start, window_start + window_length);
    let opened = match run.phase() {
        Phase::Discharge { opened, .. }
        | Phase::Pulse { opened, .. }
        | Phase::Lift { opened }
        | Phase::Rest { opened, .. } => opened,
        Phase::Done { reason, opened } => {
            return Err(crate::RunError::EndedBeforeWindow {
                reason,
                stopped: run.simulation().time() - opened,
                start: after.0,
                end: after.1,
            })
        }
        // The loop above ends only in the discharge or after it.
        Phase::Fill { .. } | Phase::Settle { .. } | Phase::Slip { .. } | Phase::Resettle { .. } => {
            return Err(crate::RunError::NotMeasured(
                "a benchmark window before the gate opened",
            ))
        }
    };
    let window = (opened + after.0, opened + after.1);
    while run.simulation().time() < window.0 {
        run.advance()?;
        ended_before(&run, opened, after)?;
    }
    let rebuilds = run.simulation().rebuilds();
    let steps0 = run.simulation().steps();
    run.time_phases(true);
    let mut particle_steps = 0.0;
    let (mut contacts, mut wall_contacts, mut candidates) = (0.0, 0.0, 0.0);
    let cpu0 = thread_cpu_ns();
    let start = Instant::now();
    while run.simulation().time() < window.1 - 0.5 * case.time_step {
        let before = run.simulation().steps();
        let n = run.simulation().particles().len() as f64;
        run.advance()?;
        ended_before(&run, opened, after)?;
        let steps = (run.simulation().steps() - before) as f64;
        particle_steps += steps * n;
        let c = run.simulation().contacts();
        contacts += steps * (2 * c.particle_particle + c.particle_wall) as f64;
        wall_contacts += steps * c.particle_wall as f64;
        candidates += steps * (2 * run.simulation().candidate_pairs()) as f64;
    }
    let secs = start.elapsed().as_secs_f64();
    let cpu = match (cpu0, thread_cpu_ns()) {
        (Some(a), Some(b)) if threads == 1 => Some((b - a) as f64),
        _ => None,
    };
    let steps = run.simulation().steps() - steps0;
    Ok(BenchResult {
        case: label.into(),
        threads,
        particles: (particle_steps / steps.max(1) as f64).round() as usize,
        steps,
        ns_per_particle_step: secs * 1e9 / particle_steps,
        particle_steps_per_second: particle_steps / secs,
        contacts_per_particle: contacts / particle_steps,
        wall_contacts_per_particle: wall_contacts / particle_steps,
        ns_per_contact: secs * 1e9 / (0.5 * (contacts + wall_contacts)),
        candidates_per_particle: candidates / particle_steps,
        rebuilds: run.simulation().rebuilds() - rebuilds,
        cpu_ns_per_particle_step: cpu.map(|c| c / particle_steps),
        peak_memory_bytes: None,
        bytes_per_particle: None,
        phases: PhaseBreakdown::of(run.simulation().phase_times(), secs, particle_steps),
        runs: None,
    })
}

/// An error when the run's discharge has ended (emptied, clogged, or at its time limit) before
/// the end of the window `(start, end)` [s after the opening]: a finished run takes no more
/// steps, so the window could not be timed.
fn ended_before(
    run: &crate::CaseRun,
    opened: f64,
    (start, end): (f64, f64),
) -> Result<(), crate::RunError> {
    let crate::Phase::Done { reason, .. } = run.phase() else {
        return Ok(());
    };
    let stopped = run.simulation().time() - opened;
    if stopped >= end - 0.5 * run.simulation().config().time_step {
        return Ok(());
    }
    Err(crate::RunError::EndedBeforeWindow {
        reason,
        stopped,
        start,
        end,
    })
}

/// Adds a plane through `point` with inward `normal` [m], of the benchmark's material and
/// Table 1's interaction, to a benchmark bed.
fn add_plane(
    sim: &mut Simulation,
    point: dem::DVec3,
    normal: dem::DVec3,
    material: dem::Material,
) -> Result<(), DemError> {
    let wall = dem::Wall::plane(
        point,
        normal,
        dem::WallMaterial::Elastic(material),
        dem::Interaction::fan2023(),
    )
    .map_err(|e| DemError::InvalidInput(e.to_string()))?;
    sim.add_wall(wall)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_benchmark_splits_its_whole_time_into_the_phases() {
        // 1000 spheres in contact, 30 steps: small enough for the test suite, and every phase
        // has work (the first steps build the lists, every step has six contacts per sphere).
        let (mut sim, _) = dense_packing(1000, 1).expect("packing");
        sim.run(10).expect("untimed steps");
        let r = time_steps(&mut sim, 30, "scaling", 1).expect("timed steps");
        let p = r.phases;
        let sum = p.forces_ns + p.integrate_ns + p.neighbour_ns + p.other_ns;
        // The four parts are the total by construction, up to the rounding of four additions.
        assert!(
            (sum - r.ns_per_particle_step).abs() <= 1e-9 * r.ns_per_particle_step,
            "{p:?} against {} ns",
            r.ns_per_particle_step
        );
        // Dense contacts: the force phase does real work on every step, and the benchmark's
        // own loop (`other`) is not negative, which it would be if a phase were counted twice.
        assert!(p.forces_ns > 0.0 && p.integrate_ns > 0.0, "{p:?}");
        assert!(p.other_ns >= 0.0, "{p:?}");
        assert_eq!(sim.phase_times().map(|t| t.steps), Some(30));
        // One thread has no parallel regions: every phase is serial, and so is the whole.
        assert_eq!(p.forces_serial_ns, p.forces_ns);
        assert_eq!(p.integrate_serial_ns, p.integrate_ns);
        assert_eq!(p.serial_share, 1.0);
    }

    #[test]
    fn two_threads_split_each_phase_into_parallel_and_serial_time() {
        // 4000 spheres in contact on two threads: the pair pass and the kicks run in the
        // pool's regions, so the force phase is mostly parallel, and the serial parts are
        // parts (never negative, never more than their phase, the share within [0, 1]).
        let (mut sim, _) = dense_packing(4000, 2).expect("packing");
        sim.run(10).expect("untimed steps");
        let r = time_steps(&mut sim, 20, "scaling", 2).expect("timed steps");
        let p = r.phases;
        for (serial, whole) in [
            (p.forces_serial_ns, p.forces_ns),
            (p.integrate_serial_ns, p.integrate_ns),
            (p.neighbour_serial_ns, p.neighbour_ns),
        ] {
            assert!((0.0..=whole).contains(&serial), "{p:?}");
        }
        assert!(p.forces_serial_ns < 0.5 * p.forces_ns, "{p:?}");
        assert!(p.serial_share > 0.0 && p.serial_share < 1.0, "{p:?}");
        let phases_serial = p.forces_serial_ns + p.integrate_serial_ns + p.neighbour_serial_ns;
        assert!((p.serial_ns - phases_serial - p.other_ns).abs() <= 1e-6 * r.ns_per_particle_step);
    }

    #[test]
    fn amdahl_keeps_the_serial_part_and_divides_the_parallel_one() {
        // 40 ns on one thread; 25 ns on two of which 5 ns serial: the parallel 20 ns on two
        // threads is 10 ns on four, so 15 ns in all and 40/15 = 2.67×; without end, 40/5 = 8×.
        // Exact up to the rounding of a few operations.
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b;
        assert!(close(amdahl_speedup(40.0, (25.0, 5.0, 2), 2), 1.6));
        assert!(close(amdahl_speedup(40.0, (25.0, 5.0, 2), 4), 40.0 / 15.0));
        assert!(amdahl_speedup(40.0, (25.0, 5.0, 2), 1 << 30) < 8.0 + 1e-6);
    }
}
