//! Particle storage as a structure of arrays; particles can be added and removed during a run.

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Index of a material registered with the simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct MaterialId(pub u16);

/// Stable identity of a particle; never reused within a simulation.
pub type ParticleTag = u64;

/// Rotation is held at zero (the block-sliding test A1).
pub const FLAG_ROTATION_LOCKED: u8 = 1;
/// Neither translation nor rotation is integrated (a fixed particle).
pub const FLAG_FROZEN: u8 = 2;
/// A member sphere of a rigid clump: its body moves it (docs/physics.md §11.4), the particle
/// integrator leaves it alone. Set by [`crate::Simulation::add_clump`] only.
pub const FLAG_CLUMP_MEMBER: u8 = 4;
/// The flags under which the particle integrator neither kicks nor drifts a particle.
pub(crate) const FLAG_HELD: u8 = FLAG_FROZEN | FLAG_CLUMP_MEMBER;
/// The clump of a particle that belongs to none.
pub const NO_CLUMP: u32 = u32::MAX;

/// What a new particle starts with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParticleInit {
    /// Centre position [m].
    pub position: DVec3,
    /// Centre velocity [m/s].
    pub velocity: DVec3,
    /// Angular velocity [rad/s].
    pub angular_velocity: DVec3,
    /// Radius [m].
    pub radius: f64,
    /// Material.
    pub material: MaterialId,
    /// Behaviour flags (`FLAG_*`).
    pub flags: u8,
}

impl ParticleInit {
    /// A particle at rest.
    pub fn at_rest(position: DVec3, radius: f64, material: MaterialId) -> Self {
        Self {
            position,
            velocity: DVec3::ZERO,
            angular_velocity: DVec3::ZERO,
            radius,
            material,
            flags: 0,
        }
    }
}

/// All particles, one array per field, index-aligned. Indices change when the set is
/// re-sorted or particles are removed; tags do not.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct ParticleSet {
    pub(crate) tag: Vec<ParticleTag>,
    pub(crate) position: Vec<DVec3>,
    pub(crate) velocity: Vec<DVec3>,
    pub(crate) omega: Vec<DVec3>,
    pub(crate) force: Vec<DVec3>,
    pub(crate) torque: Vec<DVec3>,
    pub(crate) radius: Vec<f64>,
    pub(crate) mass: Vec<f64>,
    pub(crate) inertia: Vec<f64>,
    /// Δt-free reciprocals, so the kicks multiply instead of divide.
    pub(crate) inv_mass: Vec<f64>,
    pub(crate) inv_inertia: Vec<f64>,
    pub(crate) material: Vec<u16>,
    pub(crate) flags: Vec<u8>,
    pub(crate) next_tag: ParticleTag,
    /// The clump (its index among the simulation's clumps) each particle is a member of, or
    /// [`NO_CLUMP`].
    #[serde(default)]
    pub(crate) clump: Vec<u32>,
}

