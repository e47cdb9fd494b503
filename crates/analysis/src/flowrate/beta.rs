//! The Euler Beta function B(p, q) = Γ(p)Γ(q)/Γ(p+q), which integrates the profile law:
//! ∫₋₁¹ (1 − x²)^c dx = B(1/2, 1 + c) (paper Eq. 14).

use crate::error::{AnalysisError, AnalysisResult};

/// B(p, q) for p, q > 0.
pub fn beta_function(p: f64, q: f64) -> AnalysisResult<f64> {
    statrs::function::beta::checked_beta(p, q).map_err(|e| AnalysisError::InvalidArgument {
        context: "Beta function",
        reason: format!("B({p}, {q}): {e}"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flowrate::integrate;

    #[test]
    fn beta_equals_the_profile_integral_it_replaces() {
        // ∫₋₁¹ (1 − x²)^c dx with x = sin θ becomes ∫ cos^{2c+1} θ dθ over (−π/2, π/2), a
        // smooth integrand; the quadrature is accurate to 1e-10, so 1e-9 is a safe bound.
        for c in [0.36, 0.78, 1.5] {
            let half_pi = std::f64::consts::FRAC_PI_2;
            let direct = integrate(
                |t: f64| t.cos().powf(2.0 * c + 1.0),
                -half_pi,
                half_pi,
                1e-11,
            )
            .unwrap();
            let beta = beta_function(0.5, 1.0 + c).unwrap();
            assert!((beta - direct).abs() < 1e-9, "c = {c}: {beta} vs {direct}");
        }
    }

    #[test]
    fn beta_of_a_non_positive_argument_is_an_error() {
        assert!(beta_function(0.0, 1.0).is_err());
        assert!(beta_function(0.5, -1.0).is_err());
    }
}
