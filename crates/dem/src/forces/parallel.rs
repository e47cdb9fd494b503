//! Force evaluation on several threads, bit-identical to the one-thread path.
//!
//! Two parallel passes:
//! 1. **Pair chunks.** The kernel runs over fixed chunks of the candidate list. Each chunk
//!    keeps its touching contacts' forces, in pair order.
//! 2. **Body ranges.** The particles are cut into contiguous index ranges. Each range's task
//!    writes gravity into its bodies, adds their shares of the kept pair forces, then filters,
//!    resolves and adds their wall contacts. No two tasks write the same body or history.
//!
//! Every body receives the additions of the one-thread path, in the same order:
//! - gravity first;
//! - then its pairs. The list holds i < j, sorted by i, so the contacts in which a body is j
//!   all come before its own run as i. The one-thread [`Accumulator`] subtracts those one by
//!   one, then adds the run's register sum when the run ends; a range does the same;
//! - then its walls, in increasing wall order (the list is wall-major).
//!
//! So the sums, and the whole trajectory, do not depend on the thread count.

use super::*;
use crate::ranges::even_bounds;
use rayon::prelude::*;

/// Pairs per task of the first pass. Small, so that the threads finish it within a few
/// microseconds of each other: a rayon worker left idle for longer goes to sleep, and waking
/// it costs about as much as such a task.
const CHUNK: usize = 512;

/// Ranges per pool thread in the second pass: more than one lets the pool balance ranges of
/// unequal cost (the bed's bodies have more contacts than the falling ones').
const RANGES_PER_THREAD: usize = 8;

/// Bodies per range, at least: each range also reads the contacts just below it (those whose
/// j it owns), about one cell row of the list, which must stay small beside its own.
const MIN_RANGE: usize = 128;

/// Scratch of one body range, reused from step to step.
#[derive(Debug, Default)]
pub(super) struct RangeScratch {
    /// Indices of the touching wall candidates of one piece.
    hits: Vec<u32>,
    /// Whether each wall candidate of a piece touches (1) or not (0).
    touch: Vec<u8>,
    /// The batch its wall contacts are resolved in.
    batch: Box<Batch>,
}

/// What one body range owns for the second pass.
struct RangeTask<'a> {
    /// Its first body.
    lo: usize,
    /// Force [N] of its bodies.
    force: &'a mut [DVec3],
    /// Torque [N m] of its bodies.
    torque: &'a mut [DVec3],
    /// Its wall candidates: for each wall run, the part with its bodies, in list order.
    walls: Vec<WallPiece<'a>>,
}

/// The candidates of one wall whose particles lie in one body range.
struct WallPiece<'a> {
    /// The wall's index.
    wall: usize,
    /// Index of the piece's first candidate in the whole wall list.
    base: usize,
    particles: &'a [u32],
    /// Their ξ and live flags (`HistoryArrays`).
    history: &'a mut [DVec3],
    live: &'a mut [u8],
}

