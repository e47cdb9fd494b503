//! Force evaluation: the contact kernel over candidate pairs, in parallel, then a
//! sequential scatter in pair order so that sums are bit-identical at any thread count.

use glam::DVec3;
use rayon::prelude::*;

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
    /// Deterministic merge: larger fraction wins, ties go to the lower index.
    fn merge(self, other: Self) -> Self {
        if other.fraction > self.fraction || (other.fraction == self.fraction && other.index < self.index) {
            other
        } else {
            self
        }
    }
}

/// Reusable output buffers.
#[derive(Debug, Default)]
pub(crate) struct ForceBuffers {
    pairs: Vec<Option<ContactForce>>,
    walls: Vec<Option<ContactForce>>,
}

/// Counts of contacts that carried force in the last evaluation.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ContactCount {
    /// Particle–particle contacts.
    pub particle_particle: usize,
    /// Particle–wall contacts.
    pub particle_wall: usize,
}

/// Evaluates every candidate contact into the buffers, updating histories.
/// Returns the worst particle–particle and particle–wall overlaps.
pub(crate) fn kernel(
    input: &KernelInput,
    pairs: &mut PairList,
    wall_pairs: &mut WallPairList,
    buffers: &mut ForceBuffers,
    pool: Option<&rayon::ThreadPool>,
) -> (WorstOverlap, WorstOverlap) {
    buffers.pairs.resize(pairs.len(), None);
    buffers.walls.resize(wall_pairs.particle.len(), None);

    let pair_ids = (&pairs.i[..], &pairs.j[..]);
    let wall_ids = (&wall_pairs.particle[..], &wall_pairs.wall[..]);
    let mut run = || {
        let worst_pp = match pool {
            Some(_) => pairs
                .history
                .par_chunks_mut(CHUNK)
                .zip(buffers.pairs.par_chunks_mut(CHUNK))
                .enumerate()
                .map(|(c, (h, o))| pair_chunk(input, pair_ids, c * CHUNK, h, o))
                .reduce(WorstOverlap::default, WorstOverlap::merge),
            None => pairs
                .history
                .chunks_mut(CHUNK)
                .zip(buffers.pairs.chunks_mut(CHUNK))
                .enumerate()
                .map(|(c, (h, o))| pair_chunk(input, pair_ids, c * CHUNK, h, o))
                .fold(WorstOverlap::default(), WorstOverlap::merge),
        };
        // Few wall candidates: one sequential pass is cheaper than a parallel one.
        let worst_pw = wall_chunk(input, wall_ids, &mut wall_pairs.history, &mut buffers.walls);
        (worst_pp, worst_pw)
    };
    match pool {
        Some(p) => p.install(run),
        None => run(),
    }
}

/// Accumulates gravity and the buffered contact forces, in a fixed order (gravity, pairs in
/// list order, walls in list order), so the sums do not depend on the thread count.
pub(crate) fn scatter(
    particles: &mut ParticleSet,
    pairs: &PairList,
    wall_pairs: &WallPairList,
    gravity: DVec3,
    buffers: &ForceBuffers,
) -> ContactCount {
    let (force, torque) = (&mut particles.force, &mut particles.torque);
    for k in 0..force.len() {
        force[k] = particles.mass[k] * gravity;
        torque[k] = DVec3::ZERO;
    }
    let mut count = ContactCount::default();
    for (k, out) in buffers.pairs.iter().enumerate() {
        if let Some(cf) = out {
            let (i, j) = (pairs.i[k] as usize, pairs.j[k] as usize);
            force[i] += cf.force;
            force[j] -= cf.force;
            torque[i] += cf.torque_i;
            torque[j] += cf.torque_j;
            count.particle_particle += 1;
        }
    }
    for (k, out) in buffers.walls.iter().enumerate() {
        if let Some(cf) = out {
            let i = wall_pairs.particle[k] as usize;
            force[i] += cf.force;
            torque[i] += cf.torque_i;
            count.particle_wall += 1;
        }
    }
    count
}

fn pair_chunk(
    input: &KernelInput,
    (pi, pj): (&[u32], &[u32]),
    base: usize,
    history: &mut [ContactHistory],
    out: &mut [Option<ContactForce>],
) -> WorstOverlap {
    let p = input.particles;
    let mut worst = WorstOverlap::default();
    for k in 0..history.len() {
        let (i, j) = (pi[base + k] as usize, pj[base + k] as usize);
        let d = p.position[i] - p.position[j];
        let (ri, rj) = (p.radius[i], p.radius[j]);
        let sum = ri + rj;
        let dist2 = d.length_squared();
        if dist2 >= sum * sum {
            // Separated: the contact forgets its history (physics.md §3.1).
            history[k] = ContactHistory::default();
            out[k] = None;
            continue;
        }
        let dist = dist2.sqrt();
        let overlap = sum - dist;
        let fraction = overlap / ri.min(rj);
        if fraction > worst.fraction {
            worst = WorstOverlap { fraction, index: base + k };
        }
        let (mi, mj) = (p.mass[i], p.mass[j]);
        let (ii, ij) = (p.inertia[i], p.inertia[j]);
        let g = ContactGeometry {
            normal: d / dist,
            overlap,
            r_eff: harmonic(ri, rj),
            m_eff: harmonic(mi, mj),
            arm_i: ri - 0.5 * overlap,
            arm_j: rj - 0.5 * overlap,
            inertia_reduced: harmonic(ii, ij),
            rolling_inertia: 1.4 * harmonic(mi * ri * ri, mj * rj * rj),
        };
        let c = &input.pair_coeffs[p.material[i] as usize * input.materials + p.material[j] as usize];
        let bi = BodyMotion {
            velocity: p.velocity[i],
            omega: p.omega[i],
        };
        let bj = BodyMotion {
            velocity: p.velocity[j],
            omega: p.omega[j],
        };
        out[k] = Some(input.laws.resolve(&g, &bi, &bj, c, &mut history[k], input.dt));
    }
    worst
}

fn wall_chunk(
    input: &KernelInput,
    (pi, pw): (&[u32], &[u32]),
    history: &mut [ContactHistory],
    out: &mut [Option<ContactForce>],
) -> WorstOverlap {
    let p = input.particles;
    let mut worst = WorstOverlap::default();
    for k in 0..history.len() {
        let (i, w) = (pi[k] as usize, pw[k] as usize);
        let Some(wall) = &input.walls[w] else {
            history[k] = ContactHistory::default();
            out[k] = None;
            continue;
        };
        let x = p.position[i];
        let ri = p.radius[i];
        let (cp, dist) = wall.closest_point(x);
        if dist >= ri {
            history[k] = ContactHistory::default();
            out[k] = None;
            continue;
        }
        let overlap = ri - dist;
        let fraction = overlap / ri;
        if fraction > worst.fraction {
            worst = WorstOverlap { fraction, index: k };
        }
        // A wall has infinite radius and mass: R* = R_i, m* = m_i (physics.md §5).
        let g = ContactGeometry {
            normal: wall.contact_normal(x, cp, dist),
            overlap,
            r_eff: ri,
            m_eff: p.mass[i],
            arm_i: ri - 0.5 * overlap,
            arm_j: 0.0,
            inertia_reduced: p.inertia[i],
            rolling_inertia: 1.4 * p.mass[i] * ri * ri,
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
        out[k] = Some(input.laws.resolve(&g, &bi, &bw, c, &mut history[k], input.dt));
    }
    worst
}
