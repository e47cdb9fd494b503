//! Velocity Verlet (physics.md §6.2): the half kicks and the drift, with the reductions the
//! simulation needs from the same pass (largest displacement since the last list build,
//! finiteness probes).
//!
//! Two forms of the same arithmetic:
//! - the general one walks particle by particle, honouring each one's flags, mass and
//!   moment of inertia;
//! - when every particle is free (no flags) and all share one mass and one moment of inertia
//!   (the paper's monodisperse beds), the kicks and the drift are the same operation on
//!   every component of every particle, so they run over the vectors as flat arrays of
//!   numbers, which the compiler vectorises. Each component goes through exactly the
//!   operations of the general form, in the same order, so the trajectory is bit-identical
//!   (a test checks it).
//!
//! The pass that drifts also restarts the force arrays for the coming evaluation: once a
//! particle's force and torque have given their kicks they are dead until the next
//! evaluation, which starts each body from its weight m g and zero torque. Writing those
//! here, into cache lines the pass has just read, replaces a sweep of its own over both
//! arrays at the start of the evaluation (about 4 % of a step on the paper's base case,
//! docs/performance-log.md, twenty-second session). The values are the same products, so the
//! trajectory is unchanged.

use glam::DVec3;
use rayon::prelude::*;

use crate::particles::{ParticleSet, FLAG_FROZEN, FLAG_ROTATION_LOCKED};
use crate::ranges::even_bounds;

/// 1/m [1/kg] and 1/I [1/(kg m²)] shared by every particle, when every particle is free
/// (no flags) and they are all alike (their masses too, which the flat pass writes the
/// weights from); `None` otherwise.
pub(crate) fn uniform_free_body(p: &ParticleSet) -> Option<(f64, f64)> {
    let (&m, &i, &mass) = (p.inv_mass.first()?, p.inv_inertia.first()?, p.mass.first()?);
    let alike = p.flags.iter().all(|&f| f == 0)
        && p.inv_mass.iter().all(|&x| x == m)
        && p.inv_inertia.iter().all(|&x| x == i)
        && p.mass.iter().all(|&x| x == mass);
    alike.then_some((m, i))
}

/// Half kick and drift (see [`kick_drift_general`] for the contract), leaving each body's
/// weight m g [N] (`gravity` g [m/s²]) in its force and zero in its torque once they have
/// given their kicks. `uniform`: the result of [`uniform_free_body`] for the current
/// particles. With a `pool`, contiguous ranges of
/// particles are moved in parallel: each particle's arithmetic is its own, and the reductions
/// (a maximum and two all-finite flags) do not depend on the order they are merged in, so
/// the result is the same on any number of threads.
pub(crate) fn kick_drift(
    p: &mut ParticleSet,
    reference: &[DVec3],
    (half, dt): (f64, f64),
    pending: bool,
    uniform: Option<(f64, f64)>,
    gravity: DVec3,
    pool: Option<&rayon::ThreadPool>,
) -> (f64, bool, bool) {
    let n = p.len();
    let weight = shared_weight(p, gravity);
    let bodies = Bodies::of(p, reference);
    let one = |b: Bodies| kick_drift_bodies(b, (half, dt), pending, uniform, (gravity, weight));
    let bounds =
        pool.map(|pool| even_bounds(n, pool.current_num_threads(), RANGES_PER_THREAD, MIN_RANGE));
    let (Some(pool), Some(bounds)) = (pool, bounds.filter(|b| b.len() > 2)) else {
        return one(bodies);
    };
    let mut parts = Vec::with_capacity(bounds.len() - 1);
    let mut rest = bodies;
    for w in bounds.windows(2) {
        let (part, tail) = rest.split_at(w[1] - w[0]);
        parts.push(part);
        rest = tail;
    }
    let results: Vec<(f64, bool, bool)> =
        pool.install(|| parts.into_par_iter().with_max_len(1).map(one).collect());
    results.into_iter().fold(NOTHING_MOVED, merge_drift)
}

