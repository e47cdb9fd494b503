//! A full quadratic response surface y(u) fitted by least squares, with the covariance of its
//! coefficients and so the variance of its predictions (docs/physics.md §12.1).

use serde::{Deserialize, Serialize};

use crate::error::{AnalysisError, AnalysisResult};

/// A quadratic in k ≤ 2 parameters fitted to noisy measurements.
///
/// It is written in local coordinates x = (u − centre)/scale, so that its coefficients stay
/// of order one whatever the region's size: for k = 1 the basis is (1, x, x²), for k = 2
/// (1, x₁, x₂, x₁², x₁x₂, x₂²).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResponseSurface {
    /// Centre of the local coordinates, in unit coordinates.
    pub centre: Vec<f64>,
    /// Scale of the local coordinates, in unit coordinates (> 0).
    pub scale: Vec<f64>,
    /// Coefficients of the basis (unit of the measured quantity).
    pub coefficients: Vec<f64>,
    /// Covariance of the coefficients, row-major, scaled by the residual variance.
    pub covariance: Vec<Vec<f64>>,
    /// Standard deviation of the residuals about the surface (unit of the quantity): the
    /// simulation's noise, plus any misfit of the quadratic.
    pub residual_sd: f64,
    /// Measurements it was fitted to.
    pub points: usize,
}

/// Number of basis functions of a quadratic in `k` variables.
fn basis_len(k: usize) -> usize {
    (k + 1) * (k + 2) / 2
}

/// The quadratic basis at local coordinates `x` (k = 1 or 2).
fn basis(x: &[f64]) -> Vec<f64> {
    match x {
        [a] => vec![1.0, *a, a * a],
        [a, b] => vec![1.0, *a, *b, a * a, a * b, b * b],
        _ => Vec::new(),
    }
}

/// Derivatives of the basis with respect to each local coordinate.
fn basis_gradient(x: &[f64]) -> Vec<Vec<f64>> {
    match x {
        [a] => vec![vec![0.0, 1.0, 2.0 * a]],
        [a, b] => vec![
            vec![0.0, 1.0, 0.0, 2.0 * a, *b, 0.0],
            vec![0.0, 0.0, 1.0, 0.0, *a, 2.0 * b],
        ],
        _ => Vec::new(),
    }
}

/// The Cholesky factor L (lower, row-major) of a symmetric positive-definite matrix, or
/// `None` when a pivot falls below 1e-12 of its diagonal entry: the columns of the design are
/// then dependent to working precision. The matrices here are at most 6 × 6 (a quadratic in
/// two parameters), so a direct factorisation is all that least squares needs.
fn cholesky(a: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
    let n = a.len();
    let mut l = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in 0..=i {
            let sum: f64 = (0..j).map(|m| l[i][m] * l[j][m]).sum();
            if i == j {
                let pivot = a[i][i] - sum;
                if pivot.is_nan() || pivot <= 1e-12 * a[i][i] {
                    return None;
                }
                l[i][i] = pivot.sqrt();
            } else {
                l[i][j] = (a[i][j] - sum) / l[j][j];
            }
        }
    }
    Some(l)
}

/// Solves L Lᵀ x = b.
fn cholesky_solve(l: &[Vec<f64>], b: &[f64]) -> Vec<f64> {
    let n = b.len();
    let mut y = vec![0.0; n];
    for i in 0..n {
        y[i] = (b[i] - (0..i).map(|m| l[i][m] * y[m]).sum::<f64>()) / l[i][i];
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        x[i] = (y[i] - (i + 1..n).map(|m| l[m][i] * x[m]).sum::<f64>()) / l[i][i];
    }
    x
}

