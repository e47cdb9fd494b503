//! The inverse problem on fitted response surfaces: the parameters whose predicted targets
//! best match the measured ones, and their covariance (docs/physics.md §12.1).

use rmpfit::{MPConfig, MPError, MPFitter, MPPar, MPResult};
use serde::{Deserialize, Serialize};

use super::surface::ResponseSurface;
use crate::error::{AnalysisError, AnalysisResult};
use crate::estimate::Estimate;

/// One measured target: its value and the standard error the lab gives it (same unit).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Target {
    /// Measured value.
    pub value: f64,
    /// One-sigma uncertainty of the measurement (> 0).
    pub uncertainty: f64,
}

/// The parameters that best reproduce the targets on the surfaces.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Solution {
    /// Best parameters, in unit coordinates.
    pub point: Vec<f64>,
    /// Their covariance in unit coordinates, row-major; infinite entries when the targets do
    /// not determine the parameters there (a zero or rank-deficient sensitivity).
    pub covariance: Vec<Vec<f64>>,
    /// Σᵢ ((yᵢ(û) − tᵢ)/σᵢ)² with σᵢ² the target's variance plus the surface's prediction
    /// variance: about 0 when there are as many targets as parameters and they are met, and
    /// of order (targets − parameters) when the targets are consistent with each other.
    pub chi_squared: f64,
    /// Each target's value predicted at the best parameters, with the surface's standard
    /// error there (unit of the target).
    pub predicted: Vec<Estimate>,
    /// Whether each parameter ended on the edge of the box searched: the targets may then
    /// lie beyond it, and the estimate is only a bound.
    pub at_edge: Vec<bool>,
}

impl Solution {
    /// Standard error of each parameter in unit coordinates.
    pub fn standard_errors(&self) -> Vec<f64> {
        (0..self.point.len())
            .map(|j| self.covariance[j][j].max(0.0).sqrt())
            .collect()
    }

    /// Whether every parameter's standard error is finite.
    pub fn identifiable(&self) -> bool {
        self.standard_errors().iter().all(|s| s.is_finite())
    }
}

struct Misfit<'a> {
    surfaces: &'a [ResponseSurface],
    targets: &'a [Target],
}

impl Misfit<'_> {
    fn chi_squared(&self, u: &[f64]) -> f64 {
        self.surfaces
            .iter()
            .zip(self.targets)
            .map(|(s, t)| ((s.value(u) - t.value) / t.uncertainty).powi(2))
            .sum()
    }
}

impl MPFitter for Misfit<'_> {
    fn eval(&self, params: &[f64], deviates: &mut [f64]) -> MPResult<()> {
        for ((d, s), t) in deviates.iter_mut().zip(self.surfaces).zip(self.targets) {
            *d = (s.value(params) - t.value) / t.uncertainty;
            if !d.is_finite() {
                return Err(MPError::Eval);
            }
        }
        Ok(())
    }

    fn number_of_points(&self) -> usize {
        self.targets.len()
    }
}

/// Grid points per parameter of the global search before the local polish: fine enough that
/// the polish starts in the basin of the best minimum of two quadratics.
const GRID: usize = 101;

