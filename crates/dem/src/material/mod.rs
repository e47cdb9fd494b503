//! Materials, interaction coefficients and the pair mixing rules (docs/physics.md §1); the
//! named pair table and its mixing rules for unlisted pairs (§1.2) are in the files beside.

mod mixing;
mod table;
mod table_error;

use serde::{Deserialize, Serialize};

use crate::contact::Cohesion;
pub use mixing::{mixed_cohesion, mixed_friction, mixed_interaction, mixed_restitution};
pub use table::{MaterialEntry, MaterialTable, PairEntry};
pub use table_error::{MaterialTableError, MODULUS_TOLERANCE};

/// An isotropic elastic solid.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Density ρ [kg/m³].
    pub density: f64,
    /// Young's modulus E [Pa].
    pub youngs_modulus: f64,
    /// Poisson's ratio ν [-].
    pub poisson_ratio: f64,
}

impl Material {
    /// A material from its shear modulus, as the paper's Table 1 gives it: E = 2G(1+ν).
    pub fn from_shear_modulus(density: f64, shear_modulus: f64, poisson_ratio: f64) -> Self {
        Self {
            density,
            youngs_modulus: 2.0 * shear_modulus * (1.0 + poisson_ratio),
            poisson_ratio,
        }
    }

    /// The paper's Table 1 particle: ρ = 2500 kg/m³, G = 1e8 Pa, ν = 0.25.
    pub fn fan2023() -> Self {
        Self::from_shear_modulus(2500.0, 1.0e8, 0.25)
    }

    /// Shear modulus G = E / (2(1+ν)) [Pa].
    pub fn shear_modulus(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))
    }

    /// The compliance (1−ν²)/E [1/Pa] that enters 1/E*.
    fn normal_compliance(&self) -> f64 {
        (1.0 - self.poisson_ratio * self.poisson_ratio) / self.youngs_modulus
    }

    /// The compliance (2−ν)/G [1/Pa] that enters 1/G*.
    fn shear_compliance(&self) -> f64 {
        (2.0 - self.poisson_ratio) / self.shear_modulus()
    }
}

/// What a wall is made of. A wall is a body of infinite radius and mass (docs/physics.md §5).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum WallMaterial {
    /// A rigid wall: it adds no compliance, so E* = E/(1−ν²) and G* = G/(2−ν).
    Rigid,
    /// An elastic wall with its own material.
    Elastic(Material),
}

/// Friction, rolling friction and restitution of one kind of contact (one row of Table 1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Interaction {
    /// Coulomb (sliding) friction coefficient μ_s [-].
    pub friction: f64,
    /// Rolling friction coefficient μ_r [-] (a dimensionless lever fraction, paper Eq. 8).
    pub rolling_friction: f64,
    /// Coefficient of restitution e [-], in (0, 1].
    pub restitution: f64,
    /// How the surfaces stick (docs/physics.md §2.4–2.6); dry by default.
    #[serde(default)]
    pub cohesion: Cohesion,
}

impl Interaction {
    /// The paper's Table 1 values, the same for particle–particle and particle–wall:
    /// μ_s = 0.5, μ_r = 0.01, e = 0.2.
    pub fn fan2023() -> Self {
        Self {
            friction: 0.5,
            rolling_friction: 0.01,
            restitution: 0.2,
            cohesion: Cohesion::None,
        }
    }

    /// The same interaction with cohesion `cohesion`.
    pub fn with_cohesion(self, cohesion: Cohesion) -> Self {
        Self { cohesion, ..self }
    }
}

/// Effective Young's modulus E* of two bodies; `None` stands for a rigid body
/// (1/E* = Σ (1−ν²)/E, docs/physics.md §1).
pub fn effective_youngs_modulus(a: &Material, b: Option<&Material>) -> f64 {
    1.0 / (a.normal_compliance() + b.map_or(0.0, Material::normal_compliance))
}

