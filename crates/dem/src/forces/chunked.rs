//! The one-thread evaluation cut into chunks of bodies, so that each chunk can be moved on
//! as soon as its forces are whole.
//!
//! A chunk is a contiguous range of bodies. Its part of the evaluation is its own pairs
//! (those whose i lies in it) and then its bodies' wall contacts. Visited in order from the
//! first body to the last, the chunks give every body the additions of [`super::evaluate`],
//! in the same order: its weight, its pairs in list order, its walls in increasing wall
//! order. The list holds i < j sorted by i, so the pairs in which a body is j belong to its
//! own chunk or to earlier ones, and none of a later chunk's pairs or walls reaches it.
//!
//! So once a chunk is done, its bodies' forces and torques are final, and nothing later in
//! the evaluation reads their positions, velocities or spins: the caller may kick and drift
//! them at once (`Simulation` does, for systems beyond the caches). Their numbers are then
//! still in the cache, where a separate pass after the evaluation would stream every body
//! from memory a second time.

use glam::DVec3;
use std::ops::Range;

use super::accumulator::Accumulator;
use super::loads::LoadSum;
use super::walls::{prepare_wall_batch, wall_pieces, wall_probes, wall_runs, WallPiece};
use super::{add_surface_contacts, pair_loop, ContactCount, Evaluation, ForceBuffers, KernelInput};
use crate::contact::ContactForce;
use crate::neighbour::{PairList, WallPairList};
use crate::ranges::pair_start;

/// Bodies per chunk. About 150 bytes each (position, velocity, spin, force, torque, list
/// reference) make about 300 kB: the chunk stays in the second-level cache while its pairs
/// and their partners stream through, and the fixed cost of a chunk (two searches, the
/// batch set-up, a search per wall) is spread over thousands of contacts. Smaller in the
/// tests, so that their few hundred bodies are cut into many chunks.
pub(crate) const CHUNK_BODIES: usize = if cfg!(test) { 48 } else { 16384 };

/// The bounds of the chunks of `n` bodies: 0, [`CHUNK_BODIES`], 2 [`CHUNK_BODIES`], …, n.
pub(crate) fn chunk_bounds(n: usize) -> impl Iterator<Item = Range<usize>> {
    (0..n.div_ceil(CHUNK_BODIES)).map(move |c| c * CHUNK_BODIES..((c + 1) * CHUNK_BODIES).min(n))
}

/// Evaluates the pairs whose i lies in `bodies`, then the wall contacts of `bodies`,
/// updating their histories and adding to `buffers.force` and `buffers.torque` (whole
/// arrays, indexed by body), as [`super::evaluate`] does for all bodies on one thread.
/// Only for the paper's laws (the batched wall loop).
pub(crate) fn evaluate_chunk(
    input: &KernelInput,
    pairs: &mut PairList,
    wall_pairs: &mut WallPairList,
    buffers: &mut ForceBuffers,
    bodies: Range<usize>,
    elements: &mut [super::loads::SurfaceLoads],
) -> Evaluation {
    assert!(
        input.batched(),
        "chunked evaluation needs the batched wall loop of the paper's laws"
    );
    let n = input.particles.len();
    assert!(
        buffers.force.len() == n && buffers.torque.len() == n && bodies.end <= n,
        "the force buffers hold one starting value per body"
    );
    buffers.loads.resize(input.walls.len(), LoadSum::default());
    let ids = (&pairs.i[..], &pairs.j[..]);
    let own = pair_start(ids.0, bodies.start)..pair_start(ids.0, bodies.end);
    let (tangential, rolling, live) = pairs.history.parts_mut();
    let history = (
        &mut tangential[own.clone()],
        &mut rolling[own.clone()],
        &mut live[own.clone()],
    );
    let scratch = &mut buffers.kernel;
    let mut acc = Accumulator::new(&mut buffers.force, &mut buffers.torque);
    let worst_pair = pair_loop(
        input,
        ids,
        own.start,
        history,
        (&mut scratch.touching, &mut scratch.batch),
        &mut acc,
    );
    let particle_particle = acc.contacts;

    wall_probes(input.walls, &mut buffers.wall_probes);
    prepare_wall_batch(input, &mut scratch.batch);
    let (tangential, _, live) = wall_pairs.history.parts_mut();
    let pieces = pieces_in(
        (&wall_pairs.particle, &wall_pairs.wall),
        (tangential, live),
        bodies.clone(),
    );
    let (worst_wall, particle_wall) = wall_pieces(
        input,
        &buffers.wall_probes,
        pieces,
        (
            &mut buffers.wall_hits,
            &mut buffers.wall_touch,
            &mut scratch.batch,
        ),
        &mut buffers.loads,
        // A wall contact has only the particle's share: F and M_i.
        &mut |i: usize, cf: &ContactForce| acc.add_i(i, cf),
    );
    let mut eval = Evaluation {
        count: ContactCount {
            particle_particle,
            particle_wall,
        },
        worst_pair,
        worst_wall,
    };
    // The chunk's contacts with curved, meshed and spinning walls, after its others, as
    // the whole evaluation adds them.
    add_surface_contacts(
        &mut eval, input, wall_pairs, buffers, elements, bodies, None,
    );
    eval
}

