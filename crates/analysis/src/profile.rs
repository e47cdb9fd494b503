//! Outlet profiles binned in the normalised coordinate x* = (x − x_c)/R (physics spec §7.2–7.3).

use serde::{Deserialize, Serialize};

use crate::error::{
    ensure_finite, ensure_positive, ensure_same_length, AnalysisError, AnalysisResult,
};
use crate::estimate::Estimate;

/// Half-width in x* of the central region whose bins define the centre value
/// (v_c, φ_c: "mean of the central bins, |x*| < 0.1", physics spec §7.2).
pub const CENTRE_HALF_WIDTH: f64 = 0.1;

/// A profile q(x*) averaged in bins. Bins with `counts == 0` carry no data and are
/// skipped by every method; their value may be NaN.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BinnedProfile {
    /// Bin centres in x* (dimensionless, −1 and +1 are the outlet edges).
    pub centres: Vec<f64>,
    /// Bin means (unit of the profiled quantity: m/s for v, 1 for φ).
    pub values: Vec<f64>,
    /// Number of samples (crossings, frames) per bin.
    pub counts: Vec<u64>,
    /// Standard error of each bin mean (unit of `values`); NaN where unknown.
    pub standard_errors: Vec<f64>,
}

/// One usable bin: centre x*, value, standard error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ProfilePoint {
    pub x_star: f64,
    pub value: f64,
    pub standard_error: f64,
}

/// The bin errors as fit weights when every point has a finite positive one; otherwise
/// `None`, so the fit weights all bins equally rather than mixing weighted and unweighted bins.
pub(crate) fn known_errors(points: &[ProfilePoint]) -> Option<Vec<f64>> {
    points
        .iter()
        .all(|p| p.standard_error.is_finite() && p.standard_error > 0.0)
        .then(|| points.iter().map(|p| p.standard_error).collect())
}

impl BinnedProfile {
    /// Validates and builds a profile: equal lengths, finite centres, finite values in
    /// populated bins.
    pub fn new(
        centres: Vec<f64>,
        values: Vec<f64>,
        counts: Vec<u64>,
        standard_errors: Vec<f64>,
    ) -> AnalysisResult<Self> {
        const CONTEXT: &str = "binned profile";
        ensure_same_length(CONTEXT, centres.len(), values.len())?;
        ensure_same_length(CONTEXT, centres.len(), counts.len())?;
        ensure_same_length(CONTEXT, centres.len(), standard_errors.len())?;
        ensure_finite(CONTEXT, &centres)?;
        if let Some(index) = (0..values.len()).find(|&i| counts[i] > 0 && !values[i].is_finite()) {
            return Err(AnalysisError::NonFinite {
                context: CONTEXT,
                index,
            });
        }
        Ok(Self {
            centres,
            values,
            counts,
            standard_errors,
        })
    }

    /// Bins samples (x*_k, q_k) into `bins` equal bins over [lower, upper); the value is the
    /// bin mean and the error the standard error of the mean (NaN for a single sample).
    pub fn from_samples(
        positions: &[f64],
        samples: &[f64],
        lower: f64,
        upper: f64,
        bins: usize,
    ) -> AnalysisResult<Self> {
        const CONTEXT: &str = "profile from samples";
        ensure_same_length(CONTEXT, positions.len(), samples.len())?;
        ensure_finite(CONTEXT, positions)?;
        ensure_finite(CONTEXT, samples)?;
        ensure_positive(CONTEXT, "range width", upper - lower)?;
        if bins == 0 {
            return Err(AnalysisError::InvalidArgument {
                context: CONTEXT,
                reason: "number of bins must be > 0".into(),
            });
        }
        let width = (upper - lower) / bins as f64;
        let mut sum = vec![0.0; bins];
        let mut sum_sq = vec![0.0; bins];
        let mut counts = vec![0u64; bins];
        for (&x, &q) in positions.iter().zip(samples) {
            let index = ((x - lower) / width).floor();
            if index >= 0.0 && (index as usize) < bins {
                let i = index as usize;
                sum[i] += q;
                sum_sq[i] += q * q;
                counts[i] += 1;
            }
        }
        let mut values = Vec::with_capacity(bins);
        let mut errors = Vec::with_capacity(bins);
        for i in 0..bins {
            let n = counts[i] as f64;
            if counts[i] == 0 {
                values.push(f64::NAN);
                errors.push(f64::NAN);
                continue;
            }
            let mean = sum[i] / n;
            values.push(mean);
            if counts[i] < 2 {
                errors.push(f64::NAN);
            } else {
                let variance = ((sum_sq[i] - n * mean * mean) / (n - 1.0)).max(0.0);
                errors.push((variance / n).sqrt());
            }
        }
        let centres = (0..bins)
            .map(|i| lower + (i as f64 + 0.5) * width)
            .collect();
        Self::new(centres, values, counts, errors)
    }

    /// Number of bins (populated or not).
    pub fn len(&self) -> usize {
        self.centres.len()
    }

    /// Whether the profile has no bins.
    pub fn is_empty(&self) -> bool {
        self.centres.is_empty()
    }

