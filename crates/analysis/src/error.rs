//! Typed errors for every analysis routine: degenerate input never panics.

use thiserror::Error;

/// Why an analysis routine refused its input or could not produce a result.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AnalysisError {
    /// Fewer data points than the method needs (e.g. a fit with no degrees of freedom).
    #[error("{context}: needs at least {needed} usable points, got {got}")]
    TooFewPoints {
        /// What was being computed.
        context: &'static str,
        /// Minimum number of points required.
        needed: usize,
        /// Number of points supplied (after any selection).
        got: usize,
    },
    /// A NaN or infinite value in the input.
    #[error("{context}: non-finite value at index {index}")]
    NonFinite {
        /// What was being computed.
        context: &'static str,
        /// Position of the first offending value.
        index: usize,
    },
    /// Paired inputs of different lengths.
    #[error("{context}: input lengths differ ({left} vs {right})")]
    LengthMismatch {
        /// What was being computed.
        context: &'static str,
        /// Length of the first input.
        left: usize,
        /// Length of the second input.
        right: usize,
    },
    /// A scalar argument outside its physical or mathematical domain.
    #[error("{context}: invalid argument: {reason}")]
    InvalidArgument {
        /// What was being computed.
        context: &'static str,
        /// Human-readable reason, naming the argument.
        reason: String,
    },
    /// The data are valid but carry no information for the requested quantity
    /// (e.g. all abscissae equal, zero total mass).
    #[error("{context}: degenerate data: {reason}")]
    Degenerate {
        /// What was being computed.
        context: &'static str,
        /// Human-readable reason.
        reason: String,
    },
    /// The nonlinear least-squares solver failed.
    #[error("least-squares fit failed: {reason}")]
    FitFailed {
        /// Solver message.
        reason: String,
    },
}

/// Convenience alias used across the crate.
pub type AnalysisResult<T> = Result<T, AnalysisError>;

/// Rejects any non-finite entry of `values`.
pub(crate) fn ensure_finite(context: &'static str, values: &[f64]) -> AnalysisResult<()> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(AnalysisError::NonFinite { context, index }),
        None => Ok(()),
    }
}

/// Rejects paired slices of unequal length.
pub(crate) fn ensure_same_length(
    context: &'static str,
    left: usize,
    right: usize,
) -> AnalysisResult<()> {
    if left == right {
        Ok(())
    } else {
        Err(AnalysisError::LengthMismatch {
            context,
            left,
            right,
        })
    }
}

/// Rejects inputs with fewer than `needed` points.
pub(crate) fn ensure_at_least(
    context: &'static str,
    needed: usize,
    got: usize,
) -> AnalysisResult<()> {
    if got >= needed {
        Ok(())
    } else {
        Err(AnalysisError::TooFewPoints {
            context,
            needed,
            got,
        })
    }
}

/// Rejects a scalar that is not finite and strictly positive.
pub(crate) fn ensure_positive(context: &'static str, name: &str, value: f64) -> AnalysisResult<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(AnalysisError::InvalidArgument {
            context,
            reason: format!("{name} must be finite and > 0, got {value}"),
        })
    }
}
