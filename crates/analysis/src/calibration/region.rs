//! The trust region of a calibration: where a round's design points lie, and how it moves and
//! shrinks from one round to the next (docs/physics.md §12.1).

use serde::{Deserialize, Serialize};

use super::inverse::Solution;

/// Narrowest half-width a region shrinks to, in unit coordinates: 2 % of a parameter's
/// range, below which a calibration's noisy targets could no longer tell points apart.
pub const MIN_HALF_WIDTH: f64 = 0.02;

/// A box centre ± half-width in unit coordinates, inside [0, 1]^k.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Region {
    /// Centre of the box, one entry per parameter.
    pub centre: Vec<f64>,
    /// Half-width of the box, one entry per parameter.
    pub half_width: Vec<f64>,
}

impl Region {
    /// The whole search range of `k` parameters.
    pub fn whole(k: usize) -> Self {
        Self {
            centre: vec![0.5; k],
            half_width: vec![0.5; k],
        }
    }

    /// Lower corner.
    pub fn lower(&self) -> Vec<f64> {
        self.centre
            .iter()
            .zip(&self.half_width)
            .map(|(c, h)| c - h)
            .collect()
    }

    /// Upper corner.
    pub fn upper(&self) -> Vec<f64> {
        self.centre
            .iter()
            .zip(&self.half_width)
            .map(|(c, h)| c + h)
            .collect()
    }

    /// Whether `u` lies in the box (to round-off).
    pub fn contains(&self, u: &[f64]) -> bool {
        u.iter()
            .zip(&self.centre)
            .zip(&self.half_width)
            .all(|((u, c), h)| (u - c).abs() <= h * (1.0 + 1e-9))
    }

    /// The round's design: for one parameter five equally spaced levels across the box, for
    /// two the 3 × 3 factorial of its corners, edge midpoints and centre. Both determine a
    /// quadratic with room to spare (5 points for 3 coefficients, 9 for 6), and a face-centred
    /// 3^k design is the standard one for a quadratic surface in a box (Myers et al. 2016,
    /// §7.4).
    pub fn design(&self) -> Vec<Vec<f64>> {
        let lower = self.lower();
        let upper = self.upper();
        let level = |j: usize, i: usize, n: usize| {
            lower[j] + (upper[j] - lower[j]) * i as f64 / (n - 1) as f64
        };
        match self.centre.len() {
            1 => (0..5).map(|i| vec![level(0, i, 5)]).collect(),
            _ => (0..3)
                .flat_map(|i| (0..3).map(move |j| (i, j)))
                .map(|(i, j)| vec![level(0, i, 3), level(1, j, 3)])
                .collect(),
        }
    }

    /// The next round's region, from this round's solution: centred on it, and half as wide
    /// when the solution lies inside this box, or as wide when it lies on an edge that is not
    /// the range's own (the targets may lie beyond it; the region moves without shrinking, as a
    /// trust region does after a step to its boundary). Never narrower than twice the
    /// solution's standard error, so that the next design still spans what the noise leaves
    /// undetermined, nor than [`MIN_HALF_WIDTH`]; and always inside [0, 1].
    pub fn next(&self, solution: &Solution) -> Self {
        let errors = solution.standard_errors();
        let mut centre = Vec::with_capacity(self.centre.len());
        let mut half_width = Vec::with_capacity(self.centre.len());
        for (j, error) in errors.iter().enumerate() {
            let u = solution.point[j];
            let lower = self.centre[j] - self.half_width[j];
            let upper = self.centre[j] + self.half_width[j];
            let tolerance = 1e-6 * self.half_width[j];
            let on_inner_edge = (u - lower <= tolerance && lower > tolerance)
                || (upper - u <= tolerance && upper < 1.0 - tolerance);
            let shrunk = if on_inner_edge {
                self.half_width[j]
            } else {
                0.5 * self.half_width[j]
            };
            let error = if error.is_finite() { *error } else { 0.5 };
            let h = shrunk.max(2.0 * error).clamp(MIN_HALF_WIDTH, 0.5);
            half_width.push(h);
            centre.push(u.clamp(h, 1.0 - h));
        }
        Self { centre, half_width }
    }
}

