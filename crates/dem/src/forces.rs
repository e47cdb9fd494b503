//! Force evaluation: the contact kernel over candidate pairs, then accumulation in pair
//! order, so that sums are bit-identical at any thread count.
//!
//! One thread: each contact force is added to its two bodies as soon as it is computed.
//! Several threads: contacts are computed in parallel into buffers, then added by one
//! thread in the same order. Both paths run the same kernel and the same sequence of
//! floating-point additions (gravity, pairs in list order, walls in list order).

use glam::DVec3;
use rayon::prelude::*;

use crate::contact::batch::{Batch, BATCH};
use crate::contact::{BodyMotion, ContactForce, ContactGeometry, ContactHistory, ContactLaws};
use crate::material::{harmonic, PairCoefficients};
use crate::neighbour::{PairList, WallPairList};
use crate::particles::ParticleSet;
use crate::wall::Wall;

/// Pairs per parallel task: large enough to amortise scheduling, small enough to balance.
const CHUNK: usize = 2048;

/// Read-only inputs of the kernel.
pub(crate) struct KernelInput<'a> {
    pub particles: &'a ParticleSet,
    pub laws: &'a ContactLaws,
    pub pair_coeffs: &'a [PairCoefficients],
    pub materials: usize,
    pub walls: &'a [Option<Wall>],
    pub wall_coeffs: &'a [PairCoefficients],
    pub dt: f64,
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

/// Reusable buffers.
#[derive(Debug, Default)]
pub(crate) struct ForceBuffers {
    pairs: Vec<ContactForce>,
    active: Vec<bool>,
    /// Accumulated forces [N], swapped into the particle set after evaluation.
    pub force: Vec<DVec3>,
    /// Accumulated torques [N m].
    pub torque: Vec<DVec3>,
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
pub(crate) struct Evaluation {
    pub count: ContactCount,
    pub worst_pair: WorstOverlap,
    pub worst_wall: WorstOverlap,
}

/// Adds pair forces to the bodies in pair order, the one summation both evaluation paths share.
///
/// Pairs come sorted by i, so the contributions to body i are summed in registers over its run
/// of pairs and added to it once, instead of a store and reload per contact.
struct Accumulator<'a> {
    force: &'a mut [DVec3],
    torque: &'a mut [DVec3],
    current: usize,
    sum_force: DVec3,
    sum_torque: DVec3,
}

impl<'a> Accumulator<'a> {
    fn new(force: &'a mut [DVec3], torque: &'a mut [DVec3]) -> Self {
        Self {
            force,
            torque,
            current: usize::MAX,
            sum_force: DVec3::ZERO,
            sum_torque: DVec3::ZERO,
        }
    }

    #[inline(always)]
    fn add(&mut self, i: usize, j: usize, cf: &ContactForce) {
        if i != self.current {
            self.finish();
            self.current = i;
        }
        self.sum_force += cf.force;
        self.sum_torque += cf.torque_i;
        self.force[j] -= cf.force;
        self.torque[j] += cf.torque_j;
    }

    /// Adds the open run to its body.
    #[inline(always)]
    fn finish(&mut self) {
        if self.current != usize::MAX {
            self.force[self.current] += self.sum_force;
            self.torque[self.current] += self.sum_torque;
        }
        self.sum_force = DVec3::ZERO;
        self.sum_torque = DVec3::ZERO;
    }
}

/// Evaluates all contacts, updating histories, and leaves gravity plus contact forces and
/// torques in `buffers.force` and `buffers.torque`.
pub(crate) fn evaluate(
    input: &KernelInput,
    pairs: &mut PairList,
    wall_pairs: &mut WallPairList,
    gravity: DVec3,
    buffers: &mut ForceBuffers,
    pool: Option<&rayon::ThreadPool>,
) -> Evaluation {
    let p = input.particles;
    let n = p.len();
    buffers.force.clear();
    buffers.force.extend(p.mass.iter().map(|&m| m * gravity));
    buffers.torque.clear();
    buffers.torque.resize(n, DVec3::ZERO);
    let mut count = ContactCount::default();
    let ids = (&pairs.i[..], &pairs.j[..]);

    let worst_pair = match pool {
        None => {
            let mut acc = Accumulator::new(&mut buffers.force, &mut buffers.torque);
            let worst = pair_loop(input, ids, 0, &mut pairs.history, |_, i, j, cf| {
                acc.add(i, j, cf);
                count.particle_particle += 1;
            });
            acc.finish();
            worst
        }
        Some(pool) => {
            buffers.pairs.resize(pairs.len(), ContactForce::default());
            buffers.active.clear();
            buffers.active.resize(pairs.len(), false);
            let worst = pool.install(|| {
                pairs
                    .history
                    .par_chunks_mut(CHUNK)
                    .zip(buffers.pairs.par_chunks_mut(CHUNK))
                    .zip(buffers.active.par_chunks_mut(CHUNK))
                    .enumerate()
                    .map(|(c, ((h, out), act))| {
                        let base = c * CHUNK;
                        pair_loop(input, ids, base, h, |k, _, _, cf| {
                            out[k - base] = *cf;
                            act[k - base] = true;
                        })
                    })
                    .reduce(WorstOverlap::default, WorstOverlap::merge)
            });
            let mut acc = Accumulator::new(&mut buffers.force, &mut buffers.torque);
            for k in 0..pairs.len() {
                if buffers.active[k] {
                    acc.add(pairs.i[k] as usize, pairs.j[k] as usize, &buffers.pairs[k]);
                    count.particle_particle += 1;
                }
            }
            acc.finish();
            worst
        }
    };

    // Few wall candidates: one sequential pass, accumulating directly, on every path.
    let (force, torque) = (&mut buffers.force, &mut buffers.torque);
    let worst_wall = wall_loop(
        input,
        (&wall_pairs.particle, &wall_pairs.wall),
        &mut wall_pairs.history,
        |i, cf| {
            force[i] += cf.force;
            torque[i] += cf.torque_i;
            count.particle_wall += 1;
        },
    );
    Evaluation {
        count,
        worst_pair,
        worst_wall,
    }
}

