//! Fit of the centre area fraction against outlet size, φ_c = φ∞(1 − τ₁e^{−2τ₂R}) (paper Eq. 12, Fig. 7).
//!
//! Unit decision: the paper does not state the unit of R in Eq. 12, but its τ₂ ≈ 0.18–0.19
//! only makes sense with R in millimetres (with R in metres the exponential would be 1 for
//! every outlet; physics spec §10 item 6). The API takes R in metres (SI) and converts to
//! millimetres internally, and τ₂ is reported in 1/mm so it compares directly with the paper.

use serde::{Deserialize, Serialize};

use crate::error::{
    ensure_at_least, ensure_finite, ensure_same_length, AnalysisError, AnalysisResult,
};
use crate::estimate::Estimate;
use crate::fit::{fit_curve, fit_line, CurveData, ParameterBounds};

/// Millimetres per metre: Eq. 12 is evaluated with R in mm.
const MILLIMETRES_PER_METRE: f64 = 1e3;

/// Result of an Eq. 12 fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PackingSaturationFit {
    /// Asymptotic 2D area fraction φ∞ (dimensionless; 0.78–0.79 in Table 2).
    pub phi_infinity: Estimate,
    /// Amplitude τ₁ (dimensionless).
    pub tau1: Estimate,
    /// Rate τ₂ [1/mm] (the paper's unit; see the module documentation).
    pub tau2_per_millimetre: Estimate,
    /// Weighted sum of squared residuals.
    pub chi_squared: f64,
    /// Residual degrees of freedom (n − 3).
    pub degrees_of_freedom: usize,
}

impl PackingSaturationFit {
    /// Predicted fraction at outlet half-width `radius` [m].
    pub fn fraction(&self, radius: f64) -> f64 {
        packing_saturation(
            radius,
            self.phi_infinity.value,
            self.tau1.value,
            self.tau2_per_millimetre.value,
        )
    }
}

/// Eq. 12: φ∞(1 − τ₁ e^{−2τ₂R}) with `radius` R in metres and `tau2_per_millimetre` in 1/mm.
pub fn packing_saturation(
    radius: f64,
    phi_infinity: f64,
    tau1: f64,
    tau2_per_millimetre: f64,
) -> f64 {
    let radius_mm = radius * MILLIMETRES_PER_METRE;
    phi_infinity * (1.0 - tau1 * (-2.0 * tau2_per_millimetre * radius_mm).exp())
}

