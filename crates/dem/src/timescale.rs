//! Critical time scales: the Rayleigh time (paper Eq. 9) and the Hertz contact time.

use crate::material::Material;

/// Rayleigh time t_R = π r √(ρ/G) / (0.1631 ν + 0.8766) [s] for the smallest radius `radius` [m].
///
/// The paper's Eq. 9 prints 0.163; EDEM and LIGGGHTS use 0.1631 (docs/physics.md §6.1, §10.4).
pub fn rayleigh_time(material: &Material, radius: f64) -> f64 {
    std::f64::consts::PI * radius * (material.density / material.shear_modulus()).sqrt()
        / (0.1631 * material.poisson_ratio + 0.8766)
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
}
