//! Force evaluation: the contact kernel over candidate pairs, then accumulation in pair
//! order, so that sums are bit-identical at any thread count.
//!
//! One thread (this file): each contact force is added to its two bodies as soon as it is
//! computed. Several threads (`parallel`): each range of bodies, in one parallel pass,
//! resolves its own pairs, again the pairs that reach into it from earlier ranges, and its
//! wall contacts. Both paths run the same kernel and give every body the same sequence of
//! floating-point additions (gravity, pairs in list order, walls in list order).

use glam::DVec3;

use crate::contact::{ContactForce, ContactLaws};
use crate::history::settle;
use crate::material::PairCoefficients;
use crate::neighbour::{PairList, WallPairList};
use crate::particles::ParticleSet;
use crate::wall::Wall;
use accumulator::Accumulator;
use general::{pair_loop_with, wall_loop};
use kernel::{Batch, BATCH};
use pairs::batched_pair_loop;
use walls::{batched_wall_loop, WallProbe};

mod accumulator;
pub(crate) mod area_cohesion;
pub(crate) mod bond_rows;
mod chunked;
mod compact;
mod filter;
mod gather;
mod general;
pub(crate) mod kernel;
pub(crate) mod loads;
mod pairs;
mod parallel;
mod surface_batch;
pub(crate) mod surfaces;
mod surfaces_parallel;
#[cfg(test)]
pub(super) mod tests;
mod walls;

pub(crate) use chunked::{chunk_bounds, evaluate_chunk};
use loads::{LoadQuanta, LoadSum};

/// Read-only inputs of the kernel.
pub(crate) struct KernelInput<'a> {
    pub particles: &'a ParticleSet,
    pub laws: &'a ContactLaws,
    pub pair_coeffs: &'a [PairCoefficients],
    pub materials: usize,
    pub walls: &'a [Option<Wall>],
    pub wall_coeffs: &'a [PairCoefficients],
    /// The bonding constants of `pair_coeffs` and `wall_coeffs`, index for index.
    pub bond_tables: &'a bond_rows::BondTables,
    /// Radius [m] and mass [kg] of every particle, when all are alike (the batch is then
    /// filled with them once instead of per contact).
    pub uniform_body: Option<(f64, f64)>,
    pub dt: f64,
    /// The quanta of the walls' fixed-point loads.
    pub quanta: LoadQuanta,
    /// Some particle pair bonds beyond contact (JKR, a liquid bridge): the pair filter
    /// keeps bonded pairs apart, and the batched kernel resolves them with the bonding laws.
    pub pair_bonds: bool,
    /// Some particle–wall pair bonds beyond contact: the wall filters keep bonded contacts
    /// apart, and the batched kernel resolves them with the bonding laws.
    pub wall_bonds: bool,
    /// Some pair has the simplified JKR's attraction, added to the batched kernel's dry
    /// forces ([`area_cohesion`]).
    pub area_cohesion: bool,
    /// How far beyond contact [m] a bonded pair may still interact (0 without cohesion).
    pub reach: f64,
}

impl KernelInput<'_> {
    /// Whether the particle–particle contacts go through the batched kernel: the paper's
    /// laws, with any cohesion.
    #[inline(always)]
    pub(crate) fn batched_pairs(&self) -> bool {
        *self.laws == ContactLaws::default()
    }

    /// Whether the wall contacts go through the batched kernel: the paper's laws, with any
    /// cohesion.
    #[inline(always)]
    pub(crate) fn batched(&self) -> bool {
        *self.laws == ContactLaws::default()
    }
}

/// The largest overlap seen, as a fraction of the smaller radius, and where.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct WorstOverlap {
    pub fraction: f64,
    /// Index into the pair list (or wall pair list).
    pub index: usize,
}

impl WorstOverlap {
    #[inline]
    fn see(&mut self, fraction: f64, index: usize) {
        if fraction > self.fraction {
            *self = Self { fraction, index };
        }
    }

