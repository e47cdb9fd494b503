//! Force evaluation on several threads, bit-identical to the one-thread path.
//!
//! One parallel pass. The particles are cut into contiguous index ranges of about equal
//! cost, and each range's task, alone, computes every force on its bodies:
//! 1. its bodies start from their weights and zero torques (the integrator's pass wrote them);
//! 2. its **incoming** pairs, those whose i lies before the range and whose j lies in it.
//!    They belong to an earlier range, which resolves them too, as its own. This task
//!    resolves them again from copies of their histories taken before the pass, and keeps
//!    only j's share. The kernel gives the same bits for the same inputs, so both sides of a
//!    pair see one force; only the owner writes the new history;
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

/// Pairs to scan for the incoming copies, over all ranges, from which the copies are made in
/// parallel: below it a parallel pass costs more than it saves. On two threads (four ranges)
/// the paper's hopper scans 300–400 pairs per step, the dense packings of 10^4, 10^5 and 10^6
/// spheres about 8 400, 39 000 and 179 000; the scan grows with the number of ranges.
const PARALLEL_COPY: usize = 1 << 15;

/// Scratch of one body range, reused from step to step.
#[derive(Debug, Default)]
pub(super) struct RangeScratch {
    /// Indices of the touching wall candidates of one piece.
    hits: Vec<u32>,
    /// Whether each wall candidate of a piece touches (1) or not (0).
    touch: Vec<u8>,
    /// Its pair filter's hits and the batch its pair and wall contacts are resolved in.
    kernel: KernelScratch,
    /// The incoming pairs (resolved for j's share only), in list order, with copies of their
    /// histories, live flags included, as they were before the pass.
    incoming: PairList,
    /// The walls' loads from this range's wall contacts, in fixed point.
    loads: Vec<LoadSum>,
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

