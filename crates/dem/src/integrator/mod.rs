//! Velocity Verlet (docs/physics.md §6.2): the half kicks and the drift, with the reductions the
//! simulation needs from the same pass (largest displacement since the last list build,
//! finiteness probes).
//!
//! Two forms of the same arithmetic:
//! - the general one walks particle by particle, honouring each one's flags, mass and
//!   moment of inertia;
//! - when every particle is free (no flags) and all share one mass and one moment of inertia
//!   (the paper's monodisperse beds), the kicks and the drift are the same operation on
//!   every component of every particle, so they run over the vectors as flat arrays of
//!   numbers, which the compiler vectorises. Each component goes through exactly the
//!   operations of the general form, in the same order, so the trajectory is bit-identical
//!   (a test checks it).
//!
//! The pass that drifts also restarts the force arrays for the coming evaluation: once a
//! particle's force and torque have given their kicks they are dead until the next
//! evaluation, which starts each body from its weight m g and zero torque. Writing those
//! here, into cache lines the pass has just read, replaces a sweep of its own over both
//! arrays at the start of the evaluation (about 4 % of a step on the paper's base case).
//! The values are the same products, so the trajectory is unchanged.

use glam::DVec3;

use crate::particles::{ParticleSet, FLAG_HELD, FLAG_ROTATION_LOCKED};
use crate::ranges::even_bounds;

mod bodies;
mod displacement;
mod flat;
mod per_body;
#[cfg(test)]
mod tests;

use bodies::*;
pub(crate) use displacement::*;
use flat::*;
use per_body::*;

/// 1/m [1/kg] and 1/I [1/(kg m²)] shared by every particle, when every particle is free
/// (no flags) and they are all alike (their masses too, which the flat pass writes the
/// weights from); `None` otherwise.
pub(crate) fn uniform_free_body(p: &ParticleSet) -> Option<(f64, f64)> {
    let (&m, &i, &mass) = (p.inv_mass.first()?, p.inv_inertia.first()?, p.mass.first()?);
    let alike = p.flags.iter().all(|&f| f == 0)
        && p.inv_mass.iter().all(|&x| x == m)
        && p.inv_inertia.iter().all(|&x| x == i)
        && p.mass.iter().all(|&x| x == mass);
    alike.then_some((m, i))
}

/// Half kick and drift (see [`kick_drift_per_body`] for the contract), leaving each body's
/// weight m g [N] (`gravity` g [m/s²]) in its force and zero in its torque once they have
/// given their kicks. `uniform`: the result of [`uniform_free_body`] for the current
/// particles. With a `pool`, contiguous ranges of
/// particles are moved in parallel: each particle's arithmetic is its own, and the reductions
/// (a maximum and two all-finite flags) do not depend on the order they are merged in, so
/// the result is the same on any number of threads.
pub(crate) fn kick_drift(
    p: &mut ParticleSet,
    reference: &[DVec3],
    (half, dt): (f64, f64),
    pending: bool,
    uniform: Option<(f64, f64)>,
    gravity: DVec3,
    pool: Option<&crate::team::Team>,
) -> (f64, bool, bool) {
    let n = p.len();
    let weight = shared_weight(p, gravity);
    let bodies = Bodies::of(p, reference);
    let one = |b: Bodies| kick_drift_bodies(b, (half, dt), pending, uniform, (gravity, weight));
    let results = on_ranges(bodies, n, pool, one);
    results.into_iter().fold(NOTHING_MOVED, merge_drift)
}

/// `one` of contiguous ranges of `bodies` (`n` of them) on the `pool`'s threads where it has
/// more than one and the bodies are enough to share, otherwise of all of them on this thread:
/// each range's findings, in body order.
fn on_ranges<R: Send>(
    bodies: Bodies,
    n: usize,
    pool: Option<&crate::team::Team>,
    one: impl Fn(Bodies) -> R + Sync + Send,
) -> Vec<R> {
    let bounds = pool.map(|pool| even_bounds(n, pool.threads(), RANGES_PER_THREAD, MIN_RANGE));
    let (Some(pool), Some(bounds)) = (pool, bounds.filter(|b| b.len() > 2)) else {
        return vec![one(bodies)];
    };
    let mut parts = Vec::with_capacity(bounds.len() - 1);
    let mut rest = bodies;
    for w in bounds.windows(2) {
        let (part, tail) = rest.split_at(w[1] - w[0]);
        parts.push(part);
        rest = tail;
    }
    crate::timing::parallel_region(|| pool.map(parts, one))
}

/// What [`kick_drift`] reports for no bodies: the neutral element of [`merge_drift`].
pub(crate) const NOTHING_MOVED: (f64, bool, bool) = (0.0, true, true);

/// The findings of two kick-and-drift passes over disjoint sets of bodies, as one pass over
/// both would report them: the larger squared displacement, and both finiteness flags.
pub(crate) fn merge_drift(
    (d, x, v): (f64, bool, bool),
    (d2, x2, v2): (f64, bool, bool),
) -> (f64, bool, bool) {
    (if d2 > d { d2 } else { d }, x & x2, v & v2)
}

