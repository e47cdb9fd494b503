//! A read-only view of the bodies between steps, with velocities at the full step even
//! where the step's second half kick is still pending ([`crate::Simulation::run_watched`]).

use glam::DVec3;

use crate::clump::ClumpSet;
use crate::contacts::{ContactSource, Contacts};
use crate::forces::loads::WallLoad;
use crate::particles::{ParticleSet, ParticleTag, FLAG_HELD};
use crate::wall::{Wall, WallId};

/// The bodies at one step, as a caller that measures them sees them: tags, positions,
/// radii, masses, velocities at the full step, and the loads on the walls in that step.
///
/// Between the steps of a run the velocities stored are half a kick behind: each step's
/// second half kick v += (Δt/2m) F waits for the next step's pass. [`Watched::velocity`]
/// adds it, with the same product and sum as the kick itself (`integrator::kick`), so it
/// returns the bits the kick would store.
#[derive(Debug, Clone, Copy)]
pub struct Watched<'a> {
    particles: &'a ParticleSet,
    /// The rigid clumps, whose members are among `particles`; their velocities are at the
    /// full step (a clump takes its whole second kick in its step).
    clumps: &'a ClumpSet,
    time: f64,
    /// The walls by id (`None` where one was removed) and their loads in the step.
    walls: &'a [Option<Wall>],
    wall_loads: &'a [WallLoad],
    /// Each wall's load integrated over time since it was added [N s, N m s].
    wall_impulses: &'a [WallLoad],
    /// The pending kick: Δt/2 [s], and the reciprocal mass [1/kg] and inertia [1/(kg m²)]
    /// that all bodies share when they do (`integrator::uniform_free_body`).
    pending: Option<(f64, Option<(f64, f64)>)>,
    /// What [`Watched::contacts`] recomputes the contacts from; `None` where the lists and
    /// coefficients are not those of the bodies shown (before the first step, after an edit).
    contacts: Option<ContactSource<'a>>,
}

impl<'a> Watched<'a> {
    pub(crate) fn new(
        (particles, clumps): (&'a ParticleSet, &'a ClumpSet),
        time: f64,
        walls: (&'a [Option<Wall>], &'a [WallLoad], &'a [WallLoad]),
        pending: Option<(f64, Option<(f64, f64)>)>,
        contacts: Option<ContactSource<'a>>,
    ) -> Self {
        Self {
            particles,
            clumps,
            time,
            walls: walls.0,
            wall_loads: walls.1,
            wall_impulses: walls.2,
            pending,
            contacts,
        }
    }

    /// The contacts that carry force, recomputed from the state shown: for each
    /// particle–particle contact the two indices, the force on the first [N] and the contact
    /// point [m]; for each particle–wall contact the particle, the wall, the force on the
    /// particle [N] and the wall's contact point [m] (`crates/dem/src/contacts.rs` says how,
    /// and what it costs: one pass of the scalar contact laws over the candidate lists).
    /// Reads only; the simulation keeps its bits. `None` where the view has no current
    /// contact lists: before the first step, or after an edit until the next step.
    pub fn contacts(&self) -> Option<Contacts> {
        self.contacts
            .map(|source| source.contacts(self.particles, self.walls))
    }

    /// The time integral of the load on wall `id` since it was added, as
    /// [`crate::Simulation::wall_impulse`] gives it; `None` for a wall that is not present.
    pub fn wall_impulse(&self, id: WallId) -> Option<WallLoad> {
        let k = id.0 as usize;
        self.walls.get(k)?.as_ref()?;
        Some(self.wall_impulses.get(k).copied().unwrap_or_default())
    }

    /// The load the particles exerted on wall `id` in the step, as
    /// [`crate::Simulation::wall_load`] gives it (zero for a wall that does not sum its
    /// load, and before the first step); `None` for a wall that is not present.
    pub fn wall_load(&self, id: WallId) -> Option<WallLoad> {
        let k = id.0 as usize;
        self.walls.get(k)?.as_ref()?;
        Some(self.wall_loads.get(k).copied().unwrap_or_default())
    }

    /// Simulated time of the step [s].
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.particles.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.particles.is_empty()
    }

    /// The rigid clumps: centres of mass, velocities at the full step, orientations and
    /// bodies. Their members are among the particles this view shows, each flagged by
    /// [`Watched::clump_indices`].
    pub fn clumps(&self) -> &'a ClumpSet {
        self.clumps
    }

    /// Each particle's clump, an index into [`Watched::clumps`], or
    /// [`crate::NO_CLUMP`] for a free sphere.
    pub fn clump_indices(&self) -> &'a [u32] {
        self.particles.clump_indices()
    }

    /// Stable tags.
    pub fn tags(&self) -> &'a [ParticleTag] {
        self.particles.tags()
    }

    /// Centre positions [m].
    pub fn positions(&self) -> &'a [DVec3] {
        self.particles.positions()
    }

    /// Radii [m].
    pub fn radii(&self) -> &'a [f64] {
        self.particles.radii()
    }

    /// Masses [kg].
    pub fn masses(&self) -> &'a [f64] {
        self.particles.masses()
    }

    /// Total force on body `k` in the step [N]: its weight and every contact's force.
    pub fn force(&self, k: usize) -> DVec3 {
        self.particles.force[k]
    }

    /// Centre velocity of body `k` at the full step [m/s].
    #[inline]
    pub fn velocity(&self, k: usize) -> DVec3 {
        let p = self.particles;
        let v = p.velocity[k];
        match self.pending {
            None => v,
            // `kick`'s arithmetic: v + kv F with kv = Δt/2 · 1/m formed once for all bodies,
            // or per body, and frozen bodies left alone.
            Some((half, Some((inv_mass, _)))) => v + (half * inv_mass) * p.force[k],
            Some((half, None)) => {
                if p.flags[k] & FLAG_HELD != 0 {
                    v
                } else {
                    v + (half * p.inv_mass[k]) * p.force[k]
                }
            }
        }
    }
}
