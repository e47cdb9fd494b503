//! Particle materials, size distributions and mixtures of a case, with the moments the
//! checks need. A case's particles are one or more components, each with its own size
//! distribution, material and fraction (docs/physics.md §1.2); the aggregate quantities
//! (largest diameter, mean diameter, Rayleigh time, total volume) are taken over all of them.

use serde::{Deserialize, Serialize};

use super::grain_shape::GrainShape;

/// Elastic material of particles or walls (paper Table 1 for the defaults).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MaterialSpec {
    /// Density ρ [kg/m³].
    pub density: f64,
    /// Shear modulus G [Pa].
    pub shear_modulus: f64,
    /// Poisson's ratio ν [-].
    pub poisson_ratio: f64,
}

impl MaterialSpec {
    /// Table 1: the engine's [`dem::Material::fan2023`] (ρ_p = 2500 kg/m³, G = 1e8 Pa,
    /// ν = 0.25), the one place that holds these numbers. G comes back from E = 2G(1+ν)
    /// exactly: 2.5e8 / 2.5 is 1e8 with no rounding.
    pub fn fan2023() -> Self {
        let table1 = dem::Material::fan2023();
        Self {
            density: table1.density,
            shear_modulus: table1.shear_modulus(),
            poisson_ratio: table1.poisson_ratio,
        }
    }

    /// Young's modulus E = 2G(1 + ν) [Pa].
    pub fn youngs_modulus(&self) -> f64 {
        2.0 * self.shear_modulus * (1.0 + self.poisson_ratio)
    }

    /// Rayleigh time t_R = π r √(ρ/G) / (0.1631 ν + 0.8766) [s] for a sphere of radius
    /// `radius` [m] (paper Eq. 9 with EDEM's coefficient, physics spec §6.1).
    pub fn rayleigh_time(&self, radius: f64) -> f64 {
        dem::timescale::rayleigh_time_of(
            self.density,
            self.shear_modulus,
            self.poisson_ratio,
            radius,
        )
    }
}

/// Particle diameters of a case. All diameters are in metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SizeDistribution {
    /// Every particle has the same diameter [m] (the paper: 3 mm).
    Monodisperse {
        /// The diameter [m].
        diameter: f64,
    },
    /// Diameters uniform by number on [min, max] [m].
    Uniform {
        /// Smallest diameter [m].
        min: f64,
        /// Largest diameter [m].
        max: f64,
    },
    /// Normal by number with mean and standard deviation [m], truncated to [min, max] [m].
    Normal {
        /// Mean diameter [m] before truncation.
        mean: f64,
        /// Standard deviation [m] before truncation.
        std_dev: f64,
        /// Smallest diameter kept [m].
        min: f64,
        /// Largest diameter kept [m].
        max: f64,
    },
    /// A finite set of diameters [m] with number fractions (summing to 1).
    Discrete {
        /// The diameters [m].
        diameters: Vec<f64>,
        /// The number fraction of each diameter (summing to 1).
        fractions: Vec<f64>,
    },
}

impl SizeDistribution {
    /// The same distribution with every diameter `factor` times as large.
    pub fn scaled(&self, factor: f64) -> SizeDistribution {
        match self {
            Self::Monodisperse { diameter } => Self::Monodisperse {
                diameter: diameter * factor,
            },
            Self::Uniform { min, max } => Self::Uniform {
                min: min * factor,
                max: max * factor,
            },
            Self::Normal {
                mean,
                std_dev,
                min,
                max,
            } => Self::Normal {
                mean: mean * factor,
                std_dev: std_dev * factor,
                min: min * factor,
                max: max * factor,
            },
            Self::Discrete {
                diameters,
                fractions,
            } => Self::Discrete {
                diameters: diameters.iter().map(|d| d * factor).collect(),
                fractions: fractions.clone(),
            },
        }
    }

    /// Smallest diameter that can occur [m] (sets the Rayleigh time).
    pub fn min_diameter(&self) -> f64 {
        match self {
            Self::Monodisperse { diameter } => *diameter,
            Self::Uniform { min, .. } | Self::Normal { min, .. } => *min,
            Self::Discrete { diameters, .. } => {
                diameters.iter().copied().fold(f64::INFINITY, f64::min)
            }
        }
    }

    /// Largest diameter that can occur [m] (sets the outlet, slab and fit checks).
    pub fn max_diameter(&self) -> f64 {
        match self {
            Self::Monodisperse { diameter } => *diameter,
            Self::Uniform { max, .. } | Self::Normal { max, .. } => *max,
            Self::Discrete { diameters, .. } => diameters.iter().copied().fold(0.0, f64::max),
        }
    }

