//! The paper's laws over particle–particle candidates: the touching ones gathered into
//! batches, resolved by the vectorised kernel (`forces::kernel`) and handed on in pair order.

use glam::DVec3;

use super::filter::{filter_touching, settle_bond};
use super::kernel::{Batch, BATCH};
use super::{gather, prefetch, KernelInput, PairSink, WorstOverlap, PREFETCH_BODIES};
use crate::contact::cohesion::{LAW_DRY, OUTCOME_APART};
use crate::contact::ContactForce;
use crate::material::PairCoefficients;

/// The coefficients every contact shares when there is one material.
pub(super) fn uniform_coefficients(
    c: &[PairCoefficients],
    materials: usize,
) -> Option<&PairCoefficients> {
    (materials == 1).then(|| &c[0])
}

/// The result of slot `m` of a resolved batch.
#[inline(always)]
pub(super) fn batch_force(batch: &Batch, m: usize) -> ContactForce {
    let v = |a: &[[f64; BATCH]; 3]| DVec3::new(a[0][m], a[1][m], a[2][m]);
    ContactForce {
        force: v(&batch.force),
        torque_i: v(&batch.torque_i),
        torque_j: v(&batch.torque_j),
    }
}

/// The paper's laws over structure-of-arrays batches, in two passes.
///
/// 1. A branch-free filter lists the touching candidates and marks which are live (docs/physics.md
///    §3.1: a contact that opens forgets its ξ; `HistoryArrays` explains the flags). About
///    half the candidates are not touching, and a branch on it is mispredicted about as often.
/// 2. The touching pairs are gathered [`BATCH`] at a time (ξ, or zero for a contact that was
///    not live), resolved together, and handed to `sink` in pair order.
#[inline(always)]
pub(super) fn batched_pair_loop(
    input: &KernelInput,
    (pi, pj): (&[u32], &[u32]),
    base: usize,
    (history, live): (&mut [DVec3], &mut [u8]),
    (touching, batch): (&mut Vec<u32>, &mut Batch),
    sink: &mut impl PairSink,
) -> WorstOverlap {
    let p = input.particles;
    // One common length lets the compiler check an index once for all the arrays.
    let n = p.len();
    let (pos, vel, omega) = (&p.position[..n], &p.velocity[..n], &p.omega[..n]);
    let (radius, mass, material) = (&p.radius[..n], &p.mass[..n], &p.material[..n]);
    let len = history.len();
    let (pi, pj) = (&pi[base..base + len], &pj[base..base + len]);

    let live = &mut live[..len];
    // Pairs that may bond are listed while bonded as well as while touching.
    let bonds = input.pair_bonds;
    let count = filter_touching(
        p,
        (pi, pj),
        live,
        touching,
        input.uniform_body.map(|(r, _)| r),
        bonds,
    );
    let touching = &touching[..count];

    let uniform = uniform_coefficients(input.pair_coeffs, input.materials);
    if let Some(c) = uniform {
        batch.fill_coefficients(c);
    }
    let table = &input.bond_tables.pair;
    if bonds {
        if let Some(c) = uniform {
            batch.bond.fill(&table[0], c.e_star);
        }
    }
    if let Some((r, m)) = input.uniform_body {
        batch.radius[0].fill(r);
        batch.radius[1].fill(r);
        batch.mass[0].fill(m);
        batch.mass[1].fill(m);
    }
    let mut worst = WorstOverlap::default();
    let far = n > PREFETCH_BODIES;
    for (g, group) in touching.chunks(BATCH).enumerate() {
        if far {
            // The next batch's partners, far from their first bodies in memory: asked for
            // a whole batch (kernel and scatter included) before their gather.
            let next = touching.get((g + 1) * BATCH..).unwrap_or_default();
            for &k in next.iter().take(BATCH) {
                let j = pj[k as usize] as usize;
                prefetch(&pos[j]);
                prefetch(&vel[j]);
                prefetch(&omega[j]);
                sink.prefetch(j);
            }
        }
        let state = gather::PairState {
            position: pos,
            velocity: vel,
            omega,
            pi,
            pj,
            history,
            live,
        };
        gather::pair_motion(batch, group, &state);
        // Radii, masses and coefficients, where the contacts do not share them. A `take`
        // of zero rather than an `if` around the loop: the loop's code then lays out
        // better, about 1.4 % of a step.
        let shared = input.uniform_body.is_some() && uniform.is_some();
        for (m, &k) in group
            .iter()
            .enumerate()
            .take(if shared { 0 } else { BATCH })
        {
            // `m < BATCH` already; the mask tells the compiler so.
            let m = m & (BATCH - 1);
            let k = k as usize;
            let (i, j) = (pi[k] as usize, pj[k] as usize);
            if input.uniform_body.is_none() {
                batch.radius[0][m] = radius[i];
                batch.radius[1][m] = radius[j];
                batch.mass[0][m] = mass[i];
                batch.mass[1][m] = mass[j];
            }
            if uniform.is_none() {
                let pair = material[i] as usize * input.materials + material[j] as usize;
                let c = &input.pair_coeffs[pair];
                batch.coeff.set(m, c);
                if bonds {
                    batch.bond.set(m, &table[pair], c.e_star);
                }
            }
        }
        batch.len = group.len();
        match (input.uniform_body, bonds) {
            (Some((r, m)), false) => batch.resolve_pairs_uniform(input.dt, r, m),
            (None, false) => batch.resolve_pairs(input.dt),
            (Some((r, m)), true) => batch.resolve_bonded_pairs_uniform(input.dt, r, m),
            (None, true) => batch.resolve_bonded_pairs(input.dt),
        }
        if input.area_cohesion {
            super::area_cohesion::pairs(
                batch,
                group.len(),
                (uniform, |m| {
                    let k = group[m] as usize;
                    let (i, j) = (pi[k] as usize, pj[k] as usize);
                    &input.pair_coeffs
                        [material[i] as usize * input.materials + material[j] as usize]
                }),
            );
        }
        worst.see_batch(batch, group.iter().map(|&k| base + k as usize));
        if bonds {
            for (m, &k) in group.iter().enumerate() {
                let m = m & (BATCH - 1);
                let k = k as usize;
                history[k] = DVec3::new(batch.xi[0][m], batch.xi[1][m], batch.xi[2][m]);
                let kept = batch.bond.outcome[m] != OUTCOME_APART;
                live[k] = settle_bond(live[k], kept, batch.bond.law[m] != LAW_DRY);
                if kept {
                    sink.contact(pi[k] as usize, pj[k] as usize, &batch_force(batch, m));
                }
            }
            continue;
        }
        for (m, &k) in group.iter().enumerate() {
            let m = m & (BATCH - 1);
            let k = k as usize;
            history[k] = DVec3::new(batch.xi[0][m], batch.xi[1][m], batch.xi[2][m]);
            sink.contact(pi[k] as usize, pj[k] as usize, &batch_force(batch, m));
        }
    }
    worst
}
