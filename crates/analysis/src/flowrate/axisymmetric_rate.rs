//! Discharge rate of a circular orifice of radius R from axisymmetric self-similar profiles,
//! the 3D form of Janda, Zuriguel & Maza, PRL 108 (2012) 248001:
//!
//! v(r) = v_c (1 − (r/R)²)^a, φ(r) = φ_c (1 − (r/R)²)^b,
//!
//! W = ρ_p ∫₀^R φ(r) v(r) 2πr dr = π R² ρ_p φ_c v_c / (1 + a + b),
//!
//! since with u = (r/R)², ∫₀^R (1 − (r/R)²)^{a+b} 2πr dr = πR² ∫₀¹ (1 − u)^{a+b} du =
//! πR²/(1 + a + b). φ is the 3D volume fraction (no 2/3 slab conversion as in Eq. 13) and
//! v the vertical speed through the orifice plane; a = b = 0 is plug flow, W = πR²ρ_pφ_cv_c.

use serde::{Deserialize, Serialize};

use crate::error::{ensure_positive, AnalysisError, AnalysisResult};
use crate::estimate::{propagate, Estimate};

/// Fitted profile parameters of one circular orifice; their errors are propagated as
/// independent. The amplitude and exponent of one power-profile fit are correlated, which this
/// neglects; taking v_c and φ_c as centre values (`BinnedProfile::centre_value`) rather than
/// fit amplitudes keeps them closer to independent of a and b.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AxisymmetricFlowParameters {
    /// Centre speed v_c [m/s].
    pub centre_velocity: Estimate,
    /// Velocity-profile exponent a (dimensionless).
    pub velocity_exponent: Estimate,
    /// Centre volume fraction φ_c (dimensionless).
    pub centre_fraction: Estimate,
    /// Packing-profile exponent b (dimensionless).
    pub packing_exponent: Estimate,
    /// Particle material density ρ_p [kg/m³].
    pub particle_density: f64,
}