/// [`super::evaluate`] on `pool`.
pub(super) fn evaluate(
    input: &KernelInput,
    pairs: &mut PairList,
    wall_pairs: &mut WallPairList,
    gravity: DVec3,
    buffers: &mut ForceBuffers,
    pool: &rayon::ThreadPool,
) -> Evaluation {
    let n = input.particles.len();
    let ids = (&pairs.i[..], &pairs.j[..]);
    let chunks = pairs.len().div_ceil(CHUNK);
    buffers.chunks.resize_with(chunks, ChunkScratch::default);

    // Pass 1: pair chunks.
    let (tangential, rolling, live) = pairs.history.parts_mut();
    let scratch = &mut buffers.chunks;
    let worst_pair = pool.install(|| {
        tangential
            .par_chunks_mut(CHUNK)
            .zip(rolling.par_chunks_mut(CHUNK))
            .zip(live.par_chunks_mut(CHUNK))
            .zip(scratch.par_iter_mut())
            .enumerate()
            // One chunk per task: the balance of the pass's end matters more than the
            // cost of a task.
            .with_max_len(1)
            .map(|(c, (((t, r), l), scratch))| {
                let out = &mut scratch.out;
                out.clear();
                let worst = pair_loop(
                    input,
                    ids,
                    c * CHUNK,
                    (t, r, l),
                    (&mut scratch.touching, &mut scratch.batch),
                    out,
                );
                scratch.reach.clear();
                scratch
                    .reach
                    .extend(out.iter().scan(0, |reach, &(_, j, _)| {
                        *reach = j.max(*reach);
                        Some(*reach)
                    }));
                worst
            })
            .reduce(WorstOverlap::default, WorstOverlap::merge)
    });

    // Pass 2: body ranges.
    let bounds = even_bounds(n, pool.current_num_threads(), RANGES_PER_THREAD, MIN_RANGE);
    let ranges = bounds.len() - 1;
    // Every number is overwritten by the ranges; only the length matters.
    buffers.force.resize(n, DVec3::ZERO);
    buffers.torque.resize(n, DVec3::ZERO);
    let batched_walls = *input.laws == ContactLaws::default();
    wall_probes(input.walls, &mut buffers.wall_probes);
    let wall_ids = (&wall_pairs.particle[..], &wall_pairs.wall[..]);
    let tasks = range_tasks(
        &bounds,
        (&mut buffers.force, &mut buffers.torque),
        batched_walls.then_some({
            let (tangential, _, live) = wall_pairs.history.parts_mut();
            (wall_ids, (tangential, live))
        }),
    );
    buffers.ranges.resize_with(ranges, RangeScratch::default);
    let (outs, probes) = (&buffers.chunks[..chunks], &buffers.wall_probes[..]);
    let results: Vec<(usize, WorstOverlap)> = pool.install(|| {
        tasks
            .into_par_iter()
            .zip(buffers.ranges.par_iter_mut())
            .with_max_len(1)
            .map(|(task, scratch)| range_pass(input, gravity, outs, probes, task, scratch))
            .collect()
    });

    let mut count = ContactCount {
        particle_particle: outs.iter().map(|c| c.out.len()).sum(),
        particle_wall: 0,
    };
    let mut worst_wall = WorstOverlap::default();
    for (contacts, worst) in results {
        count.particle_wall += contacts;
        worst_wall = worst_wall.merge(worst);
    }
    if !batched_walls {
        // Other laws: the walls in one pass after all pairs, in the one-thread order.
        let (force, torque) = (&mut buffers.force, &mut buffers.torque);
        worst_wall = wall_loop(input, wall_ids, wall_pairs.history.split_mut(), |i, cf| {
            force[i] += cf.force;
            torque[i] += cf.torque_i;
            count.particle_wall += 1;
        });
    }
    Evaluation {
        count,
        worst_pair,
        worst_wall,
    }
}

/// The wall candidates' particles and walls, and their ξ and live flags, as the force loop
/// takes them.
type WallList<'a> = ((&'a [u32], &'a [u32]), (&'a mut [DVec3], &'a mut [u8]));