    /// Sees every contact of a resolved batch; `index` gives their list indices in order.
    ///
    /// The batch maximum is a branch-free reduction; the contacts are walked one by one only
    /// when it beats the worst so far, which after the first batches is rare.
    #[inline(always)]
    fn see_batch(&mut self, batch: &Batch, index: impl Iterator<Item = usize>) {
        let fractions = &batch.overlap_fraction[..batch.len.min(BATCH)];
        // The largest fraction's bits, sign cleared, as an integer maximum, which vectorises
        // (a float fold is a chain of dependent compares). For numbers ≥ 0 the integers
        // order as the numbers; a negative number or a NaN (whose bits exceed every
        // number's) can only cause a walk, and the walk below decides as before.
        let largest = fractions
            .iter()
            .fold(0u64, |a, &b| a.max(b.to_bits() & !(1 << 63)));
        if !(f64::from_bits(largest) <= self.fraction) {
            for (&f, k) in fractions.iter().zip(index) {
                self.see(f, k);
            }
        }
    }

    /// Deterministic merge: larger fraction wins, ties go to the lower index.
    fn merge(self, other: Self) -> Self {
        if other.fraction > self.fraction
            || (other.fraction == self.fraction && other.index < self.index)
        {
            other
        } else {
            self
        }
    }
}

/// Scratch of one pass of the pair and wall loops, reused from step to step.
#[derive(Debug, Default)]
struct KernelScratch {
    /// Indices (into the slice being filtered) of the touching pair candidates, in order.
    touching: Vec<u32>,
    /// The batch the contacts are resolved in.
    batch: Box<Batch>,
}

/// Reusable buffers.
#[derive(Debug, Default)]
pub(crate) struct ForceBuffers {
    /// Scratch of the one-thread pass.
    kernel: KernelScratch,
    /// Indices of the touching wall candidates.
    wall_hits: Vec<u32>,
    /// Whether each wall candidate touches (1) or not (0), for the split plane filter.
    wall_touch: Vec<u8>,
    wall_probes: Vec<WallProbe>,
    /// Working arrays of the surface pass.
    surface: surfaces::SurfaceScratch,
    /// Working arrays of the surface pass's ranges on several threads.
    surface_ranges: Vec<surfaces::SurfaceScratch>,
    /// Each wall's load of the evaluation, in fixed point (by wall index).
    pub loads: Vec<LoadSum>,
    /// Scratch of the body ranges (several threads only).
    ranges: Vec<parallel::RangeScratch>,
    /// The pairs that cross from range to range, handed over during the pass.
    handoffs: parallel::Handoffs,
    /// The largest j − i of the pair list, once found for the current list (several
    /// threads only); a list build forgets it ([`ForceBuffers::forget_lists`]).
    pair_span: Option<usize>,
    /// Forces [N] the contacts are added to: during a step's evaluation, the particles'
    /// own array (holding the weights the integrator wrote), lent by swapping and swapped
    /// back after.
    pub force: Vec<DVec3>,
    /// Torques [N m], lent the same way.
    pub torque: Vec<DVec3>,
}

impl ForceBuffers {
    /// Forgets what was found of the previous lists: a list build calls it.
    pub(crate) fn forget_lists(&mut self) {
        self.pair_span = None;
    }
}

/// Counts of contacts that carried force in the last evaluation.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ContactCount {
    /// Particle–particle contacts.
    pub particle_particle: usize,
    /// Particle–wall contacts.
    pub particle_wall: usize,
}

/// What one evaluation found.
#[derive(Default)]
pub(crate) struct Evaluation {
    pub count: ContactCount,
    pub worst_pair: WorstOverlap,
    pub worst_wall: WorstOverlap,
}

/// Sets `buffers` to the starting values of an evaluation: each body's weight m g [N]
/// (gravity `g` [m/s²]) and zero torque. The step does not call it: its integrator pass
/// writes the same products.
#[cfg(test)]
pub(crate) fn start(p: &ParticleSet, g: DVec3, buffers: &mut ForceBuffers) {
    buffers.force.clear();
    buffers.force.extend(p.mass.iter().map(|&m| m * g));
    buffers.torque.clear();
    buffers.torque.resize(p.len(), DVec3::ZERO);
}