/// Largest standard error, in unit coordinates, of an estimate that counts as determined: a
/// quarter of the range. Above it the targets hardly depend on the parameter there, and a
/// calibration that stops is not converged but undetermined.
pub const MAX_DETERMINED_ERROR: f64 = 0.25;

/// Whether a calibration has converged: every parameter is determined (its standard error
/// below [`MAX_DETERMINED_ERROR`]), moved by less than its standard error from the previous
/// round's solution, which is all that further rounds could resolve, and none ended on an
/// edge of its round's region short of the range's own.
pub fn converged(previous: &Solution, current: &Solution, region: &Region) -> bool {
    let errors = current.standard_errors();
    if errors
        .iter()
        .any(|s| !(s.is_finite() && *s < MAX_DETERMINED_ERROR))
    {
        return false;
    }
    let steady = previous
        .point
        .iter()
        .zip(&current.point)
        .zip(&errors)
        .all(|((a, b), s)| (a - b).abs() <= *s);
    let inner_edge = current.at_edge.iter().enumerate().any(|(j, &edge)| {
        let u = current.point[j];
        edge && u > 1e-6 && u < 1.0 - 1e-6 && region.half_width[j] < 0.5
    });
    steady && !inner_edge
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimate::Estimate;

    fn solution(point: Vec<f64>, sd: f64, at_edge: Vec<bool>) -> Solution {
        let k = point.len();
        let mut covariance = vec![vec![0.0; k]; k];
        (0..k).for_each(|j| covariance[j][j] = sd * sd);
        Solution {
            point,
            covariance,
            chi_squared: 0.0,
            predicted: vec![Estimate::exact(0.0); k],
            at_edge,
        }
    }

    #[test]
    fn designs_span_the_box_with_enough_points_for_a_quadratic() {
        let r = Region {
            centre: vec![0.4, 0.5],
            half_width: vec![0.1, 0.2],
        };
        let d = r.design();
        assert_eq!(d.len(), 9);
        assert!(d.iter().all(|u| r.contains(u)));
        assert!(
            d.contains(&vec![0.30000000000000004, 0.3])
                || d.iter()
                    .any(|u| (u[0] - 0.3).abs() < 1e-12 && (u[1] - 0.3).abs() < 1e-12)
        );
        assert_eq!(Region::whole(1).design().len(), 5);
    }

    #[test]
    fn the_region_halves_around_an_interior_solution_and_stays_in_range() {
        let r = Region::whole(2);
        let next = r.next(&solution(vec![0.9, 0.2], 0.01, vec![false, false]));
        assert_eq!(next.half_width, vec![0.25, 0.25]);
        // Centred on the solution, moved inward so that the box stays inside [0, 1].
        assert_eq!(next.centre, vec![0.75, 0.25]);
        // A noisy solution keeps the region twice its standard error wide.
        let noisy = r.next(&solution(vec![0.5, 0.5], 0.2, vec![false, false]));
        assert_eq!(noisy.half_width, vec![0.4, 0.4]);
    }

    #[test]
    fn a_solution_on_an_inner_edge_moves_the_region_without_shrinking_it() {
        let r = Region {
            centre: vec![0.5],
            half_width: vec![0.1],
        };
        let next = r.next(&solution(vec![0.6], 0.001, vec![true]));
        assert_eq!(next.half_width, vec![0.1]);
        assert!((next.centre[0] - 0.6).abs() < 1e-12);
        assert!(!converged(
            &solution(vec![0.6], 0.1, vec![true]),
            &solution(vec![0.6], 0.1, vec![true]),
            &r
        ));
    }

    #[test]
    fn convergence_needs_a_step_within_the_standard_error() {
        let r = Region {
            centre: vec![0.5, 0.5],
            half_width: vec![0.1, 0.1],
        };
        let a = solution(vec![0.50, 0.50], 0.02, vec![false, false]);
        let b = solution(vec![0.51, 0.49], 0.02, vec![false, false]);
        let c = solution(vec![0.56, 0.49], 0.02, vec![false, false]);
        assert!(converged(&a, &b, &r));
        assert!(!converged(&a, &c, &r));
        // A step within a huge error is not convergence: the targets do not determine it.
        let vague = solution(vec![0.51, 0.49], 0.3, vec![false, false]);
        assert!(!converged(&a, &vague, &r));
    }
}
