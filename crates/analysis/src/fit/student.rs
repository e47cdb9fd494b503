//! Two-sided Student-t quantiles for confidence intervals.

use statrs::distribution::{ContinuousCDF, StudentsT};

use crate::error::{AnalysisError, AnalysisResult};

/// The factor t such that `estimate ± t·standard_error` is a two-sided confidence interval
/// at `confidence_level` (e.g. 0.95) with `degrees_of_freedom` residual degrees of freedom.
pub fn student_t_quantile(confidence_level: f64, degrees_of_freedom: usize) -> AnalysisResult<f64> {
    const CONTEXT: &str = "Student-t quantile";
    if !(confidence_level > 0.0 && confidence_level < 1.0) {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: format!("confidence level must lie in (0, 1), got {confidence_level}"),
        });
    }
    if degrees_of_freedom == 0 {
        return Err(AnalysisError::TooFewPoints {
            context: CONTEXT,
            needed: 1,
            got: 0,
        });
    }
    let distribution = StudentsT::new(0.0, 1.0, degrees_of_freedom as f64).map_err(|e| {
        AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: e.to_string(),
        }
    })?;
    Ok(distribution.inverse_cdf(0.5 + 0.5 * confidence_level))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_match_printed_student_tables() {
        // Printed tables give 12.706 (1 dof), 2.776 (4 dof), 2.228 (10 dof) at 95 %; tables
        // round to 3 decimals, hence the 1e-3 tolerance.
        for (dof, expected) in [(1, 12.706), (4, 2.776), (10, 2.228)] {
            let t = student_t_quantile(0.95, dof).unwrap();
            assert!((t - expected).abs() < 1e-3, "dof {dof}: {t}");
        }
    }

    #[test]
    fn quantile_rejects_levels_outside_the_unit_interval() {
        assert!(student_t_quantile(1.0, 5).is_err());
        assert!(student_t_quantile(0.95, 0).is_err());
    }
}