/// Where the pair loops hand each contact's force, in pair order. A trait rather than a
/// closure so that the call is always inlined into the loop.
trait PairSink {
    fn contact(&mut self, i: usize, j: usize, cf: &ContactForce);
    /// Asks for body `j`'s sums to be brought into the cache ahead of its contact.
    #[inline(always)]
    fn prefetch(&self, _j: usize) {}
}

/// Bodies beyond which the pair loops ask for the partner bodies' cache lines ahead of
/// use. Below it (the paper's hopper) the body arrays, about 120 bytes a body, stay in the
/// caches and the hints would only cost instructions. Above it a partner can lie far
/// behind in memory (the next layer of a 3D packing, 10^4 bodies on for 10^6 spheres): the
/// hints save about 4 % of the scaling benchmark's time per particle-step at 10^6 spheres.
const PREFETCH_BODIES: usize = 1 << 15;

/// Candidates ahead of the one being filtered whose partner's position is asked for.
const PREFETCH_AHEAD: usize = 32;

/// Asks for the cache line holding `x`; no effect on results.
#[inline(always)]
fn prefetch<T>(x: &T) {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
    safe_arch::prefetch_t0(x);
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
    let _ = x;
}

/// Evaluates all contacts, updating histories, and adds their forces and torques to
/// `buffers.force` and `buffers.torque`, which must hold each body's starting values on
/// entry: its weight m g and zero torque ([`start`], or the integrator's pass, which writes
/// them while its cache lines are at hand).
///
/// The walls' loads are summed into `buffers.loads`, which [`start_loads`] zeroes, and the
/// curved and meshed walls' element loads into `elements` (by wall index).
pub(crate) fn evaluate(
    input: &KernelInput,
    pairs: &mut PairList,
    wall_pairs: &mut WallPairList,
    buffers: &mut ForceBuffers,
    pool: Option<&crate::team::Team>,
    elements: &mut [loads::SurfaceLoads],
) -> Evaluation {
    // Zeroed by `start_loads`; sized here for callers that sum over several evaluations.
    buffers.loads.resize(input.walls.len(), LoadSum::default());
    let (mut eval, surfaces_done) = match pool {
        Some(pool) => parallel::evaluate(input, pairs, wall_pairs, buffers, pool, elements),
        None => (planar_contacts(input, pairs, wall_pairs, buffers), false),
    };
    if !surfaces_done {
        let everyone = 0..input.particles.len();
        add_surface_contacts(
            &mut eval, input, wall_pairs, buffers, elements, everyone, pool,
        );
    }
    eval
}

/// Zeroes the walls' loads before an evaluation of `walls` walls.
pub(crate) fn start_loads(buffers: &mut ForceBuffers, walls: usize) {
    buffers.loads.clear();
    buffers.loads.resize(walls, LoadSum::default());
}

/// Adds to `eval` the contacts of the curved, meshed and spinning walls with the particles
/// of `bodies`, after all others ([`surfaces::surface_pass`]), where there are such walls.
fn add_surface_contacts(
    eval: &mut Evaluation,
    input: &KernelInput,
    wall_pairs: &mut WallPairList,
    buffers: &mut ForceBuffers,
    elements: &mut [loads::SurfaceLoads],
    bodies: std::ops::Range<usize>,
    pool: Option<&crate::team::Team>,
) {
    if !crate::wall::any_resolved_one_by_one(input.walls) {
        return;
    }
    let len = wall_pairs.particle.len();
    // A wall that began to spin since the last build has no remembered contacts yet.
    wall_pairs.surfaces.resize_with(len, Default::default);
    let mut sinks = surfaces::SurfaceSinks {
        force: &mut buffers.force,
        torque: &mut buffers.torque,
        loads: &mut buffers.loads,
        quanta: &input.quanta,
        elements,
    };
    let ids = (&wall_pairs.particle[..], &wall_pairs.wall[..]);
    let (worst, contacts) = match pool {
        // The whole body set on several threads, the same bits as one.
        Some(pool) if bodies == (0..input.particles.len()) => {
            surfaces_parallel::surface_pass_parallel(
                input,
                ids,
                &mut wall_pairs.surfaces,
                &mut buffers.surface_ranges,
                &mut sinks,
                pool,
            )
        }
        _ => surfaces::surface_pass(
            input,
            ids,
            bodies,
            &mut wall_pairs.surfaces,
            &mut buffers.surface,
            &mut sinks,
        ),
    };
    eval.count.particle_wall += contacts;
    eval.worst_wall = eval.worst_wall.merge(worst);
}

