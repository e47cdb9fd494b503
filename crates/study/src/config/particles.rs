//! Particle material and size distribution of a case, with the moments the checks need.

use serde::{Deserialize, Serialize};

/// Elastic material of particles or walls (paper Table 1 for the defaults).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Density ρ [kg/m³].
    pub density: f64,
    /// Shear modulus G [Pa].
    pub shear_modulus: f64,
    /// Poisson's ratio ν [-].
    pub poisson_ratio: f64,
}

impl Material {
    /// Table 1: ρ_p = 2500 kg/m³, G = 1e8 Pa, ν = 0.25.
    pub fn paper() -> Self {
        Self {
            density: 2500.0,
            shear_modulus: 1.0e8,
            poisson_ratio: 0.25,
        }
    }

    /// Young's modulus E = 2G(1 + ν) [Pa].
    pub fn youngs_modulus(&self) -> f64 {
        2.0 * self.shear_modulus * (1.0 + self.poisson_ratio)
    }

    /// Rayleigh time t_R = π r √(ρ/G) / (0.1631 ν + 0.8766) [s] for a sphere of radius
    /// `radius` [m] (paper Eq. 9 with EDEM's coefficient, physics spec §6.1).
    pub fn rayleigh_time(&self, radius: f64) -> f64 {
        std::f64::consts::PI * radius * (self.density / self.shear_modulus).sqrt()
            / (0.1631 * self.poisson_ratio + 0.8766)
    }
}

/// Particle diameters of a case. All diameters are in metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SizeDistribution {
    /// Every particle has the same diameter [m] (the paper: 3 mm).
    Monodisperse { diameter: f64 },
    /// Diameters uniform by number on [min, max] [m].
    Uniform { min: f64, max: f64 },
    /// Normal by number with mean and standard deviation [m], truncated to [min, max] [m].
    Normal {
        mean: f64,
        std_dev: f64,
        min: f64,
        max: f64,
    },
    /// A finite set of diameters [m] with number fractions (summing to 1).
    Discrete {
        diameters: Vec<f64>,
        fractions: Vec<f64>,
    },
}

impl SizeDistribution {
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

/// The particles of a case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ParticleSpec {
    /// Number of particles N (paper: 3000).
    pub count: usize,
    /// Diameters.
    pub size: SizeDistribution,
    /// Particle material.
    pub material: Material,
}

impl ParticleSpec {
    /// Table 1: 3000 spheres of 3 mm, ρ = 2500 kg/m³, G = 1e8 Pa, ν = 0.25.
    pub fn paper() -> Self {
        Self {
            count: 3000,
            size: SizeDistribution::Monodisperse { diameter: 3.0e-3 },
            material: Material::paper(),
        }
    }

    /// Rayleigh time of the smallest particle [s] (physics spec §6.1).
    pub fn rayleigh_time(&self) -> f64 {
        self.material.rayleigh_time(0.5 * self.size.min_diameter())
    }

    /// Total projected (mid-plane disc) area Σ π d²/4 [m²].
    pub fn total_disc_area(&self) -> f64 {
        self.count as f64 * std::f64::consts::FRAC_PI_4 * self.size.moment(2)
    }

    /// Total solid volume Σ π d³/6 [m³].
    pub fn total_volume(&self) -> f64 {
        self.count as f64 * std::f64::consts::PI / 6.0 * self.size.moment(3)
    }
}
