//! The bidisperse benchmark: a settled 3D bed of Table-1 spheres of two diameters, d and
//! R·d, in equal volumes, which prices the neighbour search and the contacts across a size
//! ratio. R = 1 is the monodisperse bed made by the same protocol, at the same solid fraction.
//!
//! The bed starts as a simple cubic lattice of blocks, each block R × R small-sphere sites
//! on a side: half of the blocks (chosen at random) hold one large sphere at their centre, the
//! other half R³ small spheres, each site jittered. Every ratio thus starts at the same solid
//! fraction (π/6 over the site's volume, 0.51) with the same gap between neighbours, and
//! settles the same way under gravity in a box of five planes before the timed steps.

use dem::{DVec3, DemError, Interaction, Material, ParticleInit, Simulation, SimulationConfig};
use rand::{Rng, SeedableRng};

use super::{time_steps, BenchResult};
use case::Case;

/// Diameter of the small spheres [m]: Table 1's.
pub const SMALL_DIAMETER: f64 = 3.0e-3;
/// Lattice spacing of the small-sphere sites, as a fraction of the small diameter: a gap of
/// 1 % between neighbours at the start.
pub(super) const SITE_SPACING: f64 = 1.01;
/// Random displacement of each sphere along each axis, as a fraction of the small diameter,
/// up to ±: at most 0.0035 d in all, so no two spheres overlap at the start (gaps ≥ 0.01 d).
pub(super) const SITE_JITTER: f64 = 0.002;
/// Verlet skin as a fraction of the largest diameter, as the hopper set-up chooses it.
const SKIN_DIAMETERS: f64 = 0.1;

/// Which bed: the diameter ratio and the number of spheres asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BidisperseBed {
    /// Large over small diameter [-]; 1 gives the monodisperse bed.
    pub ratio: u32,
    /// Spheres asked for; the bed holds whole blocks, so the count is close to it.
    pub particles: usize,
}

impl BidisperseBed {
    /// The case name in benchmark results, e.g. "bidisperse 1:3".
    pub fn name(&self) -> String {
        format!("bidisperse 1:{}", self.ratio)
    }

    /// Number of blocks: `particles` over the mean spheres per block, (1 + R³)/2.
    fn blocks(&self) -> usize {
        let r3 = f64::from(self.ratio).powi(3);
        ((2.0 * self.particles as f64 / (1.0 + r3)).round() as usize).max(1)
    }
}

/// The bed of `bed` on its lattice, in its box, before settling. Every sphere is Table-1
/// material; the skin is 0.1 of the large diameter.
pub fn bidisperse_bed(bed: BidisperseBed, threads: usize) -> Result<Simulation, DemError> {
    if bed.ratio == 0 {
        return Err(DemError::InvalidInput(
            "the diameter ratio must be at least 1".into(),
        ));
    }
    let ratio = bed.ratio as usize;
    let large = f64::from(bed.ratio) * SMALL_DIAMETER;
    let (mut sim, id, seed) = bed_simulation(threads, large)?;

    let blocks = bed.blocks();
    let side = (blocks as f64).cbrt().ceil().max(1.0) as usize;
    let site = SITE_SPACING * SMALL_DIAMETER;
    let block = ratio as f64 * site;
    let width = side as f64 * block;
    open_box(&mut sim, (width, width))?;

    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
    // Half of the blocks hold a large sphere, in an order shuffled by Fisher–Yates.
    let mut holds_large: Vec<bool> = (0..blocks).map(|k| k < blocks / 2).collect();
    for k in (1..blocks).rev() {
        holds_large.swap(k, rng.gen_range(0..=k));
    }
    let jitter = |rng: &mut rand_xoshiro::Xoshiro256PlusPlus| {
        let u = DVec3::new(rng.gen::<f64>(), rng.gen::<f64>(), rng.gen::<f64>());
        SITE_JITTER * SMALL_DIAMETER * (2.0 * u - DVec3::ONE)
    };
    for (k, &large_here) in holds_large.iter().enumerate() {
        let corner = DVec3::new(
            (k % side) as f64,
            ((k / side) % side) as f64,
            (k / (side * side)) as f64,
        ) * block;
        if large_here {
            let at = corner + DVec3::splat(0.5 * block) + jitter(&mut rng);
            sim.add_particle(ParticleInit::at_rest(at, 0.5 * large, id))?;
            continue;
        }
        for s in 0..ratio * ratio * ratio {
            let cell = DVec3::new(
                (s % ratio) as f64,
                ((s / ratio) % ratio) as f64,
                (s / (ratio * ratio)) as f64,
            );
            let at = corner + (cell + DVec3::splat(0.5)) * site + jitter(&mut rng);
            sim.add_particle(ParticleInit::at_rest(at, 0.5 * SMALL_DIAMETER, id))?;
        }
    }
    Ok(sim)
}

