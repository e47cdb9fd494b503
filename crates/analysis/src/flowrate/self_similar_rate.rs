//! Discharge rate predicted from the self-similar profiles, paper Eq. 14:
//! W = (2√2/3) B(1/2, 1 + a + b) ρ_p √(γg) φ∞ d R^{3/2}.
//!
//! It follows from W = (2/3) ρ_p d ∫₋R^R φ(x) v(x) dx (Eq. 13; 2/3 converts the monolayer's
//! 2D area fraction to a volume fraction per slab thickness d) with v = √(2γgR)(1 − x*²)^a,
//! φ = φ∞(1 − x*²)^b and ∫₋₁¹ (1 − x*²)^{a+b} dx* = B(1/2, 1 + a + b). Using φ∞ instead of
//! φ_c(R) makes it over-predict small outlets, as the paper notes.

use serde::{Deserialize, Serialize};

use crate::error::{ensure_positive, AnalysisResult};
use crate::estimate::{propagate, Estimate};
use crate::flowrate::beta::beta_function;

/// Inputs of Eq. 14. Fitted quantities carry their errors, which are propagated (treated as
/// independent, since they come from separate fits).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SelfSimilarFlowParameters {
    /// Velocity-profile exponent a (dimensionless).
    pub velocity_exponent: Estimate,
    /// Area-fraction-profile exponent b (dimensionless).
    pub packing_exponent: Estimate,
    /// Centre-velocity factor γ (dimensionless).
    pub gamma: Estimate,
    /// Asymptotic 2D area fraction φ∞ (dimensionless).
    pub phi_infinity: Estimate,
    /// Particle diameter d [m] (the slab thickness of the monolayer).
    pub particle_diameter: f64,
    /// Particle material density ρ_p [kg/m³].
    pub particle_density: f64,
    /// Gravitational acceleration g [m/s²].
    pub gravity: f64,
}

/// Eq. 14 at outlet half-width `radius` R [m]: the mass rate [kg/s] with its propagated error.
pub fn self_similar_discharge_rate(
    parameters: &SelfSimilarFlowParameters,
    radius: f64,
) -> AnalysisResult<Estimate> {
    const CONTEXT: &str = "Eq. 14 discharge rate";
    ensure_positive(CONTEXT, "outlet half-width", radius)?;
    ensure_positive(CONTEXT, "particle diameter", parameters.particle_diameter)?;
    ensure_positive(CONTEXT, "particle density", parameters.particle_density)?;
    ensure_positive(CONTEXT, "gravity", parameters.gravity)?;
    ensure_positive(CONTEXT, "gamma", parameters.gamma.value)?;
    let exponent_sum = parameters.velocity_exponent.value + parameters.packing_exponent.value;
    // Validate B's argument once so the propagation below cannot fail silently.
    beta_function(0.5, 1.0 + exponent_sum)?;
    let prefactor = 2.0 * std::f64::consts::SQRT_2 / 3.0
        * parameters.particle_density
        * parameters.particle_diameter
        * radius.powf(1.5)
        * parameters.gravity.sqrt();
    propagate(
        |p| {
            let shape = beta_function(0.5, 1.0 + p[0] + p[1]).unwrap_or(f64::NAN);
            prefactor * shape * p[2].max(0.0).sqrt() * p[3]
        },
        &[
            parameters.velocity_exponent,
            parameters.packing_exponent,
            parameters.gamma,
            parameters.phi_infinity,
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flowrate::integrate;
    use crate::selfsimilar::power_profile;

    fn table2(a: f64, b: f64, gamma: f64, phi: f64) -> SelfSimilarFlowParameters {
        SelfSimilarFlowParameters {
            velocity_exponent: Estimate::exact(a),
            packing_exponent: Estimate::exact(b),
            gamma: Estimate::exact(gamma),
            phi_infinity: Estimate::exact(phi),
            particle_diameter: 3e-3,
            particle_density: 2500.0,
            gravity: 9.81,
        }
    }

    #[test]
    fn flat_bottom_rate_at_thirty_millimetres_is_58_grams_per_second() {
        // Physics spec §8.1 (Eq. 14 with Table 2 at 90°): 58.2 g/s at D = 30 mm and
        // 164.7 g/s at D = 60 mm; the table rounds to 0.1 g/s, hence 0.06 g/s.
        let p = table2(0.39, 0.39, 1.66, 0.78);
        let w30 = self_similar_discharge_rate(&p, 0.015).unwrap();
        let w60 = self_similar_discharge_rate(&p, 0.030).unwrap();
        assert!((w30.value * 1e3 - 58.2).abs() < 0.06, "{w30:?}");
        assert!((w60.value * 1e3 - 164.7).abs() < 0.06, "{w60:?}");
        assert_eq!(w30.standard_error, 0.0);
        // 15° row of the same table at D = 18 mm: 41.6 g/s.
        let steep = self_similar_discharge_rate(&table2(0.20, 0.16, 2.81, 0.79), 0.009).unwrap();
        assert!((steep.value * 1e3 - 41.6).abs() < 0.06);
    }

    #[test]
    fn closed_form_equals_the_integral_of_the_profiles() {
        // (2/3) ρ_p d ∫ φ v dx with the Eq. 10–11 profiles, integrated numerically in
        // x = sin θ form (smooth); must match the Beta-function form to quadrature accuracy.
        let (a, b, gamma, phi) = (0.33, 0.38, 1.64f64, 0.78);
        let (rho, d, g, radius) = (2500.0, 3e-3, 9.81f64, 0.0225);
        let centre = (2.0 * gamma * g * radius).sqrt();
        let half_pi = std::f64::consts::FRAC_PI_2;
        let integral = integrate(
            |t: f64| {
                let x = t.sin();
                power_profile(x, phi, b) * power_profile(x, centre, a) * t.cos() * radius
            },
            -half_pi,
            half_pi,
            1e-14,
        )
        .unwrap();
        let direct = 2.0 / 3.0 * rho * d * integral;
        let formula = self_similar_discharge_rate(&table2(a, b, gamma, phi), radius).unwrap();
        assert!((formula.value / direct - 1.0).abs() < 1e-9);
    }

    #[test]
    fn rate_error_follows_the_gamma_error() {
        // W ∝ √γ: a 10 % error on γ gives a 5 % error on W (first order).
        let mut p = table2(0.39, 0.39, 1.66, 0.78);
        p.gamma = Estimate::new(1.66, 0.166);
        let w = self_similar_discharge_rate(&p, 0.015).unwrap();
        assert!((w.relative_error() - 0.05).abs() < 1e-6);
    }

    #[test]
    fn non_physical_inputs_are_rejected() {
        let p = table2(0.39, 0.39, 1.66, 0.78);
        assert!(self_similar_discharge_rate(&p, 0.0).is_err());
        assert!(self_similar_discharge_rate(&table2(-2.0, 0.39, 1.66, 0.78), 0.015).is_err());
    }
}
