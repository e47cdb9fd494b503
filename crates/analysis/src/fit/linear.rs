//! Weighted straight-line and through-origin regression with standard errors and Student-t intervals.

use serde::{Deserialize, Serialize};

use crate::error::{
    ensure_at_least, ensure_finite, ensure_same_length, AnalysisError, AnalysisResult,
};
use crate::estimate::{Estimate, Interval};
use crate::fit::student::student_t_quantile;

/// Result of fitting y = slope·x + intercept.
///
/// Standard errors come from the weighted normal equations with the covariance
/// scaled by the reduced chi² (so they reflect the observed scatter even when the
/// supplied σ are only relative weights). Intervals are two-sided Student-t intervals
/// with n − 2 degrees of freedom.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinearFit {
    /// Slope (unit of y per unit of x).
    pub slope: Estimate,
    /// Intercept at x = 0 (unit of y).
    pub intercept: Estimate,
    /// Covariance of slope and intercept (unit of y² per unit of x).
    pub slope_intercept_covariance: f64,
    /// Abscissa where the line crosses y = 0, −intercept/slope (unit of x); its error
    /// is propagated to first order including the slope–intercept covariance.
    pub x_intercept: Estimate,
    /// Confidence interval of the slope.
    pub slope_interval: Interval,
    /// Confidence interval of the intercept.
    pub intercept_interval: Interval,
    /// Confidence interval of the x-intercept (first-order, symmetric).
    pub x_intercept_interval: Interval,
    /// Confidence level of the intervals, e.g. 0.95.
    pub confidence_level: f64,
    /// Student-t factor used for the intervals.
    pub t_quantile: f64,
    /// Weighted sum of squared residuals.
    pub chi_squared: f64,
    /// Residual degrees of freedom, n − 2.
    pub degrees_of_freedom: usize,
    /// Coefficient of determination (weighted).
    pub r_squared: f64,
}

/// Result of fitting y = slope·x (no intercept).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProportionalFit {
    /// Slope (unit of y per unit of x).
    pub slope: Estimate,
    /// Confidence interval of the slope.
    pub slope_interval: Interval,
    /// Confidence level of the interval.
    pub confidence_level: f64,
    /// Weighted sum of squared residuals.
    pub chi_squared: f64,
    /// Residual degrees of freedom, n − 1.
    pub degrees_of_freedom: usize,
}

fn weights_from_sigma(
    context: &'static str,
    n: usize,
    sigma: Option<&[f64]>,
) -> AnalysisResult<Vec<f64>> {
    match sigma {
        None => Ok(vec![1.0; n]),
        Some(s) => {
            ensure_same_length(context, n, s.len())?;
            ensure_finite(context, s)?;
            s.iter()
                .map(|&si| {
                    if si > 0.0 {
                        Ok(1.0 / (si * si))
                    } else {
                        Err(AnalysisError::InvalidArgument {
                            context,
                            reason: format!("standard errors must be > 0, got {si}"),
                        })
                    }
                })
                .collect()
        }
    }
}

/// Ordinary least squares of y on x with a 95 %-style interval at `confidence_level`.
pub fn fit_line(x: &[f64], y: &[f64], confidence_level: f64) -> AnalysisResult<LinearFit> {
    fit_line_weighted(x, y, None, confidence_level)
}