/// Fits Eq. 12 to fractions (centre φ_c, or φ_max for eccentric outlets, paper Fig. 13)
/// measured at half-widths `radii` [m], with optional errors `sigma`.
///
/// Needs at least 4 points. The start is found by scanning τ₂ on a log grid (for fixed τ₂
/// the model is linear in φ∞ and φ∞τ₁), then refined by Levenberg–Marquardt.
pub fn fit_packing_saturation(
    radii: &[f64],
    fractions: &[f64],
    sigma: Option<&[f64]>,
) -> AnalysisResult<PackingSaturationFit> {
    const CONTEXT: &str = "Eq. 12 fit";
    ensure_same_length(CONTEXT, radii.len(), fractions.len())?;
    ensure_finite(CONTEXT, radii)?;
    ensure_finite(CONTEXT, fractions)?;
    ensure_at_least(CONTEXT, 4, radii.len())?;
    let radii_mm: Vec<f64> = radii.iter().map(|r| r * MILLIMETRES_PER_METRE).collect();

    // Grid start: τ₂ from 0.01 to 3 per mm covers decay lengths from 0.2 mm to 50 mm.
    let mut best: Option<(f64, f64, f64, f64)> = None; // (sse, φ∞, τ₁, τ₂)
    for step in 0..=120 {
        let tau2 = 0.01 * 300f64.powf(step as f64 / 120.0);
        let basis: Vec<f64> = radii_mm.iter().map(|r| (-2.0 * tau2 * r).exp()).collect();
        let Ok(line) = fit_line(&basis, fractions, 0.95) else {
            continue;
        };
        let phi = line.intercept.value;
        if phi.is_nan() || phi <= 0.0 {
            continue;
        }
        let tau1 = -line.slope.value / phi;
        if !matches!(best, Some(b) if b.0 <= line.chi_squared) {
            best = Some((line.chi_squared, phi, tau1, tau2));
        }
    }
    let Some((_, phi0, tau10, tau20)) = best else {
        return Err(AnalysisError::Degenerate {
            context: CONTEXT,
            reason: "no saturation curve with a positive asymptote fits the data".into(),
        });
    };
    let fit = fit_curve(
        |r, p| p[0] * (1.0 - p[1] * (-2.0 * p[2] * r).exp()),
        CurveData {
            x: &radii_mm,
            y: fractions,
            sigma,
        },
        &[phi0, tau10, tau20],
        Some(&[
            ParameterBounds::between(1e-6, 1.0),
            ParameterBounds::free(),
            ParameterBounds::between(1e-6, 100.0),
        ]),
    )?;
    Ok(PackingSaturationFit {
        phi_infinity: fit.parameters[0],
        tau1: fit.parameters[1],
        tau2_per_millimetre: fit.parameters[2],
        chi_squared: fit.chi_squared,
        degrees_of_freedom: fit.degrees_of_freedom,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{normal, seeded_rng, Coverage};

    #[test]
    fn saturation_parameters_are_recovered_with_radius_in_millimetres() {
        // φ∞ = 0.78, τ₁ = 3.74, τ₂ = 0.18/mm (paper Fig. 13, s = 0), eight outlets of
        // R = 4.5–30 mm, noise 0.003 (a typical time-averaged φ error).
        let (phi, tau1, tau2) = (0.78, 3.74, 0.18);
        let mut rng = seeded_rng(12);
        let radii: Vec<f64> = (0..8).map(|i| 0.0045 + 0.0036 * i as f64).collect();
        let fractions: Vec<f64> = radii
            .iter()
            .map(|&r| packing_saturation(r, phi, tau1, tau2) + 0.003 * normal(&mut rng))
            .collect();
        let sigma = vec![0.003; radii.len()];
        let fit = fit_packing_saturation(&radii, &fractions, Some(&sigma)).unwrap();
        // 4σ recovery of each parameter with its own (χ²-scaled) error.
        assert!((fit.phi_infinity.value - phi).abs() < 4.0 * fit.phi_infinity.standard_error);
        assert!((fit.tau1.value - tau1).abs() < 4.0 * fit.tau1.standard_error);
        assert!(
            (fit.tau2_per_millimetre.value - tau2).abs()
                < 4.0 * fit.tau2_per_millimetre.standard_error
        );
        // φ∞ is pinned by the large outlets to better than 0.01.
        assert!(fit.phi_infinity.standard_error < 0.01);
    }

    #[test]
    fn one_sigma_errors_cover_the_truth_at_the_student_t_rate() {
        // The set-up of the test above (φ∞ = 0.78, τ₁ = 3.74, τ₂ = 0.18/mm, eight outlets of
        // R = 4.5–30 mm, noise 0.003 given as the errors) in 2000 data sets: ν = 5, so each
        // ±1σ interval must hold the truth at P(|t_5| ≤ 1) = 63.7 %, within the 4σ binomial band.
        let (phi, tau1, tau2) = (0.78, 3.74, 0.18);
        let radii: Vec<f64> = (0..8).map(|i| 0.0045 + 0.0036 * i as f64).collect();
        let sigma = vec![0.003; radii.len()];
        let mut coverage = [
            Coverage::new("φ∞", phi),
            Coverage::new("τ₁", tau1),
            Coverage::new("τ₂", tau2),
        ];
        let mut rng = seeded_rng(13);
        for _ in 0..2000 {
            let fractions: Vec<f64> = radii
                .iter()
                .map(|&r| packing_saturation(r, phi, tau1, tau2) + 0.003 * normal(&mut rng))
                .collect();
            let fit = fit_packing_saturation(&radii, &fractions, Some(&sigma)).unwrap();
            assert_eq!(fit.degrees_of_freedom, 5);
            coverage[0].record(fit.phi_infinity);
            coverage[1].record(fit.tau1);
            coverage[2].record(fit.tau2_per_millimetre);
        }
        for c in coverage {
            c.assert_nominal(5);
        }
    }

    #[test]
    fn eq12_uses_millimetres_for_the_radius() {
        // At R = 9 mm with τ₁ = 5.34, τ₂ = 0.19/mm: 1 − 5.34·e^{−3.42} = 0.8254.
        let value = packing_saturation(0.009, 1.0, 5.34, 0.19);
        assert!((value - (1.0 - 5.34 * (-3.42f64).exp())).abs() < 1e-12);
    }

    #[test]
    fn too_few_outlets_are_rejected() {
        assert!(matches!(
            fit_packing_saturation(&[0.009, 0.015, 0.0225], &[0.7, 0.75, 0.77], None),
            Err(AnalysisError::TooFewPoints { .. })
        ));
    }
}
