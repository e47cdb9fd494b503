//! Standard errors of per-bin window means from time blocks (batch means).
//!
//! The outlet profiles average many samples per bin: crossings for v(x), frames for φ(x).
//! Neighbouring samples are not independent (particles cross in clusters, and the packing
//! at the outlet changes over tens of milliseconds), so s/√n understates the error. Against
//! the spread of three independent fills of each of the paper's 44 cases, the bins' s/√n
//! were 1.46 (v) and 1.88 (φ) times too small; these block errors are 1.12 and 1.04 times
//! too small (docs/reproduction.md). Here the window is cut into
//! [`ERROR_BLOCKS`] equal time blocks, and the blocks are treated as the independent
//! units. The mean is the ratio of totals m = Σ s_b / Σ n_b (the same number as the plain
//! mean); its error is the delta-method (cluster) estimate
//!
//! se² = G/(G − 1) · Σ_b (s_b − m n_b)² / (Σ n_b)²,
//!
//! with s_b and n_b the sum and count of block b and G the number of blocks with samples.
//! For independent samples it reduces to s/√n in expectation.

use super::snapshot::TimeWindow;

/// Number of equal time blocks a window is cut into, the usual batch-means choice: enough
/// blocks for the variance to be estimated, each as long as the window allows. The paper's
/// study has windows of 0.2–3.3 s (median 0.54 s), so blocks of 0.02–0.33 s; where they are
/// shorter than the outlet's correlations, the error is still somewhat understated (the
/// remaining factor 1.12 for v above).
pub const ERROR_BLOCKS: usize = 10;

/// Per-bin, per-block sums and counts over one window.
///
/// Callers keep their own running total per bin for the mean: summing the block totals
/// instead would regroup the additions and change the mean's last bits.
#[derive(Debug, Clone)]
pub(crate) struct BlockSums {
    start: f64,
    block_duration: f64,
    /// Σ of the samples, bin-major: index bin · ERROR_BLOCKS + block.
    sum: Vec<f64>,
    /// Number of samples, same layout.
    count: Vec<u64>,
}

impl BlockSums {
    /// Empty sums for `bins` bins over `window`.
    pub fn new(bins: usize, window: TimeWindow) -> Self {
        Self {
            start: window.start,
            block_duration: (window.end - window.start) / ERROR_BLOCKS as f64,
            sum: vec![0.0; bins * ERROR_BLOCKS],
            count: vec![0; bins * ERROR_BLOCKS],
        }
    }

    /// Adds `value` at time `time` [s] (inside the window) to bin `bin` (< the `bins` given
    /// to [`BlockSums::new`]; a larger one panics on the index).
    pub fn add(&mut self, bin: usize, time: f64, value: f64) {
        // Clamped: the last block includes times that round onto the window's end.
        let block = (((time - self.start) / self.block_duration).floor().max(0.0) as usize)
            .min(ERROR_BLOCKS - 1);
        let k = bin * ERROR_BLOCKS + block;
        self.sum[k] += value;
        self.count[k] += 1;
    }

