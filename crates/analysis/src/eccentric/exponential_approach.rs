//! Fit of an exponential approach to a plateau, y = c₀ − c₁ e^{−c₂ s*} (paper Fig. 11b:
//! σ_s1 = 0.39 − 0.12 e^{−3.74 s*}; also usable for δ_s1(s*) growing to 0).

use serde::{Deserialize, Serialize};

use crate::error::{
    ensure_at_least, ensure_finite, ensure_same_length, AnalysisError, AnalysisResult,
};
use crate::estimate::Estimate;
use crate::fit::{fit_curve, fit_line, CurveData, ParameterBounds};

/// Result of an exponential-approach fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExponentialApproachFit {
    /// Plateau c₀ reached at large s* (unit of y).
    pub limit: Estimate,
    /// Depth c₁ of the approach, y(0) = c₀ − c₁ (unit of y).
    pub amplitude: Estimate,
    /// Rate c₂ (per unit of s*, dimensionless for s*).
    pub rate: Estimate,
    /// Whether the data determine c₂. False when the fitted approach is complete to
    /// [`UNRESOLVED_APPROACH`] of c₁ at the smallest s* > 0: the data then show a step at
    /// s* = 0, every larger c₂ fits as well, and `rate`'s error (from a derivative near zero)
    /// means nothing.
    #[serde(default = "resolved")]
    pub rate_resolved: bool,
    /// Weighted sum of squared residuals.
    pub chi_squared: f64,
    /// Residual degrees of freedom (n − 3).
    pub degrees_of_freedom: usize,
}

/// The fraction e^{−c₂ s*₁} of the approach left at the smallest s*₁ > 0 below which c₂ is
/// not determined: a thousandth of c₁ is far below any σ_s1 scatter (0.01–0.03 per case).
pub const UNRESOLVED_APPROACH: f64 = 1e-3;

fn resolved() -> bool {
    true
}

/// y = c₀ − c₁ e^{−c₂ s*}.
pub fn exponential_approach(s_star: f64, limit: f64, amplitude: f64, rate: f64) -> f64 {
    limit - amplitude * (-rate * s_star).exp()
}