/// Weighted least squares of y on x; `sigma` are the standard errors of y (weights 1/σ²).
pub fn fit_line_weighted(
    x: &[f64],
    y: &[f64],
    sigma: Option<&[f64]>,
    confidence_level: f64,
) -> AnalysisResult<LinearFit> {
    const CONTEXT: &str = "straight-line fit";
    ensure_same_length(CONTEXT, x.len(), y.len())?;
    ensure_finite(CONTEXT, x)?;
    ensure_finite(CONTEXT, y)?;
    ensure_at_least(CONTEXT, 3, x.len())?;
    let w = weights_from_sigma(CONTEXT, x.len(), sigma)?;

    let (mut s, mut sx, mut sy) = (0.0, 0.0, 0.0);
    for ((&xi, &yi), &wi) in x.iter().zip(y).zip(&w) {
        s += wi;
        sx += wi * xi;
        sy += wi * yi;
    }
    // Centre the abscissae before forming sums of squares: avoids cancellation when
    // x is far from 0 (e.g. absolute times).
    let (x_mean, y_mean) = (sx / s, sy / s);
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for ((&xi, &yi), &wi) in x.iter().zip(y).zip(&w) {
        let (dx, dy) = (xi - x_mean, yi - y_mean);
        sxx += wi * dx * dx;
        sxy += wi * dx * dy;
        syy += wi * dy * dy;
    }
    if sxx <= f64::EPSILON * s * x_mean.abs().max(1.0).powi(2) {
        return Err(AnalysisError::Degenerate {
            context: CONTEXT,
            reason: "all abscissae are equal".into(),
        });
    }
    let slope = sxy / sxx;
    let intercept = y_mean - slope * x_mean;
    let chi_squared: f64 = x
        .iter()
        .zip(y)
        .zip(&w)
        .map(|((&xi, &yi), &wi)| wi * (yi - slope * xi - intercept).powi(2))
        .sum();
    let degrees_of_freedom = x.len() - 2;
    let scale = chi_squared / degrees_of_freedom as f64;
    let var_slope = scale / sxx;
    let var_intercept = scale * (1.0 / s + x_mean * x_mean / sxx);
    let covariance = -scale * x_mean / sxx;

    let x0 = -intercept / slope;
    let var_x0 = var_intercept / (slope * slope)
        + intercept * intercept * var_slope / slope.powi(4)
        - 2.0 * intercept * covariance / slope.powi(3);
    let t = student_t_quantile(confidence_level, degrees_of_freedom)?;
    let slope_e = Estimate::new(slope, var_slope.sqrt());
    let intercept_e = Estimate::new(intercept, var_intercept.sqrt());
    let x0_e = Estimate::new(x0, var_x0.max(0.0).sqrt());
    let r_squared = if syy > 0.0 {
        1.0 - chi_squared / syy
    } else {
        1.0
    };
    Ok(LinearFit {
        slope: slope_e,
        intercept: intercept_e,
        slope_intercept_covariance: covariance,
        x_intercept: x0_e,
        slope_interval: slope_e.interval(t),
        intercept_interval: intercept_e.interval(t),
        x_intercept_interval: x0_e.interval(t),
        confidence_level,
        t_quantile: t,
        chi_squared,
        degrees_of_freedom,
        r_squared,
    })
}