/// Every contact but those of the curved, meshed and spinning walls, on this thread.
#[inline(never)]
fn planar_contacts(
    input: &KernelInput,
    pairs: &mut PairList,
    wall_pairs: &mut WallPairList,
    buffers: &mut ForceBuffers,
) -> Evaluation {
    let n = input.particles.len();
    assert!(
        buffers.force.len() == n && buffers.torque.len() == n,
        "the force buffers hold one starting value per body"
    );
    let mut count = ContactCount::default();
    let ids = (&pairs.i[..], &pairs.j[..]);

    let scratch = &mut buffers.kernel;
    let mut acc = Accumulator::new(&mut buffers.force, &mut buffers.torque);
    let worst_pair = pair_loop(
        input,
        ids,
        0,
        pairs.history.parts_mut(),
        (&mut scratch.touching, &mut scratch.batch),
        &mut acc,
    );
    count.particle_particle = acc.contacts;

    // Walls after pairs: each particle receives its wall forces in increasing wall order.
    // The sink holds the slices themselves, not references to the vectors, so that the
    // wall loop (not inlined) need not reload their addresses at every contact.
    let (force, torque) = (&mut buffers.force[..], &mut buffers.torque[..]);
    let sink = move |i: usize, cf: &ContactForce| {
        force[i] += cf.force;
        torque[i] += cf.torque_i;
    };
    let wall_ids = (&wall_pairs.particle[..], &wall_pairs.wall[..]);
    let (worst_wall, wall_contacts) = if input.batched() {
        let (tangential, _, live) = wall_pairs.history.parts_mut();
        batched_wall_loop(
            input,
            wall_ids,
            (tangential, live),
            (
                &mut buffers.wall_hits,
                &mut buffers.wall_touch,
                &mut buffers.wall_probes,
                &mut buffers.kernel.batch,
            ),
            &mut buffers.loads,
            sink,
        )
    } else {
        wall_loop(
            input,
            wall_ids,
            wall_pairs.history.split_mut(),
            &mut buffers.loads,
            sink,
        )
    };
    count.particle_wall = wall_contacts;
    Evaluation {
        count,
        worst_pair,
        worst_wall,
    }
}

/// Runs the kernel over pairs `base..base + history.len()`, calling `sink(i, j, force)` for
/// each pair in contact, in order. `history` is ξ, the rolling history and the live flags
/// (`HistoryArrays`) of those pairs.
///
/// The paper's laws (the default) get their own copy of the loop in which the law choices are
/// constants, so the compiler drops the branches and code of the other laws.
#[inline(always)]
fn pair_loop(
    input: &KernelInput,
    ids: (&[u32], &[u32]),
    base: usize,
    (tangential, rolling, live): (&mut [DVec3], &mut [DVec3], &mut [u8]),
    scratch: (&mut Vec<u32>, &mut Batch),
    sink: &mut impl PairSink,
) -> WorstOverlap {
    if input.batched_pairs() {
        // The paper's laws keep no rolling history: only ξ is passed.
        batched_pair_loop(input, ids, base, (tangential, live), scratch, sink)
    } else {
        // The scalar laws clear separated histories themselves, from arrays that hold them.
        settle(tangential, rolling, live);
        pair_loop_with(
            input,
            *input.laws,
            ids,
            base,
            (tangential, rolling, live),
            sink,
        )
    }
}
