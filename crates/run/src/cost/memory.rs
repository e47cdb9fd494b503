//! The memory a run needs at its peak, and the memory of the machine.

use crate::bench::process_memory;

/// Peak resident memory per sphere of a run [bytes]: silo runs from a packing of 10^5 and
/// 10^6 spheres peaked at 1.0 and 0.79 kB a sphere, the rise between them 0.76 kB a sphere
/// (docs/performance.md, "Memory of a silo run"): particle arrays, the candidate lists and
/// their histories (two of each, the old lists kept while the new ones take over their
/// histories), probes and the checkpoint's streamed writing included; rounded up. The
/// quasi-2D slab, with fewer contacts per sphere, needs less.
pub const BYTES_PER_SPHERE: f64 = 1000.0;

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
