//! Force evaluation on several threads, bit-identical to the one-thread path.
//!
//! One parallel pass. The particles are cut into contiguous index ranges of about equal
//! cost, and each range's task, alone, computes every force on its bodies:
//! 1. its bodies start from their weights and zero torques (the integrator's pass wrote them);
//! 2. its **incoming** pairs, those whose i lies before the range and whose j lies in it.
//!    They belong to an earlier range, which resolves them too, as its own. This task
//!    resolves them again from copies of their histories, and keeps only j's share. The
//!    kernel gives the same bits for the same inputs, so both sides of a pair see one force;
//!    only the owner writes the new history. The copies are the owners' to make: each task
//!    first hands its crossing pairs, with their histories as they stand, to the later
//!    ranges ([`Handoffs`]), and then waits until every earlier range has done the same for
//!    it, so that no range waits for the copies of a range after it;
//! 3. its own pairs, those whose i lies in it: the kernel, the new histories, i's share, and
//!    j's share when j lies in the range too (otherwise j's range resolves the pair again);
//! 4. its wall contacts (filter, kernel and history);
//! 5. under the default laws, its surface contacts (curved, meshed and spinning walls,
//!    `surfaces_parallel`), last as on one thread, in the same task: one join less per step.
//!
//! No two tasks write the same body or history, and nothing passes from one task to another
//! during the pass: no contact force is stored for a later pass, which on large systems cost
//! more memory traffic than the second thread saved. The price is the incoming pairs,
//! resolved twice: about one cell layer of pairs per range boundary.
//!
//! Every body receives the additions of the one-thread path, in the same order:
//! - the weight first;
//! - then its pairs. The list holds i < j, sorted by i, so the contacts in which a body is j
//!   all come before its own run as i, the incoming ones (i before the range) first. The
//!   one-thread [`Accumulator`] adds them one by one in that order; a range adds its
//!   incoming pairs first, then its own, in list order, and so does the same;
//! - then its walls, in increasing wall order (the list is wall-major);
//! - then its surface contacts, wall by wall, whose element loads are replayed afterwards in
//!   the one-thread order.
//!
//! So the sums, and the whole trajectory, do not depend on the thread count or on where the
//! ranges are cut.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard};

use glam::DVec3;

use super::accumulator::Accumulator;
use super::general::wall_loop;
use super::loads::LoadSum;
use super::walls::{prepare_wall_batch, wall_pieces, wall_probes, wall_runs, WallPiece, WallProbe};
use super::{
    loads, pair_loop, surfaces, surfaces_parallel, ContactCount, Evaluation, ForceBuffers,
    KernelInput, KernelScratch, PairSink, WorstOverlap,
};
use crate::contact::ContactForce;
use crate::neighbour::{PairList, WallPairList};
use crate::ranges::{cost_bounds, pair_start};

/// Ranges per thread: one. The team deals each thread the same range at every step
/// ([`crate::team::Team::map`]), so its bodies stay in that core's cache, and every further
/// boundary would add its incoming pairs, resolved twice (the reduced benchmark silo on two
/// threads: 1.37× over one thread with two ranges, 1.21× with four).
const RANGES_PER_THREAD: usize = 1;

/// Bodies per range, at least: each range resolves again the pairs that cross its lower
/// boundary, about one cell layer of them, which must stay small beside its own. (Smaller in
/// the tests, so that their few hundred bodies are cut into many ranges.)
const MIN_RANGE: usize = if cfg!(test) { 64 } else { 256 };

/// The cost of a body's gravity and wall candidates (every particle of the paper's slab is a
/// candidate of both faces), in units of one candidate pair, for cutting the ranges.
const BODY_COST: usize = 2;

/// Scratch of one body range, reused from step to step.
#[derive(Debug, Default)]
pub(super) struct RangeScratch {
    /// Indices of the touching wall candidates of one piece.
    hits: Vec<u32>,
    /// Whether each wall candidate of a piece touches (1) or not (0).
    touch: Vec<u8>,
    /// Its pair filter's hits and the batch its pair and wall contacts are resolved in.
    kernel: KernelScratch,
    /// The walls' loads from this range's wall contacts, in fixed point.
    loads: Vec<LoadSum>,
}

/// The crossing pairs handed from range to range during a pass: list `r · ranges + q` holds
/// the pairs of range q whose j lies in range r (q < r), in list order, with their histories
/// as they were before the pass; `reported[r]` counts the earlier ranges that have filled
/// theirs for r.
#[derive(Debug, Default)]
pub(super) struct Handoffs {
    lists: Vec<Mutex<PairList>>,
    reported: Vec<AtomicUsize>,
}