/// Runs the kernel over pairs `base..base + history.len()`, calling `sink(k, i, j, force)` for
/// each pair in contact, in order.
///
/// The paper's laws (the default) get their own copy of the loop in which the law choices are
/// constants, so the compiler drops the branches and code of the other laws.
#[inline(always)]
fn pair_loop(
    input: &KernelInput,
    ids: (&[u32], &[u32]),
    base: usize,
    history: &mut [ContactHistory],
    sink: impl FnMut(usize, usize, usize, &ContactForce),
) -> WorstOverlap {
    if *input.laws == ContactLaws::default() {
        batched_pair_loop(input, ids, base, history, sink)
    } else {
        pair_loop_with(input, *input.laws, ids, base, history, sink)
    }
}

/// The paper's laws over a structure-of-arrays batch: touching pairs are gathered into a
/// [`Batch`], resolved together, and handed to `sink` in pair order.
#[inline(always)]
fn batched_pair_loop(
    input: &KernelInput,
    (pi, pj): (&[u32], &[u32]),
    base: usize,
    history: &mut [ContactHistory],
    mut sink: impl FnMut(usize, usize, usize, &ContactForce),
) -> WorstOverlap {
    let p = input.particles;
    let mut worst = WorstOverlap::default();
    let pi = &pi[base..base + history.len()];
    let pj = &pj[base..base + history.len()];
    let mut batch = Box::<Batch>::default();
    let mut slot = [0u32; BATCH];
    let mut flush = |batch: &mut Batch, slot: &[u32], history: &mut [ContactHistory]| {
        batch.resolve(input.dt);
        for (m, &k) in slot[..batch.len].iter().enumerate() {
            let k = k as usize;
            history[k].tangential = DVec3::new(batch.xi[0][m], batch.xi[1][m], batch.xi[2][m]);
            let cf = ContactForce {
                force: DVec3::new(batch.force[0][m], batch.force[1][m], batch.force[2][m]),
                torque_i: DVec3::new(
                    batch.torque_i[0][m],
                    batch.torque_i[1][m],
                    batch.torque_i[2][m],
                ),
                torque_j: DVec3::new(
                    batch.torque_j[0][m],
                    batch.torque_j[1][m],
                    batch.torque_j[2][m],
                ),
            };
            worst.see(batch.overlap_fraction[m], base + k);
            sink(base + k, pi[k] as usize, pj[k] as usize, &cf);
        }
        batch.len = 0;
    };
    for k in 0..history.len() {
        let (i, j) = (pi[k] as usize, pj[k] as usize);
        let d = p.position[i] - p.position[j];
        let (ri, rj) = (p.radius[i], p.radius[j]);
        let sum = ri + rj;
        let dist2 = d.length_squared();
        if dist2 >= sum * sum {
            // Separated: the contact forgets its history (physics.md §3.1).
            if !history[k].is_empty() {
                history[k] = ContactHistory::default();
            }
            continue;
        }
        let m = batch.len;
        let c =
            &input.pair_coeffs[p.material[i] as usize * input.materials + p.material[j] as usize];
        let (dv, wi, wj, xi) = (
            p.velocity[i] - p.velocity[j],
            p.omega[i],
            p.omega[j],
            history[k].tangential,
        );
        for (a, (x, v, u, w, z)) in [
            (d.x, dv.x, wi.x, wj.x, xi.x),
            (d.y, dv.y, wi.y, wj.y, xi.y),
            (d.z, dv.z, wi.z, wj.z, xi.z),
        ]
        .into_iter()
        .enumerate()
        {
            batch.d[a][m] = x;
            batch.dv[a][m] = v;
            batch.omega[0][a][m] = u;
            batch.omega[1][a][m] = w;
            batch.xi[a][m] = z;
        }
        batch.dist2[m] = dist2;
        batch.radius[0][m] = ri;
        batch.radius[1][m] = rj;
        batch.mass[0][m] = p.mass[i];
        batch.mass[1][m] = p.mass[j];
        for (a, v) in [
            c.e_star,
            c.g_star,
            c.friction,
            c.rolling_friction,
            c.damping,
            c.stiffness_ratio_sqrt,
        ]
        .into_iter()
        .enumerate()
        {
            batch.coeff[a][m] = v;
        }
        slot[m] = k as u32;
        batch.len = m + 1;
        if batch.len == BATCH {
            flush(&mut batch, &slot, history);
        }
    }
    flush(&mut batch, &slot, history);
    worst
}