    // The incoming pairs' histories, copied before any task rewrites them.
    let (tangential, rolling, live) = pairs.history.parts_mut();
    copy_all_incoming(
        ids,
        (&*tangential, &*rolling, &*live),
        (&bounds, &pair_starts),
        &mut buffers.ranges,
        (pool, PARALLEL_COPY),
    );

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
    let mut results: Vec<RangeResult> = crate::timing::parallel_region(|| {
        pool.map(
            tasks.into_iter().zip(scratches).collect(),
            |(task, (scratch, surface_scratch))| {
                let surface = (surface_inputs.0, surface_inputs.1, surface_scratch);
                range_pass(input, ids, probes, task, scratch, surface)
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

/// Fills each range's incoming pairs (`scratch[r].incoming` for the range from `bounds[r]`,
/// whose own pairs start at `pair_starts[r]`): in parallel on `pool` when there are at least
/// `parallel_from` pairs to scan ([`PARALLEL_COPY`]), otherwise on this thread. The same
/// copies either way.
fn copy_all_incoming(
    ids: (&[u32], &[u32]),
    history: (&[DVec3], &[DVec3], &[u8]),
    (bounds, pair_starts): (&[usize], &[usize]),
    scratch: &mut [RangeScratch],
    (pool, parallel_from): (&crate::team::Team, usize),
) {
    let span = ids
        .0
        .iter()
        .zip(ids.1)
        .map(|(&i, &j)| j.saturating_sub(i))
        .max()
        .unwrap_or(0) as usize;
    // A pair with j ≥ lo and i < lo has i ≥ lo − span: each range scans that window.
    let windows: Vec<std::ops::Range<usize>> = bounds
        .iter()
        .zip(pair_starts)
        .take(scratch.len())
        .map(|(&lo, &start)| pair_start(ids.0, lo.saturating_sub(span))..start)
        .collect();
    let copy = |r: usize, s: &mut RangeScratch| {
        let range = (bounds[r], bounds[r + 1]);
        copy_incoming(ids, history, range, windows[r].clone(), &mut s.incoming)
    };
    if windows.iter().map(|w| w.len()).sum::<usize>() < parallel_from {
        scratch.iter_mut().enumerate().for_each(|(r, s)| copy(r, s));
    } else {
        crate::timing::parallel_region(|| {
            pool.map(scratch.iter_mut().enumerate().collect(), |(r, s)| {
                copy(r, s)
            })
        });
    }
}

/// Copies into `inc` the pairs of `window` (list indices) whose j lies in `lo..hi`, with
/// their histories, in list order.
fn copy_incoming(
    (pi, pj): (&[u32], &[u32]),
    history: (&[DVec3], &[DVec3], &[u8]),
    (lo, hi): (usize, usize),
    window: std::ops::Range<usize>,
    inc: &mut PairList,
) {
    inc.i.clear();
    inc.j.clear();
    inc.history.clear();
    for k in window {
        let j = pj[k];
        if (lo..hi).contains(&(j as usize)) {
            inc.i.push(pi[k]);
            inc.j.push(j);
            inc.history.push_stored(history, k);
        }
    }
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

/// One body range: its incoming and own pairs, its wall contacts, then its surface contacts
/// when it has a stretch of them (`surface`: the wall list's particles, each wall's element
/// count and the scratch),
/// onto the weights and zero torques its force arrays start with.
fn range_pass(
    input: &KernelInput,
    ids: (&[u32], &[u32]),
    probes: &[WallProbe],
    task: RangeTask,
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

    let mut result = RangeResult::default();
    let mut acc = Accumulator::new(&mut *force, &mut *torque);
    let inc = &mut scratch.incoming;
    let kernel = &mut scratch.kernel;
    // Its worst overlap is the owner's to report.
    pair_loop(
        input,
        (&inc.i, &inc.j),
        0,
        inc.history.parts_mut(),
        (&mut kernel.touching, &mut kernel.batch),
        &mut IncomingSink { acc: &mut acc, lo },
    );
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
    fn incoming_pairs_are_exactly_those_crossing_into_each_range_serial_or_parallel() {
        // The jumble's lists (random order, so pairs cross every cut) cut into 5 ranges: each
        // range must receive, in list order, exactly the pairs with i before it and j in it,
        // with their histories, against a search of the whole list; from the serial copy
        // (threshold above any scan) and from the parallel one (threshold 0).
        let jumble = Jumble::new(1, false);
        let (pairs, _) = jumble.lists();
        let ids = (&pairs.i[..], &pairs.j[..]);
        let h = &pairs.history;
        let history = (&h.tangential[..], &h.rolling[..], &h.live[..]);
        let bounds = cost_bounds(ids.0, jumble.set.len(), 5, BODY_COST);
        let starts: Vec<usize> = bounds.iter().map(|&b| pair_start(ids.0, b)).collect();
        let pool = crate::team::Team::new(2).expect("a pool");
        for parallel_from in [usize::MAX, 0] {
            let mut scratch: Vec<RangeScratch> = (0..5).map(|_| RangeScratch::default()).collect();
            copy_all_incoming(
                ids,
                history,
                (&bounds, &starts),
                &mut scratch,
                (&pool, parallel_from),
            );
            let mut crossing = 0;
            for (r, got) in scratch.iter().map(|s| &s.incoming).enumerate() {
                let (lo, hi) = (bounds[r], bounds[r + 1]);
                let want: Vec<usize> = (0..pairs.len())
                    .filter(|&k| {
                        (ids.0[k] as usize) < lo && (lo..hi).contains(&(ids.1[k] as usize))
                    })
                    .collect();
                crossing += want.len();
                let pick = |a: &[u32]| want.iter().map(|&k| a[k]).collect::<Vec<u32>>();
                assert_eq!((got.i.clone(), got.j.clone()), (pick(ids.0), pick(ids.1)));
                let t: Vec<DVec3> = want.iter().map(|&k| history.0[k]).collect();
                let l: Vec<u8> = want.iter().map(|&k| history.2[k]).collect();
                let copied = (&got.history.tangential, &got.history.live);
                assert_eq!(copied, (&t, &l), "range {r}");
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
                            buffers.ranges.iter().map(|r| r.incoming.i.len()).sum();
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