impl Handoffs {
    /// Ready for a pass over `ranges` ranges: nothing reported yet.
    fn start(&mut self, ranges: usize) {
        self.lists.resize_with(ranges * ranges, Default::default);
        self.reported.resize_with(ranges, Default::default);
        for r in &mut self.reported {
            *r.get_mut() = 0;
        }
    }

    /// Range q's hand-off: its pairs (list indices `base..`, ξ, rolling histories and live
    /// flags `history`) whose j lies beyond its end `bounds[q + 1]`, each to the range that
    /// holds its j, then reported to every later range. No pair's j lies more than `span`
    /// past its i, so only the pairs of the range's last `span` bodies are looked at.
    fn hand_off(
        &self,
        (q, bounds, span): (usize, &[usize], usize),
        (pi, pj): (&[u32], &[u32]),
        (base, history): (usize, PairHistory<'_>),
    ) {
        let ranges = bounds.len() - 1;
        let hi = bounds[q + 1];
        let len = history.2.len();
        // Its first pair that could cross, counted from `base`.
        let first = pair_start(&pi[base..base + len], hi.saturating_sub(span));
        let mut outgoing: Vec<MutexGuard<'_, PairList>> = (q + 1..ranges)
            .map(|r| lock(&self.lists[r * ranges + q]))
            .collect();
        for list in &mut outgoing {
            list.i.clear();
            list.j.clear();
            list.history.clear();
        }
        for k in first..len {
            let j = pj[base + k];
            if (j as usize) >= hi {
                // The range of j: the last bound at or below it.
                let r = bounds.partition_point(|&b| b <= j as usize) - 1;
                let list = &mut outgoing[r - q - 1];
                list.i.push(pi[base + k]);
                list.j.push(j);
                list.history.push_stored(history, k);
            }
        }
        drop(outgoing);
        for r in q + 1..ranges {
            self.reported[r].fetch_add(1, Ordering::Release);
        }
    }

    /// Waits until every range before `r` has handed its pairs off.
    fn wait_for(&self, r: usize) {
        crate::team::spin_while(|| self.reported[r].load(Ordering::Acquire) < r, None);
    }
}

/// The list behind `m`, whatever a panicking holder left in it (a panic in a pass is
/// re-raised by the team anyway).
fn lock(m: &Mutex<PairList>) -> MutexGuard<'_, PairList> {
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// What one body range owns for the pass.
struct RangeTask<'a> {
    /// Its first body.
    lo: usize,
    /// Force [N] of its bodies.
    force: &'a mut [DVec3],
    /// Torque [N m] of its bodies.
    torque: &'a mut [DVec3],
    /// Index of its first own pair in the pair list.
    pair_base: usize,
    /// ξ, rolling histories and live flags of its own pairs.
    pairs: (&'a mut [DVec3], &'a mut [DVec3], &'a mut [u8]),
    /// Its wall candidates: for each wall run, the part with its bodies, in list order.
    walls: Vec<WallPiece<'a>>,
    /// Its stretch of each curved, meshed or spinning wall's candidates, when the pass
    /// resolves those walls too (`surfaces`), in wall order.
    surfaces: Vec<surfaces_parallel::WallStretch<'a>>,
}

/// What one range's task found.
#[derive(Default)]
struct RangeResult {
    pair_contacts: usize,
    wall_contacts: usize,
    worst_pair: WorstOverlap,
    worst_wall: WorstOverlap,
    /// Its surface contacts, when the pass resolved them.
    surfaces: Option<surfaces_parallel::RangeResult>,
}

/// [`super::evaluate`] on `pool`, with the curved, meshed and spinning walls' contacts
/// (`surfaces`) resolved in the same tasks, after each range's other contacts, where the
/// laws let the planar walls be resolved in the tasks too: then each body still receives its
/// surface contacts last, and one fork-join less per step. Returns whether it resolved them;
/// otherwise the caller runs the surface pass after it.
pub(super) fn evaluate(
    input: &KernelInput,
    pairs: &mut PairList,
    wall_pairs: &mut WallPairList,
    buffers: &mut ForceBuffers,
    pool: &crate::team::Team,
    elements: &mut [loads::SurfaceLoads],
) -> (Evaluation, bool) {
    let n = input.particles.len();
    let ids = (&pairs.i[..], &pairs.j[..]);
    let ranges = (pool.threads() * RANGES_PER_THREAD)
        .min(n / MIN_RANGE)
        .max(1);
    let bounds = cost_bounds(ids.0, n, ranges, BODY_COST);
    let pair_starts: Vec<usize> = bounds.iter().map(|&b| pair_start(ids.0, b)).collect();
    buffers.ranges.resize_with(ranges, RangeScratch::default);
    buffers.handoffs.start(ranges);
    // A pair's j is at most this far past its i: a range's crossing pairs have i within it
    // of the range's end.
    let span = *buffers.pair_span.get_or_insert_with(|| {
        ids.0
            .iter()
            .zip(ids.1)
            .map(|(&i, &j)| j.saturating_sub(i))
            .max()
            .unwrap_or(0) as usize
    });
    let (tangential, rolling, live) = pairs.history.parts_mut();

    let batched_walls = input.batched();
    let with_surfaces = batched_walls && crate::wall::any_resolved_one_by_one(input.walls);
    wall_probes(input.walls, &mut buffers.wall_probes);
    let WallPairList {
        particle: wall_particles,
        wall: wall_walls,
        history: wall_history,
        surfaces: slots,
    } = wall_pairs;
    let wall_ids = (&wall_particles[..], &wall_walls[..]);
    let mut surface_stretches = if with_surfaces {
        // A wall that began to spin since the last build has no remembered contacts yet.
        slots.resize_with(wall_ids.0.len(), Default::default);
        buffers
            .surface_ranges
            .resize_with(ranges, surfaces::SurfaceScratch::default);
        surfaces_parallel::wall_stretches(input, wall_ids, slots, &bounds)
    } else {
        Vec::new()
    };
    let mut tasks = range_tasks(
        (&bounds, &pair_starts),
        (&mut buffers.force, &mut buffers.torque),
        (tangential, rolling, live),
        batched_walls.then_some({
            let (tangential, _, live) = wall_history.parts_mut();
            (wall_ids, (tangential, live))
        }),
    );
    for (task, stretches) in tasks.iter_mut().zip(surface_stretches.drain(..)) {
        task.surfaces = stretches;
    }
    let bands = surfaces_parallel::element_counts(input, elements);
    let probes = &buffers.wall_probes[..];
    let scratches: Vec<(&mut RangeScratch, Option<&mut surfaces::SurfaceScratch>)> =
        if with_surfaces {
            buffers
                .ranges
                .iter_mut()
                .zip(buffers.surface_ranges.iter_mut().map(Some))
                .collect()
        } else {
            buffers.ranges.iter_mut().map(|r| (r, None)).collect()
        };
    let surface_inputs = (wall_ids.0, &bands[..]);
    let handoffs = (&buffers.handoffs, &bounds[..], span);
    let mut results: Vec<RangeResult> = crate::timing::parallel_region(|| {
        pool.map(
            tasks.into_iter().enumerate().zip(scratches).collect(),
            |((q, task), (scratch, surface_scratch))| {
                let surface = (surface_inputs.0, surface_inputs.1, surface_scratch);
                range_pass(input, (ids, handoffs), probes, (q, task), scratch, surface)
            },
        )
    });

    // Integer sums: the same total in any order (`loads`).
    for r in &buffers.ranges {
        super::loads::merge_loads(&mut buffers.loads, &r.loads);
    }
    let mut count = ContactCount::default();
    let (mut worst_pair, mut worst_wall) = (WorstOverlap::default(), WorstOverlap::default());
    for r in &results {
        count.particle_particle += r.pair_contacts;
        count.particle_wall += r.wall_contacts;
        worst_pair = worst_pair.merge(r.worst_pair);
        worst_wall = worst_wall.merge(r.worst_wall);
    }
    if with_surfaces {
        let surface_results: Vec<surfaces_parallel::RangeResult> = results
            .iter_mut()
            .filter_map(|r| r.surfaces.take())
            .collect();
        let mut sinks = surfaces::SurfaceSinks {
            force: &mut buffers.force,
            torque: &mut buffers.torque,
            loads: &mut buffers.loads,
            quanta: &input.quanta,
            elements,
        };
        let (worst, contacts) =
            surfaces_parallel::merge_ranges(&surface_results, &mut sinks, input.dt);
        count.particle_wall += contacts;
        worst_wall = worst_wall.merge(worst);
    }
    if !batched_walls {
        // Other laws: the walls in one pass after all pairs, in the one-thread order.
        let (force, torque) = (&mut buffers.force, &mut buffers.torque);
        let walls;
        (worst_wall, walls) = wall_loop(
            input,
            wall_ids,
            wall_history.split_mut(),
            &mut buffers.loads,
            |i, cf| {
                force[i] += cf.force;
                torque[i] += cf.torque_i;
            },
        );
        count.particle_wall += walls;
    }
    (
        Evaluation {
            count,
            worst_pair,
            worst_wall,
        },
        with_surfaces,
    )
}

/// The wall candidates' particles and walls, and their ξ and live flags, as the force loop
/// takes them.
type WallList<'a> = ((&'a [u32], &'a [u32]), (&'a mut [DVec3], &'a mut [u8]));

/// Cuts the force and torque buffers at `bounds`, the pair histories at `pair_starts`, and
/// the wall list (when given) into each range's pieces: one per wall run, holding the run's
/// candidates with a particle in the range.
fn range_tasks<'a>(
    (bounds, pair_starts): (&[usize], &[usize]),
    (mut force, mut torque): (&'a mut [DVec3], &'a mut [DVec3]),
    (mut tangential, mut rolling, mut live): (&'a mut [DVec3], &'a mut [DVec3], &'a mut [u8]),
    walls: Option<WallList<'a>>,
) -> Vec<RangeTask<'a>> {
    let mut tasks = Vec::with_capacity(bounds.len() - 1);
    for (w, p) in bounds.windows(2).zip(pair_starts.windows(2)) {
        let len = w[1] - w[0];
        let (f, rest_f) = std::mem::take(&mut force).split_at_mut(len);
        let (t, rest_t) = std::mem::take(&mut torque).split_at_mut(len);
        (force, torque) = (rest_f, rest_t);
        let pairs = p[1] - p[0];
        let (pt, rest_t) = std::mem::take(&mut tangential).split_at_mut(pairs);
        let (pr, rest_r) = std::mem::take(&mut rolling).split_at_mut(pairs);
        let (pl, rest_l) = std::mem::take(&mut live).split_at_mut(pairs);
        (tangential, rolling, live) = (rest_t, rest_r, rest_l);
        tasks.push(RangeTask {
            lo: w[0],
            force: f,
            torque: t,
            pair_base: p[0],
            pairs: (pt, pr, pl),
            walls: Vec::new(),
            surfaces: Vec::new(),
        });
    }
    let Some(((pi, pw), (mut history, mut live))) = walls else {
        return tasks;
    };
    for (wall, runs) in wall_runs(pw) {
        let start = runs.start;
        let run = &pi[runs];
        let mut from = 0;
        for (task, &hi) in tasks.iter_mut().zip(&bounds[1..]) {
            let to = run.partition_point(|&i| (i as usize) < hi);
            let (h, rest) = std::mem::take(&mut history).split_at_mut(to - from);
            history = rest;
            let (l, rest) = std::mem::take(&mut live).split_at_mut(to - from);
            live = rest;
            if to > from {
                task.walls.push(WallPiece {
                    wall: wall as usize,
                    base: start + from,
                    particles: &run[from..to],
                    history: h,
                    live: l,
                });
            }
            from = to;
        }
    }
    tasks
}

