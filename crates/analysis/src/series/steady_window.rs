//! Automatic detection of the steady discharge window (the plateau of paper Fig. 2a).
//!
//! The window is first placed by discharged mass (physics spec §7: from 15 % to 70 % of the
//! particles discharged), which skips the start-up transient and the final emptying whatever
//! the orifice size. The fractions refer to a reference mass, the fill's when the caller
//! gives it: then the window does not depend on when the run was stopped, as long as it ran
//! past the window's end. Without one, or when the series stops short of the window's end
//! (a clog, a time limit), they refer to the mass that left during the series.
//!
//! The window is then refined by cutting it past outlying bins near its ends (robust
//! median/MAD test), and verified by the relative drift of a straight line fitted through
//! the rates inside it.

use serde::{Deserialize, Serialize};

use crate::error::{AnalysisError, AnalysisResult};
use crate::estimate::Estimate;
use crate::fit::fit_line;
use crate::series::rate_series::RateSeries;

/// Settings of [`find_steady_window`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SteadyWindowOptions {
    /// Fraction of the reference mass discharged when the window starts (default 0.15).
    pub start_fraction: f64,
    /// Fraction of the reference mass discharged when the window ends (default 0.70).
    pub end_fraction: f64,
    /// The mass the fractions refer to [kg], normally the whole fill's (default `None`: the
    /// mass discharged during the series). When the series discharges less than
    /// `end_fraction` of it, the series' own total is used instead: the flow stopped before
    /// the window's end, and a window reaching past the stop would average the stall in.
    #[serde(default)]
    pub reference_mass: Option<f64>,
    /// Fewest bins a window may have and still count as a plateau (default 5: a drift
    /// line through fewer bins has too few degrees of freedom to mean anything).
    pub minimum_bins: usize,
    /// Bins further than this many robust standard deviations (1.4826·MAD) from the window
    /// median count as outliers (default 3).
    pub outlier_threshold: f64,
    /// Fraction of the window, at each end, searched for outlying bins to cut (default 0.2).
    pub edge_fraction: f64,
    /// Largest acceptable relative change of the rate across the window,
    /// |slope|·(t₁ − t₀)/mean (default 0.15, i.e. 15 %).
    pub maximum_relative_drift: f64,
}

impl Default for SteadyWindowOptions {
    fn default() -> Self {
        Self {
            start_fraction: 0.15,
            end_fraction: 0.70,
            reference_mass: None,
            minimum_bins: 5,
            outlier_threshold: 3.0,
            edge_fraction: 0.2,
            maximum_relative_drift: 0.15,
        }
    }
}

/// The steady window found in a rate series.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SteadyWindow {
    /// Window start t₀ [s] (a bin edge).
    pub start_time: f64,
    /// Window end t₁ [s] (a bin edge).
    pub end_time: f64,
    /// Index of the first bin inside the window.
    pub first_bin: usize,
    /// One past the index of the last bin inside the window.
    pub end_bin: usize,
    /// Number of bins removed by the outlier refinement.
    pub trimmed_bins: usize,
    /// Relative drift of the rate across the window, slope·(t₁ − t₀)/mean (dimensionless),
    /// with its standard error from the line fit.
    pub relative_drift: Estimate,
    /// True when the window has at least `minimum_bins` bins and its drift is not
    /// significantly (2σ) above `maximum_relative_drift`.
    pub is_plateau: bool,
}