    /// Number-weighted mean of d^k [m^k], k = 1, 2, 3.
    ///
    /// k = 2 gives the mean projected disc area (π/4)⟨d²⟩, k = 3 the mean volume
    /// (π/6)⟨d³⟩. The truncated normal is integrated numerically (Simpson, 400 panels,
    /// far below any tolerance the fit check needs).
    pub fn moment(&self, k: i32) -> f64 {
        match self {
            Self::Monodisperse { diameter } => diameter.powi(k),
            Self::Uniform { min, max } => {
                if max > min {
                    (max.powi(k + 1) - min.powi(k + 1)) / ((k + 1) as f64 * (max - min))
                } else {
                    min.powi(k)
                }
            }
            Self::Normal {
                mean,
                std_dev,
                min,
                max,
            } => {
                let density = |d: f64| (-0.5 * ((d - mean) / std_dev).powi(2)).exp();
                let panels = 400;
                let h = (max - min) / panels as f64;
                let (mut weight, mut weighted) = (0.0, 0.0);
                for i in 0..=panels {
                    let d = min + i as f64 * h;
                    let simpson = if i == 0 || i == panels {
                        1.0
                    } else if i % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    weight += simpson * density(d);
                    weighted += simpson * density(d) * d.powi(k);
                }
                if weight > 0.0 {
                    weighted / weight
                } else {
                    mean.powi(k)
                }
            }
            Self::Discrete {
                diameters,
                fractions,
            } => diameters
                .iter()
                .zip(fractions)
                .map(|(d, f)| f * d.powi(k))
                .sum(),
        }
    }

    /// Number-mean diameter [m].
    pub fn mean_diameter(&self) -> f64 {
        self.moment(1)
    }
}

/// How the fractions of a mixture's components are counted (`particles.fraction_by`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FractionBasis {
    /// Fractions of the number of particles (default).
    Number,
    /// Fractions of the particles' mass; the fill turns them into number fractions with
    /// [`number_fractions_from_mass`].
    Mass,
}

/// Number fractions of a mixture given by mass: component i, with mass fraction w_i and
/// mean particle mass m̄_i [kg], holds N_i ∝ w_i / m̄_i particles, so
///
/// n_i = (w_i / m̄_i) / Σ_j (w_j / m̄_j)
///
/// (docs/physics.md §1.2). For spheres m̄_i = ρ_i (π/6)⟨d³⟩_i, ⟨d³⟩_i the number-mean cube of
/// the component's diameters: two sizes 1:2 of one material, 50/50 by mass, give 8/9 and 1/9
/// by number. A zero mass fraction gives a zero number fraction.
pub fn number_fractions_from_mass(mass_fractions: &[f64], mean_masses: &[f64]) -> Vec<f64> {
    let weights: Vec<f64> = mass_fractions
        .iter()
        .zip(mean_masses)
        .map(|(w, m)| w / m)
        .collect();
    let total: f64 = weights.iter().sum();
    weights.iter().map(|w| w / total).collect()
}

/// Mass fractions of a mixture with number fractions n_i and mean particle masses m̄_i [kg]:
/// w_i = n_i m̄_i / Σ_j n_j m̄_j, the inverse of [`number_fractions_from_mass`].
pub fn mass_fractions_from_number(number_fractions: &[f64], mean_masses: &[f64]) -> Vec<f64> {
    let weights: Vec<f64> = number_fractions
        .iter()
        .zip(mean_masses)
        .map(|(n, m)| n * m)
        .collect();
    let total: f64 = weights.iter().sum();
    weights.iter().map(|w| w / total).collect()
}

/// One component of a case's particles: a size distribution of one material, and its share.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Component {
    /// Its name in outputs (`composition.csv` columns); `c1`, `c2`, … unless given.
    pub name: String,
    /// Diameters.
    pub size: SizeDistribution,
    /// Its material's properties.
    pub material: MaterialSpec,
    /// The material's name in the case's `[materials]` table; `None` when the case has no
    /// table (the material is then `particles.material`, and the contact coefficients come
    /// from `[contact]` and `[wall]`).
    pub material_name: Option<String>,
    /// Its fraction as given, counted as [`ParticleSpec::fraction_by`] says [-]; 1 for a
    /// case of one component.
    pub fraction: f64,
    /// The shape of its grains, rigid clumps of spheres whose size is the diameter of the
    /// sphere of equal volume; `None` for spheres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<GrainShape>,
}

