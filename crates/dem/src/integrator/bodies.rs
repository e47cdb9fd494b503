//! The bodies one kick-and-drift pass moves, as disjoint mutable views, so that contiguous
//! ranges of them can move on several threads at once.

use super::*;

/// The half kick and drift of the bodies `b`, by the flat pass when `uniform` holds 1/m and
/// 1/I, particle by particle otherwise; `weight` is [`shared_weight`]. Inlined with both
/// passes, so that each caller holds its own copy of the loops.
#[inline(always)]
pub(super) fn kick_drift_bodies(
    b: Bodies,
    (half, dt): (f64, f64),
    pending: bool,
    uniform: Option<(f64, f64)>,
    (gravity, weight): (DVec3, DVec3),
) -> (f64, bool, bool) {
    match uniform {
        Some((inv_mass, inv_inertia)) => kick_drift_flat(
            b,
            (half * inv_mass, half * inv_inertia),
            (dt, weight),
            pending,
            (true, false),
        )
        .into(),
        None => kick_drift_per_body(b, (half, dt), gravity, pending),
    }
}

/// Ranges per pool thread in the parallel [`kick_drift`]: more than one balances them.
pub(super) const RANGES_PER_THREAD: usize = 4;

/// Particles per range of the parallel [`kick_drift`], at least. The pass is short (about
/// 3 ns a particle), but even for the paper's 3000 spheres it pays to share it: left idle
/// for its duration, the pool's other thread would go to sleep, and waking it for the force
/// passes costs more (two threads, `hopperflow bench --case hopper`: 52–59 ns per
/// particle-step with this pass shared, 63–71 ns with it on one thread).
pub(super) const MIN_RANGE: usize = 256;

/// The slices of one contiguous range of particles that a half kick and drift read and write,
/// cut to one length so that indexing is checked once.
pub(super) struct Bodies<'a> {
    pub(super) flags: &'a [u8],
    /// Forces [N]: read for the kicks, then set to the weight m g.
    pub(super) force: &'a mut [DVec3],
    /// Torques [N m]: read for the kicks, then set to zero.
    pub(super) torque: &'a mut [DVec3],
    /// Masses [kg].
    pub(super) mass: &'a [f64],
    pub(super) inv_mass: &'a [f64],
    pub(super) inv_inertia: &'a [f64],
    pub(super) velocity: &'a mut [DVec3],
    pub(super) omega: &'a mut [DVec3],
    pub(super) position: &'a mut [DVec3],
    /// Positions at the last list build [m].
    pub(super) reference: &'a [DVec3],
}

impl<'a> Bodies<'a> {
    /// Every particle of `p`.
    pub(super) fn of(p: &'a mut ParticleSet, reference: &'a [DVec3]) -> Self {
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

    pub(super) fn len(&self) -> usize {
        self.flags.len()
    }

    /// The first `k` particles and the rest.
    pub(super) fn split_at(self, k: usize) -> (Self, Self) {
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