/// The candidates of a wall-major list (`pi`, `pw`) whose particle lies in `bodies`: one
/// piece per wall run that has some, in list order, each with its ξ and live flags.
fn pieces_in<'a>(
    (pi, pw): (&'a [u32], &[u32]),
    (mut history, mut live): (&'a mut [DVec3], &'a mut [u8]),
    bodies: Range<usize>,
) -> Vec<WallPiece<'a>> {
    let mut pieces = Vec::new();
    // Candidates before `history` and `live`'s first, cut off as the pieces are taken.
    let mut taken = 0;
    for (wall, run) in wall_runs(pw) {
        let ids = &pi[run.clone()];
        let from = run.start + ids.partition_point(|&i| (i as usize) < bodies.start);
        let to = run.start + ids.partition_point(|&i| (i as usize) < bodies.end);
        if to == from {
            continue;
        }
        let (_, rest) = std::mem::take(&mut history).split_at_mut(from - taken);
        let (h, rest) = rest.split_at_mut(to - from);
        history = rest;
        let (_, rest) = std::mem::take(&mut live).split_at_mut(from - taken);
        let (l, rest) = rest.split_at_mut(to - from);
        live = rest;
        taken = to;
        pieces.push(WallPiece {
            wall: wall as usize,
            base: from,
            particles: &pi[from..to],
            history: h,
            live: l,
        });
    }
    pieces
}

impl Evaluation {
    /// Both evaluations' findings: counts added, the worse overlaps kept (ties to the lower
    /// list index, as one pass over the lists finds them).
    pub(crate) fn merge(self, other: Self) -> Self {
        Self {
            count: ContactCount {
                particle_particle: self.count.particle_particle + other.count.particle_particle,
                particle_wall: self.count.particle_wall + other.count.particle_wall,
            },
            worst_pair: self.worst_pair.merge(other.worst_pair),
            worst_wall: self.worst_wall.merge(other.worst_wall),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{bits, jumble_input, Jumble};
    use super::*;

    #[test]
    fn chunks_in_order_give_the_one_pass_sums_bit_for_bit() {
        // The jumble (planes, a tilted polygon, a removed wall, spinning spheres, random ξ;
        // random order, so that pairs cross every chunk boundary) evaluated in one pass and
        // in chunks of CHUNK_BODIES bodies, twice in a row each: forces, torques, histories,
        // counts and worst overlaps must be the same bits. Exact equality: the chunks
        // promise each body the same additions in the same order. One and two materials,
        // equal and unequal spheres.
        let laws = crate::contact::ContactLaws::default();
        for (materials, poly) in [(1, false), (2, true)] {
            let jumble = Jumble::new(materials, poly);
            let input = jumble_input(&jumble, &laws);
            let (pairs, walls) = jumble.lists();
            let n = jumble.set.len();
            let start = |buffers: &mut ForceBuffers| {
                super::super::start(&jumble.set, jumble.gravity, buffers);
            };

            let (mut p, mut w) = (pairs.clone(), walls.clone());
            let mut buffers = ForceBuffers::default();
            let mut whole = Vec::new();
            for _ in 0..2 {
                start(&mut buffers);
                let eval =
                    super::super::evaluate(&input, &mut p, &mut w, &mut buffers, None, &mut []);
                assert!(eval.count.particle_particle > 100 && eval.count.particle_wall > 10);
                whole.extend(bits(&buffers, &p, &w, &eval));
            }

            let (mut p, mut w) = (pairs.clone(), walls.clone());
            let mut buffers = ForceBuffers::default();
            let mut chunked = Vec::new();
            let chunks: Vec<Range<usize>> = chunk_bounds(n).collect();
            assert!(chunks.len() >= 8, "{} chunks of {n} bodies", chunks.len());
            // Pairs whose j lies in a later chunk than their i: those the order must carry.
            let crossing = (0..pairs.len())
                .filter(|&k| {
                    pairs.i[k] as usize / CHUNK_BODIES != pairs.j[k] as usize / CHUNK_BODIES
                })
                .count();
            assert!(crossing > 100, "{crossing} pairs cross a chunk boundary");
            for _ in 0..2 {
                start(&mut buffers);
                let eval = chunks
                    .iter()
                    .map(|c| {
                        evaluate_chunk(&input, &mut p, &mut w, &mut buffers, c.clone(), &mut [])
                    })
                    .reduce(Evaluation::merge)
                    .expect("some chunks");
                chunked.extend(bits(&buffers, &p, &w, &eval));
            }
            assert!(whole == chunked, "{materials} materials");
        }
    }

    #[test]
    fn chunk_bounds_cover_every_body_once_in_order() {
        // Adjoining, increasing, none empty, all but the last CHUNK_BODIES long.
        for n in [0, 1, CHUNK_BODIES - 1, CHUNK_BODIES, 5 * CHUNK_BODIES + 7] {
            let chunks: Vec<Range<usize>> = chunk_bounds(n).collect();
            let mut next = 0;
            for (k, c) in chunks.iter().enumerate() {
                assert_eq!(c.start, next);
                assert!(!c.is_empty());
                assert!(c.len() == CHUNK_BODIES || k + 1 == chunks.len());
                next = c.end;
            }
            assert_eq!(next, n);
        }
    }
}
