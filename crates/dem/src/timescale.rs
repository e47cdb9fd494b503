//! Critical time scales: the Rayleigh time (paper Eq. 9) and the Hertz contact time.

use crate::material::Material;

/// Rayleigh time t_R = π r √(ρ/G) / (0.1631 ν + 0.8766) [s] of `material` for the smallest
/// radius `radius` [m] ([`rayleigh_time_of`] with the material's ρ, G and ν).
pub fn rayleigh_time(material: &Material, radius: f64) -> f64 {
    rayleigh_time_of(
        material.density,
        material.shear_modulus(),
        material.poisson_ratio,
        radius,
    )
}

/// Rayleigh time t_R = π r √(ρ/G) / (0.1631 ν + 0.8766) [s] of a sphere of radius `radius`
/// [m], density `density` ρ [kg/m³], shear modulus `shear_modulus` G [Pa] and Poisson's
/// ratio `poisson_ratio` ν [-]: the time a Rayleigh surface wave takes to cross the sphere,
/// which the time step must stay well below (the paper's Eq. 9).
///
/// The paper's Eq. 9 prints 0.163; EDEM and LIGGGHTS use 0.1631 (docs/physics.md §6.1, §10.4).
/// The engine's time-step guard calls it through [`rayleigh_time`]; a caller holding the
/// moduli rather than a [`Material`] (a case's particle specification) calls it directly.
pub fn rayleigh_time_of(density: f64, shear_modulus: f64, poisson_ratio: f64, radius: f64) -> f64 {
    std::f64::consts::PI * radius * (density / shear_modulus).sqrt()
        / (0.1631 * poisson_ratio + 0.8766)
}

pub use crate::contact::normal::hertz_contact_time;

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn table1_rayleigh_time_is_25_7_microseconds() {
        // docs/physics.md §1.1: t_R = 2.5684e-5 s (5 significant digits).
        assert_relative_eq!(
            rayleigh_time(&Material::fan2023(), 1.5e-3),
            2.5684e-5,
            max_relative = 5e-5
        );
    }

    #[test]
    fn the_rayleigh_time_of_the_moduli_is_that_of_the_material() {
        // Table 1 by its moduli: ρ = 2500 kg/m³, G = 1e8 Pa, ν = 0.25, r = 1.5 mm.
        let m = Material::fan2023();
        assert_eq!(
            rayleigh_time_of(m.density, m.shear_modulus(), m.poisson_ratio, 1.5e-3),
            rayleigh_time(&m, 1.5e-3)
        );
        assert_relative_eq!(
            rayleigh_time_of(2500.0, 1.0e8, 0.25, 1.5e-3),
            2.5684e-5,
            max_relative = 5e-5
        );
    }
}