/// Hands a range's incoming contacts to it: j's share only.
struct IncomingSink<'s, 'a> {
    acc: &'s mut Accumulator<'a>,
    lo: usize,
}

impl PairSink for IncomingSink<'_, '_> {
    #[inline(always)]
    fn contact(&mut self, _i: usize, j: usize, cf: &ContactForce) {
        self.acc.add_j(j - self.lo, cf);
    }
}

/// Hands a range's own contacts to it: i's share, and j's when j is in the range.
struct OwnSink<'s, 'a> {
    acc: &'s mut Accumulator<'a>,
    lo: usize,
    hi: usize,
    contacts: usize,
}

impl PairSink for OwnSink<'_, '_> {
    #[inline(always)]
    fn contact(&mut self, i: usize, j: usize, cf: &ContactForce) {
        self.contacts += 1;
        self.acc.add_i(i - self.lo, cf);
        if j < self.hi {
            self.acc.add_j(j - self.lo, cf);
        }
    }
}

/// A range's pair histories as handed off: the tangential springs ξ [m], the rolling
/// histories [m] and the live flags of its pairs, in list order.
type PairHistory<'a> = (&'a [DVec3], &'a [DVec3], &'a [u8]);

/// How the ranges share crossing pairs: the hand-off lists, the ranges' body bounds and the
/// farthest any pair's j lies past its i.
type RangeSharing<'a> = (&'a Handoffs, &'a [usize], usize);

