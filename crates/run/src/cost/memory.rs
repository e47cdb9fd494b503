//! The memory a run needs at its peak, and the memory of the machine.

use crate::bench::process_memory;

/// Peak resident memory per sphere of a run [bytes]: the benchmark silo's runs peaked at 2.5
/// and 2.9 kB per sphere (docs/reproduction.md), particle arrays, pair lists with their
/// histories, probes, the checkpoint's copy of the state and its serialised bytes included;
/// rounded up. The quasi-2D slab, with fewer contacts per sphere, needs less.
pub const BYTES_PER_SPHERE: f64 = 3000.0;

/// Memory of a run's outputs besides the particles [bytes]: the plots are drawn as bitmaps
/// in memory. The base case's run (3000 spheres, 16.6 MB at its peak) peaked 2.2 MB above the
/// baseline and its spheres' share; 8 MiB covers that with room.
pub const OUTPUT_MEMORY: f64 = 8.0 * 1024.0 * 1024.0;

/// The process's resident memory before the run [bytes] (Linux `VmRSS`; 0 where the system
/// does not report it): the program, its thread pool and the case, which a run adds to.
pub fn baseline_memory() -> f64 {
    process_memory("VmRSS:").unwrap_or(0) as f64
}

/// A run's peak resident memory for `particles` spheres [bytes]: the baseline,
/// [`OUTPUT_MEMORY`] and [`BYTES_PER_SPHERE`] for each sphere.
pub fn peak_memory(particles: usize, baseline: f64) -> f64 {
    baseline + OUTPUT_MEMORY + BYTES_PER_SPHERE * particles as f64
}

/// The machine's physical memory [bytes] (Linux `MemTotal`), where the system reports it.
pub fn physical_memory() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}
