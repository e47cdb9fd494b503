//! Engine benchmarks on the paper's problem: a settled bed in the slab, and the hopper's
//! discharge. Wall-clock timing lives here, never in tests.

use std::time::Instant;

use dem::{DemError, Simulation};
use rand::SeedableRng;
use serde::Serialize;

use crate::config::Case;
use crate::hopper::{hopper_simulation, lattice_bed};

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
    /// Neighbour-list rebuilds during the window.
    pub rebuilds: u64,
    /// CPU time of the calling thread per particle and step [ns], where the OS reports it
    /// (Linux schedstat); less sensitive than wall time to other load on the machine.
    pub cpu_ns_per_particle_step: Option<f64>,
}

/// CPU time consumed by the calling thread [ns], from Linux's schedstat.
fn thread_cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

/// Times `steps` steps of `sim` and reports per particle-step.
pub fn time_steps(sim: &mut Simulation, steps: u64, case: &str, threads: usize) -> Result<BenchResult, DemError> {
    let n = sim.particles().len();
    let rebuilds = sim.rebuilds();
    let cpu0 = thread_cpu_ns();
    let start = Instant::now();
    let (mut contacts, mut wall_contacts) = (0.0, 0.0);
    for _ in 0..steps {
        sim.step()?;
        let c = sim.contacts();
        contacts += (2 * c.particle_particle + c.particle_wall) as f64;
        wall_contacts += c.particle_wall as f64;
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
        rebuilds: sim.rebuilds() - rebuilds,
        cpu_ns_per_particle_step: cpu.map(|c| c / ps),
    })
}

/// A settled bed of `count` Table-1 spheres in the paper's slab under gravity, gate closed.
/// Returns the simulation after `settle_steps` untimed steps.
pub fn settled_bed(count: usize, threads: usize, settle_steps: u64) -> Result<Simulation, DemError> {
    let case = Case::paper_base();
    let (mut sim, _walls, material) = hopper_simulation(&case, threads)?;
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(case.seed);
    lattice_bed(&mut sim, &case, material, count, &mut rng)?;
    sim.run(settle_steps)?;
    Ok(sim)
}
