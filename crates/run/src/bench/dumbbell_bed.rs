//! The dumbbell benchmark: a settled 3D bed of rigid clumps, each two touching Table-1 beads
//! (d = 3 mm), which prices a member sphere against a free sphere. It is the monodisperse
//! bidisperse bed (`--case bidisperse --ratio 1`) with the spheres of each pair of lattice
//! sites along x joined into one dumbbell: the same sites, jitter, box and settling, so the
//! two beds differ only in the clumps.

use dem::clump::ClumpShape;
use dem::{DQuat, DVec3, DemError, Simulation};
use rand::{Rng, SeedableRng};

use super::bidisperse::{
    bed_simulation, open_box, settled, SITE_JITTER, SITE_SPACING, SMALL_DIAMETER,
};
use super::{time_steps, BenchResult};

/// The bed of about `beads` member spheres (whole dumbbells) on its lattice, in its box,
/// before settling: Table-1 material, the skin 0.1 d.
pub fn dumbbell_bed(beads: usize, threads: usize) -> Result<Simulation, DemError> {
    let (mut sim, id, seed) = bed_simulation(threads, SMALL_DIAMETER)?;
    let r = 0.5 * SMALL_DIAMETER;
    let shape = ClumpShape::new(vec![
        (DVec3::new(-r, 0.0, 0.0), r),
        (DVec3::new(r, 0.0, 0.0), r),
    ])
    .map_err(|e| DemError::InvalidInput(e.to_string()))?;

    let dumbbells = (beads / 2).max(1);
    // A lattice of sites `side` wide in y and z and an even number of sites along x.
    let side = ((2 * dumbbells) as f64).cbrt().ceil().max(1.0) as usize;
    let pairs_x = (dumbbells as f64 / (side * side) as f64).ceil().max(1.0) as usize;
    let site = SITE_SPACING * SMALL_DIAMETER;
    let (width_x, width) = ((2 * pairs_x) as f64 * site, side as f64 * site);
    open_box(&mut sim, (width_x, width))?;
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
    for k in 0..dumbbells {
        let (a, b, c) = (k % pairs_x, (k / pairs_x) % side, k / (pairs_x * side));
        let centre = DVec3::new((2 * a + 1) as f64, b as f64 + 0.5, c as f64 + 0.5) * site;
        let u = DVec3::new(rng.gen::<f64>(), rng.gen::<f64>(), rng.gen::<f64>());
        let at = centre + SITE_JITTER * SMALL_DIAMETER * (2.0 * u - DVec3::ONE);
        sim.add_clump(
            &shape,
            id,
            (at, DQuat::IDENTITY),
            (DVec3::ZERO, DVec3::ZERO),
        )?;
    }
    Ok(sim)
}

/// Times `steps` steps of the dumbbell bed of about `beads` beads after `settle_steps` untimed
/// steps, the settled state read from or written to `cache`.
pub fn dumbbell_benchmark(
    beads: usize,
    threads: usize,
    settle_steps: u64,
    steps: u64,
    cache: Option<&std::path::Path>,
) -> Result<BenchResult, crate::RunError> {
    let mut sim = settled(
        || dumbbell_bed(beads, threads),
        threads,
        settle_steps,
        cache,
    )?;
    Ok(time_steps(&mut sim, steps, "dumbbells", threads)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bed_holds_whole_dumbbells_of_touching_beads_without_overlaps() {
        // About 500 beads: 250 dumbbells, every bead a member, the two beads of each one d
        // apart, and no two beads of different dumbbells overlapping at the start.
        let sim = dumbbell_bed(500, 1).expect("bed");
        let p = sim.particles();
        assert_eq!((sim.clumps().len(), p.len()), (250, 500));
        let x = p.positions();
        for i in 0..p.len() {
            for j in i + 1..p.len() {
                let d = x[i].distance(x[j]);
                if p.clump_indices()[i] == p.clump_indices()[j] {
                    assert!((d - SMALL_DIAMETER).abs() <= 1e-15, "{i} {j} {d}");
                } else {
                    assert!(d > SMALL_DIAMETER, "beads {i} and {j} overlap");
                }
            }
        }
    }
}
