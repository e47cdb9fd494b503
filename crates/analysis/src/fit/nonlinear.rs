//! General nonlinear least squares y ≈ f(x; p) by Levenberg–Marquardt (the `rmpfit` port of MINPACK/CMPFIT).

use rmpfit::{MPConfig, MPError, MPFitter, MPPar, MPResult, MPSuccess};
use serde::{Deserialize, Serialize};

use crate::error::{
    ensure_at_least, ensure_finite, ensure_same_length, AnalysisError, AnalysisResult,
};
use crate::estimate::Estimate;

/// The data of a one-dimensional curve fit.
#[derive(Debug, Clone, Copy)]
pub struct CurveData<'a> {
    /// Abscissae.
    pub x: &'a [f64],
    /// Ordinates.
    pub y: &'a [f64],
    /// Standard errors of y (weights 1/σ²); `None` weights all points equally.
    pub sigma: Option<&'a [f64]>,
}

/// Box constraints on one parameter; `fixed` holds it at its initial value.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ParameterBounds {
    /// Lower limit, if any.
    pub lower: Option<f64>,
    /// Upper limit, if any.
    pub upper: Option<f64>,
    /// Hold the parameter at its initial value.
    pub fixed: bool,
}

impl ParameterBounds {
    /// No constraint.
    pub fn free() -> Self {
        Self::default()
    }

    /// Bounded below and above.
    pub fn between(lower: f64, upper: f64) -> Self {
        Self {
            lower: Some(lower),
            upper: Some(upper),
            fixed: false,
        }
    }

    /// Held fixed at the initial value.
    pub fn held() -> Self {
        Self {
            fixed: true,
            ..Self::default()
        }
    }
}

/// Result of a nonlinear least-squares fit.
///
/// Standard errors are √diag(C)·√(χ²/ν): the covariance of the weighted problem scaled
/// by the reduced chi², i.e. the errors reflect the observed scatter about the model.
/// A parameter held fixed, or pegged at a bound, has a zero standard error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NonlinearFit {
    /// Fitted parameters in the model's order, with standard errors.
    pub parameters: Vec<Estimate>,
    /// Scaled covariance matrix, row-major, `parameters.len()` square.
    pub covariance: Vec<Vec<f64>>,
    /// Weighted sum of squared residuals at the optimum.
    pub chi_squared: f64,
    /// Number of points minus number of free parameters.
    pub degrees_of_freedom: usize,
    /// χ²/ν.
    pub reduced_chi_squared: f64,
    /// Levenberg–Marquardt iterations used.
    pub iterations: usize,
}

struct Problem<'a, F> {
    model: F,
    data: CurveData<'a>,
}

impl<F: Fn(f64, &[f64]) -> f64> MPFitter for Problem<'_, F> {
    fn eval(&self, params: &[f64], deviates: &mut [f64]) -> MPResult<()> {
        for (i, d) in deviates.iter_mut().enumerate() {
            let sigma = self.data.sigma.map_or(1.0, |s| s[i]);
            let r = (self.data.y[i] - (self.model)(self.data.x[i], params)) / sigma;
            if !r.is_finite() {
                // Abort rather than let a NaN poison the QR factorisation.
                return Err(MPError::Eval);
            }
            *d = r;
        }
        Ok(())
    }

    fn number_of_points(&self) -> usize {
        self.data.x.len()
    }
}

fn describe(error: MPError) -> String {
    error.to_string()
}