/// Finds the parameters in the box [lower, upper] (unit coordinates) that minimise the
/// targets' χ² on the surfaces, each target weighted by its own uncertainty: a global grid
/// search, then Levenberg–Marquardt within the box (`rmpfit`).
///
/// The covariance is that of a weighted least-squares estimate, (Jᵀ Σ⁻¹ J)⁻¹, with J the
/// surfaces' gradients at the solution and Σ diagonal, each target's variance plus its
/// surface's prediction variance there: so it carries both the lab's uncertainty and the
/// simulations' noise, as averaged by the surfaces (first-order propagation, as for any
/// least-squares estimate; Bard 1974, *Nonlinear Parameter Estimation*, ch. 7).
pub fn solve(
    surfaces: &[ResponseSurface],
    targets: &[Target],
    lower: &[f64],
    upper: &[f64],
) -> AnalysisResult<Solution> {
    const CONTEXT: &str = "calibration";
    let k = lower.len();
    if surfaces.len() != targets.len() || surfaces.is_empty() {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: format!(
                "needs one surface per target, got {} and {}",
                surfaces.len(),
                targets.len()
            ),
        });
    }
    if targets.len() < k || upper.len() != k || !(1..=super::MAX_PARAMETERS).contains(&k) {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: format!(
                "{} targets cannot determine {k} parameters (at most {}, and no more than targets)",
                targets.len(),
                super::MAX_PARAMETERS
            ),
        });
    }
    if targets
        .iter()
        .any(|t| !(t.value.is_finite() && t.uncertainty.is_finite() && t.uncertainty > 0.0))
    {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: "targets need finite values and uncertainties > 0".into(),
        });
    }
    if lower
        .iter()
        .zip(upper)
        .any(|(l, u)| !(l.is_finite() && u.is_finite() && l < u))
    {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: format!("the box must have lower < upper, got {lower:?} and {upper:?}"),
        });
    }
    let misfit = Misfit { surfaces, targets };
    let at = |index: usize, j: usize| {
        lower[j] + (upper[j] - lower[j]) * index as f64 / (GRID - 1) as f64
    };
    let mut best = (f64::INFINITY, lower.to_vec());
    let mut visit = |u: Vec<f64>| {
        let c = misfit.chi_squared(&u);
        if c < best.0 {
            best = (c, u);
        }
    };
    if k == 1 {
        (0..GRID).for_each(|i| visit(vec![at(i, 0)]));
    } else {
        for i in 0..GRID {
            for j in 0..GRID {
                visit(vec![at(i, 0), at(j, 1)]);
            }
        }
    }
    let mut point = best.1;
    let settings: Vec<MPPar> = (0..k)
        .map(|j| MPPar {
            limited_low: true,
            limited_up: true,
            limit_low: lower[j],
            limit_up: upper[j],
            ..MPPar::default()
        })
        .collect();
    let mut polished = point.clone();
    // The polish only refines the grid's best point; should it fail (a flat misfit), that
    // point stands.
    if misfit
        .mpfit(&mut polished, Some(&settings), &MPConfig::default())
        .is_ok()
        && misfit.chi_squared(&polished) <= misfit.chi_squared(&point)
    {
        point = polished;
    }

    let mut fisher = vec![vec![0.0; k]; k];
    let mut predicted = Vec::with_capacity(targets.len());
    let mut chi_squared = 0.0;
    for (s, t) in surfaces.iter().zip(targets) {
        let value = s.value(&point);
        let surface_variance = s.value_variance(&point);
        let variance = t.uncertainty * t.uncertainty + surface_variance;
        predicted.push(Estimate::new(value, surface_variance.sqrt()));
        chi_squared += (value - t.value).powi(2) / variance;
        let g = s.gradient(&point);
        for a in 0..k {
            for b in 0..k {
                fisher[a][b] += g[a] * g[b] / variance;
            }
        }
    }
    let covariance = invert(&fisher);
    let span = |j: usize| upper[j] - lower[j];
    let at_edge = (0..k)
        .map(|j| point[j] - lower[j] <= 1e-6 * span(j) || upper[j] - point[j] <= 1e-6 * span(j))
        .collect();
    Ok(Solution {
        point,
        covariance,
        chi_squared,
        predicted,
        at_edge,
    })
}

