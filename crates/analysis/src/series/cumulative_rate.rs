//! Discharge rate as the slope of cumulative discharged mass M(t) over a time window.

use serde::{Deserialize, Serialize};

use crate::error::{ensure_finite, ensure_same_length, AnalysisError, AnalysisResult};
use crate::estimate::Estimate;
use crate::fit::{fit_line, LinearFit};

/// Rate from a straight-line fit of M(t).
///
/// The regression standard error assumes independent residuals, but residuals of a
/// cumulative series are strongly correlated (each point contains all earlier noise), so
/// `rate.standard_error` underestimates the true error; use the block-averaged mean rate
/// for error bars and this value as an independent check of the central value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CumulativeRate {
    /// Slope dM/dt [kg/s] with its (optimistic) regression error.
    pub rate: Estimate,
    /// Number of samples used.
    pub samples: usize,
    /// The full regression.
    pub line: LinearFit,
}

/// Fits M(t) = W·t + M₀ to the samples with `start_time ≤ t ≤ end_time` [s]; masses in kg.
pub fn rate_from_cumulative_mass(
    times: &[f64],
    masses: &[f64],
    start_time: f64,
    end_time: f64,
) -> AnalysisResult<CumulativeRate> {
    const CONTEXT: &str = "rate from cumulative mass";
    ensure_same_length(CONTEXT, times.len(), masses.len())?;
    ensure_finite(CONTEXT, times)?;
    ensure_finite(CONTEXT, masses)?;
    if start_time >= end_time {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: format!("start time {start_time} is not before end time {end_time}"),
        });
    }
    let (t, m): (Vec<f64>, Vec<f64>) = times
        .iter()
        .zip(masses)
        .filter(|(t, _)| **t >= start_time && **t <= end_time)
        .map(|(t, m)| (*t, *m))
        .unzip();
    let line = fit_line(&t, &m, 0.95)?;
    Ok(CumulativeRate {
        rate: line.slope,
        samples: t.len(),
        line,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::series::steady_window::tests::synthetic_discharge;
    use crate::series::{find_steady_window, mean_rate, SteadyWindowOptions};

    #[test]
    fn regression_rate_agrees_with_the_block_averaged_mean() {
        let series = synthetic_discharge(0.058, 0.1, 4);
        let window = find_steady_window(&series, &SteadyWindowOptions::default()).unwrap();
        let mean = mean_rate(&series, &window).unwrap();
        let (t, m) = series.cumulative_mass();
        let regression =
            rate_from_cumulative_mass(&t, &m, window.start_time, window.end_time).unwrap();
        // Both estimate the same plateau from the same bins; they differ only by how the
        // noise is weighted, which is within ~2 standard errors of the mean.
        assert!((regression.rate.value - mean.rate.value).abs() < 2.0 * mean.rate.standard_error);
        // And the truth is recovered to within 4 blocking errors.
        assert!((regression.rate.value - 0.058).abs() < 4.0 * mean.rate.standard_error);
    }

    #[test]
    fn an_empty_selection_is_rejected() {
        let t = [0.0, 0.1, 0.2, 0.3];
        let m = [0.0, 1.0, 2.0, 3.0];
        assert!(rate_from_cumulative_mass(&t, &m, 1.0, 2.0).is_err());
        assert!(rate_from_cumulative_mass(&t, &m, 0.3, 0.0).is_err());
    }
}