/// What [`kick_drift`] reports for no bodies: the neutral element of [`merge_drift`].
pub(crate) const NOTHING_MOVED: (f64, bool, bool) = (0.0, true, true);

/// The findings of two kick-and-drift passes over disjoint sets of bodies, as one pass over
/// both would report them: the larger squared displacement, and both finiteness flags.
pub(crate) fn merge_drift(
    (d, x, v): (f64, bool, bool),
    (d2, x2, v2): (f64, bool, bool),
) -> (f64, bool, bool) {
    (if d2 > d { d2 } else { d }, x & x2, v & v2)
}

/// [`kick_drift`] of the particles in `range` only, on the calling thread: each of them
/// gets exactly the arithmetic of the whole pass, and the reductions cover the range. The
/// one-thread evaluation of large systems (`Simulation`) calls it on each chunk of bodies
/// as soon as the chunk's forces are whole, while its numbers are still in the cache.
pub(crate) fn kick_drift_range(
    p: &mut ParticleSet,
    reference: &[DVec3],
    range: std::ops::Range<usize>,
    (half, dt): (f64, f64),
    pending: bool,
    uniform: Option<(f64, f64)>,
    gravity: DVec3,
) -> (f64, bool, bool) {
    let weight = shared_weight(p, gravity);
    let (_, rest) = Bodies::of(p, reference).split_at(range.start);
    let (bodies, _) = rest.split_at(range.len());
    kick_drift_bodies(bodies, (half, dt), pending, uniform, (gravity, weight))
}

/// Every body's weight m g [N] (`gravity` g [m/s²]) when they share one mass
/// (`uniform_free_body` checks it): the same product as each body's own.
fn shared_weight(p: &ParticleSet, gravity: DVec3) -> DVec3 {
    p.mass.first().map_or(DVec3::ZERO, |&m| m * gravity)
}

/// The half kick and drift of the bodies `b`, by the flat pass when `uniform` holds 1/m and
/// 1/I, particle by particle otherwise; `weight` is [`shared_weight`]. Inlined with both
/// passes, so that each caller holds its own copy of the loops.
#[inline(always)]
fn kick_drift_bodies(
    b: Bodies,
    (half, dt): (f64, f64),
    pending: bool,
    uniform: Option<(f64, f64)>,
    (gravity, weight): (DVec3, DVec3),
) -> (f64, bool, bool) {
    match uniform {
        Some((inv_mass, inv_inertia)) => kick_drift_uniform(
            b,
            (half * inv_mass, half * inv_inertia),
            (dt, weight),
            pending,
            (true, false),
        )
        .into(),
        None => kick_drift_general(b, (half, dt), gravity, pending),
    }
}

/// Ranges per pool thread in the parallel [`kick_drift`]: more than one balances them.
const RANGES_PER_THREAD: usize = 4;

/// Particles per range of the parallel [`kick_drift`], at least. The pass is short (about
/// 3 ns a particle), but even for the paper's 3000 spheres it pays to share it: left idle
/// for its duration, the pool's other thread would go to sleep, and waking it for the force
/// passes costs more (two threads, `hopperflow bench --case hopper`: 52–59 ns per
/// particle-step with this pass shared, 63–71 ns with it on one thread).
const MIN_RANGE: usize = 256;

/// The slices of one contiguous range of particles that a half kick and drift read and write,
/// cut to one length so that indexing is checked once.
struct Bodies<'a> {
    flags: &'a [u8],
    /// Forces [N]: read for the kicks, then set to the weight m g.
    force: &'a mut [DVec3],
    /// Torques [N m]: read for the kicks, then set to zero.
    torque: &'a mut [DVec3],
    /// Masses [kg].
    mass: &'a [f64],
    inv_mass: &'a [f64],
    inv_inertia: &'a [f64],
    velocity: &'a mut [DVec3],
    omega: &'a mut [DVec3],
    position: &'a mut [DVec3],
    /// Positions at the last list build [m].
    reference: &'a [DVec3],
}

