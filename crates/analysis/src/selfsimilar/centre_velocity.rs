//! Fit of the centre velocity law v_c = √(2γgR) across outlet sizes (paper Fig. 4, Table 2).

use serde::{Deserialize, Serialize};

use crate::error::{
    ensure_finite, ensure_positive, ensure_same_length, AnalysisError, AnalysisResult,
};
use crate::estimate::{Estimate, Interval};
use crate::fit::fit_proportional;

/// Result of fitting v_c = √(2γgR).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CentreVelocityFit {
    /// γ, the dome-height factor (dimensionless; 1.66 at α = 90° in the paper).
    pub gamma: Estimate,
    /// 95 % confidence interval of γ (the square of the interval of √γ).
    pub gamma_interval: Interval,
    /// Weighted sum of squared velocity residuals.
    pub chi_squared: f64,
    /// Residual degrees of freedom (n − 1).
    pub degrees_of_freedom: usize,
    /// Gravitational acceleration used [m/s²].
    pub gravity: f64,
}

impl CentreVelocityFit {
    /// Predicted centre velocity √(2γgR) [m/s] at outlet half-width `radius` [m].
    pub fn centre_velocity(&self, radius: f64) -> f64 {
        (2.0 * self.gamma.value * self.gravity * radius).sqrt()
    }
}

/// Least squares in v_c (not v_c²) of v_c = √γ·√(2gR) over the outlet half-widths `radii` [m]
/// with measured centre speeds `centre_velocities` [m/s] and optional errors `sigma` [m/s].
///
/// The model is linear in k = √γ, so this is an exact weighted regression through the origin;
/// γ = k² and σ_γ = 2kσ_k.
pub fn fit_centre_velocity(
    radii: &[f64],
    centre_velocities: &[f64],
    sigma: Option<&[f64]>,
    gravity: f64,
) -> AnalysisResult<CentreVelocityFit> {
    const CONTEXT: &str = "centre-velocity fit";
    ensure_same_length(CONTEXT, radii.len(), centre_velocities.len())?;
    ensure_finite(CONTEXT, radii)?;
    ensure_positive(CONTEXT, "gravity", gravity)?;
    if let Some(r) = radii.iter().find(|r| **r <= 0.0) {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: format!("outlet half-widths must be > 0 m, got {r}"),
        });
    }
    let free_fall: Vec<f64> = radii.iter().map(|r| (2.0 * gravity * r).sqrt()).collect();
    let line = fit_proportional(&free_fall, centre_velocities, sigma, 0.95)?;
    let k = line.slope;
    if k.value.is_nan() || k.value <= 0.0 {
        return Err(AnalysisError::Degenerate {
            context: CONTEXT,
            reason: "centre velocities are not positive".into(),
        });
    }
    let lower = line.slope_interval.lower.max(0.0);
    Ok(CentreVelocityFit {
        gamma: Estimate::new(k.value * k.value, 2.0 * k.value * k.standard_error),
        gamma_interval: Interval {
            lower: lower * lower,
            upper: line.slope_interval.upper.powi(2),
        },
        chi_squared: line.chi_squared,
        degrees_of_freedom: line.degrees_of_freedom,
        gravity,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{normal, seeded_rng};

    #[test]
    fn gamma_is_recovered_from_noisy_centre_velocities() {
        // γ = 1.66 (Table 2, 90°) at the paper's four outlets, 2 % noise, 3 fills each.
        let mut rng = seeded_rng(8);
        let g = 9.81;
        let mut radii = Vec::new();
        let mut speeds = Vec::new();
        for r in [0.009f64, 0.015, 0.0225, 0.03] {
            for _ in 0..3 {
                radii.push(r);
                speeds.push((2.0 * 1.66 * g * r).sqrt() * (1.0 + 0.02 * normal(&mut rng)));
            }
        }
        let fit = fit_centre_velocity(&radii, &speeds, None, g).unwrap();
        // 4σ recovery; and σ_γ must be near 2·1.66·0.02/√12 ≈ 0.019 (within a factor 2,
        // the spread of an 11-dof error estimate plus the unequal lever arms).
        assert!((fit.gamma.value - 1.66).abs() < 4.0 * fit.gamma.standard_error);
        assert!(fit.gamma.standard_error > 0.0096 && fit.gamma.standard_error < 0.04);
        assert!(fit.gamma_interval.contains(fit.gamma.value));
    }

    #[test]
    fn predicted_centre_velocity_matches_the_physics_spec_table() {
        // Physics spec §8.1: γ = 1.66 gives v_c = 0.699 m/s at D = 30 mm (table rounds to 1e-3).
        let fit = CentreVelocityFit {
            gamma: Estimate::exact(1.66),
            gamma_interval: Interval {
                lower: 1.66,
                upper: 1.66,
            },
            chi_squared: 0.0,
            degrees_of_freedom: 1,
            gravity: 9.81,
        };
        assert!((fit.centre_velocity(0.015) - 0.699).abs() < 5e-4);
        assert!((fit.centre_velocity(0.030) - 0.988).abs() < 5e-4);
    }

    #[test]
    fn non_positive_radii_are_rejected() {
        assert!(fit_centre_velocity(&[0.0, 0.01], &[0.1, 0.2], None, 9.81).is_err());
        assert!(fit_centre_velocity(&[0.01, 0.02], &[0.1, 0.2], None, 0.0).is_err());
    }
}