    /// Populated bins with |x*| ≤ `maximum_abs_x_star`.
    pub(crate) fn points_within(&self, maximum_abs_x_star: f64) -> Vec<ProfilePoint> {
        (0..self.len())
            .filter(|&i| self.counts[i] > 0 && self.centres[i].abs() <= maximum_abs_x_star)
            .map(|i| ProfilePoint {
                x_star: self.centres[i],
                value: self.values[i],
                standard_error: self.standard_errors[i],
            })
            .collect()
    }

    /// Centre value q_c: the mean of the populated bins with |x*| < `half_width`
    /// (use [`CENTRE_HALF_WIDTH`]). Its error combines the bin errors,
    /// √(Σ se_i²)/n; it is NaN if any of those is unknown.
    pub fn centre_value(&self, half_width: f64) -> AnalysisResult<Estimate> {
        let points: Vec<ProfilePoint> = self
            .points_within(half_width)
            .into_iter()
            .filter(|p| p.x_star.abs() < half_width)
            .collect();
        if points.is_empty() {
            return Err(AnalysisError::TooFewPoints {
                context: "profile centre value",
                needed: 1,
                got: 0,
            });
        }
        let n = points.len() as f64;
        let mean = points.iter().map(|p| p.value).sum::<f64>() / n;
        let error = points
            .iter()
            .map(|p| p.standard_error.powi(2))
            .sum::<f64>()
            .sqrt()
            / n;
        Ok(Estimate::new(mean, error))
    }

    /// Largest populated bin value (φ_max of paper Eq. 17) with its bin error, and the bin
    /// centre x* where it occurs.
    pub fn maximum(&self) -> AnalysisResult<(Estimate, f64)> {
        (0..self.len())
            .filter(|&i| self.counts[i] > 0)
            .max_by(|&a, &b| self.values[a].total_cmp(&self.values[b]))
            .map(|i| {
                (
                    Estimate::new(self.values[i], self.standard_errors[i]),
                    self.centres[i],
                )
            })
            .ok_or(AnalysisError::TooFewPoints {
                context: "profile maximum",
                needed: 1,
                got: 0,
            })
    }

    /// The profile divided by `scale` (values and errors), e.g. v/v_c or v/√(2gR).
    pub fn scaled(&self, scale: f64) -> AnalysisResult<Self> {
        if !(scale.is_finite() && scale != 0.0) {
            return Err(AnalysisError::InvalidArgument {
                context: "profile scaling",
                reason: format!("scale must be finite and non-zero, got {scale}"),
            });
        }
        Ok(Self {
            centres: self.centres.clone(),
            values: self.values.iter().map(|v| v / scale).collect(),
            counts: self.counts.clone(),
            standard_errors: self
                .standard_errors
                .iter()
                .map(|e| e / scale.abs())
                .collect(),
        })
    }

    /// The profile normalised by its centre value (q/q_c, paper Figs. 3e–h and 6e–h).
    pub fn normalised_by_centre(&self) -> AnalysisResult<Self> {
        let centre = self.centre_value(CENTRE_HALF_WIDTH)?;
        self.scaled(centre.value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parabola() -> BinnedProfile {
        // 20 bins of width 0.1 on [−1, 1): centres ±0.05, ±0.15, …
        let positions: Vec<f64> = (0..2000).map(|i| -1.0 + (i as f64 + 0.5) * 0.001).collect();
        let samples: Vec<f64> = positions.iter().map(|x| 2.0 * (1.0 - x * x)).collect();
        BinnedProfile::from_samples(&positions, &samples, -1.0, 1.0, 20).unwrap()
    }

    #[test]
    fn centre_value_averages_the_two_central_bins() {
        let profile = parabola();
        let centre = profile.centre_value(CENTRE_HALF_WIDTH).unwrap();
        // Bins [−0.1, 0) and [0, 0.1) average 2(1 − x²) to 2(1 − 0.01/3) = 1.99333.
        assert!((centre.value - 2.0 * (1.0 - 0.01 / 3.0)).abs() < 1e-6);
        let normalised = profile.normalised_by_centre().unwrap();
        let central = normalised.centre_value(CENTRE_HALF_WIDTH).unwrap();
        assert!((central.value - 1.0).abs() < 1e-12);
    }

    #[test]
    fn maximum_is_found_at_the_centre_of_a_symmetric_profile() {
        let (maximum, position) = parabola().maximum().unwrap();
        assert!(position.abs() < 0.1);
        assert!(maximum.value > 1.99 && maximum.value < 2.0);
    }

    #[test]
    fn empty_bins_are_ignored_and_empty_centres_are_errors() {
        let profile =
            BinnedProfile::from_samples(&[0.5, 0.55], &[1.0, 3.0], -1.0, 1.0, 10).unwrap();
        assert_eq!(profile.counts.iter().sum::<u64>(), 2);
        assert!(matches!(
            profile.centre_value(CENTRE_HALF_WIDTH),
            Err(AnalysisError::TooFewPoints { .. })
        ));
        assert!(BinnedProfile::new(vec![0.0], vec![f64::NAN], vec![3], vec![0.1]).is_err());
        assert!(profile.scaled(0.0).is_err());
    }
}