impl<'a> Bodies<'a> {
    /// Every particle of `p`.
    fn of(p: &'a mut ParticleSet, reference: &'a [DVec3]) -> Self {
        let n = p.len();
        Self {
            flags: &p.flags[..n],
            force: &mut p.force[..n],
            torque: &mut p.torque[..n],
            mass: &p.mass[..n],
            inv_mass: &p.inv_mass[..n],
            inv_inertia: &p.inv_inertia[..n],
            velocity: &mut p.velocity[..n],
            omega: &mut p.omega[..n],
            position: &mut p.position[..n],
            reference: &reference[..n],
        }
    }

    fn len(&self) -> usize {
        self.flags.len()
    }

    /// The first `k` particles and the rest.
    fn split_at(self, k: usize) -> (Self, Self) {
        let (flags, flags_b) = self.flags.split_at(k);
        let (force, force_b) = self.force.split_at_mut(k);
        let (torque, torque_b) = self.torque.split_at_mut(k);
        let (mass, mass_b) = self.mass.split_at(k);
        let (inv_mass, inv_mass_b) = self.inv_mass.split_at(k);
        let (inv_inertia, inv_inertia_b) = self.inv_inertia.split_at(k);
        let (velocity, velocity_b) = self.velocity.split_at_mut(k);
        let (omega, omega_b) = self.omega.split_at_mut(k);
        let (position, position_b) = self.position.split_at_mut(k);
        let (reference, reference_b) = self.reference.split_at(k);
        (
            Self {
                flags,
                force,
                torque,
                mass,
                inv_mass,
                inv_inertia,
                velocity,
                omega,
                position,
                reference,
            },
            Self {
                flags: flags_b,
                force: force_b,
                torque: torque_b,
                mass: mass_b,
                inv_mass: inv_mass_b,
                inv_inertia: inv_inertia_b,
                velocity: velocity_b,
                omega: omega_b,
                position: position_b,
                reference: reference_b,
            },
        )
    }
}

/// Second half kick of every free particle; false when some velocity or spin may be
/// non-finite. `uniform` as in [`kick_drift`].
pub(crate) fn kick(p: &mut ParticleSet, half: f64, uniform: Option<(f64, f64)>) -> bool {
    match uniform {
        Some((inv_mass, inv_inertia)) => {
            let (kv, kw) = (half * inv_mass, half * inv_inertia);
            let (v, w, x) = (&mut p.velocity, &mut p.omega, &mut p.position);
            let forces = (&mut p.force[..], &mut p.torque[..]);
            flat_pass::<true, false>((v, w, x), forces, (kv, kw, 0.0), DVec3::ZERO) == 0.0
        }
        None => kick_general(p, half),
    }
}

/// [`kick_drift`] on the calling thread for free bodies that share 1/m and 1/I
/// (`uniform`, as [`uniform_free_body`] finds them), measuring the displacements since the
/// last list build only when `measure` ([`Moved`]). The simulation asks for them only when
/// its bound on them ([`crate::reach::ReachBound`]) cannot rule a list build out.
pub(crate) fn kick_drift_measured(
    p: &mut ParticleSet,
    reference: &[DVec3],
    (half, dt): (f64, f64),
    pending: bool,
    (inv_mass, inv_inertia): (f64, f64),
    gravity: DVec3,
    measure: bool,
) -> Moved {
    let weight = shared_weight(p, gravity);
    let b = Bodies::of(p, reference);
    let (kv, kw) = (half * inv_mass, half * inv_inertia);
    kick_drift_uniform(b, (kv, kw), (dt, weight), pending, (measure, true))
}

