//! The per-body form of the kicks and the drift: body by body, honouring each one's flags,
//! mass and moment of inertia.

use super::*;

/// Half kick and drift of every free particle (velocity Verlet, docs/physics.md §6.2), preceded
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
pub(super) fn kick_drift_per_body(
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
pub(super) const LANES: usize = 4;

/// One lane's reductions.
#[derive(Clone, Copy, Default)]
pub(super) struct Reduction {
    /// Largest squared displacement seen [m²] (non-finite ones are caught by the probe).
    pub(super) max_disp2: f64,
    /// Σ |Δx|²·0: zero unless some displacement is NaN or infinite.
    pub(super) position_probe: f64,
    /// Σ (v + ω)·0 after the pending kick: zero unless some velocity or spin is not finite.
    pub(super) velocity_probe: f64,
}

impl Reduction {
    /// Takes one particle's squared displacement |Δx|² [m²].
    #[inline(always)]
    pub(super) fn see_displacement(&mut self, d2: f64) {
        // `!(≤)` would let a NaN in; the probe reports those instead.
        if d2 > self.max_disp2 {
            self.max_disp2 = d2;
        }
        self.position_probe += d2 * 0.0;
    }

    /// The lanes merged in order: the largest displacement and the sums of the probes.
    pub(super) fn merge_lanes(lanes: &[Self]) -> Self {
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

/// [`kick_drift_per_body`]'s particles and step.
pub(super) struct KickDrift<'a> {
    pub(super) b: Bodies<'a>,
    /// Δt/2 [s].
    pub(super) half: f64,
    /// Δt [s].
    pub(super) dt: f64,
    /// Gravitational acceleration g [m/s²].
    pub(super) gravity: DVec3,
}

impl KickDrift<'_> {
    #[inline(always)]
    pub(super) fn one(&mut self, k: usize, pending: bool, acc: &mut Reduction) {
        let b = &mut self.b;
        let (f, t) = (b.force[k], b.torque[k]);
        // The evaluation's starting values (the same product as its own), frozen bodies' too.
        b.force[k] = b.mass[k] * self.gravity;
        b.torque[k] = DVec3::ZERO;
        let flags = b.flags[k];
        if flags & FLAG_HELD != 0 {
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
pub(super) fn kick_per_body(p: &mut ParticleSet, half: f64) -> bool {
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
        if flags & FLAG_HELD != 0 {
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
