//! Residence times of a batch discharge (docs/physics.md §7.15): how long each grain stayed
//! after the opening, their distribution, and how far the silo empties first-in-first-out.
//!
//! The FIFO index is Spearman's rank correlation (Spearman 1904, Am. J. Psychol. 15, 72)
//! between a grain's height in the bed at the opening and its residence time, over the grains
//! that left: +1 where the grains leave in the order they were filled, bottom first (the
//! mass flow of a steep, smooth hopper), near 0 or below where a central core carries grains
//! from the top down past the stagnant ones beside it (funnel flow). Ties take the mean of
//! their ranks.

/// The distribution of residence times and the FIFO index.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResidenceStatistics {
    /// Grains in the bed at the opening [-].
    pub grains: usize,
    /// Grains that left [-]; the statistics are theirs.
    pub left: usize,
    /// Mean residence time [s].
    pub mean: f64,
    /// Quantiles of the residence time at 10 %, 50 % and 90 % [s] (linear between order
    /// statistics).
    pub quantiles: [f64; 3],
    /// Spearman's ρ between height at the opening and residence time [-]; NaN below three
    /// grains or where either is constant.
    pub fifo_index: f64,
}

/// The statistics of grains at `heights` [m] at the opening with residence `times` [s] (NaN
/// for a grain that never left); `None` when no grain left or the slices differ in length.
pub fn residence_statistics(heights: &[f64], times: &[f64]) -> Option<ResidenceStatistics> {
    if heights.len() != times.len() {
        return None;
    }
    let (z, t): (Vec<f64>, Vec<f64>) = heights
        .iter()
        .zip(times)
        .filter(|(z, t)| z.is_finite() && t.is_finite())
        .map(|(&z, &t)| (z, t))
        .unzip();
    if t.is_empty() {
        return None;
    }
    let mut sorted = t.clone();
    sorted.sort_by(f64::total_cmp);
    Some(ResidenceStatistics {
        grains: heights.len(),
        left: t.len(),
        mean: t.iter().sum::<f64>() / t.len() as f64,
        quantiles: [0.1, 0.5, 0.9].map(|q| quantile(&sorted, q)),
        fifo_index: spearman(&z, &t),
    })
}

/// The `q`-quantile of ascending `sorted` values, linear between the order statistics at
/// (n − 1) q (Hyndman and Fan 1996, Am. Stat. 50, 361, their type 7).
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    match sorted.len() {
        0 => f64::NAN,
        1 => sorted[0],
        n => {
            let at = q.clamp(0.0, 1.0) * (n - 1) as f64;
            let k = (at.floor() as usize).min(n - 2);
            let f = at - k as f64;
            sorted[k] + f * (sorted[k + 1] - sorted[k])
        }
    }
}

/// Ranks 1..n of `x`, ties given the mean of the ranks they span.
fn ranks(x: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..x.len()).collect();
    order.sort_by(|&a, &b| x[a].total_cmp(&x[b]));
    let mut r = vec![0.0; x.len()];
    let mut k = 0;
    while k < order.len() {
        let mut end = k + 1;
        while end < order.len() && x[order[end]] == x[order[k]] {
            end += 1;
        }
        // Positions k..end hold ranks k + 1 ..= end: their mean.
        let mean = 0.5 * ((k + 1) + end) as f64;
        for &i in &order[k..end] {
            r[i] = mean;
        }
        k = end;
    }
    r
}

/// Spearman's ρ of paired samples: Pearson's correlation of their ranks; NaN below three
/// pairs or where either sample is constant.
pub fn spearman(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len();
    if n < 3 || y.len() != n {
        return f64::NAN;
    }
    let (rx, ry) = (ranks(x), ranks(y));
    let mean = 0.5 * (n + 1) as f64;
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in rx.iter().zip(&ry) {
        let (dx, dy) = (a - mean, b - mean);
        sxy += dx * dy;
        sxx += dx * dx;
        syy += dy * dy;
    }
    if sxx == 0.0 || syy == 0.0 {
        return f64::NAN;
    }
    sxy / (sxx * syy).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spearman_is_one_for_any_increasing_relation_and_minus_one_reversed() {
        // A monotone but far from linear relation: ranks, not values, are correlated.
        let x = [0.1, 0.4, 0.2, 0.9, 0.5];
        let y: Vec<f64> = x.iter().map(|v: &f64| v.powi(5).exp()).collect();
        assert!((spearman(&x, &y) - 1.0).abs() < 1e-12);
        let reversed: Vec<f64> = y.iter().map(|v| -v).collect();
        assert!((spearman(&x, &reversed) + 1.0).abs() < 1e-12);
    }

    #[test]
    fn spearman_with_ties_matches_the_hand_computed_value() {
        // x ranks 1, 2.5, 2.5, 4; y ranks 2, 1, 4, 3. Rank deviations from 2.5: x −1.5, 0,
        // 0, 1.5; y −0.5, −1.5, 1.5, 0.5: Σ dx dy = 1.5, Σ dx² = 4.5, Σ dy² = 5, so
        // ρ = 1.5/√22.5.
        let rho = spearman(&[1.0, 2.0, 2.0, 3.0], &[20.0, 10.0, 40.0, 30.0]);
        assert!((rho - 1.5 / 22.5f64.sqrt()).abs() < 1e-12, "{rho}");
        assert!(spearman(&[1.0, 1.0, 1.0], &[1.0, 2.0, 3.0]).is_nan());
    }

    #[test]
    fn grains_that_stayed_are_left_out_and_the_quantiles_interpolate() {
        // Five grains leave at 1..5 s in the order of their heights, one stays (NaN): FIFO
        // index 1; the median of 1..5 is 3, the 10 % quantile 1 + 0.4 · 1 = 1.4, the 90 %
        // one 4.6.
        let heights = [0.01, 0.02, 0.03, 0.04, 0.05, 0.06];
        let times = [1.0, 2.0, 3.0, 4.0, 5.0, f64::NAN];
        let s = residence_statistics(&heights, &times).expect("five left");
        assert_eq!((s.grains, s.left), (6, 5));
        assert!((s.mean - 3.0).abs() < 1e-12);
        for (got, want) in s.quantiles.iter().zip([1.4, 3.0, 4.6]) {
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
        assert!((s.fifo_index - 1.0).abs() < 1e-12);
        assert!(residence_statistics(&heights, &[f64::NAN; 6]).is_none());
    }
}
