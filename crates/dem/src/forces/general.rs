//! Any choice of contact laws, one contact at a time through `ContactLaws::resolve`: the
//! path of the laws the batched kernel does not cover, and the reference the tests hold
//! the batched path to.

use super::*;

#[inline(always)]
pub(super) fn pair_loop_with(
    input: &KernelInput,
    laws: ContactLaws,
    (pi, pj): (&[u32], &[u32]),
    base: usize,
    (tangential, rolling): (&mut [DVec3], &mut [DVec3]),
    sink: &mut impl PairSink,
) -> WorstOverlap {
    let p = input.particles;
    let mut worst = WorstOverlap::default();
    let pi = &pi[base..base + tangential.len()];
    let pj = &pj[base..base + tangential.len()];
    let history = tangential.iter_mut().zip(rolling.iter_mut());
    for (k, ((&i, &j), (t, r))) in pi.iter().zip(pj).zip(history).enumerate() {
        let (i, j) = (i as usize, j as usize);
        let d = p.position[i] - p.position[j];
        let (ri, rj) = (p.radius[i], p.radius[j]);
        let sum = ri + rj;
        let dist2 = d.length_squared();
        if dist2 >= sum * sum {
            // Separated: the contact forgets its history (physics.md §3.1).
            (*t, *r) = (DVec3::ZERO, DVec3::ZERO);
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
        let mut h = ContactHistory {
            tangential: *t,
            rolling: *r,
        };
        let cf = laws.resolve(&g, &bi, &bj, c, &mut h, input.dt);
        (*t, *r) = (h.tangential, h.rolling);
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
    (tangential, rolling): (&mut [DVec3], &mut [DVec3]),
    mut sink: impl FnMut(usize, &ContactForce),
) -> (WorstOverlap, usize) {
    let p = input.particles;
    let mut worst = WorstOverlap::default();
    let mut contacts = 0;
    let history = tangential.iter_mut().zip(rolling.iter_mut());
    for (k, ((&i, &w), (t, r))) in pi.iter().zip(pw).zip(history).enumerate() {
        let (i, w) = (i as usize, w as usize);
        let Some(wall) = &input.walls[w] else {
            (*t, *r) = (DVec3::ZERO, DVec3::ZERO);
            continue;
        };
        let x = p.position[i];
        let ri = p.radius[i];
        let (cp, dist) = wall.closest_point(x);
        if dist >= ri {
            (*t, *r) = (DVec3::ZERO, DVec3::ZERO);
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
            velocity: wall.velocity_at(x),
            omega: DVec3::ZERO,
        };
        let mut h = ContactHistory {
            tangential: *t,
            rolling: *r,
        };
        let cf = input.laws.resolve(&g, &bi, &bw, c, &mut h, input.dt);
        (*t, *r) = (h.tangential, h.rolling);
        sink(i, &cf);
        contacts += 1;
    }
    (worst, contacts)
}