#[inline(always)]
fn pair_loop_with(
    input: &KernelInput,
    laws: ContactLaws,
    (pi, pj): (&[u32], &[u32]),
    base: usize,
    history: &mut [ContactHistory],
    mut sink: impl FnMut(usize, usize, usize, &ContactForce),
) -> WorstOverlap {
    let p = input.particles;
    let mut worst = WorstOverlap::default();
    let pi = &pi[base..base + history.len()];
    let pj = &pj[base..base + history.len()];
    for (k, ((&i, &j), h)) in pi.iter().zip(pj).zip(history.iter_mut()).enumerate() {
        let (i, j) = (i as usize, j as usize);
        let d = p.position[i] - p.position[j];
        let (ri, rj) = (p.radius[i], p.radius[j]);
        let sum = ri + rj;
        let dist2 = d.length_squared();
        if dist2 >= sum * sum {
            // Separated: the contact forgets its history (physics.md §3.1).
            if !h.is_empty() {
                *h = ContactHistory::default();
            }
            continue;
        }
        let dist = dist2.sqrt();
        let overlap = sum - dist;
        worst.see(overlap / ri.min(rj), base + k);
        let (mi, mj) = (p.mass[i], p.mass[j]);
        let g = ContactGeometry {
            normal: d * (1.0 / dist),
            overlap,
            // harmonic(ri, rj), reusing the sum.
            r_eff: ri * rj / sum,
            m_eff: harmonic(mi, mj),
            arm_i: ri - 0.5 * overlap,
            arm_j: rj - 0.5 * overlap,
            inertia: [p.inertia[i], p.inertia[j]],
            mass_radius2: [mi * ri * ri, mj * rj * rj],
        };
        let c =
            &input.pair_coeffs[p.material[i] as usize * input.materials + p.material[j] as usize];
        let bi = BodyMotion {
            velocity: p.velocity[i],
            omega: p.omega[i],
        };
        let bj = BodyMotion {
            velocity: p.velocity[j],
            omega: p.omega[j],
        };
        let cf = laws.resolve(&g, &bi, &bj, c, h, input.dt);
        sink(base + k, i, j, &cf);
    }
    worst
}

/// Runs the kernel over the particle–wall candidates, calling `sink(i, force)` per contact.
#[inline(always)]
fn wall_loop(
    input: &KernelInput,
    (pi, pw): (&[u32], &[u32]),
    history: &mut [ContactHistory],
    mut sink: impl FnMut(usize, &ContactForce),
) -> WorstOverlap {
    let p = input.particles;
    let mut worst = WorstOverlap::default();
    for (k, ((&i, &w), h)) in pi.iter().zip(pw).zip(history.iter_mut()).enumerate() {
        let (i, w) = (i as usize, w as usize);
        let Some(wall) = &input.walls[w] else {
            *h = ContactHistory::default();
            continue;
        };
        let x = p.position[i];
        let ri = p.radius[i];
        let (cp, dist) = wall.closest_point(x);
        if dist >= ri {
            if !h.is_empty() {
                *h = ContactHistory::default();
            }
            continue;
        }
        let overlap = ri - dist;
        worst.see(overlap / ri, k);
        // A wall has infinite radius and mass: R* = R_i, m* = m_i (physics.md §5).
        let g = ContactGeometry {
            normal: wall.contact_normal(x, cp, dist),
            overlap,
            r_eff: ri,
            m_eff: p.mass[i],
            arm_i: ri - 0.5 * overlap,
            arm_j: 0.0,
            inertia: [p.inertia[i], f64::INFINITY],
            mass_radius2: [p.mass[i] * ri * ri, f64::INFINITY],
        };
        let c = &input.wall_coeffs[w * input.materials + p.material[i] as usize];
        let bi = BodyMotion {
            velocity: p.velocity[i],
            omega: p.omega[i],
        };
        let bw = BodyMotion {
            velocity: wall.velocity,
            omega: DVec3::ZERO,
        };
        let cf = input.laws.resolve(&g, &bi, &bw, c, h, input.dt);
        sink(i, &cf);
    }
    worst
}