/// Weighted least squares of y = slope·x through the origin; `sigma` as in [`fit_line_weighted`].
pub fn fit_proportional(
    x: &[f64],
    y: &[f64],
    sigma: Option<&[f64]>,
    confidence_level: f64,
) -> AnalysisResult<ProportionalFit> {
    const CONTEXT: &str = "proportional fit";
    ensure_same_length(CONTEXT, x.len(), y.len())?;
    ensure_finite(CONTEXT, x)?;
    ensure_finite(CONTEXT, y)?;
    ensure_at_least(CONTEXT, 2, x.len())?;
    let w = weights_from_sigma(CONTEXT, x.len(), sigma)?;
    let sxx: f64 = x.iter().zip(&w).map(|(&xi, &wi)| wi * xi * xi).sum();
    let sxy: f64 = x
        .iter()
        .zip(y)
        .zip(&w)
        .map(|((&xi, &yi), &wi)| wi * xi * yi)
        .sum();
    if sxx <= 0.0 {
        return Err(AnalysisError::Degenerate {
            context: CONTEXT,
            reason: "all abscissae are zero".into(),
        });
    }
    let slope = sxy / sxx;
    let chi_squared: f64 = x
        .iter()
        .zip(y)
        .zip(&w)
        .map(|((&xi, &yi), &wi)| wi * (yi - slope * xi).powi(2))
        .sum();
    let degrees_of_freedom = x.len() - 1;
    let standard_error = (chi_squared / degrees_of_freedom as f64 / sxx).sqrt();
    let t = student_t_quantile(confidence_level, degrees_of_freedom)?;
    let slope_e = Estimate::new(slope, standard_error);
    Ok(ProportionalFit {
        slope: slope_e,
        slope_interval: slope_e.interval(t),
        confidence_level,
        chi_squared,
        degrees_of_freedom,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{normal, seeded_rng};

    #[test]
    fn exact_line_is_recovered_with_vanishing_errors() {
        let x = [1.0, 2.0, 3.0, 4.0];
        let y: Vec<f64> = x.iter().map(|v| 2.5 * v - 1.0).collect();
        let fit = fit_line(&x, &y, 0.95).unwrap();
        // Exact data: only rounding error remains.
        assert!((fit.slope.value - 2.5).abs() < 1e-12);
        assert!((fit.intercept.value + 1.0).abs() < 1e-12);
        assert!((fit.x_intercept.value - 0.4).abs() < 1e-12);
        assert!(fit.slope.standard_error < 1e-10);
    }

    #[test]
    fn confidence_intervals_cover_the_true_slope_at_the_nominal_rate() {
        // 400 synthetic data sets of 8 noisy points: a 95 % interval must cover the truth in
        // 95 ± 2.2 % of cases (binomial σ = √(0.95·0.05/400) ≈ 1.1 %, 2σ band).
        let mut rng = seeded_rng(7);
        let x: Vec<f64> = (0..8).map(|i| 0.018 + 0.006 * i as f64).collect();
        let (mut cover_slope, mut cover_x0) = (0, 0);
        let trials = 400;
        for _ in 0..trials {
            let y: Vec<f64> = x
                .iter()
                .map(|&v| 3.0 * (v - 0.005) + 0.002 * normal(&mut rng))
                .collect();
            let fit = fit_line(&x, &y, 0.95).unwrap();
            cover_slope += fit.slope_interval.contains(3.0) as usize;
            cover_x0 += fit.x_intercept_interval.contains(0.005) as usize;
        }
        let rate = cover_slope as f64 / trials as f64;
        assert!((rate - 0.95).abs() < 0.022, "slope coverage {rate}");
        // The x-intercept interval is first-order (delta method); allow a wider 4σ band.
        let rate_x0 = cover_x0 as f64 / trials as f64;
        assert!(
            (rate_x0 - 0.95).abs() < 0.045,
            "x-intercept coverage {rate_x0}"
        );
    }

    #[test]
    fn proportional_fit_recovers_slope_within_its_standard_error() {
        let mut rng = seeded_rng(11);
        let x: Vec<f64> = (1..=20).map(|i| i as f64).collect();
        let y: Vec<f64> = x
            .iter()
            .map(|&v| 0.7 * v + 0.05 * normal(&mut rng))
            .collect();
        let fit = fit_proportional(&x, &y, None, 0.95).unwrap();
        // Recovery within 4 standard errors: a failure would mean a biased estimator or a
        // wrong error formula (probability of a 4σ excursion ≈ 6e-5).
        assert!((fit.slope.value - 0.7).abs() < 4.0 * fit.slope.standard_error);
        // σ_k = 0.05/√Σx² ≈ 0.00092; the scaled estimate must be within 50 % of it (dof = 19).
        let expected = 0.05 / x.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!((fit.slope.standard_error / expected - 1.0).abs() < 0.5);
    }

    #[test]
    fn degenerate_inputs_give_typed_errors() {
        assert!(matches!(
            fit_line(&[1.0, 2.0], &[1.0, 2.0], 0.95),
            Err(AnalysisError::TooFewPoints { .. })
        ));
        assert!(matches!(
            fit_line(&[1.0, 1.0, 1.0], &[1.0, 2.0, 3.0], 0.95),
            Err(AnalysisError::Degenerate { .. })
        ));
        assert!(matches!(
            fit_line(&[1.0, f64::NAN, 3.0], &[1.0, 2.0, 3.0], 0.95),
            Err(AnalysisError::NonFinite { .. })
        ));
        assert!(matches!(
            fit_line(&[1.0, 2.0, 3.0], &[1.0, 2.0], 0.95),
            Err(AnalysisError::LengthMismatch { .. })
        ));
    }
}
