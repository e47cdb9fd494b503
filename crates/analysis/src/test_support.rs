//! Shared helpers for unit tests: a seeded generator and normal deviates.

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// A reproducible generator, so every noisy test sees the same data on every run.
pub(crate) fn seeded_rng(seed: u64) -> Xoshiro256PlusPlus {
    Xoshiro256PlusPlus::seed_from_u64(seed)
}

/// One standard normal deviate by the Box–Muller transform (rand 0.8 has no normal
/// distribution without an extra crate).
pub(crate) fn normal<R: Rng>(rng: &mut R) -> f64 {
    let u1: f64 = rng.gen_range(f64::EPSILON..1.0);
    let u2: f64 = rng.gen();
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

/// The coverage a ±1 standard-error interval should reach when the error is scaled by the
/// observed scatter, √(χ²/ν), as every fit here does: (estimate − truth)/error is then
/// Student-t with ν = `degrees_of_freedom` (exactly for a linear model with Gaussian noise, to
/// first order in the noise for a nonlinear one), so the coverage is P(|t_ν| ≤ 1) = 2F_ν(1) − 1,
/// which rises to 68.27 % only as ν → ∞ (66.6 % at ν = 14, 63.7 % at ν = 5).
pub(crate) fn one_sigma_coverage(degrees_of_freedom: usize) -> f64 {
    use statrs::distribution::{ContinuousCDF, StudentsT};
    StudentsT::new(0.0, 1.0, degrees_of_freedom as f64).map_or(f64::NAN, |t| 2.0 * t.cdf(1.0) - 1.0)
}

/// Counts how often a fitted parameter's ±1 standard-error interval holds the truth.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Coverage {
    /// The parameter's name, for the failure message.
    pub name: &'static str,
    /// The true value of the parameter.
    pub truth: f64,
    /// Trials in which value ± standard_error held the truth.
    pub hits: usize,
    /// Trials recorded.
    pub trials: usize,
}

impl Coverage {
    /// A counter for the parameter `name` whose true value is `truth`.
    pub(crate) fn new(name: &'static str, truth: f64) -> Self {
        Self {
            name,
            truth,
            hits: 0,
            trials: 0,
        }
    }

    /// Records one trial's estimate.
    pub(crate) fn record(&mut self, estimate: crate::estimate::Estimate) {
        self.trials += 1;
        self.hits += estimate.interval(1.0).contains(self.truth) as usize;
    }

    /// Observed coverage [-].
    pub(crate) fn rate(&self) -> f64 {
        self.hits as f64 / self.trials as f64
    }

    /// Asserts that the observed coverage lies within 4 binomial standard errors
    /// √(p(1 − p)/n) of the expected p = [`one_sigma_coverage`]`(degrees_of_freedom)`. With
    /// 2000 trials that band is ±4.2 %: a correct error bar leaves it with probability 6e-5,
    /// while an error bar 15 % too large or too small moves the coverage to 75.0 % or 60.5 %
    /// (at large ν), 7–8 % away, outside it.
    pub(crate) fn assert_nominal(&self, degrees_of_freedom: usize) {
        let p = one_sigma_coverage(degrees_of_freedom);
        let band = 4.0 * (p * (1.0 - p) / self.trials as f64).sqrt();
        let rate = self.rate();
        assert!(
            (rate - p).abs() < band,
            "{}: coverage {rate:.4} over {} trials, expected {p:.4} ± {band:.4}",
            self.name,
            self.trials
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sigma_coverage_has_its_closed_form_limits() {
        // ν = 1 is the Cauchy law, F(1) = 3/4, so the coverage is exactly 1/2; as ν → ∞ it is
        // the normal erf(1/√2) = 0.682689. statrs evaluates the t CDF through the regularised
        // incomplete beta function to about 1e-10; at ν = 10⁶ the t law differs from the normal
        // by O(1/ν) ≈ 1e-7, hence 1e-6.
        assert!((one_sigma_coverage(1) - 0.5).abs() < 1e-9);
        assert!((one_sigma_coverage(1_000_000) - 0.682_689_492).abs() < 1e-6);
    }
}