/// Fits `model(x, parameters)` to `data` starting from `initial`.
///
/// `bounds`, if given, has one entry per parameter; initial values outside their bounds
/// are clamped into them. Fails with [`AnalysisError::FitFailed`] when the solver does not
/// converge or the model returns a non-finite value.
pub fn fit_curve<F>(
    model: F,
    data: CurveData<'_>,
    initial: &[f64],
    bounds: Option<&[ParameterBounds]>,
) -> AnalysisResult<NonlinearFit>
where
    F: Fn(f64, &[f64]) -> f64,
{
    const CONTEXT: &str = "nonlinear fit";
    ensure_same_length(CONTEXT, data.x.len(), data.y.len())?;
    ensure_finite(CONTEXT, data.x)?;
    ensure_finite(CONTEXT, data.y)?;
    ensure_finite(CONTEXT, initial)?;
    if let Some(sigma) = data.sigma {
        ensure_same_length(CONTEXT, data.x.len(), sigma.len())?;
        ensure_finite(CONTEXT, sigma)?;
        if let Some(bad) = sigma.iter().find(|s| **s <= 0.0) {
            return Err(AnalysisError::InvalidArgument {
                context: CONTEXT,
                reason: format!("standard errors must be > 0, got {bad}"),
            });
        }
    }
    if initial.is_empty() {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: "no parameters".into(),
        });
    }
    let default_bounds = vec![ParameterBounds::free(); initial.len()];
    let bounds = bounds.unwrap_or(&default_bounds);
    ensure_same_length(CONTEXT, initial.len(), bounds.len())?;
    let free = bounds.iter().filter(|b| !b.fixed).count();
    // At least one residual degree of freedom, otherwise χ²/ν (and the errors) are undefined.
    ensure_at_least(CONTEXT, free + 1, data.x.len())?;

    let mut parameters = initial.to_vec();
    let mut settings = Vec::with_capacity(bounds.len());
    for (p, b) in parameters.iter_mut().zip(bounds) {
        if let (Some(lo), Some(hi)) = (b.lower, b.upper) {
            if lo.is_nan() || hi.is_nan() || lo >= hi {
                return Err(AnalysisError::InvalidArgument {
                    context: CONTEXT,
                    reason: format!("lower bound {lo} is not below upper bound {hi}"),
                });
            }
        }
        if let Some(lo) = b.lower {
            *p = p.max(lo);
        }
        if let Some(hi) = b.upper {
            *p = p.min(hi);
        }
        // rmpfit compares parameters with their limits even when the limits are disabled:
        // a fixed parameter must lie within them, and a free parameter equal to a disabled
        // limit (0 by default) is treated as pegged and never moves. So a held parameter
        // gets limits equal to its value, and a disabled limit is set to ±∞.
        let (limit_low, limit_up) = if b.fixed {
            (*p, *p)
        } else {
            (
                b.lower.unwrap_or(f64::NEG_INFINITY),
                b.upper.unwrap_or(f64::INFINITY),
            )
        };
        settings.push(MPPar {
            fixed: b.fixed,
            limited_low: b.lower.is_some() && !b.fixed,
            limited_up: b.upper.is_some() && !b.fixed,
            limit_low,
            limit_up,
            ..MPPar::default()
        });
    }
    let config = MPConfig {
        max_iter: 2000,
        ..MPConfig::default()
    };
    let problem = Problem { model, data };
    let status = problem
        .mpfit(&mut parameters, Some(&settings), &config)
        .map_err(|e| AnalysisError::FitFailed {
            reason: describe(e),
        })?;
    if status.success == MPSuccess::MaxIter {
        return Err(AnalysisError::FitFailed {
            reason: format!("no convergence in {} iterations", status.n_iter),
        });
    }
    let n = parameters.len();
    let degrees_of_freedom = data.x.len() - status.n_free;
    let chi_squared = status.best_norm;
    let reduced_chi_squared = chi_squared / degrees_of_freedom as f64;
    let covariance: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| status.covar[i * n + j] * reduced_chi_squared)
                .collect()
        })
        .collect();
    let estimates = parameters
        .iter()
        .enumerate()
        .map(|(i, &value)| Estimate::new(value, covariance[i][i].max(0.0).sqrt()))
        .collect();
    Ok(NonlinearFit {
        parameters: estimates,
        covariance,
        chi_squared,
        degrees_of_freedom,
        reduced_chi_squared,
        iterations: status.n_iter,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{normal, seeded_rng, Coverage};

    #[test]
    fn exponential_decay_parameters_are_recovered_within_their_errors() {
        // y = A e^{−x/λ} + c with 2 % of A as Gaussian noise on 60 points.
        let mut rng = seeded_rng(3);
        let x: Vec<f64> = (0..60).map(|i| i as f64 * 0.1).collect();
        let y: Vec<f64> = x
            .iter()
            .map(|&v| 2.0 * (-v / 1.5).exp() + 0.3 + 0.04 * normal(&mut rng))
            .collect();
        let fit = fit_curve(
            |v, p| p[0] * (-v / p[1]).exp() + p[2],
            CurveData {
                x: &x,
                y: &y,
                sigma: None,
            },
            &[1.0, 1.0, 0.0],
            None,
        )
        .unwrap();
        // 4σ recovery: the probability that an unbiased estimator misses by more is < 1e-4.
        for (p, truth) in fit.parameters.iter().zip([2.0, 1.5, 0.3]) {
            assert!(
                (p.value - truth).abs() < 4.0 * p.standard_error,
                "{p:?} vs {truth}"
            );
        }
        // Reduced χ² of unweighted residuals estimates the noise variance 0.04² within ~20 %
        // (relative sd of a χ² with 57 dof is √(2/57) ≈ 19 %, 2σ band ≈ 40 %).
        assert!((fit.reduced_chi_squared / 0.0016 - 1.0).abs() < 0.4);
    }

    /// Fits y = A e^{−x/λ} + c to `trials` synthetic data sets of 30 points on [0, 5.8] with
    /// Gaussian noise of standard deviation `noise(x)`, weighted by it when `weighted`, and
    /// returns the coverage counters of A, λ and c.
    fn decay_coverage(
        trials: usize,
        noise: impl Fn(f64) -> f64,
        weighted: bool,
        seed: u64,
    ) -> [Coverage; 3] {
        let truth = [2.0, 1.5, 0.3];
        let mut coverage = [
            Coverage::new("A", truth[0]),
            Coverage::new("λ", truth[1]),
            Coverage::new("c", truth[2]),
        ];
        let mut rng = seeded_rng(seed);
        let x: Vec<f64> = (0..30).map(|i| i as f64 * 0.2).collect();
        let sigma: Vec<f64> = x.iter().map(|&v| noise(v)).collect();
        for _ in 0..trials {
            let y: Vec<f64> = x
                .iter()
                .zip(&sigma)
                .map(|(&v, &s)| truth[0] * (-v / truth[1]).exp() + truth[2] + s * normal(&mut rng))
                .collect();
            let fit = fit_curve(
                |v, p| p[0] * (-v / p[1]).exp() + p[2],
                CurveData {
                    x: &x,
                    y: &y,
                    sigma: weighted.then_some(sigma.as_slice()),
                },
                &[1.0, 1.0, 0.0],
                None,
            )
            .unwrap();
            for (c, p) in coverage.iter_mut().zip(&fit.parameters) {
                c.record(*p);
            }
        }
        coverage
    }

    #[test]
    fn one_sigma_errors_cover_the_truth_at_the_student_t_rate() {
        // 2000 data sets with homoscedastic noise of 2 % of A, unweighted: the χ²-scaled
        // errors must hold the truth at P(|t_27| ≤ 1) = 67.4 %, within the 4σ binomial band
        // (`Coverage::assert_nominal`). The noise is small enough that the model is close to
        // linear over the scatter of the estimates, where the t law is exact.
        for c in decay_coverage(2000, |_| 0.04, false, 5) {
            c.assert_nominal(27);
        }
    }

    #[test]
    fn weighted_one_sigma_errors_cover_the_truth_at_the_student_t_rate() {
        // Noise growing from 1 % to 4 % of A along x, with those σ_i as weights: the errors of
        // the weighted problem, scaled by √(χ²/ν), must cover as in the unweighted case.
        for c in decay_coverage(2000, |v| 0.02 * (1.0 + v / 2.0), true, 6) {
            c.assert_nominal(27);
        }
    }

    #[test]
    fn a_held_parameter_keeps_its_value_and_has_no_error() {
        let x: Vec<f64> = (0..10).map(|i| i as f64).collect();
        let y: Vec<f64> = x
            .iter()
            .map(|v| 2.0 * v + 1.0 + 0.01 * (v * 7.0).sin())
            .collect();
        let fit = fit_curve(
            |v, p| p[0] * v + p[1],
            CurveData {
                x: &x,
                y: &y,
                sigma: None,
            },
            &[1.0, 1.0],
            Some(&[ParameterBounds::free(), ParameterBounds::held()]),
        )
        .unwrap();
        assert_eq!(fit.parameters[1].value, 1.0);
        assert_eq!(fit.parameters[1].standard_error, 0.0);
        assert_eq!(fit.degrees_of_freedom, 9);
        // Slope with intercept fixed at the truth: only the 0.01 ripple perturbs it.
        assert!((fit.parameters[0].value - 2.0).abs() < 1e-2);
    }

    #[test]
    fn a_free_parameter_starting_at_zero_is_not_treated_as_pegged() {
        // Regression: rmpfit treats a free parameter equal to a disabled limit as pegged at
        // that limit. With disabled limits left at 0, a slope started at 0 never moved while
        // another parameter was bounded. Exact data: the fit must reach the truth.
        let x: Vec<f64> = (0..12).map(|i| -1.0 + i as f64 * 0.18).collect();
        let y: Vec<f64> = x.iter().map(|v| -0.3 * v + 1.2 * (-v * v).exp()).collect();
        let fit = fit_curve(
            |v, p| p[0] * v + p[1] * (-v * v / p[2]).exp(),
            CurveData {
                x: &x,
                y: &y,
                sigma: None,
            },
            &[0.0, 1.0, 0.8],
            Some(&[
                ParameterBounds::free(),
                ParameterBounds::free(),
                ParameterBounds::between(0.1, 10.0),
            ]),
        )
        .unwrap();
        // Noise-free data: convergence tolerance (1e-10 relative) bounds the error.
        assert!((fit.parameters[0].value + 0.3).abs() < 1e-6, "{fit:?}");
        assert!((fit.parameters[2].value - 1.0).abs() < 1e-6, "{fit:?}");
    }

    #[test]
    fn a_model_returning_nan_is_reported_not_panicked() {
        let x = [1.0, 2.0, 3.0];
        let y = [1.0, 2.0, 3.0];
        let result = fit_curve(
            |_, _| f64::NAN,
            CurveData {
                x: &x,
                y: &y,
                sigma: None,
            },
            &[1.0],
            None,
        );
        assert!(matches!(result, Err(AnalysisError::FitFailed { .. })));
    }

    #[test]
    fn fits_without_residual_freedom_are_rejected() {
        let x = [1.0, 2.0];
        let y = [1.0, 2.0];
        let result = fit_curve(
            |v, p| p[0] * v + p[1],
            CurveData {
                x: &x,
                y: &y,
                sigma: None,
            },
            &[1.0, 0.0],
            None,
        );
        assert!(matches!(result, Err(AnalysisError::TooFewPoints { .. })));
    }
}