/// Effective shear modulus G* of two bodies; `None` stands for a rigid body
/// (1/G* = Σ (2−ν)/G, docs/physics.md §1).
pub fn effective_shear_modulus(a: &Material, b: Option<&Material>) -> f64 {
    1.0 / (a.shear_compliance() + b.map_or(0.0, Material::shear_compliance))
}

/// Harmonic combination 1/(1/a + 1/b), used for R* and m*.
#[inline(always)]
pub fn harmonic(a: f64, b: f64) -> f64 {
    a * b / (a + b)
}

/// Everything the contact kernel needs about one pairing of materials, fixed at setup.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PairCoefficients {
    /// Effective Young's modulus E* [Pa].
    pub e_star: f64,
    /// Effective shear modulus G* [Pa].
    pub g_star: f64,
    /// Sliding friction μ_s [-].
    pub friction: f64,
    /// Rolling friction μ_r [-].
    pub rolling_friction: f64,
    /// Restitution e [-].
    pub restitution: f64,
    /// Dashpot prefactor 2√(5/6)|β(e)| [-] (docs/physics.md §2.1).
    pub damping: f64,
    /// √(S_t/S_n) = √(4G*/E*) [-], relating the tangential and normal dashpots.
    pub stiffness_ratio_sqrt: f64,
    /// Cohesion of the pair (docs/physics.md §2.4–2.6).
    pub cohesion: Cohesion,
}

impl PairCoefficients {
    /// Mix two materials (or a material and a wall) with the given interaction.
    pub fn new(a: &Material, b: Option<&Material>, interaction: &Interaction) -> Self {
        let e_star = effective_youngs_modulus(a, b);
        let g_star = effective_shear_modulus(a, b);
        Self {
            e_star,
            g_star,
            stiffness_ratio_sqrt: (4.0 * g_star / e_star).sqrt(),
            friction: interaction.friction,
            rolling_friction: interaction.rolling_friction,
            restitution: interaction.restitution,
            damping: crate::contact::damping::dashpot_prefactor(interaction.restitution),
            cohesion: interaction.cohesion,
        }
    }

    /// Particle–wall coefficients for a wall of the given material.
    pub fn with_wall(a: &Material, wall: &WallMaterial, interaction: &Interaction) -> Self {
        match wall {
            WallMaterial::Rigid => Self::new(a, None, interaction),
            WallMaterial::Elastic(m) => Self::new(a, Some(m), interaction),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    // Table 1 derived numbers, docs/physics.md §1.1, printed to 5 significant digits.
    const TABLE_TOL: f64 = 1e-4;

    #[test]
    fn table1_effective_moduli_match_physics_spec() {
        let m = Material::fan2023();
        assert_relative_eq!(m.youngs_modulus, 2.5e8, max_relative = 1e-12);
        assert_relative_eq!(
            effective_youngs_modulus(&m, Some(&m)),
            1.3333e8,
            max_relative = TABLE_TOL
        );
        assert_relative_eq!(
            effective_shear_modulus(&m, Some(&m)),
            2.8571e7,
            max_relative = TABLE_TOL
        );
        assert_relative_eq!(
            effective_youngs_modulus(&m, None),
            2.6667e8,
            max_relative = TABLE_TOL
        );
        assert_relative_eq!(
            effective_shear_modulus(&m, None),
            5.7143e7,
            max_relative = TABLE_TOL
        );
    }

    #[test]
    fn stiffness_ratio_kappa_is_two_one_minus_nu_over_two_minus_nu() {
        // κ = 4G*/E* = 2(1−ν)/(2−ν) = 0.857 for ν = 0.25 (docs/physics.md §1.1); exact identity.
        let m = Material::fan2023();
        let kappa =
            4.0 * effective_shear_modulus(&m, Some(&m)) / effective_youngs_modulus(&m, Some(&m));
        assert_relative_eq!(kappa, 2.0 * 0.75 / 1.75, max_relative = 1e-12);
    }
}
