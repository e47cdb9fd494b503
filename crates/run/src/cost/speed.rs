//! The engine's speed on this machine for a case: a short timed run of a small dense block
//! of the case's spheres, with its materials, contact laws, time step and thread count.
//!
//! The block is a simple cubic lattice of spheres of the case's largest diameter 0.995 d
//! apart, closed tightly by six planes of the first wall's material: every inner sphere
//! touches its six neighbours, about as many contacts as a settled bed holds (4-6) and more
//! than a flowing one (2.5-3). The components' materials are drawn by their number fractions.
//! The container's own walls, the probes and the outputs are left out: the run's probes and
//! pictures add to the time measured here (docs/performance.md).

use std::time::Instant;

use dem::{DVec3, ParticleInit, Wall};
use rand::SeedableRng;
use serde::Serialize;

use crate::bench::time_steps;
use crate::{case_simulation_by_component, ParticleDraws, RunError};
use case::Case;

/// Lattice spacing of the block as a fraction of the largest diameter: 0.5 % overlap, as the
/// scaling benchmark's packing (`run::bench::dense_packing`).
const SPACING: f64 = 0.995;
/// Spheres of the block per worker thread: enough that the threads' ranges of bodies keep
/// them busy as a run's would.
const SPHERES_PER_THREAD: usize = 2000;
/// Most spheres in the block: a block this size times in a fraction of a second.
const MAX_SPHERES: usize = 50_000;
/// Particle-steps timed: about 0.1 s at the engine's 30-70 ns per particle-step on one
/// thread, long enough for the clock and the lists' builds to be small parts of it.
const TIMED_PARTICLE_STEPS: f64 = 2.0e6;
/// Steps before the timing, which build the neighbour lists and first touch every array.
const WARM_UP_STEPS: u64 = 10;

/// What the short timed run measured.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MeasuredSpeed {
    /// Spheres in the block [-].
    pub spheres: usize,
    /// Steps timed [-].
    pub steps: u64,
    /// Worker threads of the engine [-].
    pub threads: usize,
    /// Wall time per particle and step [ns].
    pub ns_per_particle_step: f64,
    /// Contacts per sphere in the block (particle–particle counted for both partners, plus
    /// walls) [-].
    pub contacts_per_particle: f64,
    /// Wall time of the whole calibration: building the block and its steps [s].
    pub seconds: f64,
}

/// Times the dense block of `case`'s spheres ([module docs](self)) for `particles` spheres
/// of the run on `threads` worker threads: min(`particles`, 2000 per thread, 50 000) spheres
/// over about 2·10⁶ particle-steps (20 to 1000 steps).
pub fn measure_speed(
    case: &Case,
    particles: usize,
    threads: usize,
) -> Result<MeasuredSpeed, RunError> {
    let started = Instant::now();
    let threads = threads.max(1);
    let count = particles
        .min(SPHERES_PER_THREAD * threads)
        .clamp(1, MAX_SPHERES);
    let (mut sim, walls, materials) = case_simulation_by_component(case, threads)?;
    // The container's walls give way to the block's box, of the first wall's material.
    let mut template = None;
    for id in walls.all() {
        let wall = sim.remove_wall(id)?;
        template.get_or_insert(wall);
    }
    let d = case.particles.max_diameter();
    let spacing = SPACING * d;
    let side = (count as f64).cbrt().ceil().max(1.0) as usize;
    let layers = count.div_ceil(side * side);
    let edge = [
        side as f64 * spacing,
        side as f64 * spacing,
        layers as f64 * spacing,
    ];
    if let Some(template) = template {
        for (axis, &length) in [DVec3::X, DVec3::Y, DVec3::Z].into_iter().zip(&edge) {
            for (point, normal) in [(DVec3::ZERO, axis), (length * axis, -axis)] {
                let wall = Wall::plane(point, normal, template.material, template.interaction)
                    .map_err(|e| dem::DemError::InvalidInput(e.to_string()))?;
                sim.add_wall(wall)?;
            }
        }
    }
    let draws = ParticleDraws::new(&case.particles, &materials);
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(case.seed);
    'fill: for z in 0..layers {
        for y in 0..side {
            for x in 0..side {
                if sim.particles().len() == count {
                    break 'fill;
                }
                let site = (DVec3::new(x as f64, y as f64, z as f64) + DVec3::splat(0.5)) * spacing;
                let material = draws.draw(&mut rng).material;
                sim.add_particle(ParticleInit::at_rest(site, 0.5 * d, material))?;
            }
        }
    }
    sim.run(WARM_UP_STEPS)?;
    let steps = (TIMED_PARTICLE_STEPS / count as f64).clamp(20.0, 1000.0) as u64;
    let timed = time_steps(&mut sim, steps, "cost", threads)?;
    Ok(MeasuredSpeed {
        spheres: count,
        steps,
        threads,
        ns_per_particle_step: timed.ns_per_particle_step,
        contacts_per_particle: timed.contacts_per_particle,
        seconds: started.elapsed().as_secs_f64(),
    })
}