impl ResponseSurface {
    /// Fits the quadratic to `(u, y)` measurements (u in unit coordinates, one entry per
    /// parameter), in local coordinates about `centre` with `scale`.
    ///
    /// Needs more measurements than coefficients (3 for one parameter, 6 for two), at
    /// distinct enough points to determine them; the residual variance then estimates the
    /// noise, and the coefficients' covariance is scaled by it, as for any least-squares fit
    /// whose errors are not known beforehand.
    pub fn fit(
        measurements: &[(Vec<f64>, f64)],
        centre: &[f64],
        scale: &[f64],
    ) -> AnalysisResult<Self> {
        const CONTEXT: &str = "response surface";
        let k = centre.len();
        if !(1..=super::MAX_PARAMETERS).contains(&k) || scale.len() != k {
            return Err(AnalysisError::InvalidArgument {
                context: CONTEXT,
                reason: format!("needs 1 or 2 parameters with a scale each, got {k}"),
            });
        }
        if scale.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
            return Err(AnalysisError::InvalidArgument {
                context: CONTEXT,
                reason: format!("scales must be finite and > 0, got {scale:?}"),
            });
        }
        let n_coefficients = basis_len(k);
        if measurements.len() <= n_coefficients {
            return Err(AnalysisError::TooFewPoints {
                context: CONTEXT,
                needed: n_coefficients + 1,
                got: measurements.len(),
            });
        }
        let mut rows = Vec::with_capacity(measurements.len());
        let mut y = Vec::with_capacity(measurements.len());
        for (index, (u, value)) in measurements.iter().enumerate() {
            if u.len() != k || !value.is_finite() || u.iter().any(|v| !v.is_finite()) {
                return Err(AnalysisError::NonFinite {
                    context: CONTEXT,
                    index,
                });
            }
            let x: Vec<f64> = u
                .iter()
                .zip(centre)
                .zip(scale)
                .map(|((u, c), s)| (u - c) / s)
                .collect();
            rows.push(basis(&x));
            y.push(*value);
        }
        // Normal equations XᵀX c = Xᵀy; the coefficients' covariance is s²(XᵀX)⁻¹ with s² the
        // residual variance on n − p degrees of freedom.
        let mut normal = vec![vec![0.0; n_coefficients]; n_coefficients];
        let mut rhs = vec![0.0; n_coefficients];
        for (row, value) in rows.iter().zip(&y) {
            for i in 0..n_coefficients {
                rhs[i] += row[i] * value;
                for j in 0..n_coefficients {
                    normal[i][j] += row[i] * row[j];
                }
            }
        }
        let Some(factor) = cholesky(&normal) else {
            return Err(AnalysisError::Degenerate {
                context: CONTEXT,
                reason: "the measurements' points do not determine a quadratic".into(),
            });
        };
        let coefficients = cholesky_solve(&factor, &rhs);
        let residual_sum: f64 = rows
            .iter()
            .zip(&y)
            .map(|(row, value)| {
                let model: f64 = row.iter().zip(&coefficients).map(|(b, c)| b * c).sum();
                (value - model).powi(2)
            })
            .sum();
        let dof = y.len() - n_coefficients;
        let residual_variance = residual_sum / dof as f64;
        let mut covariance = vec![vec![0.0; n_coefficients]; n_coefficients];
        for j in 0..n_coefficients {
            let mut unit = vec![0.0; n_coefficients];
            unit[j] = 1.0;
            for (i, v) in cholesky_solve(&factor, &unit).into_iter().enumerate() {
                covariance[i][j] = v * residual_variance;
            }
        }
        Ok(Self {
            centre: centre.to_vec(),
            scale: scale.to_vec(),
            coefficients,
            covariance,
            residual_sd: residual_variance.sqrt(),
            points: y.len(),
        })
    }

    fn local(&self, u: &[f64]) -> Vec<f64> {
        u.iter()
            .zip(&self.centre)
            .zip(&self.scale)
            .map(|((u, c), s)| (u - c) / s)
            .collect()
    }

    /// The surface's value at `u` (unit coordinates).
    pub fn value(&self, u: &[f64]) -> f64 {
        basis(&self.local(u))
            .iter()
            .zip(&self.coefficients)
            .map(|(b, c)| b * c)
            .sum()
    }

    /// ∂y/∂u_j at `u`, one entry per parameter (unit of the quantity per unit coordinate).
    pub fn gradient(&self, u: &[f64]) -> Vec<f64> {
        basis_gradient(&self.local(u))
            .iter()
            .zip(&self.scale)
            .map(|(row, s)| {
                row.iter()
                    .zip(&self.coefficients)
                    .map(|(b, c)| b * c)
                    .sum::<f64>()
                    / s
            })
            .collect()
    }

    /// Variance of the predicted value at `u` from the coefficients' uncertainty: bᵀ C b.
    pub fn value_variance(&self, u: &[f64]) -> f64 {
        let b = basis(&self.local(u));
        let mut v = 0.0;
        for (i, bi) in b.iter().enumerate() {
            for (j, bj) in b.iter().enumerate() {
                v += bi * self.covariance[i][j] * bj;
            }
        }
        v.max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{normal, seeded_rng};

    fn grid(k: usize) -> Vec<Vec<f64>> {
        let levels = [0.0, 0.5, 1.0];
        match k {
            1 => levels.iter().map(|a| vec![*a]).collect(),
            _ => levels
                .iter()
                .flat_map(|a| levels.iter().map(move |b| vec![*a, *b]))
                .collect(),
        }
    }

    #[test]
    fn an_exact_quadratic_is_reproduced_to_round_off() {
        let f = |u: &[f64]| {
            3.0 + 2.0 * u[0] - u[1] + 0.5 * u[0] * u[0] + 0.25 * u[0] * u[1] - 4.0 * u[1] * u[1]
        };
        let mut data: Vec<(Vec<f64>, f64)> =
            grid(2).into_iter().map(|u| (u.clone(), f(&u))).collect();
        data.push((vec![0.3, 0.7], f(&[0.3, 0.7])));
        let s = ResponseSurface::fit(&data, &[0.5, 0.5], &[0.5, 0.5]).unwrap();
        // Exact data: only the solver's round-off remains (its tolerances are 1e-10).
        for u in [[0.1, 0.9], [0.6, 0.2]] {
            assert!(
                (s.value(&u) - f(&u)).abs() < 1e-8,
                "{} vs {}",
                s.value(&u),
                f(&u)
            );
        }
        let g = s.gradient(&[0.2, 0.4]);
        assert!((g[0] - (2.0 + 0.2 + 0.25 * 0.4)).abs() < 1e-7, "{g:?}");
        assert!(
            (g[1] - (-1.0 + 0.25 * 0.2 - 8.0 * 0.4)).abs() < 1e-7,
            "{g:?}"
        );
        assert!(s.residual_sd < 1e-8);
    }

    #[test]
    fn noise_is_estimated_and_the_prediction_error_covers_the_truth() {
        // y = 10 + 4u − 2u² with noise of sd 0.3, five replicates at five points: the residual
        // sd estimates 0.3 within a few tens of per cent (22 dof), and the truth at the centre
        // lies within 4 predicted standard errors (a miss has probability < 1e-4).
        let mut rng = seeded_rng(11);
        let mut data = Vec::new();
        for &u in &[0.0, 0.25, 0.5, 0.75, 1.0] {
            for _ in 0..5 {
                data.push((
                    vec![u],
                    10.0 + 4.0 * u - 2.0 * u * u + 0.3 * normal(&mut rng),
                ));
            }
        }
        let s = ResponseSurface::fit(&data, &[0.5], &[0.5]).unwrap();
        assert!((s.residual_sd - 0.3).abs() < 0.12, "{}", s.residual_sd);
        let truth = 10.0 + 2.0 - 0.5;
        let sd = s.value_variance(&[0.5]).sqrt();
        assert!(
            sd > 0.0 && (s.value(&[0.5]) - truth).abs() < 4.0 * sd,
            "{} ± {sd}",
            s.value(&[0.5])
        );
    }

    #[test]
    fn too_few_or_collinear_points_are_refused() {
        let data: Vec<(Vec<f64>, f64)> = grid(1).into_iter().map(|u| (u, 1.0)).collect();
        assert!(matches!(
            ResponseSurface::fit(&data, &[0.5], &[0.5]),
            Err(AnalysisError::TooFewPoints { .. })
        ));
        // Ten measurements on the line u₁ = u₂ cannot separate x₁ from x₂.
        let line: Vec<(Vec<f64>, f64)> = (0..10)
            .map(|i| (vec![i as f64 / 9.0; 2], i as f64))
            .collect();
        assert!(ResponseSurface::fit(&line, &[0.5, 0.5], &[0.5, 0.5]).is_err());
    }
}