/// W = πR²ρ_pφ_cv_c/(1 + a + b) [kg/s] at orifice radius `radius` R [m], with its error
/// propagated to first order from v_c, a, φ_c and b.
pub fn axisymmetric_discharge_rate(
    parameters: &AxisymmetricFlowParameters,
    radius: f64,
) -> AnalysisResult<Estimate> {
    const CONTEXT: &str = "axisymmetric discharge rate";
    ensure_positive(CONTEXT, "orifice radius", radius)?;
    ensure_positive(CONTEXT, "particle density", parameters.particle_density)?;
    ensure_positive(CONTEXT, "centre velocity", parameters.centre_velocity.value)?;
    ensure_positive(CONTEXT, "centre fraction", parameters.centre_fraction.value)?;
    let exponent_sum = parameters.velocity_exponent.value + parameters.packing_exponent.value;
    if !(exponent_sum.is_finite() && 1.0 + exponent_sum > 0.0) {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: format!("need 1 + a + b > 0 for a finite flux, got a + b = {exponent_sum}"),
        });
    }
    let area = std::f64::consts::PI * radius * radius;
    let density = parameters.particle_density;
    propagate(
        |p| area * density * p[0] * p[2] / (1.0 + p[1] + p[3]),
        &[
            parameters.centre_velocity,
            parameters.velocity_exponent,
            parameters.centre_fraction,
            parameters.packing_exponent,
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flowrate::integrate;
    use crate::profile::BinnedProfile;
    use crate::selfsimilar::{fit_power_profile, power_profile, PROFILE_FIT_HALF_WIDTH};
    use crate::test_support::{normal, seeded_rng};

    fn exact(v: f64, a: f64, phi: f64, b: f64) -> AxisymmetricFlowParameters {
        AxisymmetricFlowParameters {
            centre_velocity: Estimate::exact(v),
            velocity_exponent: Estimate::exact(a),
            centre_fraction: Estimate::exact(phi),
            packing_exponent: Estimate::exact(b),
            particle_density: 2500.0,
        }
    }

    #[test]
    fn closed_form_equals_the_flux_integral_over_the_orifice() {
        // ρ_p ∫₀^R φ v 2πr dr by adaptive Simpson with r = R sin θ (which tames the
        // (R − r)^{a+b} end, the integrand becoming R² sin θ cos^{2(a+b)+1} θ); the Beta-free
        // closed form must agree to 1e-9.
        let (v, a, phi, b, radius) = (1.05, 0.42, 0.58, 0.27, 0.0125);
        let integral = integrate(
            |t: f64| {
                let r = radius * t.sin();
                let x = r / radius;
                power_profile(x, phi, b)
                    * power_profile(x, v, a)
                    * 2.0
                    * std::f64::consts::PI
                    * r
                    * radius
                    * t.cos()
            },
            0.0,
            std::f64::consts::FRAC_PI_2,
            1e-14,
        )
        .unwrap();
        let w = axisymmetric_discharge_rate(&exact(v, a, phi, b), radius).unwrap();
        assert!((w.value / (2500.0 * integral) - 1.0).abs() < 1e-9, "{w:?}");
        assert_eq!(w.standard_error, 0.0);
    }

    #[test]
    fn flat_profiles_give_the_plug_flow_through_the_orifice_area() {
        // a = b = 0: uniform φ and v over πR², W = πR²ρ_pφv exactly (to rounding).
        let radius = 0.02;
        let w = axisymmetric_discharge_rate(&exact(0.9, 0.0, 0.6, 0.0), radius).unwrap();
        let plug = std::f64::consts::PI * radius * radius * 2500.0 * 0.6 * 0.9;
        assert!((w.value / plug - 1.0).abs() < 1e-14);
        // Steeper profiles carry less through the same orifice.
        let steeper = axisymmetric_discharge_rate(&exact(0.9, 0.5, 0.6, 0.3), radius).unwrap();
        assert!(steeper.value < w.value);
    }

    #[test]
    fn errors_combine_by_first_order_propagation() {
        // W ∝ v_c φ_c/(1 + a + b): relative errors 3 % on v_c, 2 % on φ_c and σ_a = 0.05,
        // σ_b = 0.04 give (σ_W/W)² = 0.03² + 0.02² + (0.05² + 0.04²)/(1 + a + b)². The central
        // differences are exact for the bilinear part and O(step²) ≈ 1e-10 for 1/(1 + a + b).
        let (a, b) = (0.4, 0.3);
        let p = AxisymmetricFlowParameters {
            centre_velocity: Estimate::new(1.0, 0.03),
            velocity_exponent: Estimate::new(a, 0.05),
            centre_fraction: Estimate::new(0.6, 0.012),
            packing_exponent: Estimate::new(b, 0.04),
            particle_density: 2500.0,
        };
        let w = axisymmetric_discharge_rate(&p, 0.015).unwrap();
        let s = 1.0 + a + b;
        let expected =
            (0.03f64.powi(2) + 0.02f64.powi(2) + (0.05f64.powi(2) + 0.04f64.powi(2)) / (s * s))
                .sqrt();
        assert!((w.relative_error() - expected).abs() < 1e-8);
    }

    #[test]
    fn rates_from_fitted_noisy_radial_profiles_recover_the_true_flux() {
        // End to end: radial v and φ profiles of known shape in ten annuli with 2 % / 1 %
        // noise, fitted one-sided; v_c and φ_c taken as fitted amplitudes. The predicted W must
        // hold the true πR²ρ_pφ_cv_c/(1 + a + b) within 4 propagated σ, and σ_W/W be a few %.
        let (v, a, phi, b, radius) = (1.1, 0.45, 0.58, 0.25, 0.015);
        let mut rng = seeded_rng(91);
        let mut profile = |amplitude: f64, exponent: f64, noise: f64| {
            let centres: Vec<f64> = (0..10).map(|i| 0.05 + 0.1 * i as f64).collect();
            let values = centres
                .iter()
                .map(|&r| {
                    power_profile(r, amplitude, exponent) + noise * amplitude * normal(&mut rng)
                })
                .collect();
            BinnedProfile::new(centres, values, vec![50; 10], vec![noise * amplitude; 10]).unwrap()
        };
        let velocity = fit_power_profile(&profile(v, a, 0.02), PROFILE_FIT_HALF_WIDTH).unwrap();
        let packing = fit_power_profile(&profile(phi, b, 0.01), PROFILE_FIT_HALF_WIDTH).unwrap();
        let w = axisymmetric_discharge_rate(
            &AxisymmetricFlowParameters {
                centre_velocity: velocity.amplitude,
                velocity_exponent: velocity.exponent,
                centre_fraction: packing.amplitude,
                packing_exponent: packing.exponent,
                particle_density: 2500.0,
            },
            radius,
        )
        .unwrap();
        let truth = axisymmetric_discharge_rate(&exact(v, a, phi, b), radius)
            .unwrap()
            .value;
        assert!(
            (w.value - truth).abs() < 4.0 * w.standard_error,
            "{w:?} vs {truth}"
        );
        assert!(w.relative_error() < 0.05, "{w:?}");
    }

    #[test]
    fn non_physical_inputs_are_rejected() {
        let p = exact(1.0, 0.4, 0.6, 0.3);
        assert!(axisymmetric_discharge_rate(&p, 0.0).is_err());
        assert!(axisymmetric_discharge_rate(&exact(1.0, -0.8, 0.6, -0.3), 0.01).is_err());
        assert!(axisymmetric_discharge_rate(&exact(0.0, 0.4, 0.6, 0.3), 0.01).is_err());
        assert!(axisymmetric_discharge_rate(&exact(1.0, 0.4, f64::NAN, 0.3), 0.01).is_err());
        let mut q = p;
        q.particle_density = -1.0;
        assert!(axisymmetric_discharge_rate(&q, 0.01).is_err());
    }
}