/// [`kick_drift`] of the particles in `range` only, on the calling thread: each of them
/// gets exactly the arithmetic of the whole pass, and the reductions cover the range. The
/// one-thread evaluation of large systems (`Simulation`) calls it on each chunk of bodies
/// as soon as the chunk's forces are whole, while its numbers are still in the cache.
pub(crate) fn kick_drift_range(
    p: &mut ParticleSet,
    reference: &[DVec3],
    range: std::ops::Range<usize>,
    (half, dt): (f64, f64),
    pending: bool,
    uniform: Option<(f64, f64)>,
    gravity: DVec3,
) -> (f64, bool, bool) {
    let weight = shared_weight(p, gravity);
    let (_, rest) = Bodies::of(p, reference).split_at(range.start);
    let (bodies, _) = rest.split_at(range.len());
    kick_drift_bodies(bodies, (half, dt), pending, uniform, (gravity, weight))
}

/// Every body's weight m g [N] (`gravity` g [m/s²]) when they share one mass
/// (`uniform_free_body` checks it): the same product as each body's own.
fn shared_weight(p: &ParticleSet, gravity: DVec3) -> DVec3 {
    p.mass.first().map_or(DVec3::ZERO, |&m| m * gravity)
}

/// Second half kick of every free particle; false when some velocity or spin may be
/// non-finite. `uniform` as in [`kick_drift`].
pub(crate) fn kick(p: &mut ParticleSet, half: f64, uniform: Option<(f64, f64)>) -> bool {
    match uniform {
        Some((inv_mass, inv_inertia)) => {
            let (kv, kw) = (half * inv_mass, half * inv_inertia);
            let (v, w, x) = (&mut p.velocity, &mut p.omega, &mut p.position);
            let forces = (&mut p.force[..], &mut p.torque[..]);
            flat_pass::<true, false>((v, w, x), forces, (kv, kw, 0.0), DVec3::ZERO) == 0.0
        }
        None => kick_per_body(p, half),
    }
}

/// [`kick_drift`] for free bodies that share 1/m and 1/I (`uniform`, as
/// [`uniform_free_body`] finds them), measuring the displacements since the last list build
/// only when `measure` ([`Moved`]). The simulation asks for them only when its bound on them
/// ([`crate::reach::ReachBound`]) cannot rule a list build out. With a `pool`, contiguous
/// ranges of bodies move in parallel; the findings are maxima and conjunctions, the same in
/// any order of merging, so the result is that of one thread.
pub(crate) fn kick_drift_flat_tracked(
    p: &mut ParticleSet,
    reference: &[DVec3],
    (half, dt): (f64, f64),
    pending: bool,
    (inv_mass, inv_inertia): (f64, f64),
    (gravity, measure): (DVec3, bool),
    pool: Option<&crate::team::Team>,
) -> Moved {
    let n = p.len();
    let weight = shared_weight(p, gravity);
    let b = Bodies::of(p, reference);
    let (kv, kw) = (half * inv_mass, half * inv_inertia);
    let one = |b: Bodies| kick_drift_flat(b, (kv, kw), (dt, weight), pending, (measure, true));
    on_ranges(b, n, pool, one)
        .into_iter()
        .reduce(Moved::merge)
        .expect("at least one range")
}

/// What a uniform kick-and-drift pass found.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Moved {
    /// Largest squared displacement since the last list build [m²], where it was measured.
    pub max_disp2: Option<f64>,
    /// Every position is finite.
    pub finite: bool,
    /// The pending kick left every velocity and spin finite.
    pub kicked_finite: bool,
    /// The step's reach: the largest |Δt v_c| of any component of any body's drift [m]
    /// (0 where it was not asked for).
    pub reach: f64,
}

impl Moved {
    /// The findings of two passes over disjoint sets of bodies, as one pass over both
    /// would report them.
    fn merge(self, other: Self) -> Self {
        let larger = |a: f64, b: f64| if b > a { b } else { a };
        Self {
            max_disp2: match (self.max_disp2, other.max_disp2) {
                (Some(a), Some(b)) => Some(larger(a, b)),
                _ => None,
            },
            finite: self.finite & other.finite,
            kicked_finite: self.kicked_finite & other.kicked_finite,
            reach: larger(self.reach, other.reach),
        }
    }
}

impl From<Moved> for (f64, bool, bool) {
    /// The findings as the other passes report them (the displacement measured).
    fn from(m: Moved) -> Self {
        (
            m.max_disp2.unwrap_or(f64::INFINITY),
            m.finite,
            m.kicked_finite,
        )
    }
}

/// A reach [m] below which a drift cannot make a finite position non-finite, short of
/// positions some 10³⁰⁸ m out.
pub(crate) const FINITE_REACH: f64 = 1e100;