impl ParticleSet {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.tag.len()
    }
    /// True when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.tag.is_empty()
    }
    /// Stable tags.
    pub fn tags(&self) -> &[ParticleTag] {
        &self.tag
    }
    /// Centre positions [m].
    pub fn positions(&self) -> &[DVec3] {
        &self.position
    }
    /// Centre velocities [m/s] (full step).
    pub fn velocities(&self) -> &[DVec3] {
        &self.velocity
    }
    /// Angular velocities [rad/s].
    pub fn angular_velocities(&self) -> &[DVec3] {
        &self.omega
    }
    /// Forces of the last evaluation [N].
    pub fn forces(&self) -> &[DVec3] {
        &self.force
    }
    /// Torques of the last evaluation [N m].
    pub fn torques(&self) -> &[DVec3] {
        &self.torque
    }
    /// Radii [m].
    pub fn radii(&self) -> &[f64] {
        &self.radius
    }
    /// Masses [kg].
    pub fn masses(&self) -> &[f64] {
        &self.mass
    }
    /// Moments of inertia I = (2/5) m r² [kg m²].
    pub fn inertias(&self) -> &[f64] {
        &self.inertia
    }
    /// Material index of each particle.
    pub fn materials(&self) -> &[u16] {
        &self.material
    }
    /// Behaviour flags of each particle (`FLAG_*`).
    pub fn flags(&self) -> &[u8] {
        &self.flags
    }
    /// The clump each particle belongs to (an index into the simulation's clumps), or
    /// [`NO_CLUMP`].
    pub fn clump_indices(&self) -> &[u32] {
        &self.clump
    }
    /// Current index of the particle with this tag (linear search).
    pub fn index_of(&self, tag: ParticleTag) -> Option<usize> {
        self.tag.iter().position(|&t| t == tag)
    }

    /// Reserves room for exactly `additional` more particles in every array.
    pub(crate) fn reserve_exact(&mut self, additional: usize) {
        self.tag.reserve_exact(additional);
        self.position.reserve_exact(additional);
        self.velocity.reserve_exact(additional);
        self.omega.reserve_exact(additional);
        self.force.reserve_exact(additional);
        self.torque.reserve_exact(additional);
        self.radius.reserve_exact(additional);
        self.mass.reserve_exact(additional);
        self.inertia.reserve_exact(additional);
        self.inv_mass.reserve_exact(additional);
        self.inv_inertia.reserve_exact(additional);
        self.material.reserve_exact(additional);
        self.flags.reserve_exact(additional);
        self.clump.reserve_exact(additional);
    }

    pub(crate) fn push(&mut self, init: &ParticleInit, density: f64) -> ParticleTag {
        let r = init.radius;
        let mass = density * 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
        let tag = self.next_tag;
        self.next_tag += 1;
        self.tag.push(tag);
        self.position.push(init.position);
        self.velocity.push(init.velocity);
        self.omega.push(init.angular_velocity);
        self.force.push(DVec3::ZERO);
        self.torque.push(DVec3::ZERO);
        self.radius.push(r);
        self.mass.push(mass);
        // Solid sphere, I = (2/5) m r² (docs/physics.md §6.2).
        self.inertia.push(0.4 * mass * r * r);
        self.inv_mass.push(1.0 / mass);
        self.inv_inertia.push(1.0 / (0.4 * mass * r * r));
        self.material.push(init.material.0);
        self.flags.push(init.flags);
        self.clump.push(NO_CLUMP);
        tag
    }

    /// Keeps the particles for which `keep[index]` is true, preserving their order.
    pub(crate) fn retain_mask(&mut self, keep: &[bool]) {
        retain_by_mask(&mut self.tag, keep);
        retain_by_mask(&mut self.position, keep);
        retain_by_mask(&mut self.velocity, keep);
        retain_by_mask(&mut self.omega, keep);
        retain_by_mask(&mut self.force, keep);
        retain_by_mask(&mut self.torque, keep);
        retain_by_mask(&mut self.radius, keep);
        retain_by_mask(&mut self.mass, keep);
        retain_by_mask(&mut self.inertia, keep);
        retain_by_mask(&mut self.inv_mass, keep);
        retain_by_mask(&mut self.inv_inertia, keep);
        retain_by_mask(&mut self.material, keep);
        retain_by_mask(&mut self.flags, keep);
        retain_by_mask(&mut self.clump, keep);
    }

    /// Reorders every field so that new index k holds old index `order[k]`, in place: each
    /// array keeps its memory, so that a re-sort does not move the bodies' arrays about
    /// during a run (their placement changes the step's speed by a few per cent on the
    /// paper's hopper).
    pub(crate) fn permute(&mut self, order: &[u32]) {
        fn apply<T: Copy>(v: &mut [T], order: &[u32]) {
            let new: Vec<T> = order.iter().map(|&o| v[o as usize]).collect();
            v.copy_from_slice(&new);
        }
        apply(&mut self.tag, order);
        apply(&mut self.position, order);
        apply(&mut self.velocity, order);
        apply(&mut self.omega, order);
        apply(&mut self.force, order);
        apply(&mut self.torque, order);
        apply(&mut self.radius, order);
        apply(&mut self.mass, order);
        apply(&mut self.inertia, order);
        apply(&mut self.inv_mass, order);
        apply(&mut self.inv_inertia, order);
        apply(&mut self.material, order);
        apply(&mut self.flags, order);
        apply(&mut self.clump, order);
    }
}

/// Keeps the entries of `v` for which `keep[index]` is true, preserving their order: the one
/// rule by which the particle arrays and the clumps' arrays drop entries.
pub(crate) fn retain_by_mask<T>(v: &mut Vec<T>, keep: &[bool]) {
    let mut k = 0;
    v.retain(|_| {
        k += 1;
        keep[k - 1]
    });
}