/// Cuts the force and torque buffers at `bounds`, and the wall list (when given) into each
/// range's pieces: one per wall run, holding the run's candidates with a particle in the range.
fn range_tasks<'a>(
    bounds: &[usize],
    (mut force, mut torque): (&'a mut [DVec3], &'a mut [DVec3]),
    walls: Option<WallList<'a>>,
) -> Vec<RangeTask<'a>> {
    let mut tasks = Vec::with_capacity(bounds.len() - 1);
    for w in bounds.windows(2) {
        let len = w[1] - w[0];
        let (f, rest_f) = std::mem::take(&mut force).split_at_mut(len);
        let (t, rest_t) = std::mem::take(&mut torque).split_at_mut(len);
        (force, torque) = (rest_f, rest_t);
        tasks.push(RangeTask {
            lo: w[0],
            force: f,
            torque: t,
            walls: Vec::new(),
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

/// One body range: gravity, its shares of the pair forces, its wall contacts. Returns its
/// wall contacts and their worst overlap.
fn range_pass(
    input: &KernelInput,
    gravity: DVec3,
    outs: &[ChunkScratch],
    probes: &[WallProbe],
    task: RangeTask,
    scratch: &mut RangeScratch,
) -> (usize, WorstOverlap) {
    let RangeTask {
        lo,
        force,
        torque,
        walls,
    } = task;
    let hi = lo + force.len();
    // The same product as the one-thread path's.
    for (f, &m) in force.iter_mut().zip(&input.particles.mass[lo..hi]) {
        *f = m * gravity;
    }
    torque.fill(DVec3::ZERO);

    let mut acc = Accumulator::new(&mut *force, &mut *torque);
    'chunks: for chunk in outs {
        // Contacts before `first` have j < lo, and i < j: none of this range's bodies.
        let first = chunk.reach.partition_point(|&j| (j as usize) < lo);
        for (i, j, cf) in &chunk.out[first..] {
            let (i, j) = (*i as usize, *j as usize);
            if i >= hi {
                // Sorted by i: every later contact belongs to later bodies.
                break 'chunks;
            }
            if i >= lo {
                acc.add_i(i - lo, cf);
            }
            if (lo..hi).contains(&j) {
                acc.add_j(j - lo, cf);
            }
        }
    }
    acc.finish();

    let mut worst = WorstOverlap::default();
    let mut contacts = 0;
    if walls.is_empty() {
        return (contacts, worst);
    }
    prepare_wall_batch(input, &mut scratch.batch);
    let mut sink = |i: usize, cf: &ContactForce| {
        force[i - lo] += cf.force;
        torque[i - lo] += cf.torque_i;
        contacts += 1;
    };
    for piece in walls {
        let len = piece.particles.len();
        // Only grown, never cleared, as in `batched_wall_loop`.
        if scratch.hits.len() < len {
            scratch.hits.resize(len, 0);
            scratch.touch.resize(len, 0);
        }
        let run = WallRun {
            probe: probes[piece.wall],
            index: piece.wall,
            base: piece.base,
        };
        wall_run(
            input,
            &run,
            piece.particles,
            (piece.history, piece.live),
            (
                &mut scratch.hits[..len],
                &mut scratch.touch[..len],
                &mut scratch.batch,
            ),
            &mut worst,
            &mut sink,
        );
    }
    (contacts, worst)
}

#[cfg(test)]
mod tests {
    use super::super::tests::{jumble_input, Jumble};
    use super::*;
    use crate::contact::{RollingLaw, TangentialLaw};

    /// Everything an evaluation leaves behind, as bits.
    fn bits(
        buffers: &ForceBuffers,
        pairs: &PairList,
        walls: &WallPairList,
        eval: &Evaluation,
    ) -> Vec<u64> {
        let histories = pairs.history.iter().chain(walls.history.iter());
        let vectors = buffers
            .force
            .iter()
            .copied()
            .chain(buffers.torque.iter().copied())
            .chain(histories.flat_map(|h| [h.tangential, h.rolling]));
        let mut out: Vec<u64> = vectors
            .flat_map(|v| v.to_array().map(f64::to_bits))
            .collect();
        out.extend([
            eval.count.particle_particle as u64,
            eval.count.particle_wall as u64,
            eval.worst_pair.index as u64,
            eval.worst_pair.fraction.to_bits(),
            eval.worst_wall.index as u64,
            eval.worst_wall.fraction.to_bits(),
        ]);
        out
    }

    #[test]
    fn several_threads_give_the_one_thread_sums_bit_for_bit() {
        // The jumble (planes, a tilted polygon, a removed wall, spinning spheres, random ξ)
        // evaluated on 1, 2, 3 and 5 threads: forces, torques, histories, counts and worst
        // overlaps must be the same bits. Exact equality: the several-thread passes promise
        // the same additions in the same order. Both the paper's laws (the batched wall
        // pass, split by range) and other laws (the scalar wall loop after the ranges), one
        // and two materials, equal and unequal spheres; and twice in a row, so that scratch
        // left by one evaluation cannot leak into the next.
        let other = ContactLaws {
            normal_clamp: true,
            tangential: TangentialLaw::default(),
            rolling: RollingLaw::Epsd {
                viscous_damping: 0.3,
            },
        };
        let pools: Vec<rayon::ThreadPool> = [2, 3, 5]
            .iter()
            .map(|&t| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(t)
                    .build()
                    .expect("a pool")
            })
            .collect();
        for laws in [ContactLaws::default(), other] {
            for (materials, poly) in [(1, false), (2, true)] {
                let jumble = Jumble::new(materials, poly);
                let input = jumble_input(&jumble, &laws);
                let (pairs, walls) = jumble.lists();
                let run = |pool: Option<&rayon::ThreadPool>| {
                    let (mut p, mut w) = (pairs.clone(), walls.clone());
                    let mut buffers = ForceBuffers::default();
                    let mut all = Vec::new();
                    for _ in 0..2 {
                        let eval = super::super::evaluate(
                            &input,
                            &mut p,
                            &mut w,
                            jumble.gravity,
                            &mut buffers,
                            pool,
                        );
                        assert!(
                            eval.count.particle_particle > 100 && eval.count.particle_wall > 10
                        );
                        all.extend(bits(&buffers, &p, &w, &eval));
                    }
                    all
                };
                let one = run(None);
                for pool in &pools {
                    assert!(
                        one == run(Some(pool)),
                        "{} threads, {laws:?}, {materials} materials",
                        pool.current_num_threads()
                    );
                }
            }
        }
    }
}