impl SteadyWindow {
    /// Number of bins in the window.
    pub fn bins(&self) -> usize {
        self.end_bin - self.first_bin
    }
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(|a, b| a.total_cmp(b));
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

/// Finds the steady window of `series` (see the module documentation for the method).
///
/// Errors when the series discharges no mass, the options are inconsistent, or the mass
/// window holds fewer than 3 whole bins (no drift can be estimated); a short or drifting
/// window is returned with `is_plateau = false` instead.
pub fn find_steady_window(
    series: &RateSeries,
    options: &SteadyWindowOptions,
) -> AnalysisResult<SteadyWindow> {
    const CONTEXT: &str = "steady window";
    let fractions_ok = options.start_fraction >= 0.0
        && options.start_fraction < options.end_fraction
        && options.end_fraction <= 1.0
        && (0.0..=0.5).contains(&options.edge_fraction)
        && options.outlier_threshold > 0.0
        && options
            .reference_mass
            .is_none_or(|m| m.is_finite() && m > 0.0);
    if !fractions_ok {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: format!(
                "need 0 ≤ start_fraction < end_fraction ≤ 1, 0 ≤ edge_fraction ≤ 0.5, \
                 outlier_threshold > 0 and a finite reference_mass > 0, got {options:?}"
            ),
        });
    }
    let total = series.total_mass();
    if total.is_nan() || total <= 0.0 {
        return Err(AnalysisError::Degenerate {
            context: CONTEXT,
            reason: format!("total discharged mass is {total} kg"),
        });
    }
    let (_, cumulative) = series.cumulative_mass();
    let reference = match options.reference_mass {
        Some(m) if total >= options.end_fraction * m => m,
        _ => total,
    };
    let start_mass = options.start_fraction * reference;
    let end_mass = options.end_fraction * reference;
    // Whole bins only: the first bin starting at or after the start mass, the last bin
    // ending at or before the end mass.
    let first_bin = cumulative
        .iter()
        .position(|&m| m >= start_mass)
        .unwrap_or(series.len());
    let end_bin = cumulative.iter().rposition(|&m| m <= end_mass).unwrap_or(0);
    if end_bin < first_bin + 3 {
        return Err(AnalysisError::TooFewPoints {
            context: CONTEXT,
            needed: 3,
            got: end_bin.saturating_sub(first_bin),
        });
    }

    // Refinement: cut the window just past any outlying bin (a late start-up, a transient
    // arch, an early collapse) found in its outer `edge_fraction` at either end. Outliers in
    // the interior are kept: they belong to the steady flow's fluctuations.
    let (mut lo, mut hi) = (first_bin, end_bin);
    let mut window: Vec<f64> = series.rates[lo..hi].to_vec();
    let centre = median(&mut window);
    let mut deviations: Vec<f64> = window.iter().map(|r| (r - centre).abs()).collect();
    let spread = 1.4826 * median(&mut deviations);
    if spread > 0.0 {
        let zone = ((options.edge_fraction * (hi - lo) as f64).ceil() as usize).max(1);
        let outlier =
            |i: usize| (series.rates[i] - centre).abs() / spread > options.outlier_threshold;
        if let Some(i) = (lo..lo + zone).rev().find(|&i| outlier(i)) {
            lo = i + 1;
        }
        if let Some(j) = (hi - zone..hi).find(|&j| outlier(j)) {
            hi = j.max(lo);
        }
    }
    let trimmed_bins = (end_bin - first_bin) - (hi - lo);
    if hi < lo + 3 {
        return Err(AnalysisError::TooFewPoints {
            context: CONTEXT,
            needed: 3,
            got: hi - lo,
        });
    }

    let times: Vec<f64> = (lo..hi).map(|i| series.bin_centre(i)).collect();
    let rates = &series.rates[lo..hi];
    let mean = rates.iter().sum::<f64>() / rates.len() as f64;
    let span = series.bin_width * (hi - lo) as f64;
    let line = fit_line(&times, rates, 0.95)?;
    let relative_drift = if mean > 0.0 {
        Estimate::new(
            line.slope.value * span / mean,
            line.slope.standard_error * span / mean,
        )
    } else {
        Estimate::new(f64::INFINITY, 0.0)
    };
    let is_plateau = hi - lo >= options.minimum_bins
        && relative_drift.value.abs() - 2.0 * relative_drift.standard_error
            <= options.maximum_relative_drift;
    Ok(SteadyWindow {
        start_time: series.bin_edge(lo),
        end_time: series.bin_edge(hi),
        first_bin: lo,
        end_bin: hi,
        trimmed_bins,
        relative_drift,
        is_plateau,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::test_support::{normal, seeded_rng};

    /// Synthetic discharge (paper Fig. 2a shape): linear rise over 0.1 s to `plateau` [kg/s],
    /// steady until 1.0 s, linear fall to zero by 1.3 s, in 0.02 s bins, with Gaussian noise
    /// of relative size `noise`.
    pub(crate) fn synthetic_discharge(plateau: f64, noise: f64, seed: u64) -> RateSeries {
        let mut rng = seeded_rng(seed);
        let width = 0.02;
        let rates = (0..70)
            .map(|i| {
                let t = (i as f64 + 0.5) * width;
                let clean = if t < 0.1 {
                    plateau * t / 0.1
                } else if t < 1.0 {
                    plateau
                } else {
                    (plateau * (1.3 - t) / 0.3).max(0.0)
                };
                (clean + noise * plateau * normal(&mut rng)).max(0.0)
            })
            .collect();
        RateSeries::new(0.0, width, rates).unwrap()
    }

    #[test]
    fn window_lies_inside_the_plateau_of_a_rise_steady_fall_series() {
        let series = synthetic_discharge(0.058, 0.1, 1);
        let window = find_steady_window(&series, &SteadyWindowOptions::default()).unwrap();
        // Mass budget: rise 0.05 W, plateau 0.9 W, fall 0.15 W (total 1.1 W), so 15 % and
        // 70 % of the mass are reached at t ≈ 0.215 s and 0.82 s; noise moves these by
        // about one bin (0.02 s), so the window must sit inside [0.1, 1.0] s and cover
        // at least [0.26, 0.78] s.
        assert!(
            window.start_time >= 0.1 && window.start_time <= 0.26,
            "{window:?}"
        );
        assert!(
            window.end_time <= 1.0 && window.end_time >= 0.78,
            "{window:?}"
        );
        assert!(window.is_plateau);
    }

    #[test]
    fn a_steadily_decaying_rate_is_flagged_as_no_plateau() {
        // W(t) falls linearly from 0.1 to 0 kg/s: the 15–70 % window spans a 50 % change.
        let rates: Vec<f64> = (0..50)
            .map(|i| 0.1 * (1.0 - (i as f64 + 0.5) / 50.0))
            .collect();
        let series = RateSeries::new(0.0, 0.02, rates).unwrap();
        let window = find_steady_window(&series, &SteadyWindowOptions::default()).unwrap();
        assert!(!window.is_plateau, "{window:?}");
        assert!(window.relative_drift.value < -0.3);
    }

    #[test]
    fn a_stalled_bin_at_the_window_edge_is_trimmed() {
        // Steady 0.05 kg/s with 5 % noise; then the bin at the window start stalls to zero
        // (a transient arch). The stall lies ~20 robust σ from the median and must be cut.
        let mut rng = seeded_rng(17);
        let rates: Vec<f64> = (0..60)
            .map(|_| 0.05 * (1.0 + 0.05 * normal(&mut rng)))
            .collect();
        let mut series = RateSeries::new(0.0, 0.02, rates).unwrap();
        let before = find_steady_window(&series, &SteadyWindowOptions::default()).unwrap();
        assert_eq!(before.trimmed_bins, 0);
        series.rates[before.first_bin] = 0.0;
        let after = find_steady_window(&series, &SteadyWindowOptions::default()).unwrap();
        assert!(after.trimmed_bins >= 1, "{after:?}");
        assert!(after.first_bin > before.first_bin, "{after:?}");
        assert!(after.is_plateau);
    }

    /// The first `bins` bins of `series`: the same run stopped earlier.
    fn stopped_after(series: &RateSeries, bins: usize) -> RateSeries {
        RateSeries::new(0.0, series.bin_width, series.rates[..bins].to_vec()).unwrap()
    }

    /// Number of whole bins until at least `fraction` of `reference` [kg] has left.
    fn bins_until(series: &RateSeries, fraction: f64, reference: f64) -> usize {
        let (_, cumulative) = series.cumulative_mass();
        cumulative
            .iter()
            .position(|&m| m >= fraction * reference)
            .unwrap()
    }

    #[test]
    fn with_the_fill_as_reference_the_window_ignores_when_the_run_stopped() {
        // The same discharge stopped at 75 %, 90 % and 100 % of its mass: fractions of the
        // fill place the window identically (exact equality, the same bins), whereas
        // fractions of each series' own total move its end with the stop.
        let full = synthetic_discharge(0.058, 0.1, 4);
        let fill = full.total_mass();
        let options = SteadyWindowOptions {
            reference_mass: Some(fill),
            ..SteadyWindowOptions::default()
        };
        let reference = find_steady_window(&full, &options).unwrap();
        for stop in [0.75, 0.9] {
            let stopped = stopped_after(&full, bins_until(&full, stop, fill));
            assert_eq!(find_steady_window(&stopped, &options).unwrap(), reference);
            let own = find_steady_window(&stopped, &SteadyWindowOptions::default()).unwrap();
            assert!(own.end_bin < reference.end_bin, "stop {stop}: {own:?}");
        }
    }

    #[test]
    fn a_series_that_stops_before_the_window_end_falls_back_to_its_own_total() {
        // A clog after 50 % of the fill: 70 % of the fill is never reached, so the window
        // is placed on the series' own total (15–70 % of what left), as without a reference.
        let full = synthetic_discharge(0.058, 0.1, 5);
        let fill = full.total_mass();
        let clogged = stopped_after(&full, bins_until(&full, 0.5, fill));
        let with_fill = SteadyWindowOptions {
            reference_mass: Some(fill),
            ..SteadyWindowOptions::default()
        };
        assert_eq!(
            find_steady_window(&clogged, &with_fill).unwrap(),
            find_steady_window(&clogged, &SteadyWindowOptions::default()).unwrap()
        );
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let options = SteadyWindowOptions {
                reference_mass: Some(bad),
                ..SteadyWindowOptions::default()
            };
            assert!(
                matches!(
                    find_steady_window(&full, &options),
                    Err(AnalysisError::InvalidArgument { .. })
                ),
                "reference {bad}"
            );
        }
    }

    #[test]
    fn series_without_mass_or_bins_give_typed_errors() {
        let empty = RateSeries::new(0.0, 0.02, vec![0.0; 10]).unwrap();
        assert!(matches!(
            find_steady_window(&empty, &SteadyWindowOptions::default()),
            Err(AnalysisError::Degenerate { .. })
        ));
        let short = RateSeries::new(0.0, 0.02, vec![1.0; 3]).unwrap();
        assert!(matches!(
            find_steady_window(&short, &SteadyWindowOptions::default()),
            Err(AnalysisError::TooFewPoints { .. })
        ));
    }
}
