//! The bodies of a simulation as grains, for measures that count and weigh grains whatever
//! their shape: each free sphere as it is, each clump once, at its centre of mass, with its
//! velocity, its whole mass and the radius of the sphere of its volume (docs/physics.md
//! §11.8).

use glam::DVec3;

use crate::particles::{ParticleTag, NO_CLUMP};
use crate::watch::Watched;

/// Grains as parallel arrays: free spheres first (in the particles' order), then clumps (in
/// their order).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Bodies {
    /// A free sphere's tag; a clump's first member's tag.
    pub tags: Vec<ParticleTag>,
    /// Centre, or centre of mass [m].
    pub positions: Vec<DVec3>,
    /// Velocity of the centre (of mass) at the full step [m/s].
    pub velocities: Vec<DVec3>,
    /// A sphere's radius; a clump's equal-volume radius (3V/4π)^(1/3) [m].
    pub radii: Vec<f64>,
    /// Mass [kg], a clump's whole mass once.
    pub masses: Vec<f64>,
}

impl Bodies {
    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.tags.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.tags.is_empty()
    }

    fn push(&mut self, tag: ParticleTag, x: DVec3, v: DVec3, r: f64, m: f64) {
        self.tags.push(tag);
        self.positions.push(x);
        self.velocities.push(v);
        self.radii.push(r);
        self.masses.push(m);
    }
}

impl Watched<'_> {
    /// The bodies whose centre (a clump's centre of mass) satisfies `keep`.
    pub fn bodies(&self, keep: impl Fn(DVec3) -> bool) -> Bodies {
        let mut b = Bodies::default();
        let (clump, positions) = (self.clump_indices(), self.positions());
        for k in 0..self.len() {
            if clump[k] == NO_CLUMP && keep(positions[k]) {
                b.push(
                    self.tags()[k],
                    positions[k],
                    self.velocity(k),
                    self.radii()[k],
                    self.masses()[k],
                );
            }
        }
        let clumps = self.clumps();
        for c in 0..clumps.len() {
            let x = clumps.positions()[c];
            if keep(x) {
                let body = clumps.body(c);
                let radius = (0.75 * body.volume / std::f64::consts::PI).cbrt();
                b.push(
                    clumps.first_tags()[c],
                    x,
                    clumps.velocities()[c],
                    radius,
                    body.mass,
                );
            }
        }
        b
    }

    /// Number of bodies: free spheres and clumps.
    pub fn body_count(&self) -> usize {
        let free = self
            .clump_indices()
            .iter()
            .filter(|&&c| c == NO_CLUMP)
            .count();
        free + self.clumps().len()
    }
}
