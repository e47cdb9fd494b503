//! The insertion loop both fills share: draw a particle, draw a candidate centre, keep it if
//! it lies inside the container and clear of every particle placed, until the batch is full
//! or the attempts run out. The container (where candidates are drawn and which of them fit)
//! and the record of placed particles (a list for the slab, a cell grid in 3D) are the
//! callers'; the loop's order of random draws and tests is theirs unchanged.

use dem::{DVec3, ParticleInit, Simulation};
use rand::Rng;

use super::draw::{Draw, ParticleDraws};
use super::slab::Inserted;

/// Clearance kept between inserted particles and from the walls [m].
pub(super) const GAP: f64 = 1.0e-5;

/// The particles a batch must keep clear of: those already in the simulation near the band,
/// then each one the batch places.
pub(super) trait Placed {
    /// Whether a particle at `x` of radius `r` keeps [`GAP`] to every placed particle.
    fn is_free(&self, x: DVec3, r: f64) -> bool;
    /// Records a particle placed at `x` with radius `r`.
    fn add(&mut self, x: DVec3, r: f64);
}

/// Whether a particle at `x` of radius `r` comes within [`GAP`] of one placed at `q` with
/// radius `rq`: the one overlap test of both records.
pub(super) fn overlaps(x: DVec3, r: f64, q: DVec3, rq: f64) -> bool {
    q.distance_squared(x) < (r + rq + GAP) * (r + rq + GAP)
}

/// Random sequential insertion of up to `count` particles drawn by `draws`: `candidate`
/// draws a centre for a radius and returns it when the particle lies inside the container
/// (`None` otherwise), `placed` tests it against the particles placed. Each particle starts
/// with velocity `v0` [m/s]. A draw that does not fit is kept for the next attempt, and left
/// in `pending` for the next batch when the attempts run out (see [`ParticleDraws`]).
#[allow(clippy::too_many_arguments)]
pub(super) fn insert_batch<R: Rng>(
    sim: &mut Simulation,
    rng: &mut R,
    count: usize,
    draws: &ParticleDraws,
    pending: &mut Option<Draw>,
    v0: DVec3,
    max_attempts: usize,
    placed: &mut impl Placed,
    mut candidate: impl FnMut(&mut R, f64) -> Option<DVec3>,
) -> Result<Vec<Inserted>, dem::DemError> {
    let mut inserted = Vec::new();
    let mut attempts = 0;
    while inserted.len() < count && attempts < max_attempts {
        attempts += 1;
        let drawn = *pending.get_or_insert_with(|| draws.draw(rng));
        let r = drawn.radius;
        let Some(c) = candidate(rng, r) else {
            continue;
        };
        if !placed.is_free(c, r) {
            continue;
        }
        let tag = sim.add_particle(ParticleInit {
            position: c,
            velocity: v0,
            angular_velocity: DVec3::ZERO,
            radius: r,
            material: drawn.material,
            flags: 0,
        })?;
        *pending = None;
        placed.add(c, r);
        inserted.push((tag, drawn.component));
    }
    Ok(inserted)
}
