//! Repeated runs of one benchmark and their spread, reported the way hyperfine reports the
//! runs of a command: a median with its range, not one timing. On a shared or virtual machine
//! one timing is not a figure: this project's VM reads the same binary up to 15 % apart
//! within minutes (docs/performance.md), more than most of the effects worth measuring.

use serde::Serialize;

use super::BenchResult;

/// The spread of one benchmark's wall time per particle-step over repeated runs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunSpread {
    /// Each run's wall time per particle-step, in run order [ns].
    pub ns_per_particle_step: Vec<f64>,
    /// Median [ns]: the middle run, or the mean of the middle two.
    pub median_ns: f64,
    /// Mean [ns].
    pub mean_ns: f64,
    /// Sample standard deviation (n − 1 in the denominator) [ns]; zero for one run.
    pub std_dev_ns: f64,
    /// Fastest run [ns].
    pub min_ns: f64,
    /// Slowest run [ns].
    pub max_ns: f64,
}

impl RunSpread {
    /// The spread of `values` [ns]; `None` when there is none, or one is not finite.
    pub fn of(values: &[f64]) -> Option<Self> {
        if values.is_empty() || values.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len();
        let median = if n % 2 == 1 {
            sorted[n / 2]
        } else {
            0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
        };
        let mean = values.iter().sum::<f64>() / n as f64;
        let std_dev = if n > 1 {
            let ss: f64 = values.iter().map(|v| (v - mean) * (v - mean)).sum();
            (ss / (n - 1) as f64).sqrt()
        } else {
            0.0
        };
        Some(Self {
            ns_per_particle_step: values.to_vec(),
            median_ns: median,
            mean_ns: mean,
            std_dev_ns: std_dev,
            min_ns: sorted[0],
            max_ns: sorted[n - 1],
        })
    }

    /// Range over median, (max − min) / median [-]: how far apart two single timings of
    /// the same binary can be, the bar an A/B difference must clear.
    pub fn relative_range(&self) -> f64 {
        (self.max_ns - self.min_ns) / self.median_ns
    }
}

/// Combines repeated runs of one benchmark into one result: the median run, whose fields
/// (phases, contacts, rebuilds) are those of a run that happened, with the spread of all the
/// runs in [`BenchResult::runs`]. With an even count the median run is the faster of the
/// middle two. `None` when `runs` is empty, when the runs are not of one case, thread count
/// and size, or when a timing is not finite.
pub fn combine(mut runs: Vec<BenchResult>) -> Option<BenchResult> {
    let first = runs.first()?;
    let same = |r: &BenchResult| {
        r.case == first.case
            && r.threads == first.threads
            && r.particles == first.particles
            && r.steps == first.steps
    };
    if !runs.iter().all(same) {
        return None;
    }
    let times: Vec<f64> = runs.iter().map(|r| r.ns_per_particle_step).collect();
    let spread = RunSpread::of(&times)?;
    let mut order: Vec<usize> = (0..runs.len()).collect();
    order.sort_by(|&a, &b| times[a].total_cmp(&times[b]));
    let middle = order[(runs.len() - 1) / 2];
    let mut median = runs.swap_remove(middle);
    median.runs = Some(spread);
    Some(median)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::PhaseBreakdown;

    fn result(ns: f64, rebuilds: u64) -> BenchResult {
        BenchResult {
            case: "hopper".into(),
            threads: 1,
            particles: 2761,
            steps: 80_000,
            ns_per_particle_step: ns,
            particle_steps_per_second: 1e9 / ns,
            contacts_per_particle: 2.6,
            wall_contacts_per_particle: 0.36,
            ns_per_contact: ns / 1.48,
            candidates_per_particle: 4.0,
            rebuilds,
            cpu_ns_per_particle_step: Some(ns),
            peak_memory_bytes: None,
            bytes_per_particle: None,
            phases: PhaseBreakdown::default(),
            runs: None,
        }
    }

    #[test]
    fn the_spread_of_known_samples() {
        // A textbook sample: mean 5, squared deviations summing to 32, so the sample
        // standard deviation is √(32/7). Exact up to the rounding of a few additions.
        let s = RunSpread::of(&[2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0]).expect("spread");
        assert_eq!(s.mean_ns, 5.0);
        assert!((s.std_dev_ns - (32.0f64 / 7.0).sqrt()).abs() < 1e-12);
        // Even count: the mean of the middle two (4 and 5).
        assert_eq!(s.median_ns, 4.5);
        assert_eq!((s.min_ns, s.max_ns), (2.0, 9.0));
        // Odd count, given out of order: the middle value, whatever the run order.
        let s = RunSpread::of(&[60.0, 52.0, 55.0]).expect("spread");
        assert_eq!(s.median_ns, 55.0);
        assert_eq!(s.ns_per_particle_step, vec![60.0, 52.0, 55.0]);
        assert!((s.relative_range() - 8.0 / 55.0).abs() < 1e-15);
        // One run: nothing to spread.
        let s = RunSpread::of(&[53.1]).expect("spread");
        assert_eq!(
            (s.median_ns, s.std_dev_ns, s.relative_range()),
            (53.1, 0.0, 0.0)
        );
    }

    #[test]
    fn no_spread_without_finite_runs() {
        assert_eq!(RunSpread::of(&[]), None);
        assert_eq!(RunSpread::of(&[50.0, f64::NAN]), None);
        assert_eq!(RunSpread::of(&[f64::INFINITY]), None);
    }

    #[test]
    fn the_combined_result_is_the_median_run_with_every_run_attached() {
        // The rebuild counts tag the runs, so the test sees which run was kept.
        let runs = vec![result(61.0, 1), result(54.0, 2), result(57.0, 3)];
        let c = combine(runs).expect("combined");
        assert_eq!((c.ns_per_particle_step, c.rebuilds), (57.0, 3));
        let spread = c.runs.expect("spread attached");
        assert_eq!(spread.ns_per_particle_step, vec![61.0, 54.0, 57.0]);
        assert_eq!(spread.median_ns, 57.0);
        // Even count: the faster of the middle two is the run kept; the spread's median is
        // still the mean of the two.
        let c = combine(vec![
            result(58.0, 1),
            result(52.0, 2),
            result(56.0, 3),
            result(70.0, 4),
        ])
        .expect("combined");
        assert_eq!(c.rebuilds, 3);
        assert_eq!(c.runs.expect("spread").median_ns, 57.0);
    }

    #[test]
    fn runs_of_different_benchmarks_do_not_combine() {
        assert!(combine(Vec::new()).is_none());
        let mut other = result(50.0, 1);
        other.threads = 2;
        assert!(combine(vec![result(55.0, 1), other]).is_none());
        let mut other = result(50.0, 1);
        other.case = "bed".into();
        assert!(combine(vec![result(55.0, 1), other]).is_none());
        let mut other = result(50.0, 1);
        other.particles = 10_000;
        assert!(combine(vec![result(55.0, 1), other]).is_none());
        assert!(combine(vec![result(55.0, 1), result(f64::NAN, 2)]).is_none());
    }
}
