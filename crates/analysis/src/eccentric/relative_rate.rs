//! Flow rate relative to the centred outlet, W/W₀ against s* (paper Fig. 16).

use serde::{Deserialize, Serialize};

use crate::error::{ensure_finite, ensure_same_length, AnalysisError, AnalysisResult};
use crate::estimate::Estimate;

/// One point of Fig. 16.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RelativeRate {
    /// Normalised eccentricity s* (dimensionless).
    pub s_star: f64,
    /// W/W₀ (dimensionless) with the errors of W and W₀ combined in quadrature.
    pub ratio: Estimate,
}

/// Divides the rates `rates` [kg/s] measured at eccentricities `s_star` by the centred rate
/// `reference` W₀ [kg/s] of the same outlet width. Errors are independent:
/// (σ_r/r)² = (σ_W/W)² + (σ_W₀/W₀)².
pub fn relative_discharge_rates(
    s_star: &[f64],
    rates: &[Estimate],
    reference: Estimate,
) -> AnalysisResult<Vec<RelativeRate>> {
    const CONTEXT: &str = "relative discharge rate";
    ensure_same_length(CONTEXT, s_star.len(), rates.len())?;
    ensure_finite(CONTEXT, s_star)?;
    if !(reference.value > 0.0 && reference.value.is_finite()) {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: format!("reference rate must be > 0 kg/s, got {}", reference.value),
        });
    }
    Ok(s_star
        .iter()
        .zip(rates)
        .map(|(&s, w)| {
            let ratio = w.value / reference.value;
            let relative = (w.relative_error().powi(2) + reference.relative_error().powi(2)).sqrt();
            RelativeRate {
                s_star: s,
                ratio: Estimate::new(ratio, ratio.abs() * relative),
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratio_errors_combine_in_quadrature() {
        // 3 % and 4 % relative errors give 5 % on the ratio.
        let out = relative_discharge_rates(
            &[0.0],
            &[Estimate::new(0.078, 0.078 * 0.03)],
            Estimate::new(0.06, 0.06 * 0.04),
        )
        .unwrap();
        assert!((out[0].ratio.value - 1.3).abs() < 1e-12);
        assert!((out[0].ratio.relative_error() - 0.05).abs() < 1e-12);
        assert!(
            relative_discharge_rates(&[0.0], &[Estimate::exact(1.0)], Estimate::exact(0.0))
                .is_err()
        );
    }
}
