//! Filling the hopper: random non-overlapping insertion in the upper part, in batches that
//! fall under gravity (docs/physics.md §10.8: the paper does not describe its fill).

use dem::{DVec3, ParticleTag, Simulation};
use rand::Rng;

use super::batch::{insert_batch, overlaps, Placed, GAP};
use super::draw::{Draw, ParticleDraws};
use case::SlabGeometry;

/// A particle a batch placed: its tag and its component (index into `particles.components`).
pub type Inserted = (ParticleTag, u8);

/// Whether a disc of radius `r` [m] centred at (x, z) lies inside the hopper's in-plane
/// outline with clearance `gap` [m].
pub fn inside_slab(geometry: &SlabGeometry, x: f64, z: f64, r: f64, gap: f64) -> bool {
    let half = 0.5 * geometry.width;
    let c = r + gap;
    if x - c < -half || x + c > half || z - c < 0.0 || z + c > geometry.height {
        return false;
    }
    if geometry.hopper_angle_deg >= 90.0 {
        return true;
    }
    // Distance to each inclined plate's line must exceed the clearance. The plates rise from
    // the outlet edges outward at angle α from the vertical.
    let (xl, xr) = geometry.outlet_edges();
    let a = geometry.hopper_angle();
    let (sa, ca) = (a.sin(), a.cos());
    // Left plate line through (xl, 0) with direction (−sin α, cos α); inner normal (cos α, sin α).
    let left = (x - xl) * ca + z * sa;
    let right = (xr - x) * ca + z * sa;
    left >= c && right >= c
}

/// Random sequential insertion of up to `count` particles drawn by `draws` into the band
/// z ∈ [z_low, z_high] [m], avoiding every particle already in `sim`. Returns the particles
/// inserted. Each starts at the slab mid-plane with velocity `v0` [m/s].
///
/// A draw that does not fit is kept for the next attempt, and left in `pending` for the next
/// batch when the attempts run out (see [`ParticleDraws`]).
#[allow(clippy::too_many_arguments)]
pub fn insert_slab_batch(
    sim: &mut Simulation,
    geometry: &SlabGeometry,
    rng: &mut impl Rng,
    count: usize,
    draws: &ParticleDraws,
    pending: &mut Option<Draw>,
    band: (f64, f64),
    v0: DVec3,
    max_attempts: usize,
) -> Result<Vec<Inserted>, dem::DemError> {
    let half = 0.5 * geometry.width;
    let y_mid = 0.5 * geometry.thickness;
    // Existing particles in or near the band, for the overlap test.
    let p = sim.particles();
    let mut placed: Vec<(DVec3, f64)> = p
        .positions()
        .iter()
        .zip(p.radii())
        .filter(|(x, r)| x.z + **r > band.0 - 0.01 && x.z - **r < band.1 + 0.01)
        .map(|(x, r)| (*x, *r))
        .collect();
    insert_batch(
        sim,
        rng,
        count,
        draws,
        pending,
        v0,
        max_attempts,
        &mut placed,
        |rng, r| {
            let x = rng.gen_range(-half + r..half - r);
            let z = rng.gen_range(band.0..band.1);
            // Quasi-2D slab: start on the mid-plane (docs/physics.md §5). A thick slab (room
            // for half a diameter of play or more) gets a random depth.
            let y = if geometry.thickness >= 3.0 * r {
                rng.gen_range(r..geometry.thickness - r)
            } else {
                y_mid
            };
            inside_slab(geometry, x, z, r, GAP).then(|| DVec3::new(x, y, z))
        },
    )
}

/// The slab's record of placed particles: few enough for a list.
impl Placed for Vec<(DVec3, f64)> {
    fn is_free(&self, x: DVec3, r: f64) -> bool {
        !self.iter().any(|(q, rq)| overlaps(x, r, *q, *rq))
    }

    fn add(&mut self, x: DVec3, r: f64) {
        self.push((x, r));
    }
}
