//! A value with its one-sigma standard error, and first-order error propagation.

use serde::{Deserialize, Serialize};

use crate::error::{AnalysisError, AnalysisResult};

/// A measured or fitted quantity with its one-standard-deviation uncertainty.
///
/// The unit is that of the quantity it describes; the field that holds an
/// `Estimate` documents it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// Best value.
    pub value: f64,
    /// One-sigma standard error (same unit as `value`); 0 for exact or fixed values.
    pub standard_error: f64,
}

impl Estimate {
    /// A value with its standard error.
    pub fn new(value: f64, standard_error: f64) -> Self {
        Self {
            value,
            standard_error,
        }
    }

    /// An exact value (zero uncertainty), e.g. a parameter held fixed in a fit.
    pub fn exact(value: f64) -> Self {
        Self::new(value, 0.0)
    }

    /// Standard error divided by |value| (infinite for a zero value).
    pub fn relative_error(&self) -> f64 {
        self.standard_error / self.value.abs()
    }

    /// Symmetric interval `value ± half_width_factor · standard_error`.
    pub fn interval(&self, half_width_factor: f64) -> Interval {
        Interval {
            lower: self.value - half_width_factor * self.standard_error,
            upper: self.value + half_width_factor * self.standard_error,
        }
    }
}

/// A closed interval [lower, upper], typically a confidence interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Interval {
    /// Lower bound (unit of the quantity).
    pub lower: f64,
    /// Upper bound (unit of the quantity).
    pub upper: f64,
}

impl Interval {
    /// Whether `value` lies inside the closed interval.
    pub fn contains(&self, value: f64) -> bool {
        value >= self.lower && value <= self.upper
    }
}

/// Propagates independent uncertainties through `function` to first order,
/// σ_f² = Σ (∂f/∂x_i)² σ_i², with central differences of step max(σ_i, 1e-6 |x_i|)·1e-3.
///
/// Used for predictions built from fitted parameters (Eqs. 14 and 18), where the
/// parameters come from separate fits and are treated as uncorrelated.
pub fn propagate<F>(function: F, inputs: &[Estimate]) -> AnalysisResult<Estimate>
where
    F: Fn(&[f64]) -> f64,
{
    let values: Vec<f64> = inputs.iter().map(|e| e.value).collect();
    let centre = function(&values);
    if !centre.is_finite() {
        return Err(AnalysisError::Degenerate {
            context: "error propagation",
            reason: "function is not finite at the central values".into(),
        });
    }
    let mut variance = 0.0;
    let mut shifted = values.clone();
    for (i, input) in inputs.iter().enumerate() {
        if input.standard_error == 0.0 {
            continue;
        }
        // A small fraction of sigma keeps the derivative local; the floor avoids a zero step.
        let step = 1e-3 * input.standard_error.abs().max(1e-6 * input.value.abs());
        shifted[i] = input.value + step;
        let plus = function(&shifted);
        shifted[i] = input.value - step;
        let minus = function(&shifted);
        shifted[i] = input.value;
        let derivative = (plus - minus) / (2.0 * step);
        if !derivative.is_finite() {
            return Err(AnalysisError::Degenerate {
                context: "error propagation",
                reason: format!("derivative with respect to input {i} is not finite"),
            });
        }
        variance += (derivative * input.standard_error).powi(2);
    }
    Ok(Estimate::new(centre, variance.sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn propagation_of_a_product_matches_the_relative_error_rule() {
        // For f = x·y with independent errors, (σ_f/f)² = (σ_x/x)² + (σ_y/y)² exactly to first order;
        // central differences on a bilinear function are exact, so 1e-9 covers rounding only.
        let x = Estimate::new(3.0, 0.3);
        let y = Estimate::new(2.0, 0.1);
        let f = propagate(|p| p[0] * p[1], &[x, y]).unwrap();
        let expected = 6.0 * (0.1f64.powi(2) + 0.05f64.powi(2)).sqrt();
        assert!((f.value - 6.0).abs() < 1e-12);
        assert!((f.standard_error - expected).abs() < 1e-9);
    }

    #[test]
    fn propagation_rejects_a_function_that_is_not_finite() {
        let x = Estimate::new(0.0, 0.1);
        assert!(propagate(|p| 1.0 / p[0], &[x]).is_err());
    }
}
