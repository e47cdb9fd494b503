//! Drawing the particles of a fill: each particle's component by the number fractions of the
//! case's mixture, then its radius from that component's size distribution (docs/physics.md
//! §1.2, §10.8).

use dem::clump::ClumpShape;
use dem::{DVec3, MaterialId};
use rand::Rng;
use serde::{Deserialize, Serialize};

use crate::simulation::sample_radius;
use case::{ParticleSpec, SizeDistribution};

/// One drawn particle, not yet placed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Draw {
    /// Radius [m].
    pub radius: f64,
    /// Engine material.
    pub material: MaterialId,
    /// Index of its component in the case's `particles.components` (0 for a case of one).
    pub component: u8,
}

/// The particles a fill draws from: the components' sizes, materials and cumulative number
/// fractions.
///
/// A fill keeps each drawn particle until it is placed. Drawing anew after a failed
/// placement would favour the particles that are easier to place, the small ones: in a
/// random sequential addition to 16 % solid volume of the 2 mm and 4 mm spheres of
/// `cases/mixture-1to2.toml`, redrawing placed 40 % of the large ones the fractions ask for.
/// Kept draws make the placed particles the first draws in order, so their components and
/// sizes are samples of the case's distributions. A monodisperse component draws no random
/// number, so for it keeping or redrawing is the same (the same bits as before mixtures).
#[derive(Debug, Clone)]
pub struct ParticleDraws {
    sizes: Vec<SizeDistribution>,
    materials: Vec<MaterialId>,
    /// Σ_{j ≤ i} n_j for each component i [-].
    cumulative: Vec<f64>,
    /// Each component's grain shape, where it has one: the clump of unit equal-volume
    /// diameter, its reach from the centre of mass and that centre in the members' frame
    /// [equal-volume diameters].
    shapes: Vec<Option<(ClumpShape, f64, DVec3)>>,
    max_reach: f64,
}

impl ParticleDraws {
    /// The draws of `particles`, whose component i is of engine material `materials[i]`.
    pub fn new(particles: &ParticleSpec, materials: &[MaterialId]) -> Self {
        let mut total = 0.0;
        let cumulative = particles
            .number_fractions()
            .iter()
            .map(|n| {
                total += n;
                total
            })
            .collect();
        let shapes: Vec<Option<(ClumpShape, f64, DVec3)>> = particles
            .components
            .iter()
            .map(|c| {
                c.shape
                    .as_ref()
                    .map(|s| (s.unit_clump(), s.unit_reach, DVec3::from(s.unit_centre)))
            })
            .collect();
        // A grain reaches at most its shape's reach times its largest diameter from its
        // centre; a sphere, half its diameter.
        let max_reach = particles
            .components
            .iter()
            .zip(&shapes)
            .map(|(c, shape)| {
                c.size.max_diameter() * shape.as_ref().map_or(0.5, |(_, reach, _)| *reach)
            })
            .fold(0.0, f64::max);
        Self {
            sizes: particles
                .components
                .iter()
                .map(|c| c.size.clone())
                .collect(),
            materials: materials.to_vec(),
            cumulative,
            shapes,
            max_reach,
        }
    }

    /// The farthest any drawn grain reaches from its centre (of mass) [m]: the largest
    /// radius for spheres, more for elongated shapes.
    pub fn max_reach(&self) -> f64 {
        self.max_reach
    }

    /// The shape of component `component`'s grains (unit equal-volume diameter), its reach
    /// and its centre of mass [equal-volume diameters]; `None` for spheres.
    pub fn shape(&self, component: u8) -> Option<&(ClumpShape, f64, DVec3)> {
        self.shapes.get(component as usize).and_then(Option::as_ref)
    }

    /// Whether there are several components.
    pub fn is_mixture(&self) -> bool {
        self.sizes.len() > 1
    }

    /// Draws one particle. One component draws only its radius, with exactly the random
    /// numbers a fill drew before mixtures existed; a mixture first draws u uniform in
    /// [0, 1) and takes the first component whose cumulative number fraction exceeds it (the
    /// last one if rounding leaves the sum below u), so component i is drawn with
    /// probability n_i.
    pub fn draw(&self, rng: &mut dyn rand::RngCore) -> Draw {
        let component = if self.is_mixture() {
            let u: f64 = rng.gen();
            self.cumulative
                .iter()
                .position(|&c| u < c)
                .unwrap_or(self.sizes.len() - 1)
        } else {
            0
        };
        Draw {
            radius: sample_radius(&self.sizes[component], rng),
            material: self.materials[component],
            component: component as u8,
        }
    }
}