impl Component {
    /// Mean mass of one of its particles, ρ (π/6)⟨d³⟩ [kg].
    pub fn mean_particle_mass(&self) -> f64 {
        self.material.density * std::f64::consts::PI / 6.0 * self.size.moment(3)
    }

    /// Rayleigh time of its smallest sphere [s] (physics spec §6.1): of its smallest
    /// particle, or of the smallest member of its smallest shaped grain, which is what
    /// the contact laws meet.
    pub fn rayleigh_time(&self) -> f64 {
        let member = self
            .shape
            .as_ref()
            .map_or(1.0, GrainShape::smallest_member_diameter);
        self.material
            .rayleigh_time(0.5 * self.size.min_diameter() * member)
    }
}

/// The particles of a case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ParticleSpec {
    /// Number of particles N (paper: 3000).
    pub count: usize,
    /// The components, in the order of the case file; one for a case of one size
    /// distribution and material (the paper's), then of fraction 1.
    pub components: Vec<Component>,
    /// How the components' fractions are counted.
    pub fraction_by: FractionBasis,
    /// Where the case file asks for coarse-grained parcels (`particles.coarse_graining`):
    /// the grains it gives, which the count and the components' sizes above stand for.
    /// `None` for grains simulated as they are.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coarse_graining: Option<CoarseGraining>,
}

/// Parcels that stand for grains (coarse-grained DEM, docs/physics.md §2.8): each parcel is
/// κ times a grain's diameter, of the grains' material, and stands for κ³ grains; the
/// count of parcels is the grains' over κ³, rounded.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CoarseGraining {
    /// κ [-], ≥ 1: a parcel's diameter over its grains'.
    pub factor: f64,
    /// The number of grains the case file gives.
    pub grain_count: usize,
    /// Each component's grain sizes [m] as the case file gives them.
    pub grain_sizes: Vec<SizeDistribution>,
}

impl CoarseGraining {
    /// κ³ [-]: how many grains a parcel stands for (their volume over a grain's).
    pub fn grains_per_parcel(&self) -> f64 {
        self.factor * self.factor * self.factor
    }
}

/// The parcels of factor κ that `grains` grains make: their count over κ³, rounded to the
/// nearest whole parcel (zero when the grains are fewer than half a parcel's).
pub(crate) fn parcel_count(grains: usize, factor: f64) -> usize {
    (grains as f64 / (factor * factor * factor)).round() as usize
}

impl ParticleSpec {
    /// Table 1: 3000 spheres of 3 mm, ρ = 2500 kg/m³, G = 1e8 Pa, ν = 0.25.
    pub fn paper() -> Self {
        Self::single(
            3000,
            SizeDistribution::Monodisperse { diameter: 3.0e-3 },
            MaterialSpec::fan2023(),
        )
    }

    /// `count` particles of one size distribution and material.
    pub fn single(count: usize, size: SizeDistribution, material: MaterialSpec) -> Self {
        Self {
            count,
            components: vec![Component {
                name: "c1".to_string(),
                size,
                material,
                material_name: None,
                fraction: 1.0,
                shape: None,
            }],
            fraction_by: FractionBasis::Number,
            coarse_graining: None,
        }
    }

    /// Parcels of `factor` κ > 1 times these grains' diameters (docs/physics.md §2.8): the
    /// count over κ³, rounded to the nearest whole parcel (at least one), the same
    /// components, materials and fractions, and the grains kept in
    /// [`ParticleSpec::coarse_graining`].
    pub fn coarse_grained(&self, factor: f64) -> ParticleSpec {
        ParticleSpec {
            count: parcel_count(self.count, factor).max(1),
            components: self
                .components
                .iter()
                .map(|c| Component {
                    size: c.size.scaled(factor),
                    ..c.clone()
                })
                .collect(),
            fraction_by: self.fraction_by,
            coarse_graining: Some(CoarseGraining {
                factor,
                grain_count: self.count,
                grain_sizes: self.components.iter().map(|c| c.size.clone()).collect(),
            }),
        }
    }

    /// κ [-]: 1 for grains simulated as they are, else the parcels' factor.
    pub fn coarse_graining_factor(&self) -> f64 {
        self.coarse_graining.as_ref().map_or(1.0, |c| c.factor)
    }

    /// The grains' number-weighted mean diameter [m]: the parcels' over κ.
    pub fn grain_mean_diameter(&self) -> f64 {
        self.mean_diameter() / self.coarse_graining_factor()
    }

