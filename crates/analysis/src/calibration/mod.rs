//! Calibration of up to two model parameters against up to two noisy targets by sequential
//! response surfaces in a shrinking trust region (docs/physics.md §12).
//!
//! Each round runs the simulation at the points of a small factorial design inside the
//! current region ([`Region::design`]), with replicates; a full quadratic in the parameters is
//! fitted to each target's measurements by least squares ([`ResponseSurface`], Box & Wilson
//! 1951; Myers, Montgomery & Anderson-Cook 2016, *Response Surface Methodology*, ch. 6),
//! which averages the simulation's noise instead of chasing it; the parameters whose
//! predicted targets best match the lab's are found on those surfaces ([`solve`]), with a
//! covariance that propagates both the lab's uncertainty and the surfaces' own; and the next
//! region is centred there, half as wide but never narrower than the estimate's uncertainty
//! ([`Region::next`]), as a trust-region method shrinks its region (Conn, Gould & Toint
//! 2000, *Trust-Region Methods*, ch. 6).
//!
//! The parameters are handled in unit coordinates u ∈ [0, 1]^k over their search ranges, so
//! that nothing here knows their units; the caller maps them back.

mod inverse;
mod region;
mod surface;

pub use inverse::{solve, Solution, Target};
pub use region::{converged, Region, MAX_DETERMINED_ERROR, MIN_HALF_WIDTH};
pub use surface::ResponseSurface;

/// Most parameters a calibration searches.
pub const MAX_PARAMETERS: usize = 2;

/// Most targets a calibration matches.
pub const MAX_TARGETS: usize = 2;

use crate::error::AnalysisResult;

/// The fits of one round: a surface per target and the solution on them.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RoundFit {
    /// One response surface per target, fitted to the measurements inside the region.
    pub surfaces: Vec<ResponseSurface>,
    /// The best parameters on those surfaces, searched inside the region.
    pub solution: Solution,
}

/// Fits one round: for each target, a quadratic to its measurements `(u, y)` that lie inside
/// `region` (from this round and any earlier one), in the region's local coordinates; then
/// the parameters that best match `targets` inside the region.
pub fn fit_round(
    measurements: &[Vec<(Vec<f64>, f64)>],
    targets: &[Target],
    region: &Region,
) -> AnalysisResult<RoundFit> {
    let surfaces = measurements
        .iter()
        .map(|m| {
            let inside: Vec<(Vec<f64>, f64)> = m
                .iter()
                .filter(|(u, _)| region.contains(u))
                .cloned()
                .collect();
            ResponseSurface::fit(&inside, &region.centre, &region.half_width)
        })
        .collect::<AnalysisResult<Vec<_>>>()?;
    let solution = solve(&surfaces, targets, &region.lower(), &region.upper())?;
    Ok(RoundFit { surfaces, solution })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{normal, seeded_rng};

    /// Two noisy, nonlinear responses of two parameters, like an angle of repose (degrees,
    /// saturating in rolling friction u₁, rising with cohesion u₂) and a discharge rate (falling
    /// with both), with noise of the size of a small DEM test's replicate scatter.
    fn responses(u: &[f64], rng: &mut impl rand::Rng) -> [f64; 2] {
        [
            22.0 + 14.0 * (2.5 * u[0]).tanh() + 6.0 * u[1] * u[1] + 0.6 * normal(rng),
            0.12 - 0.03 * u[0] - 0.05 * u[1] + 0.002 * normal(rng),
        ]
    }

    #[test]
    fn the_rounds_recover_known_parameters_within_their_stated_uncertainty() {
        let truth = [0.35, 0.6];
        let mut rng = seeded_rng(5);
        // The targets as a lab would give them: the mean of 5 measurements at the truth and
        // its standard error.
        let lab: Vec<[f64; 2]> = (0..5).map(|_| responses(&truth, &mut rng)).collect();
        let targets: Vec<Target> = (0..2)
            .map(|i| {
                let v: Vec<f64> = lab.iter().map(|m| m[i]).collect();
                let mean = v.iter().sum::<f64>() / 5.0;
                let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 4.0).sqrt();
                Target {
                    value: mean,
                    uncertainty: sd / 5f64.sqrt(),
                }
            })
            .collect();
        let mut region = Region::whole(2);
        let mut measurements = vec![Vec::new(), Vec::new()];
        let mut previous: Option<Solution> = None;
        let mut rounds = 0;
        let solution = loop {
            rounds += 1;
            for u in region.design() {
                for _ in 0..3 {
                    let y = responses(&u, &mut rng);
                    measurements[0].push((u.clone(), y[0]));
                    measurements[1].push((u.clone(), y[1]));
                }
            }
            let fit = fit_round(&measurements, &targets, &region).unwrap();
            let done = previous
                .as_ref()
                .is_some_and(|p| converged(p, &fit.solution, &region));
            if done || rounds == 8 {
                break fit.solution;
            }
            region = region.next(&fit.solution);
            previous = Some(fit.solution);
        };
        assert!(rounds < 8, "no convergence in 8 rounds");
        let sd = solution.standard_errors();
        for j in 0..2 {
            // Within 3 standard errors (a miss has probability 0.3 % per parameter for an
            // unbiased estimate with a correct error), and the error is a useful one: under a
            // tenth of the range.
            assert!(
                (solution.point[j] - truth[j]).abs() < 3.0 * sd[j] && sd[j] < 0.1,
                "parameter {j}: {} ± {} against {}",
                solution.point[j],
                sd[j],
                truth[j]
            );
        }
    }
}