/// What a uniform kick-and-drift pass found.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Moved {
    /// Largest squared displacement since the last list build [m²], where it was measured.
    pub max_disp2: Option<f64>,
    /// Every position is finite.
    pub finite: bool,
    /// The pending kick left every velocity and spin finite.
    pub kicked_finite: bool,
    /// The step's reach: the largest |Δt v_c| of any component of any body's drift [m]
    /// (0 where it was not asked for).
    pub reach: f64,
}

impl From<Moved> for (f64, bool, bool) {
    /// The findings as the other passes report them (the displacement measured).
    fn from(m: Moved) -> Self {
        (
            m.max_disp2.unwrap_or(f64::INFINITY),
            m.finite,
            m.kicked_finite,
        )
    }
}

/// [`kick_drift`] for free particles sharing `kv` = Δt/2m [s/kg] and `kw` = Δt/2I
/// [s/(kg m²)], and the weight m g [N]: per component, v += kv F (pending), v += kv F,
/// x += Δt v, and the same for ω with kw and the torque, then F = m g and T = 0; each
/// block of particles then gives its displacements, when `measure`, and its reach, when
/// `track` (only the one-thread pass whose caller keeps bounds uses it).
#[inline(always)]
fn kick_drift_uniform(
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

/// A reach [m] below which a drift cannot make a finite position non-finite, short of
/// positions some 10³⁰⁸ m out.
pub(crate) const FINITE_REACH: f64 = 1e100;

/// Numbers per vector of the flat loops (eight f64 fill a 512-bit register).
const WIDTH: usize = 8;

/// Particles per block of [`kick_drift_uniform`]: a multiple of WIDTH, and 7 arrays of
/// 24 bytes a particle in under half the 48 kB first-level cache.
const BLOCK: usize = 8 * WIDTH;

/// One pass over every component of every particle, with kv = Δt/2m, kw = Δt/2I and Δt
/// in `k`: with `KICK`, `kick`'s v += kv F, ω += kw T and its check on v + ω; with
/// `KICK_DRIFT`, this step's v += kv F, ω += kw T and x += Δt v, and then F = `weight` and
/// T = 0 for the next evaluation. Returns the check's sum, zero unless some velocity or
/// spin is not finite (0 without `KICK`).
fn flat_pass<const KICK: bool, const KICK_DRIFT: bool>(
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
fn reach_of(v: &[f64], dt: f64) -> f64 {
    let bits: &[u64] = bytemuck::cast_slice(v);
    let largest = bits.iter().fold(0u64, |m, &b| m.max(b & !SIGN));
    dt * f64::from_bits(largest)
}

/// The sign bit of an f64.
const SIGN: u64 = 1 << 63;

/// [`flat_pass`] on one number of v, ω and x.
#[inline(always)]
fn one<const KICK: bool, const KICK_DRIFT: bool>(
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

/// Largest |x − x_ref|² [m²] and a probe that is zero unless some displacement is not
/// finite, in [`LANES`] independent accumulators, as [`kick_drift_general`] takes them;
/// also the measure a [`kick_drift_measured`] pass without `measure` left out.
pub(crate) fn largest_displacement(position: &[DVec3], reference: &[DVec3]) -> (f64, f64) {
    let mut acc = [Reduction::default(); LANES];
    let chunks = position
        .chunks_exact(LANES)
        .zip(reference.chunks_exact(LANES));
    let rest = position.len() - position.len() % LANES;
    for (x, r) in chunks {
        for (lane, a) in acc.iter_mut().enumerate() {
            a.see_displacement((x[lane] - r[lane]).length_squared());
        }
    }
    for (x, r) in position[rest..].iter().zip(&reference[rest..]) {
        acc[0].see_displacement((*x - *r).length_squared());
    }
    let all = Reduction::merge_lanes(&acc);
    (all.max_disp2, all.position_probe)
}

/// The length [m] of the diagonal of the smallest axis-aligned box that holds every
/// displacement x − x_ref: twice the largest distance of a displacement from the box's
/// centre, at most. Minima and maxima do not depend on the order they are taken in, so the
/// result is the same however the bodies are grouped. Non-finite positions are reported by
/// the kick and drift before this is asked for.
pub(crate) fn displacement_box_diagonal(position: &[DVec3], reference: &[DVec3]) -> f64 {
    if position.is_empty() {
        return 0.0;
    }
    let x: &[f64] = bytemuck::cast_slice(position);
    let r: &[f64] = bytemuck::cast_slice(&reference[..position.len()]);
    // Over the flat arrays, WIDTH × 3 numbers at a time, each lane with its own extremes, so
    // that no lane waits on another's comparison; lane l always holds component l mod 3.
    const LANES3: usize = 3 * WIDTH;
    let (mut lo, mut hi) = ([f64::INFINITY; LANES3], [f64::NEG_INFINITY; LANES3]);
    for (xc, rc) in x.chunks_exact(LANES3).zip(r.chunks_exact(LANES3)) {
        for l in 0..LANES3 {
            let d = xc[l] - rc[l];
            lo[l] = if d < lo[l] { d } else { lo[l] };
            hi[l] = if d > hi[l] { d } else { hi[l] };
        }
    }
    let whole = x.len() - x.len() % LANES3;
    for (q, (a, b)) in x[whole..].iter().zip(&r[whole..]).enumerate() {
        let d = a - b;
        // `whole` is a multiple of 3, so number q of the rest is component q mod 3.
        let l = q % 3;
        lo[l] = if d < lo[l] { d } else { lo[l] };
        hi[l] = if d > hi[l] { d } else { hi[l] };
    }
    let mut extent = [0.0; 3];
    for (c, e) in extent.iter_mut().enumerate() {
        let low = lo
            .iter()
            .skip(c)
            .step_by(3)
            .fold(f64::INFINITY, |a, &b| a.min(b));
        let high = hi
            .iter()
            .skip(c)
            .step_by(3)
            .fold(f64::NEG_INFINITY, |a, &b| a.max(b));
        *e = high - low;
    }
    DVec3::from(extent).length()
}

/// Half kick and drift of every free particle (velocity Verlet, physics.md §6.2), preceded
/// when `pending` by the previous step's second half kick, with Δt/2 and Δt [s] in
/// `(half, dt)`; then every body's force becomes its weight m g (`gravity` g [m/s²]) and
/// its torque zero, frozen bodies' too (the evaluation starts from them). Returns the largest squared
/// displacement from `reference` [m²], whether every displacement was finite, and whether
/// the pending kick left every velocity finite.
///
/// The three reductions (largest displacement, finiteness of positions and of velocities)
/// are kept in [`LANES`] independent accumulators, merged at the end: one accumulator per
/// reduction made each particle wait on the previous one's `max` and additions. The maximum
/// of a set does not depend on the order it is taken in, and the two finiteness probes are
/// sums of zeros unless something is not finite, so the results are the same as one pass.
#[inline(always)]
fn kick_drift_general(
    b: Bodies,
    (half, dt): (f64, f64),
    gravity: DVec3,
    pending: bool,
) -> (f64, bool, bool) {
    let n = b.len();
    let mut body = KickDrift {
        b,
        half,
        dt,
        gravity,
    };
    let mut acc = [Reduction::default(); LANES];
    let whole = n - n % LANES;
    for start in (0..whole).step_by(LANES) {
        for (lane, acc) in acc.iter_mut().enumerate() {
            body.one(start + lane, pending, acc);
        }
    }
    for k in whole..n {
        body.one(k, pending, &mut acc[0]);
    }
    let all = Reduction::merge_lanes(&acc);
    (
        all.max_disp2,
        all.position_probe == 0.0,
        all.velocity_probe == 0.0,
    )
}

/// Independent accumulators of [`kick_drift`].
const LANES: usize = 4;

/// One lane's reductions.
#[derive(Clone, Copy, Default)]
struct Reduction {
    /// Largest squared displacement seen [m²] (non-finite ones are caught by the probe).
    max_disp2: f64,
    /// Σ |Δx|²·0: zero unless some displacement is NaN or infinite.
    position_probe: f64,
    /// Σ (v + ω)·0 after the pending kick: zero unless some velocity or spin is not finite.
    velocity_probe: f64,
}

impl Reduction {
    /// Takes one particle's squared displacement |Δx|² [m²].
    #[inline(always)]
    fn see_displacement(&mut self, d2: f64) {
        // `!(≤)` would let a NaN in; the probe reports those instead.
        if d2 > self.max_disp2 {
            self.max_disp2 = d2;
        }
        self.position_probe += d2 * 0.0;
    }

    /// The lanes merged in order: the largest displacement and the sums of the probes.
    fn merge_lanes(lanes: &[Self]) -> Self {
        lanes.iter().fold(Self::default(), |a, b| Self {
            max_disp2: if b.max_disp2 > a.max_disp2 {
                b.max_disp2
            } else {
                a.max_disp2
            },
            position_probe: a.position_probe + b.position_probe,
            velocity_probe: a.velocity_probe + b.velocity_probe,
        })
    }
}

/// [`kick_drift_general`]'s particles and step.
struct KickDrift<'a> {
    b: Bodies<'a>,
    /// Δt/2 [s].
    half: f64,
    /// Δt [s].
    dt: f64,
    /// Gravitational acceleration g [m/s²].
    gravity: DVec3,
}

impl KickDrift<'_> {
    #[inline(always)]
    fn one(&mut self, k: usize, pending: bool, acc: &mut Reduction) {
        let b = &mut self.b;
        let (f, t) = (b.force[k], b.torque[k]);
        // The evaluation's starting values (the same product as its own), frozen bodies' too.
        b.force[k] = b.mass[k] * self.gravity;
        b.torque[k] = DVec3::ZERO;
        let flags = b.flags[k];
        if flags & FLAG_FROZEN != 0 {
            return;
        }
        let rotates = flags & FLAG_ROTATION_LOCKED == 0;
        let (kv, kw) = (self.half * b.inv_mass[k], self.half * b.inv_inertia[k]);
        let (mut v, mut w) = (b.velocity[k], b.omega[k]);
        if pending {
            // Exactly `kick`'s operations, then the same check.
            v += kv * f;
            if rotates {
                w += kw * t;
            }
            acc.velocity_probe += (v + w).element_sum() * 0.0;
        }
        v += kv * f;
        if rotates {
            w += kw * t;
        }
        let x = b.position[k] + self.dt * v;
        b.velocity[k] = v;
        b.omega[k] = w;
        b.position[k] = x;
        acc.see_displacement((x - b.reference[k]).length_squared());
    }
}

/// Second half kick of every free particle. Returns false when some velocity or spin may be
/// non-finite: x·0 is 0 for finite x and NaN otherwise, so one sum checks all six components.
fn kick_general(p: &mut ParticleSet, half: f64) -> bool {
    let mut probe = 0.0;
    let bodies = p
        .flags
        .iter()
        .zip(&p.force)
        .zip(&p.torque)
        .zip(&p.inv_mass)
        .zip(&p.inv_inertia);
    for (((((&flags, &f), &t), &inv_m), &inv_i), (v, w)) in
        bodies.zip(p.velocity.iter_mut().zip(p.omega.iter_mut()))
    {
        if flags & FLAG_FROZEN != 0 {
            continue;
        }
        *v += (half * inv_m) * f;
        if flags & FLAG_ROTATION_LOCKED == 0 {
            *w += (half * inv_i) * t;
        }
        probe += (*v + *w).element_sum() * 0.0;
    }
    probe == 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::particles::{MaterialId, ParticleInit};
    use rand::{Rng, SeedableRng};

    /// Gravity [m/s²] with three unequal components, so that a weight written from the
    /// wrong component of the flat force array shows.
    const G: DVec3 = DVec3::new(0.3, -1.7, -9.81);

    /// The flat, many-lane pass must give the box of the displacements exactly: the same
    /// extremes, in every component, as one body at a time, for counts below, at and past
    /// the 24 numbers of a vector chunk. Displacements are uniform in a cube of ±50 µm, so
    /// the extremes fall on different bodies and lanes from one count to the next.
    #[test]
    fn displacement_box_is_that_of_one_body_at_a_time() {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(11);
        for n in [0, 1, 2, 7, 8, 9, 23, 24, 25, 64, 203] {
            let reference: Vec<DVec3> = (0..n)
                .map(|_| DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 0.1)
                .collect();
            let position: Vec<DVec3> = reference
                .iter()
                .map(|r| *r + DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 1e-4 - 5e-5)
                .collect();
            let (lo, hi) = position.iter().zip(&reference).fold(
                (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                |(lo, hi), (x, r)| (lo.min(*x - *r), hi.max(*x - *r)),
            );
            let expected = if n == 0 { 0.0 } else { (hi - lo).length() };
            // Exact: extremes are found, not computed, and the diagonal is the same formula.
            assert_eq!(
                displacement_box_diagonal(&position, &reference).to_bits(),
                expected.to_bits(),
                "{n} bodies"
            );
        }
    }

    /// 203 equal free spheres (not a multiple of the vector width, so the remainder loop
    /// runs too) with random positions, velocities, spins, forces and torques.
    fn bed(seed: u64) -> (ParticleSet, Vec<DVec3>) {
        bed_of(seed, 203)
    }

    /// [`bed`] with `n` particles.
    fn bed_of(seed: u64, n: usize) -> (ParticleSet, Vec<DVec3>) {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let mut u = move |s: f64| DVec3::new(rng.gen(), rng.gen(), rng.gen()) * s - s / 2.0;
        let mut p = ParticleSet::default();
        let mut reference = Vec::new();
        for _ in 0..n {
            let mut init = ParticleInit::at_rest(u(0.1), 1.5e-3, MaterialId(0));
            init.velocity = u(2.0);
            init.angular_velocity = u(500.0);
            p.push(&init, 2500.0);
            reference.push(init.position + u(1e-4));
        }
        for k in 0..p.len() {
            p.force[k] = u(1e-2);
            p.torque[k] = u(1e-5);
        }
        (p, reference)
    }

    #[test]
    fn flat_form_is_bit_identical_to_the_particle_by_particle_form() {
        // The flat form claims the same operations per component in the same order, so
        // every number must agree exactly, with and without a pending kick.
        for (seed, pending) in [(1, false), (2, true)] {
            let (mut general, reference) = bed(seed);
            let mut flat = general.clone();
            let uniform = uniform_free_body(&flat);
            assert!(uniform.is_some(), "equal free spheres share one body");
            let (half, dt) = (1.25e-6, 2.5e-6);
            let a =
                kick_drift_general(Bodies::of(&mut general, &reference), (half, dt), G, pending);
            let b = kick_drift(&mut flat, &reference, (half, dt), pending, uniform, G, None);
            assert_eq!(a, b, "displacement and probes");
            assert_eq!(general.position, flat.position);
            assert_eq!(general.velocity, flat.velocity);
            assert_eq!(general.omega, flat.omega);
            // Both forms leave the evaluation's starting values: the weight m g, the same
            // product the evaluation used to form itself, exactly, and zero torque.
            for p in [&general, &flat] {
                for k in 0..p.len() {
                    assert_eq!(p.force[k], p.mass[k] * G, "particle {k}");
                    assert_eq!(p.torque[k], DVec3::ZERO, "particle {k}");
                }
            }
            assert_eq!(
                kick_general(&mut general, half),
                kick(&mut flat, half, uniform)
            );
            assert_eq!(general.velocity, flat.velocity);
            assert_eq!(general.omega, flat.omega);
        }
    }

    #[test]
    fn flat_form_reports_what_the_general_form_reports() {
        // A NaN force must fail the velocity probe of `kick`, and a displaced particle
        // must give the largest displacement, in both forms.
        let (mut general, _) = bed(3);
        general.force[150].y = f64::NAN;
        let mut flat = general.clone();
        let uniform = uniform_free_body(&flat);
        assert!(!kick_general(&mut general, 1e-6));
        assert!(!kick(&mut flat, 1e-6, uniform));
        let (mut general, mut reference2) = bed(4);
        reference2[77] -= DVec3::new(0.0, 0.0, 5e-3);
        let mut flat = general.clone();
        let uniform = uniform_free_body(&flat);
        let a = kick_drift_general(
            Bodies::of(&mut general, &reference2),
            (1e-6, 2e-6),
            G,
            false,
        );
        let b = kick_drift(
            &mut flat,
            &reference2,
            (1e-6, 2e-6),
            false,
            uniform,
            G,
            None,
        );
        assert_eq!(a, b);
        assert!(
            a.0 >= 2.4e-5,
            "the moved particle sets the maximum: {}",
            a.0
        );
    }

    #[test]
    fn flags_or_unequal_bodies_take_the_general_form() {
        let (mut p, _) = bed(5);
        assert!(uniform_free_body(&p).is_some());
        p.flags[10] = FLAG_ROTATION_LOCKED;
        assert!(uniform_free_body(&p).is_none(), "a flag");
        let (mut p, _) = bed(5);
        p.inv_mass[3] *= 2.0;
        assert!(uniform_free_body(&p).is_none(), "a different mass");
    }

    #[test]
    fn parallel_ranges_match_one_pass_bit_for_bit() {
        // With a pool the particles are moved in ranges on several threads. Each particle's
        // arithmetic is unchanged and the reductions are a maximum and two flags, so every
        // number and the reported maximum must agree exactly, in both forms. 10 000 particles
        // on three threads make twelve ranges; the largest displacement and a NaN force are
        // placed in a late range, so that the merge, not the first range, must carry them.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .expect("a three-thread pool");
        for general in [false, true] {
            for pending in [false, true] {
                let (mut one, mut reference) = bed_of(7, 10_000);
                reference[9000] -= DVec3::new(0.0, 3e-3, 0.0);
                if general {
                    one.flags[40] = FLAG_ROTATION_LOCKED;
                }
                let mut many = one.clone();
                let uniform = uniform_free_body(&one);
                assert_eq!(uniform.is_none(), general);
                let step = (1.25e-6, 2.5e-6);
                let a = kick_drift(&mut one, &reference, step, pending, uniform, G, None);
                let b = kick_drift(
                    &mut many,
                    &reference,
                    step,
                    pending,
                    uniform,
                    G,
                    Some(&pool),
                );
                assert_eq!(a, b, "displacement and probes");
                // Moved 3 mm from a reference within 0.1 mm of it: d² ≥ (2.9 mm)².
                assert!(
                    a.0 >= 8.4e-6,
                    "the moved particle sets the maximum: {}",
                    a.0
                );
                assert_eq!(one.position, many.position);
                assert_eq!(one.velocity, many.velocity);
                assert_eq!(one.omega, many.omega);
                assert_eq!(one.force, many.force, "the weights");
                assert_eq!(one.torque, many.torque);
            }
        }
        let (mut one, reference) = bed_of(8, 10_000);
        one.force[9500].x = f64::NAN;
        let mut many = one.clone();
        let uniform = uniform_free_body(&one);
        let step = (1.25e-6, 2.5e-6);
        let a = kick_drift(&mut one, &reference, step, true, uniform, G, None);
        let b = kick_drift(&mut many, &reference, step, true, uniform, G, Some(&pool));
        assert!(
            !a.2 && !b.2,
            "a NaN force fails the velocity probe on any thread count"
        );
        assert!(!a.1 && !b.1, "and the position probe");
    }
}
