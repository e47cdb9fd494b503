//! The engine's speed on this machine for a case: a short timed run of a small dense block
//! of the case's spheres, with its materials, contact laws, time step and thread count.
//!
//! The block is a simple cubic lattice of spheres of the case's largest diameter 0.995 d
//! apart, closed tightly by six planes of the first wall's material: every inner sphere
//! touches its six neighbours, about as many contacts as a settled bed holds (4-6) and more
//! than a flowing one (2.5-3). The components' materials are drawn by their number fractions.
//! Shaped grains stand in the lattice as they were given, unrotated, 0.995 of their largest
//! extent along each axis apart, so that each touches its neighbours there (a rod side by
//! side with four and end to end with two); the speed is then given per grain and step, all
//! its members together, which is what the run's grain count is multiplied by.
//! The container's own walls, the probes and the outputs are left out: the run's probes and
//! pictures add to the time measured here (docs/performance.md).

use std::time::Instant;

use dem::{DQuat, DVec3, ParticleInit, Wall};
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
    /// Spheres in the block, the members of its shaped grains counted one by one [-].
    pub spheres: usize,
    /// Grains in the block: spheres, and shaped grains as one each [-].
    pub grains: usize,
    /// Steps timed [-].
    pub steps: u64,
    /// Worker threads of the engine [-].
    pub threads: usize,
    /// Wall time per grain and step [ns]: per sphere for spheres, per grain with all its
    /// members for shaped grains.
    pub ns_per_particle_step: f64,
    /// Contacts per sphere in the block (particle–particle counted for both partners, plus
    /// walls) [-].
    pub contacts_per_particle: f64,
    /// Wall time of the whole calibration: building the block and its steps [s].
    pub seconds: f64,
}

/// Half the largest extent [m] along each axis of a grain of `draws`' largest diameter `d`:
/// d/2 for spheres, for a shaped grain unrotated the farthest any member reaches from its
/// centre of mass along that axis.
fn half_extent(draws: &ParticleDraws, components: usize, d: f64) -> DVec3 {
    (0..components).fold(DVec3::ZERO, |half, c| {
        let Some((shape, _, centre)) = draws.shape(c as u8) else {
            return half.max(DVec3::splat(0.5 * d));
        };
        shape.members().iter().fold(half, |half, &(m, r)| {
            half.max(((m - *centre).abs() + DVec3::splat(r)) * d)
        })
    })
}

/// Times the dense block of `case`'s grains ([module docs](self)) for `particles` grains of
/// the run on `threads` worker threads: as many grains as hold min(`particles` × the spheres
/// per grain, 2000 spheres per thread, 50 000) spheres, over about 2·10⁶ sphere-steps (20 to
/// 1000 steps).
pub fn measure_speed(
    case: &Case,
    particles: usize,
    threads: usize,
) -> Result<MeasuredSpeed, RunError> {
    let started = Instant::now();
    let threads = threads.max(1);
    let per_grain = case.particles.mean_spheres_per_grain().max(1.0);
    let spheres = (particles as f64 * per_grain)
        .min((SPHERES_PER_THREAD * threads) as f64)
        .min(MAX_SPHERES as f64);
    let count = ((spheres / per_grain).round() as usize).max(1);
    let (mut sim, walls, materials) = case_simulation_by_component(case, threads)?;
    // The container's walls give way to the block's box, of the first wall's material.
    let mut template = None;
    for id in walls.all() {
        let wall = sim.remove_wall(id)?;
        template.get_or_insert(wall);
    }
    let d = case.particles.max_diameter();
    let draws = ParticleDraws::new(&case.particles, &materials);
    let spacing = 2.0 * SPACING * half_extent(&draws, case.particles.components.len(), d);
    let side = (count as f64).cbrt().ceil().max(1.0) as usize;
    let layers = count.div_ceil(side * side);
    let edge = [
        side as f64 * spacing.x,
        side as f64 * spacing.y,
        layers as f64 * spacing.z,
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
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(case.seed);
    let mut grains = 0;
    'fill: for z in 0..layers {
        for y in 0..side {
            for x in 0..side {
                if grains == count {
                    break 'fill;
                }
                grains += 1;
                let site = (DVec3::new(x as f64, y as f64, z as f64) + DVec3::splat(0.5)) * spacing;
                let drawn = draws.draw(&mut rng);
                match draws.shape(drawn.component) {
                    // A grain of the largest diameter, its centre of mass on the site.
                    Some((shape, _, _)) => {
                        sim.add_scaled_clump(
                            (shape, d),
                            drawn.material,
                            (site, DQuat::IDENTITY),
                            (DVec3::ZERO, DVec3::ZERO),
                        )?;
                    }
                    None => {
                        sim.add_particle(ParticleInit::at_rest(site, 0.5 * d, drawn.material))?;
                    }
                }
            }
        }
    }
    sim.run(WARM_UP_STEPS)?;
    let steps = (TIMED_PARTICLE_STEPS / sim.particles().len() as f64).clamp(20.0, 1000.0) as u64;
    let timed = time_steps(&mut sim, steps, "cost", threads)?;
    let spheres = sim.particles().len();
    Ok(MeasuredSpeed {
        spheres,
        grains,
        steps,
        threads,
        ns_per_particle_step: timed.ns_per_particle_step * spheres as f64 / grains as f64,
        contacts_per_particle: timed.contacts_per_particle,
        seconds: started.elapsed().as_secs_f64(),
    })
}
