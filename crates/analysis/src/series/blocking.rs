//! Flyvbjerg–Petersen blocking: the standard error of the mean of a correlated series.
//!
//! H. Flyvbjerg and H. G. Petersen, J. Chem. Phys. 91 (1989) 461. Neighbouring values are
//! averaged pairwise repeatedly; once blocks are longer than the correlation time the
//! naive error of the block means stops growing and gives the true error of the mean.

use serde::{Deserialize, Serialize};

use crate::error::{ensure_at_least, ensure_finite, AnalysisResult};
use crate::estimate::Estimate;

/// Levels with fewer blocks than this are reported but never chosen: the error estimate of
/// a variance from 3 or fewer values is larger than the estimate itself.
const MINIMUM_BLOCKS: usize = 4;

/// One blocking level.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BlockingLevel {
    /// Number of original samples per block.
    pub block_size: usize,
    /// Number of blocks at this level.
    pub blocks: usize,
    /// Naive standard error of the mean from the block means, √(c₀/(n−1)) (unit of the data).
    pub standard_error: f64,
    /// Uncertainty of that standard error, se/√(2(n−1)).
    pub standard_error_uncertainty: f64,
}

/// Result of a blocking analysis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BlockingAnalysis {
    /// Sample mean with the chosen standard error (unit of the data).
    pub mean: Estimate,
    /// Naive standard error, σ/√N, that assumes independent samples.
    pub naive_standard_error: f64,
    /// All levels, from block size 1 upward.
    pub levels: Vec<BlockingLevel>,
    /// Index into `levels` of the level used for `mean.standard_error`.
    pub chosen_level: usize,
    /// Whether the error stopped growing (a plateau was found) before blocks ran out;
    /// if false the chosen error is the last eligible level's and is likely an underestimate.
    pub converged: bool,
}

/// Block-averages `values` and picks the standard error of their mean.
///
/// Choice rule: the first level (with at least 4 blocks) whose successor's error is not
/// larger than it by more than its own uncertainty — i.e. where the growth with block size
/// has stopped within noise. Needs at least 2 values; with fewer than 4 only the naive error
/// is available and `converged` is false.
pub fn block_average(values: &[f64]) -> AnalysisResult<BlockingAnalysis> {
    const CONTEXT: &str = "blocking analysis";
    ensure_finite(CONTEXT, values)?;
    ensure_at_least(CONTEXT, 2, values.len())?;
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;

    let mut levels = Vec::new();
    let mut blocks: Vec<f64> = values.to_vec();
    let mut block_size = 1;
    while blocks.len() >= 2 {
        let m = blocks.len() as f64;
        let block_mean = blocks.iter().sum::<f64>() / m;
        let c0 = blocks.iter().map(|b| (b - block_mean).powi(2)).sum::<f64>() / m;
        let se = (c0 / (m - 1.0)).sqrt();
        levels.push(BlockingLevel {
            block_size,
            blocks: blocks.len(),
            standard_error: se,
            standard_error_uncertainty: se / (2.0 * (m - 1.0)).sqrt(),
        });
        blocks = blocks
            .chunks_exact(2)
            .map(|p| 0.5 * (p[0] + p[1]))
            .collect();
        block_size *= 2;
    }
    let naive_standard_error = levels[0].standard_error;
    let eligible = levels
        .iter()
        .take_while(|l| l.blocks >= MINIMUM_BLOCKS)
        .count();
    let (chosen_level, converged) = if eligible == 0 {
        (0, false)
    } else {
        let plateau = (0..eligible.saturating_sub(1)).find(|&k| {
            levels[k + 1].standard_error
                <= levels[k].standard_error + levels[k].standard_error_uncertainty
        });
        match plateau {
            Some(k) => (k, true),
            None => (eligible - 1, false),
        }
    };
    Ok(BlockingAnalysis {
        mean: Estimate::new(mean, levels[chosen_level].standard_error),
        naive_standard_error,
        levels,
        chosen_level,
        converged,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{normal, seeded_rng};

    #[test]
    fn independent_samples_keep_the_naive_error() {
        let mut rng = seeded_rng(21);
        let values: Vec<f64> = (0..4096).map(|_| 5.0 + normal(&mut rng)).collect();
        let result = block_average(&values).unwrap();
        // True error 1/√4096 = 0.015625; the chosen level has ≥ 512 blocks, so its own
        // relative uncertainty is ≤ 1/√1022 ≈ 3 %; 12 % is a 4σ band.
        assert!((result.mean.standard_error / 0.015625 - 1.0).abs() < 0.12);
        assert!(result.converged);
    }

    #[test]
    fn correlated_samples_get_the_inflated_error_of_an_ar1_process() {
        // AR(1) with ρ = 0.5 and unit variance: the error of the mean is
        // √((1+ρ)/(1−ρ)/N) = √3/√N, i.e. 1.73 × the naive value.
        let rho: f64 = 0.5;
        let n = 16384;
        let mut rng = seeded_rng(5);
        let mut x = 0.0;
        let values: Vec<f64> = (0..n)
            .map(|_| {
                x = rho * x + (1.0 - rho * rho).sqrt() * normal(&mut rng);
                x
            })
            .collect();
        let result = block_average(&values).unwrap();
        let truth = (3.0 / n as f64).sqrt();
        // Tolerance 20 %: the plateau is picked where blocks (size ≥ 8) still carry a
        // truncation bias of up to ~10 % in the error for ρ = 0.5, plus ~5 % statistical noise.
        assert!(
            (result.mean.standard_error / truth - 1.0).abs() < 0.2,
            "{} vs {truth}",
            result.mean.standard_error
        );
        // The naive error must be clearly too small (ratio ≈ 1/√3 ≈ 0.58).
        assert!(result.naive_standard_error < 0.7 * truth);
    }

    #[test]
    fn short_series_fall_back_to_the_naive_error_without_claiming_convergence() {
        let result = block_average(&[1.0, 2.0, 3.0]).unwrap();
        assert!(!result.converged);
        assert_eq!(result.chosen_level, 0);
        assert!(block_average(&[1.0]).is_err());
    }
}
