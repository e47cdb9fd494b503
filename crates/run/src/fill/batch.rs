//! The insertion loop both fills share: draw a particle, draw a candidate centre, keep it if
//! it lies inside the container and clear of every particle placed, until the batch is full
//! or the attempts run out. The container (where candidates are drawn and which of them fit)
//! and the record of placed particles (a list for the slab, a cell grid in 3D) are the
//! callers'; the loop's order of random draws and tests is theirs unchanged.

use dem::{DQuat, DVec3, ParticleInit, Simulation};
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
///
/// A grain of a shaped component is a clump: its centre of mass is drawn as a sphere's
/// centre is, with its reach (the farthest any member gets from it) as the radius that must
/// lie inside the container, then its orientation, uniform over rotations; it is placed when
/// every member keeps [`GAP`] to every particle placed. The batch lists it once, by its first
/// member's tag. Spheres draw no orientation, so cases without shapes keep their draws.
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
        if let Some((shape, reach, unit_centre)) = draws.shape(drawn.component) {
            let diameter = 2.0 * r;
            let Some(c) = candidate(rng, reach * diameter) else {
                continue;
            };
            let q = uniform_rotation(rng);
            // Members about the body's centre of mass, as the engine will place them.
            let centre = *unit_centre * diameter;
            let world: Vec<(DVec3, f64)> = shape
                .members()
                .iter()
                .map(|&(m, rm)| (c + q * (m * diameter - centre), rm * diameter))
                .collect();
            if !world.iter().all(|&(x, rm)| placed.is_free(x, rm)) {
                continue;
            }
            let k =
                sim.add_scaled_clump((shape, diameter), drawn.material, (c, q), (v0, DVec3::ZERO))?;
            *pending = None;
            for &(x, rm) in &world {
                placed.add(x, rm);
            }
            inserted.push((sim.clumps().first_tags()[k], drawn.component));
            continue;
        }
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

/// A rotation drawn uniformly over all rotations (Shoemake 1992, "Uniform random rotations",
/// Graphics Gems III): three uniform numbers u₁, u₂, u₃ give the unit quaternion
/// (√(1−u₁) sin 2πu₂, √(1−u₁) cos 2πu₂, √u₁ sin 2πu₃, √u₁ cos 2πu₃).
pub(super) fn uniform_rotation(rng: &mut impl Rng) -> DQuat {
    let (u1, u2, u3): (f64, f64, f64) = (rng.gen(), rng.gen(), rng.gen());
    let tau = std::f64::consts::TAU;
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    DQuat::from_xyzw(
        a * (tau * u2).sin(),
        a * (tau * u2).cos(),
        b * (tau * u3).sin(),
        b * (tau * u3).cos(),
    )
}