/// The inverse of a symmetric 1×1 or 2×2 information matrix; infinite entries when it is
/// singular to working precision (the targets do not determine the parameters).
fn invert(m: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let singular = |k: usize| vec![vec![f64::INFINITY; k]; k];
    match m.len() {
        1 if m[0][0] > 0.0 => vec![vec![1.0 / m[0][0]]],
        2 => {
            let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
            // Relative to the diagonal's product: a determinant this small means the two
            // sensitivities are parallel to 1e-9 of their size.
            if det.is_nan() || det <= 1e-9 * m[0][0] * m[1][1] {
                return singular(2);
            }
            vec![
                vec![m[1][1] / det, -m[0][1] / det],
                vec![-m[1][0] / det, m[0][0] / det],
            ]
        }
        k => singular(k),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A surface through exact values of `f` on a 5 × 5 grid over the unit square.
    fn surface_of(f: impl Fn(&[f64]) -> f64) -> ResponseSurface {
        let mut data = Vec::new();
        for i in 0..5 {
            for j in 0..5 {
                let u = vec![i as f64 / 4.0, j as f64 / 4.0];
                let y = f(&u);
                data.push((u, y));
            }
        }
        ResponseSurface::fit(&data, &[0.5, 0.5], &[0.5, 0.5]).unwrap()
    }

    #[test]
    fn two_linear_targets_are_inverted_with_the_propagated_covariance() {
        // y₁ = 20 + 10u₁ + 2u₂, y₂ = 5 − u₁ + 4u₂: exact surfaces, so Σ is the targets' own
        // variance and the covariance is J⁻¹ Σ J⁻ᵀ exactly.
        let s1 = surface_of(|u| 20.0 + 10.0 * u[0] + 2.0 * u[1]);
        let s2 = surface_of(|u| 5.0 - u[0] + 4.0 * u[1]);
        let truth = [0.3, 0.6];
        let targets = [
            Target {
                value: 20.0 + 3.0 + 1.2,
                uncertainty: 0.5,
            },
            Target {
                value: 5.0 - 0.3 + 2.4,
                uncertainty: 0.2,
            },
        ];
        let sol = solve(&[s1, s2], &targets, &[0.0, 0.0], &[1.0, 1.0]).unwrap();
        for (p, t) in sol.point.iter().zip(truth) {
            // The polish's tolerance, far below any standard error here.
            assert!((p - t).abs() < 1e-6, "{:?}", sol.point);
        }
        // J = [[10, 2], [−1, 4]], det 42; var(u₁) = (16·0.25 + 4·0.04)/42².
        let var_u1 = (16.0 * 0.25 + 4.0 * 0.04) / (42.0 * 42.0);
        assert!(
            (sol.covariance[0][0] - var_u1).abs() < 1e-6 * var_u1,
            "{:?}",
            sol.covariance
        );
        assert!(sol.chi_squared < 1e-10);
        assert!(sol.identifiable() && sol.at_edge == vec![false, false]);
    }

    #[test]
    fn a_parameter_the_targets_ignore_is_reported_as_not_identifiable() {
        // Both targets depend on u₁ only: u₂ has zero sensitivity.
        let s1 = surface_of(|u| 1.0 + u[0]);
        let s2 = surface_of(|u| 2.0 - 3.0 * u[0]);
        let t = [
            Target {
                value: 1.5,
                uncertainty: 0.1,
            },
            Target {
                value: 0.5,
                uncertainty: 0.1,
            },
        ];
        let sol = solve(&[s1, s2], &t, &[0.0, 0.0], &[1.0, 1.0]).unwrap();
        assert!(!sol.identifiable());
        assert!((sol.point[0] - 0.5).abs() < 1e-6);
    }

    #[test]
    fn a_target_beyond_the_box_pegs_the_parameter_at_its_edge() {
        let s = ResponseSurface::fit(
            &(0..6)
                .map(|i| (vec![i as f64 / 5.0], 1.0 + i as f64 / 5.0))
                .collect::<Vec<_>>(),
            &[0.5],
            &[0.5],
        )
        .unwrap();
        let sol = solve(
            &[s],
            &[Target {
                value: 3.0,
                uncertainty: 0.1,
            }],
            &[0.0],
            &[1.0],
        )
        .unwrap();
        assert_eq!(sol.at_edge, vec![true]);
        assert!((sol.point[0] - 1.0).abs() < 1e-9);
        assert!(sol.chi_squared > 10.0);
    }

    #[test]
    fn more_parameters_than_targets_are_refused() {
        let s = surface_of(|u| u[0] + u[1]);
        let t = [Target {
            value: 1.0,
            uncertainty: 0.1,
        }];
        assert!(solve(&[s], &t, &[0.0, 0.0], &[1.0, 1.0]).is_err());
    }
}