/// Body range `q`: its hand-off of crossing pairs to the later ranges, its incoming and own
/// pairs, its wall contacts, then its surface contacts when it has a stretch of them
/// (`surface`: the wall list's particles, each wall's element count and the scratch), onto
/// the weights and zero torques its force arrays start with.
fn range_pass(
    input: &KernelInput,
    (ids, (handoffs, bounds, span)): ((&[u32], &[u32]), RangeSharing<'_>),
    probes: &[WallProbe],
    (q, task): (usize, RangeTask),
    scratch: &mut RangeScratch,
    surface: (&[u32], &[usize], Option<&mut surfaces::SurfaceScratch>),
) -> RangeResult {
    let RangeTask {
        lo,
        force,
        torque,
        pair_base,
        pairs,
        walls,
        surfaces: stretches,
    } = task;
    let hi = lo + force.len();
    scratch.loads.clear();
    scratch.loads.resize(input.walls.len(), LoadSum::default());

    let history = (&*pairs.0, &*pairs.1, &*pairs.2);
    handoffs.hand_off((q, bounds, span), ids, (pair_base, history));
    handoffs.wait_for(q);

    let mut result = RangeResult::default();
    let mut acc = Accumulator::new(&mut *force, &mut *torque);
    let kernel = &mut scratch.kernel;
    // Each earlier range's crossing pairs in turn: together, in list order. Their worst
    // overlap is the owner's to report.
    let ranges = bounds.len() - 1;
    for from in 0..q {
        let mut inc = lock(&handoffs.lists[q * ranges + from]);
        let inc = &mut *inc;
        pair_loop(
            input,
            (&inc.i, &inc.j),
            0,
            inc.history.parts_mut(),
            (&mut kernel.touching, &mut kernel.batch),
            &mut IncomingSink { acc: &mut acc, lo },
        );
    }
    let mut own = OwnSink {
        acc: &mut acc,
        lo,
        hi,
        contacts: 0,
    };
    result.worst_pair = pair_loop(
        input,
        ids,
        pair_base,
        pairs,
        (&mut kernel.touching, &mut kernel.batch),
        &mut own,
    );
    result.pair_contacts = own.contacts;

    if !walls.is_empty() {
        prepare_wall_batch(input, &mut kernel.batch);
        let mut sink = |i: usize, cf: &ContactForce| {
            force[i - lo] += cf.force;
            torque[i - lo] += cf.torque_i;
        };
        (result.worst_wall, result.wall_contacts) = wall_pieces(
            input,
            probes,
            walls,
            (&mut scratch.hits, &mut scratch.touch, &mut kernel.batch),
            &mut scratch.loads,
            &mut sink,
        );
    }
    // Last, as in the one-thread order: the surface contacts of the range's bodies.
    if let (wall_particles, bands, Some(surface_scratch)) = surface {
        let task = surfaces_parallel::RangeTask {
            bodies: lo..hi,
            force,
            torque,
            stretches,
        };
        result.surfaces = Some(surfaces_parallel::range_pass(
            input,
            wall_particles,
            bands,
            &input.quanta,
            task,
            surface_scratch,
        ));
    }
    result
}

#[cfg(test)]
mod tests {
    use super::super::tests::{bits, jumble_input, Jumble};
    use super::*;
    use crate::contact::{RollingLaw, TangentialLaw};

    #[test]
    fn the_handed_off_pairs_are_exactly_those_crossing_into_each_range() {
        // The jumble's lists (random order, so pairs cross every cut) cut into 5 ranges, each
        // range handing its pairs off in turn: each range must receive, in list order,
        // exactly the pairs with i before it and j in it, with their histories, against a
        // search of the whole list, and each must hear from every range before it.
        let jumble = Jumble::new(1, false);
        let (pairs, _) = jumble.lists();
        let ids = (&pairs.i[..], &pairs.j[..]);
        let h = &pairs.history;
        let history = (&h.tangential[..], &h.rolling[..], &h.live[..]);
        let bounds = cost_bounds(ids.0, jumble.set.len(), 5, BODY_COST);
        let starts: Vec<usize> = bounds.iter().map(|&b| pair_start(ids.0, b)).collect();
        let span = ids.0.iter().zip(ids.1).map(|(&i, &j)| j - i).max().unwrap() as usize;
        let mut handoffs = Handoffs::default();
        // Twice, so that lists left by one pass cannot leak into the next.
        for _ in 0..2 {
            handoffs.start(5);
            for q in 0..5 {
                let own = starts[q]..starts[q + 1];
                let mine = (
                    &history.0[own.clone()],
                    &history.1[own.clone()],
                    &history.2[own],
                );
                handoffs.hand_off((q, &bounds, span), ids, (starts[q], mine));
            }
            let mut crossing = 0;
            for r in 0..5 {
                assert_eq!(handoffs.reported[r].load(Ordering::Acquire), r);
                let (lo, hi) = (bounds[r], bounds[r + 1]);
                let want: Vec<usize> = (0..pairs.len())
                    .filter(|&k| {
                        (ids.0[k] as usize) < lo && (lo..hi).contains(&(ids.1[k] as usize))
                    })
                    .collect();
                crossing += want.len();
                let (mut gi, mut gj, mut gt, mut gl) = (vec![], vec![], vec![], vec![]);
                for q in 0..r {
                    let got = lock(&handoffs.lists[r * 5 + q]);
                    gi.extend_from_slice(&got.i);
                    gj.extend_from_slice(&got.j);
                    gt.extend_from_slice(&got.history.tangential);
                    gl.extend_from_slice(&got.history.live);
                }
                let pick = |a: &[u32]| want.iter().map(|&k| a[k]).collect::<Vec<u32>>();
                assert_eq!((gi, gj), (pick(ids.0), pick(ids.1)), "range {r}");
                let t: Vec<DVec3> = want.iter().map(|&k| history.0[k]).collect();
                let l: Vec<u8> = want.iter().map(|&k| history.2[k]).collect();
                assert_eq!((gt, gl), (t, l), "range {r}");
            }
            assert!(crossing > 100, "pairs must cross the cuts: {crossing}");
        }
    }

    #[test]
    fn several_threads_give_the_one_thread_sums_bit_for_bit() {
        // The jumble (planes, a tilted polygon, a removed wall, spinning spheres, random ξ)
        // evaluated on 1, 2, 3 and 5 threads (as many ranges, cut by cost): forces,
        // torques, histories, counts and worst overlaps must be the same bits. Exact
        // equality: the several-thread passes promise the same additions in the same order. Both the paper's laws (the batched wall
        // pass, split by range) and other laws (the scalar wall loop after the ranges), one
        // and two materials, equal and unequal spheres; and twice in a row, so that scratch
        // left by one evaluation cannot leak into the next.
        let other = crate::contact::ContactLaws {
            normal_clamp: true,
            tangential: TangentialLaw::default(),
            rolling: RollingLaw::Epsd {
                viscous_damping: 0.3,
            },
        };
        let pools: Vec<crate::team::Team> = [2, 3, 5]
            .iter()
            .map(|&t| crate::team::Team::new(t).expect("a pool"))
            .collect();
        for laws in [crate::contact::ContactLaws::default(), other] {
            for (materials, poly) in [(1, false), (2, true)] {
                let jumble = Jumble::new(materials, poly);
                let input = jumble_input(&jumble, &laws);
                let (pairs, walls) = jumble.lists();
                let run = |pool: Option<&crate::team::Team>| {
                    let (mut p, mut w) = (pairs.clone(), walls.clone());
                    let mut buffers = ForceBuffers::default();
                    let mut all = Vec::new();
                    for _ in 0..2 {
                        super::super::start(&jumble.set, jumble.gravity, &mut buffers);
                        let eval = super::super::evaluate(
                            &input,
                            &mut p,
                            &mut w,
                            &mut buffers,
                            pool,
                            &mut [],
                        );
                        assert!(
                            eval.count.particle_particle > 100 && eval.count.particle_wall > 10
                        );
                        all.extend(bits(&buffers, &p, &w, &eval));
                    }
                    if pool.is_some() {
                        // The jumble's order is random, so pairs cross every cut: the
                        // comparison covers the incoming pairs resolved twice.
                        let crossing: usize =
                            buffers.handoffs.lists.iter().map(|l| lock(l).i.len()).sum();
                        assert!(buffers.ranges.len() >= 2 && crossing > 50, "{crossing}");
                    }
                    all
                };
                let one = run(None);
                for pool in &pools {
                    assert!(
                        one == run(Some(pool)),
                        "{} threads, {laws:?}, {materials} materials",
                        pool.threads()
                    );
                }
            }
        }
    }
}