/// The beds' simulation before its box and spheres: the paper's Δt on `threads` threads, the
/// skin 0.1 of the `largest` diameter [m], and Table-1 material, with its id and the paper's
/// seed for the beds' random draws.
pub(super) fn bed_simulation(
    threads: usize,
    largest: f64,
) -> Result<(Simulation, dem::MaterialId, u64), DemError> {
    let case = Case::paper_base();
    let mut config = SimulationConfig::new(case.time_step);
    config.threads = threads;
    config.skin = SKIN_DIAMETERS * largest;
    let mut sim = Simulation::new(config)?;
    let id = sim.add_material(Material::fan2023(), Interaction::fan2023())?;
    Ok((sim, id, case.seed))
}

/// A floor at z = 0 and four side planes of Table-1 material around [0, `wx`] × [0, `wy`]
/// [m]; the top open.
pub(super) fn open_box(sim: &mut Simulation, (wx, wy): (f64, f64)) -> Result<(), DemError> {
    let material = Material::fan2023();
    let planes = [
        (DVec3::ZERO, DVec3::Z),
        (DVec3::ZERO, DVec3::X),
        (DVec3::ZERO, DVec3::Y),
        (DVec3::new(wx, 0.0, 0.0), -DVec3::X),
        (DVec3::new(0.0, wy, 0.0), -DVec3::Y),
    ];
    for (point, normal) in planes {
        super::add_plane(sim, point, normal, material)?;
    }
    Ok(())
}

/// The bed of `bed` after `settle_steps` untimed steps (2.5 µs each). With `cache`, the
/// settled state is read from that file when it holds one, and written there otherwise, so
/// that repeated benchmarks and two builds compared A/B time the same bed.
pub fn settled_bidisperse_bed(
    bed: BidisperseBed,
    threads: usize,
    settle_steps: u64,
    cache: Option<&std::path::Path>,
) -> Result<Simulation, crate::RunError> {
    settled(
        || bidisperse_bed(bed, threads),
        threads,
        settle_steps,
        cache,
    )
}

/// The simulation `make` builds, after `settle_steps` untimed steps, read from `cache` when
/// it holds a settled state and written there otherwise (see [`settled_bidisperse_bed`]).
pub(super) fn settled(
    make: impl FnOnce() -> Result<Simulation, DemError>,
    threads: usize,
    settle_steps: u64,
    cache: Option<&std::path::Path>,
) -> Result<Simulation, crate::RunError> {
    let cached: Option<dem::SimulationState> = cache
        .and_then(|p| std::fs::read(p).ok())
        .and_then(|bytes| postcard::from_bytes(&bytes).ok());
    if let Some(state) = cached {
        return Ok(Simulation::from_state(state, threads)?);
    }
    let mut sim = make()?;
    sim.run(settle_steps)?;
    if let Some(path) = cache {
        if let Some(dir) = path.parent() {
            let _ = std::fs::create_dir_all(dir);
        }
        if let Ok(bytes) = postcard::to_allocvec(sim.state()) {
            files::write_atomic(path, &bytes)?;
        }
    }
    Ok(sim)
}

/// Times `steps` steps of the settled bed of `bed` (see [`settled_bidisperse_bed`] for
/// `settle_steps` and `cache`).
pub fn bidisperse_benchmark(
    bed: BidisperseBed,
    threads: usize,
    settle_steps: u64,
    steps: u64,
    cache: Option<&std::path::Path>,
) -> Result<BenchResult, crate::RunError> {
    let mut sim = settled_bidisperse_bed(bed, threads, settle_steps, cache)?;
    Ok(time_steps(&mut sim, steps, &bed.name(), threads)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bed_holds_equal_volumes_of_the_two_sizes_without_overlaps() {
        // 1:3 with about 600 spheres: 43 blocks, 21 large spheres and 22 × 27 small ones.
        let bed = BidisperseBed {
            ratio: 3,
            particles: 600,
        };
        let sim = bidisperse_bed(bed, 1).expect("bed");
        let p = sim.particles();
        let radii = p.radii();
        let small = radii.iter().filter(|&&r| r == 0.5 * SMALL_DIAMETER).count();
        let large = radii.iter().filter(|&&r| r == 1.5 * SMALL_DIAMETER).count();
        assert_eq!((large, small, p.len()), (21, 22 * 27, 21 + 22 * 27));
        // Equal volumes up to one block: 22 blocks of small spheres against 21 large ones.
        assert_eq!(small, 27 * (large + 1));
        // No overlaps at the start: the jitter is smaller than half the smallest gap.
        let x = p.positions();
        for i in 0..p.len() {
            for j in i + 1..p.len() {
                assert!(
                    x[i].distance(x[j]) > radii[i] + radii[j],
                    "spheres {i} and {j} overlap"
                );
            }
        }
        // Ratio 1 is the monodisperse bed of about the same count.
        let mono = bidisperse_bed(
            BidisperseBed {
                ratio: 1,
                particles: 600,
            },
            1,
        )
        .expect("bed");
        assert_eq!(mono.particles().len(), 600);
        assert!(mono
            .particles()
            .radii()
            .iter()
            .all(|&r| r == 0.5 * SMALL_DIAMETER));
    }
}
