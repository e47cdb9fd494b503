//! The flat form of the kicks and the drift, for free bodies that all share one mass and
//! moment of inertia: the same operation on every component of every body, over the vectors
//! as flat arrays of numbers, which the compiler vectorises. Each component goes through the
//! operations of the per-body form in the same order (a test checks the bits).

use super::*;

/// [`kick_drift`] for free particles sharing `kv` = Δt/2m [s/kg] and `kw` = Δt/2I
/// [s/(kg m²)], and the weight m g [N]: per component, v += kv F (pending), v += kv F,
/// x += Δt v, and the same for ω with kw and the torque, then F = m g and T = 0; each
/// block of particles then gives its displacements, when `measure`, and its reach, when
/// `track` (only the one-thread pass whose caller keeps bounds uses it).
#[inline(always)]
pub(super) fn kick_drift_flat(
    b: Bodies,
    (kv, kw): (f64, f64),
    (dt, weight): (f64, DVec3),
    pending: bool,
    (measure, track): (bool, bool),
) -> Moved {
    // In blocks, so that the displacements read positions just written, from the
    // first-level cache rather than from memory once the arrays outgrow the caches. A
    // block's numbers are a multiple of 3 × WIDTH, so every block starts a weight pattern
    // (`flat_pass`) and holds whole particles. The maximum and the probes do not depend on
    // how the particles are grouped.
    let (mut max_disp2, mut position_probe, mut velocity_probe) = (0.0f64, 0.0, 0.0);
    let mut reach = 0.0f64;
    let blocks = b
        .velocity
        .chunks_mut(BLOCK)
        .zip(b.omega.chunks_mut(BLOCK))
        .zip(b.position.chunks_mut(BLOCK))
        .zip(b.force.chunks_mut(BLOCK).zip(b.torque.chunks_mut(BLOCK)))
        .zip(b.reference.chunks(BLOCK));
    for ((((v, w), x), (f, t)), r) in blocks {
        velocity_probe += if pending {
            flat_pass::<true, true>((&mut *v, w, &mut *x), (f, t), (kv, kw, dt), weight)
        } else {
            flat_pass::<false, true>((&mut *v, w, &mut *x), (f, t), (kv, kw, dt), weight)
        };
        if track {
            // From the block just written, in the first-level cache; NaN-keeping.
            let r = reach_of(bytemuck::cast_slice(v), dt);
            reach = if r > reach || r.is_nan() { r } else { reach };
        }
        if measure {
            let (d2, probe) = largest_displacement(x, r);
            max_disp2 = if d2 > max_disp2 { d2 } else { max_disp2 };
            position_probe += probe;
        }
    }
    Moved {
        max_disp2: measure.then_some(max_disp2),
        // Measured, the displacements' probe. Otherwise the reach: a finite position moved
        // by less than `FINITE_REACH` stays finite unless it lay within that of the largest
        // number, some 10³⁰⁸ m out, and the caller measures nothing for bodies that were
        // farther out than `FINITE_REACH` at the last list build.
        finite: if measure {
            position_probe == 0.0
        } else {
            reach < FINITE_REACH
        },
        kicked_finite: velocity_probe == 0.0,
        reach,
    }
}

/// Numbers per vector of the flat loops (eight f64 fill a 512-bit register).
pub(super) const WIDTH: usize = 8;

/// Particles per block of [`kick_drift_flat`]: a multiple of WIDTH, and 7 arrays of
/// 24 bytes a particle in under half the 48 kB first-level cache.
pub(super) const BLOCK: usize = 8 * WIDTH;