/// Fits c₀, c₁, c₂ to values `values` at eccentricities `s_star`, with optional errors.
///
/// Needs at least 4 points. As for Eq. 12, the start comes from a scan of c₂ on a log grid
/// (for fixed c₂ the model is linear in c₀ and c₁), refined by Levenberg–Marquardt with
/// c₂ > 0.
pub fn fit_exponential_approach(
    s_star: &[f64],
    values: &[f64],
    sigma: Option<&[f64]>,
) -> AnalysisResult<ExponentialApproachFit> {
    const CONTEXT: &str = "exponential-approach fit";
    ensure_same_length(CONTEXT, s_star.len(), values.len())?;
    ensure_finite(CONTEXT, s_star)?;
    ensure_finite(CONTEXT, values)?;
    ensure_at_least(CONTEXT, 4, s_star.len())?;
    // Rates from 0.05 to 100 per unit s*: decay lengths from the whole range to 1 % of it.
    let mut best: Option<(f64, f64, f64, f64)> = None;
    for step in 0..=150 {
        let rate = 0.05 * 2000f64.powf(step as f64 / 150.0);
        let basis: Vec<f64> = s_star.iter().map(|s| (-rate * s).exp()).collect();
        let Ok(line) = fit_line(&basis, values, 0.95) else {
            continue;
        };
        if !matches!(best, Some(b) if b.0 <= line.chi_squared) {
            best = Some((
                line.chi_squared,
                line.intercept.value,
                -line.slope.value,
                rate,
            ));
        }
    }
    let Some((_, limit, amplitude, rate)) = best else {
        return Err(AnalysisError::Degenerate {
            context: CONTEXT,
            reason: "all eccentricities are equal".into(),
        });
    };
    let fit = fit_curve(
        |s, p| exponential_approach(s, p[0], p[1], p[2]),
        CurveData {
            x: s_star,
            y: values,
            sigma,
        },
        &[limit, amplitude, rate],
        Some(&[
            ParameterBounds::free(),
            ParameterBounds::free(),
            ParameterBounds::between(1e-6, 1e3),
        ]),
    )?;
    let rate = fit.parameters[2];
    let first = s_star
        .iter()
        .copied()
        .filter(|s| *s > 0.0)
        .fold(f64::INFINITY, f64::min);
    Ok(ExponentialApproachFit {
        limit: fit.parameters[0],
        amplitude: fit.parameters[1],
        rate,
        // A NaN rate counts as resolved, so that the table prints it, NaN and all.
        rate_resolved: (-rate.value * first).exp() >= UNRESOLVED_APPROACH || rate.value.is_nan(),
        chi_squared: fit.chi_squared,
        degrees_of_freedom: fit.degrees_of_freedom,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{normal, seeded_rng, Coverage};

    #[test]
    fn one_sigma_errors_cover_the_truth_at_the_student_t_rate() {
        // The σ_s1 law of paper Fig. 11b, σ_s1 = 0.39 − 0.12 e^{−3.74 s*}, sampled as in the
        // test below (17 eccentricities in [0, 1], three outlet widths) with noise 0.005, in
        // 2000 data sets: ν = 14, so each ±1σ interval must hold the truth at
        // P(|t_14| ≤ 1) = 66.6 %, within the 4σ binomial band.
        let mut s_star = Vec::new();
        for width in [0.018, 0.030, 0.045] {
            for gap in [0.0, 0.006, 0.012, 0.018, 0.024, 0.030] {
                let s = 2.0 * gap / (0.1 - width);
                if s <= 1.0 {
                    s_star.push(s);
                }
            }
        }
        let mut coverage = [
            Coverage::new("c₀", 0.39),
            Coverage::new("c₁", 0.12),
            Coverage::new("c₂", 3.74),
        ];
        let mut rng = seeded_rng(78);
        for _ in 0..2000 {
            let values: Vec<f64> = s_star
                .iter()
                .map(|&s| exponential_approach(s, 0.39, 0.12, 3.74) + 0.005 * normal(&mut rng))
                .collect();
            let fit = fit_exponential_approach(&s_star, &values, None).unwrap();
            assert_eq!(fit.degrees_of_freedom, 14);
            coverage[0].record(fit.limit);
            coverage[1].record(fit.amplitude);
            coverage[2].record(fit.rate);
        }
        for c in coverage {
            c.assert_nominal(14);
        }
    }

    #[test]
    fn sigma_s1_law_is_recovered_from_noisy_eccentricity_series() {
        // Paper Fig. 11b: σ_s1 = 0.39 − 0.12 e^{−3.74 s*}. Six gaps s = 0…30 mm at three
        // outlet widths (18, 30, 45 mm) give 18 points in s* ∈ [0, 1]; noise 0.005.
        let mut rng = seeded_rng(77);
        let mut s_star = Vec::new();
        let mut values = Vec::new();
        for width in [0.018, 0.030, 0.045] {
            for gap in [0.0, 0.006, 0.012, 0.018, 0.024, 0.030] {
                let s = 2.0 * gap / (0.1 - width);
                if s <= 1.0 {
                    s_star.push(s);
                    values
                        .push(exponential_approach(s, 0.39, 0.12, 3.74) + 0.005 * normal(&mut rng));
                }
            }
        }
        let fit = fit_exponential_approach(&s_star, &values, None).unwrap();
        // 4σ recovery of each parameter with its own error.
        assert!(
            (fit.limit.value - 0.39).abs() < 4.0 * fit.limit.standard_error,
            "{fit:?}"
        );
        assert!(
            (fit.amplitude.value - 0.12).abs() < 4.0 * fit.amplitude.standard_error,
            "{fit:?}"
        );
        assert!(
            (fit.rate.value - 3.74).abs() < 4.0 * fit.rate.standard_error,
            "{fit:?}"
        );
        assert!(fit.rate_resolved);
    }

    #[test]
    fn a_step_at_zero_eccentricity_leaves_the_rate_undetermined() {
        // As σ_s1 in the three-replica study (Table 3): 0.27 at s* = 0, then 0.40–0.43
        // from the first gap on (s* ≥ 0.146), the first of them the highest: no sign of a gradual
        // approach. The fit runs c₂ up until the exponential vanishes at s*₁; it must say
        // that c₂ is not determined rather than report a huge c₂ with a vanishing error.
        let s_star = [
            0.0, 0.0, 0.146, 0.171, 0.293, 0.343, 0.439, 0.514, 0.585, 0.686,
        ];
        let values = [0.27, 0.275, 0.42, 0.41, 0.40, 0.41, 0.42, 0.40, 0.41, 0.41];
        let fit = fit_exponential_approach(&s_star, &values, None).unwrap();
        assert!(!fit.rate_resolved, "{fit:?}");
        // The plateau and the depth are still measured: c₀ near the mean of the s* > 0
        // points (0.41) and c₁ near 0.41 − 0.2725; 0.02 is twice the points' scatter.
        assert!((fit.limit.value - 0.41).abs() < 0.02, "{fit:?}");
        assert!((fit.amplitude.value - 0.1375).abs() < 0.02, "{fit:?}");
    }

    #[test]
    fn too_few_eccentricities_are_rejected() {
        assert!(matches!(
            fit_exponential_approach(&[0.0, 0.5, 1.0], &[0.27, 0.37, 0.39], None),
            Err(AnalysisError::TooFewPoints { .. })
        ));
    }
}