    /// The grains' smallest diameter [m], as the case file gives it.
    pub fn grain_min_diameter(&self) -> f64 {
        match &self.coarse_graining {
            Some(c) => c
                .grain_sizes
                .iter()
                .map(SizeDistribution::min_diameter)
                .fold(f64::INFINITY, f64::min),
            None => self.min_diameter(),
        }
    }

    /// Whether any component's grains are shaped (rigid clumps of spheres).
    pub fn has_shapes(&self) -> bool {
        self.components.iter().any(|c| c.shape.is_some())
    }

    /// Spheres per grain on average [-]: 1 for spheres, a shaped grain's members, weighted by
    /// the components' number fractions. What a run's cost and memory scale with beside its
    /// grain count.
    pub fn mean_spheres_per_grain(&self) -> f64 {
        self.number_fractions()
            .iter()
            .zip(&self.components)
            .map(|(n, c)| n * c.shape.as_ref().map_or(1, GrainShape::members) as f64)
            .sum()
    }

    /// Whether the particles are a mixture of several components.
    pub fn is_mixture(&self) -> bool {
        self.components.len() > 1
    }

    /// The one component of a case that is not a mixture.
    fn only(&self) -> Option<&Component> {
        match self.components.as_slice() {
            [one] => Some(one),
            _ => None,
        }
    }

    /// Number fraction of each component [-], summing to 1: the fractions as given, or
    /// converted from mass fractions by [`number_fractions_from_mass`].
    pub fn number_fractions(&self) -> Vec<f64> {
        let given: Vec<f64> = self.components.iter().map(|c| c.fraction).collect();
        match self.fraction_by {
            FractionBasis::Number => given,
            FractionBasis::Mass => {
                let masses: Vec<f64> = self
                    .components
                    .iter()
                    .map(Component::mean_particle_mass)
                    .collect();
                number_fractions_from_mass(&given, &masses)
            }
        }
    }

    /// Smallest diameter that can occur [m].
    pub fn min_diameter(&self) -> f64 {
        self.components
            .iter()
            .map(|c| c.size.min_diameter())
            .fold(f64::INFINITY, f64::min)
    }

    /// Largest diameter that can occur [m] (sets the outlet, slab and fit checks).
    pub fn max_diameter(&self) -> f64 {
        self.components
            .iter()
            .map(|c| c.size.max_diameter())
            .fold(0.0, f64::max)
    }

    /// Number-weighted mean of d^k over all particles [m^k], k = 1, 2, 3: Σ n_i ⟨d^k⟩_i.
    pub fn moment(&self, k: i32) -> f64 {
        if let Some(one) = self.only() {
            return one.size.moment(k);
        }
        self.number_fractions()
            .iter()
            .zip(&self.components)
            .map(|(n, c)| n * c.size.moment(k))
            .sum()
    }

    /// Number-mean diameter [m].
    pub fn mean_diameter(&self) -> f64 {
        self.moment(1)
    }

    /// Solid density of the particles [kg/m³]: the material's, or for a mixture the mean
    /// weighted by solid volume, Σ n_i ρ_i ⟨d³⟩_i / Σ n_i ⟨d³⟩_i (total mass over total volume).
    pub fn density(&self) -> f64 {
        if let Some(one) = self.only() {
            return one.material.density;
        }
        let (mut mass, mut volume) = (0.0, 0.0);
        for (n, c) in self.number_fractions().iter().zip(&self.components) {
            volume += n * c.size.moment(3);
            mass += n * c.size.moment(3) * c.material.density;
        }
        mass / volume
    }

    /// Rayleigh time of the smallest particle [s]: the shortest over the components
    /// (physics spec §6.1).
    pub fn rayleigh_time(&self) -> f64 {
        self.components
            .iter()
            .map(Component::rayleigh_time)
            .fold(f64::INFINITY, f64::min)
    }

    /// Total projected (mid-plane disc) area Σ π d²/4 [m²].
    pub fn total_disc_area(&self) -> f64 {
        self.count as f64 * std::f64::consts::FRAC_PI_4 * self.moment(2)
    }

    /// Total solid volume Σ π d³/6 [m³].
    pub fn total_volume(&self) -> f64 {
        self.count as f64 * std::f64::consts::PI / 6.0 * self.moment(3)
    }

    /// Total mass of the particles, estimated from the mean sphere volume [kg].
    pub fn total_mass(&self) -> f64 {
        self.total_volume() * self.density()
    }
}