/// One pass over every component of every particle, with kv = Δt/2m, kw = Δt/2I and Δt
/// in `k`: with `KICK`, `kick`'s v += kv F, ω += kw T and its check on v + ω; with
/// `KICK_DRIFT`, this step's v += kv F, ω += kw T and x += Δt v, and then F = `weight` and
/// T = 0 for the next evaluation. Returns the check's sum, zero unless some velocity or
/// spin is not finite (0 without `KICK`).
pub(super) fn flat_pass<const KICK: bool, const KICK_DRIFT: bool>(
    (v, w, x): (&mut [DVec3], &mut [DVec3], &mut [DVec3]),
    (f, t): (&mut [DVec3], &mut [DVec3]),
    (kv, kw, dt): (f64, f64, f64),
    weight: DVec3,
) -> f64 {
    let v: &mut [f64] = bytemuck::cast_slice_mut(v);
    let w: &mut [f64] = bytemuck::cast_slice_mut(w);
    let x: &mut [f64] = bytemuck::cast_slice_mut(x);
    let f: &mut [f64] = bytemuck::cast_slice_mut(f);
    let t: &mut [f64] = bytemuck::cast_slice_mut(t);
    // The flat force array repeats the weight's three components: the run of WIDTH numbers
    // that starts at flat index q is `weights[q % 3..][..WIDTH]`.
    let weights: [f64; WIDTH + 2] = std::array::from_fn(|q| weight[q % 3]);
    let mut phase = 0;
    let mut probe = [0.0; WIDTH];
    // Whole vectors of WIDTH numbers, each lane with its own probe, copied into registers
    // (which tells the compiler that the five arrays do not overlap), then the remainder.
    let chunks = v
        .chunks_exact_mut(WIDTH)
        .zip(w.chunks_exact_mut(WIDTH))
        .zip(x.chunks_exact_mut(WIDTH))
        .zip(f.chunks_exact_mut(WIDTH).zip(t.chunks_exact_mut(WIDTH)));
    for (((vc, wc), xc), (fc, tc)) in chunks {
        let mut vv: [f64; WIDTH] = (&*vc).try_into().expect("whole chunk");
        let mut ww: [f64; WIDTH] = (&*wc).try_into().expect("whole chunk");
        let mut xx: [f64; WIDTH] = (&*xc).try_into().expect("whole chunk");
        for l in 0..WIDTH {
            one::<KICK, KICK_DRIFT>(
                (&mut vv[l], &mut ww[l], &mut xx[l]),
                (fc[l], tc[l]),
                (kv, kw, dt),
                &mut probe[l],
            );
        }
        vc.copy_from_slice(&vv);
        wc.copy_from_slice(&ww);
        xc.copy_from_slice(&xx);
        if KICK_DRIFT {
            fc.copy_from_slice(&weights[phase..phase + WIDTH]);
            tc.fill(0.0);
            phase = (phase + WIDTH) % 3;
        }
    }
    let whole = v.len() - v.len() % WIDTH;
    let rest = v[whole..]
        .iter_mut()
        .zip(&mut w[whole..])
        .zip(&mut x[whole..])
        .zip(f[whole..].iter_mut().zip(&mut t[whole..]));
    for (q, (((v, w), x), (f, t))) in (whole..).zip(rest) {
        one::<KICK, KICK_DRIFT>((v, w, x), (*f, *t), (kv, kw, dt), &mut probe[0]);
        if KICK_DRIFT {
            (*f, *t) = (weight[q % 3], 0.0);
        }
    }
    probe.iter().sum()
}

/// The largest |Δt v| of the numbers `v` [m]: a drift's reach, read back from the block
/// the flat pass has just written. Rounding is monotonic, so the
/// largest of the drift's products Δt v is Δt times the largest |v|, to the bit. A NaN
/// comes out as NaN.
///
/// The largest |v| as the maximum of the numbers' bits, as unsigned integers, sign
/// cleared: their order is that of the numbers, and every NaN lies above infinity, so it
/// is kept where a floating-point `>` would drop it. A plain integer reduction, which the
/// compiler vectorises; with the product inside the loop it vectorised across chunks, with
/// gathers.
pub(super) fn reach_of(v: &[f64], dt: f64) -> f64 {
    let bits: &[u64] = bytemuck::cast_slice(v);
    let largest = bits.iter().fold(0u64, |m, &b| m.max(b & !SIGN));
    dt * f64::from_bits(largest)
}

/// The sign bit of an f64.
pub(super) const SIGN: u64 = 1 << 63;

/// [`flat_pass`] on one number of v, ω and x.
#[inline(always)]
pub(super) fn one<const KICK: bool, const KICK_DRIFT: bool>(
    (v, w, x): (&mut f64, &mut f64, &mut f64),
    (f, t): (f64, f64),
    (kv, kw, dt): (f64, f64, f64),
    probe: &mut f64,
) {
    if KICK {
        *v += kv * f;
        *w += kw * t;
        *probe += (*v + *w) * 0.0;
    }
    if KICK_DRIFT {
        *v += kv * f;
        *w += kw * t;
        *x += dt * *v;
    }
}
