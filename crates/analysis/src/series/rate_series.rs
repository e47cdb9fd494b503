//! A mass discharge rate W(t) sampled in equal time bins (paper Fig. 2a).

use serde::{Deserialize, Serialize};

use crate::error::{
    ensure_finite, ensure_positive, ensure_same_length, AnalysisError, AnalysisResult,
};

/// Mass discharge rate in consecutive equal bins: bin i covers
/// [start_time + i·bin_width, start_time + (i+1)·bin_width).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RateSeries {
    /// Start of the first bin [s].
    pub start_time: f64,
    /// Bin width [s] (0.02–0.05 s in the paper's analysis).
    pub bin_width: f64,
    /// Mean mass rate in each bin [kg/s].
    pub rates: Vec<f64>,
}

impl RateSeries {
    /// Validates and builds a series: finite rates, finite start, positive bin width.
    pub fn new(start_time: f64, bin_width: f64, rates: Vec<f64>) -> AnalysisResult<Self> {
        const CONTEXT: &str = "rate series";
        ensure_positive(CONTEXT, "bin width", bin_width)?;
        ensure_finite(CONTEXT, &[start_time])?;
        ensure_finite(CONTEXT, &rates)?;
        Ok(Self {
            start_time,
            bin_width,
            rates,
        })
    }

    /// Bins discrete discharge events (e.g. particle crossings of the outlet line) into a
    /// rate series over [start_time, end_time): each event adds its mass [kg] at its time [s].
    /// Events outside the interval are ignored; a trailing partial bin is dropped.
    pub fn from_events(
        event_times: &[f64],
        event_masses: &[f64],
        start_time: f64,
        end_time: f64,
        bin_width: f64,
    ) -> AnalysisResult<Self> {
        const CONTEXT: &str = "rate series from events";
        ensure_same_length(CONTEXT, event_times.len(), event_masses.len())?;
        ensure_finite(CONTEXT, event_times)?;
        ensure_finite(CONTEXT, event_masses)?;
        ensure_positive(CONTEXT, "bin width", bin_width)?;
        ensure_finite(CONTEXT, &[start_time, end_time])?;
        let bins = ((end_time - start_time) / bin_width).floor();
        if bins < 1.0 {
            return Err(AnalysisError::InvalidArgument {
                context: CONTEXT,
                reason: format!("interval [{start_time}, {end_time}) holds no full bin"),
            });
        }
        let bins = bins as usize;
        let mut mass = vec![0.0; bins];
        for (&t, &m) in event_times.iter().zip(event_masses) {
            let index = ((t - start_time) / bin_width).floor();
            if index >= 0.0 && (index as usize) < bins {
                mass[index as usize] += m;
            }
        }
        let rates = mass.into_iter().map(|m| m / bin_width).collect();
        Self::new(start_time, bin_width, rates)
    }

    /// Number of bins.
    pub fn len(&self) -> usize {
        self.rates.len()
    }

    /// Whether the series has no bins.
    pub fn is_empty(&self) -> bool {
        self.rates.is_empty()
    }

    /// Centre time of bin `index` [s].
    pub fn bin_centre(&self, index: usize) -> f64 {
        self.start_time + (index as f64 + 0.5) * self.bin_width
    }

    /// Start time of bin `index` [s] (also the end of bin `index − 1`).
    pub fn bin_edge(&self, index: usize) -> f64 {
        self.start_time + index as f64 * self.bin_width
    }

    /// Total discharged mass over the series [kg].
    pub fn total_mass(&self) -> f64 {
        self.rates.iter().sum::<f64>() * self.bin_width
    }

    /// Cumulative discharged mass at every bin edge: `len() + 1` pairs (time [s], mass [kg]),
    /// starting at (start_time, 0).
    pub fn cumulative_mass(&self) -> (Vec<f64>, Vec<f64>) {
        let mut times = Vec::with_capacity(self.len() + 1);
        let mut masses = Vec::with_capacity(self.len() + 1);
        let mut total = 0.0;
        times.push(self.start_time);
        masses.push(0.0);
        for (i, r) in self.rates.iter().enumerate() {
            total += r * self.bin_width;
            times.push(self.bin_edge(i + 1));
            masses.push(total);
        }
        (times, masses)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binning_events_conserves_the_mass_inside_the_interval() {
        // 100 events of 1 g spread uniformly over 1 s, plus two outside the interval.
        let mut times: Vec<f64> = (0..100).map(|i| 0.005 + 0.01 * i as f64).collect();
        times.extend([-0.1, 1.5]);
        let masses = vec![1e-3; times.len()];
        let series = RateSeries::from_events(&times, &masses, 0.0, 1.0, 0.05).unwrap();
        assert_eq!(series.len(), 20);
        // Mass is summed exactly, so only rounding error (1e-12 kg) is allowed.
        assert!((series.total_mass() - 0.1).abs() < 1e-12);
        // Uniform events: each 0.05 s bin holds 5 g, i.e. 0.1 kg/s.
        assert!(series.rates.iter().all(|r| (r - 0.1).abs() < 1e-9));
        let (t, m) = series.cumulative_mass();
        assert_eq!(t.len(), 21);
        assert!((m[20] - 0.1).abs() < 1e-12);
    }

    #[test]
    fn invalid_series_are_rejected() {
        assert!(RateSeries::new(0.0, 0.0, vec![1.0]).is_err());
        assert!(RateSeries::new(0.0, 0.02, vec![1.0, f64::NAN]).is_err());
        assert!(RateSeries::from_events(&[0.1], &[1.0], 0.0, 0.01, 0.02).is_err());
    }
}
