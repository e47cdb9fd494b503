//! Any choice of contact laws, one contact at a time through `ContactLaws::resolve`: the
//! path of the laws the batched kernel does not cover, and the reference the tests hold
//! the batched path to.

use glam::DVec3;

use super::loads::{add_load, LoadSum};
use super::{KernelInput, PairSink, WorstOverlap};
use crate::contact::geometry::{sphere_sphere, sphere_wall, Sphere};
use crate::contact::{BodyMotion, ContactForce, ContactHistory, ContactLaws};
use crate::history::BONDED;
use crate::particles::ParticleSet;

/// Body `k` of `p` as the contact geometry sees it.
#[inline(always)]
fn sphere(p: &ParticleSet, k: usize) -> Sphere {
    Sphere {
        radius: p.radius[k],
        mass: p.mass[k],
        inertia: p.inertia[k],
    }
}

/// The bonded flag of a live flag byte.
#[inline(always)]
fn bonded(live: u8) -> bool {
    live & BONDED != 0
}

/// Writes a resolved history back into the arrays.
#[inline(always)]
fn store(h: &ContactHistory, (t, r, l): (&mut DVec3, &mut DVec3, &mut u8)) {
    (*t, *r) = (h.tangential, h.rolling);
    *l = if h.bonded { *l | BONDED } else { *l & !BONDED };
}

/// Runs `laws` over pairs `base..base + tangential.len()`, one at a time, calling `sink`
/// for each pair that carries force, in order. The histories must be settled (every flag
/// live, [`crate::history::settle`]). A pair interacts while its surfaces overlap, and
/// beyond that while it is bonded (a JKR contact or a liquid bridge, docs/physics.md §2.4,
/// §2.6).
#[inline(always)]
pub(super) fn pair_loop_with(
    input: &KernelInput,
    laws: ContactLaws,
    (pi, pj): (&[u32], &[u32]),
    base: usize,
    (tangential, rolling, live): (&mut [DVec3], &mut [DVec3], &mut [u8]),
    sink: &mut impl PairSink,
) -> WorstOverlap {
    let p = input.particles;
    let mut worst = WorstOverlap::default();
    let pi = &pi[base..base + tangential.len()];
    let pj = &pj[base..base + tangential.len()];
    let history = tangential
        .iter_mut()
        .zip(rolling.iter_mut())
        .zip(live.iter_mut());
    for (k, ((&i, &j), ((t, r), l))) in pi.iter().zip(pj).zip(history).enumerate() {
        let (i, j) = (i as usize, j as usize);
        let d = p.position[i] - p.position[j];
        let (ri, rj) = (p.radius[i], p.radius[j]);
        let sum = ri + rj;
        let dist2 = d.length_squared();
        if dist2 >= sum * sum && !bonded(*l) {
            // Separated: the contact forgets its history (docs/physics.md §3.1).
            (*t, *r) = (DVec3::ZERO, DVec3::ZERO);
            continue;
        }
        let g = sphere_sphere(d, dist2, &sphere(p, i), &sphere(p, j));
        worst.see(g.overlap / ri.min(rj), base + k);
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
        let mut h = ContactHistory {
            tangential: *t,
            rolling: *r,
            bonded: bonded(*l),
        };
        let cf = laws.resolve(&g, &bi, &bj, c, &mut h, input.dt);
        store(&h, (t, r, l));
        if g.overlap <= 0.0 && !h.bonded {
            // A bond that broke this step carries no force.
            continue;
        }
        sink.contact(i, j, &cf);
    }
    worst
}

/// Runs the kernel over the particle–wall candidates, calling `sink(i, force)` per contact;
/// returns the largest overlap and the number of contacts.
#[inline(always)]
pub(super) fn wall_loop(
    input: &KernelInput,
    (pi, pw): (&[u32], &[u32]),
    (tangential, rolling, live): (&mut [DVec3], &mut [DVec3], &mut [u8]),
    loads: &mut [LoadSum],
    mut sink: impl FnMut(usize, &ContactForce),
) -> (WorstOverlap, usize) {
    let p = input.particles;
    let mut worst = WorstOverlap::default();
    let mut contacts = 0;
    let history = tangential
        .iter_mut()
        .zip(rolling.iter_mut())
        .zip(live.iter_mut());
    for (k, ((&i, &w), ((t, r), l))) in pi.iter().zip(pw).zip(history).enumerate() {
        let (i, w) = (i as usize, w as usize);
        let Some(wall) = &input.walls[w] else {
            (*t, *r) = (DVec3::ZERO, DVec3::ZERO);
            *l &= !BONDED;
            continue;
        };
        if wall.resolved_one_by_one() {
            // The surface pass's (`surfaces`).
            continue;
        }
        let x = p.position[i];
        let ri = p.radius[i];
        let (cp, dist) = wall.closest_point(x);
        if dist >= ri && !bonded(*l) {
            (*t, *r) = (DVec3::ZERO, DVec3::ZERO);
            continue;
        }
        let g = sphere_wall(wall.contact_normal(x, cp, dist), dist, &sphere(p, i));
        worst.see(g.overlap / ri, k);
        let c = &input.wall_coeffs[w * input.materials + p.material[i] as usize];
        let bi = BodyMotion {
            velocity: p.velocity[i],
            omega: p.omega[i],
        };
        let bw = BodyMotion {
            velocity: wall.velocity_at(x),
            omega: DVec3::ZERO,
        };
        let mut h = ContactHistory {
            tangential: *t,
            rolling: *r,
            bonded: bonded(*l),
        };
        let cf = input.laws.resolve(&g, &bi, &bw, c, &mut h, input.dt);
        store(&h, (t, r, l));
        if g.overlap <= 0.0 && !h.bonded {
            // A bond that broke this step carries no force.
            continue;
        }
        add_load(&mut loads[w], &input.quanta, x, &cf);
        sink(i, &cf);
        contacts += 1;
    }
    (worst, contacts)
}