    /// Standard error of bin `bin`'s mean `mean` (the ratio of its totals, computed by the
    /// caller); `None` unless at least two blocks hold samples.
    pub fn standard_error(&self, bin: usize, mean: f64) -> Option<f64> {
        let range = bin * ERROR_BLOCKS..(bin + 1) * ERROR_BLOCKS;
        let (sums, counts) = (&self.sum[range.clone()], &self.count[range]);
        let blocks = counts.iter().filter(|&&n| n > 0).count();
        if blocks < 2 {
            return None;
        }
        let total: u64 = counts.iter().sum();
        let residual: f64 = sums
            .iter()
            .zip(counts)
            .map(|(&s, &n)| (s - mean * n as f64).powi(2))
            .sum();
        let g = blocks as f64;
        Some((g / (g - 1.0) * residual).sqrt() / total as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    fn window() -> TimeWindow {
        TimeWindow::new(1.0, 3.0).unwrap()
    }

    /// Mean and block error of one bin's samples (time, value).
    fn estimate(samples: &[(f64, f64)]) -> (f64, Option<f64>) {
        let mut sums = BlockSums::new(1, window());
        for &(t, v) in samples {
            sums.add(0, t, v);
        }
        let mean = samples.iter().map(|s| s.1).sum::<f64>() / samples.len() as f64;
        (mean, sums.standard_error(0, mean))
    }

    #[test]
    fn independent_samples_give_the_plain_standard_error() {
        // 20 000 uniform samples on [0, 1): σ/√n = 0.2887/141.4 = 2.04e-3. The block
        // estimate has 9 degrees of freedom, a relative scatter of about 1/√18 = 24 %;
        // averaged over 40 seeds that falls to 4 %, so 10 % is a safe bound.
        let mut ratio = 0.0;
        for seed in 0..40 {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
            let samples: Vec<_> = (0..20_000)
                .map(|_| (1.0 + 2.0 * rng.gen::<f64>(), rng.gen::<f64>()))
                .collect();
            let (_, se) = estimate(&samples);
            ratio += se.unwrap() / (1.0 / 12f64.sqrt() / 20_000f64.sqrt()) / 40.0;
        }
        assert!((ratio - 1.0).abs() < 0.1, "mean ratio {ratio}");
    }

    #[test]
    fn correlated_samples_get_the_larger_error_that_their_spread_shows() {
        // Each value repeats 50 times in a row (clusters of 50 samples in time): the mean
        // of 20 000 such samples is that of 400 independent values, so its error is
        // σ/√400 = 1.44e-2, √50 ≈ 7 times the naive σ/√20000. The block estimate must
        // recover it: within 15 % on the average of 20 seeds (its own scatter is about 24 %
        // per seed, 5 % over 20), where s/√n would give a seventh.
        let mut ratio = 0.0;
        for seed in 0..20 {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
            let mut samples = Vec::new();
            let mut value = 0.0;
            for k in 0..20_000 {
                if k % 50 == 0 {
                    value = rng.gen::<f64>();
                }
                samples.push((1.0 + 2.0 * (k as f64 + 0.5) / 20_000.0, value));
            }
            let (_, se) = estimate(&samples);
            ratio += se.unwrap() / (1.0 / 12f64.sqrt() / 400f64.sqrt()) / 20.0;
        }
        assert!((ratio - 1.0).abs() < 0.15, "mean ratio {ratio}");
    }

    #[test]
    fn one_occupied_block_has_no_error() {
        // All samples in the first tenth of the window: the spread between blocks is
        // unknown, so no error is claimed.
        let samples = [(1.01, 1.0), (1.02, 2.0), (1.05, 3.0)];
        assert_eq!(estimate(&samples).1, None);
        // Two occupied blocks: an error exists.
        let samples = [(1.01, 1.0), (1.02, 2.0), (2.5, 3.0)];
        assert!(estimate(&samples).1.is_some_and(|e| e > 0.0));
    }

    #[test]
    fn times_at_the_window_edges_fall_into_the_first_and_last_blocks() {
        let mut sums = BlockSums::new(2, window());
        sums.add(1, 1.0, 5.0);
        sums.add(1, 3.0 - 1e-15, 7.0);
        assert_eq!(sums.count[ERROR_BLOCKS], 1);
        assert_eq!(sums.count[2 * ERROR_BLOCKS - 1], 1);
        assert_eq!(sums.sum[2 * ERROR_BLOCKS - 1], 7.0);
        // Two blocks of one sample each, 5 and 7 around the mean 6: se² = 2 · 2 / 2² = 1.
        assert_eq!(sums.standard_error(1, 6.0), Some(1.0));
        assert_eq!(sums.standard_error(0, 0.0), None);
    }
}
