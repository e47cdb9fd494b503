//! Bounds on how far the bodies have moved since the last list build, carried from step
//! to step, so that the exact measures the list-build test needs (the largest displacement,
//! the box of the displacements: `Simulation::lists_may_miss`) are taken only on the steps
//! where a build could be due.
//!
//! Each step's drift moves every coordinate of every body by at most its reach, the largest
//! |Δt v_c| of the pass ([`crate::integrator::Moved`]). So R, the sum of the reaches since
//! the last exact measure, bounds each coordinate's change since then, and √3 R each body's
//! displacement. From a measure with largest displacement L and box diagonal B:
//!
//! - every displacement is now at most L + √3 R (triangle inequality);
//! - the box of displacements has grown by at most R on each side in each coordinate, so
//!   its diagonal is at most B + 2√3 R.
//!
//! Where those bounds keep the test's every branch false, with a margin far above the
//! rounding of the sums, the test would have said "no build", and it is not evaluated. The
//! lists are therefore built at exactly the steps where they were before, and the
//! trajectories keep every bit. On the paper's hopper the measures would be 3 % of a step.

use crate::integrator::FINITE_REACH;

/// Relative margin of the bounds' comparisons: far above the rounding of the measures and
/// the sums (about 10⁻¹⁵ relative), far below anything that changes how often the
/// measures are taken.
const MARGIN: f64 = 1e-9;

/// The bounds since the last exact measure.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct ReachBound {
    /// The bounds hold: the steps since the last exact measure all reported their reach.
    valid: bool,
    /// Largest displacement L [m] at the last exact measure.
    largest: f64,
    /// Diagonal B [m] of the box of displacements at the last exact measure, when it was
    /// taken.
    diagonal: Option<f64>,
    /// R: the reaches since then, each with its rounding slack [m].
    reach: f64,
    /// The largest |coordinate| of any body at the last build [m]. A drift x + Δt v rounds
    /// to within half a unit in the last place of the result, so each step's change of a
    /// coordinate exceeds its reach by at most (this + the displacement since the build) ε.
    extent: f64,
    /// The last step's reach [m], from which the next one is guessed.
    last_reach: f64,
}

impl ReachBound {
    /// The bounds just after a list build: nothing has moved. `extent` [m] is the largest
    /// |coordinate| of any body. Bodies farther out than [`FINITE_REACH`] get no bounds:
    /// their drifts are measured at every step, whose probe of the positions' finiteness
    /// the bounds would otherwise stand in for.
    pub(crate) fn at_build(extent: f64) -> Self {
        Self {
            valid: extent < FINITE_REACH,
            largest: 0.0,
            diagonal: Some(0.0),
            reach: 0.0,
            extent,
            last_reach: 0.0,
        }
    }

    /// The bound on every body's displacement since the build [m], with a further reach
    /// `ahead` [m].
    fn displacement(&self, ahead: f64) -> f64 {
        self.largest + 3f64.sqrt() * (self.reach + ahead)
    }

    /// Forgets the bounds: a step went by without reporting its reach.
    pub(crate) fn forget(&mut self) {
        self.valid = false;
    }

    /// Takes one step's reach [m].
    pub(crate) fn step(&mut self, reach: f64) {
        // A NaN reach (a non-finite velocity, which the pass reports) must not be lost.
        let reach = if reach >= 0.0 { reach } else { f64::INFINITY };
        // The rounding of the drift, from the farthest any coordinate can now lie (twice
        // the half unit in the last place).
        let slack = (self.extent + self.displacement(reach)) * f64::EPSILON;
        self.reach += reach + slack;
        self.last_reach = reach;
    }

    /// Takes an exact measure: the largest displacement [m], and the box's diagonal [m]
    /// where it was taken.
    pub(crate) fn measured(&mut self, largest: f64, diagonal: Option<f64>) {
        if self.valid {
            (self.largest, self.diagonal, self.reach) = (largest, diagonal, 0.0);
        }
    }

    /// Whether no list build can be due, with a further reach `ahead` [m] beyond the
    /// steps taken, for lists built with skin `skin` [m] and, where there are walls, walls
    /// moved by `wall_drift` [m] since the build (the test's two branches:
    /// `Simulation::lists_may_miss`).
    pub(crate) fn rules_out(&self, skin: f64, wall_drift: Option<f64>, ahead: f64) -> bool {
        if !self.valid {
            return false;
        }
        let moved = 3f64.sqrt() * (self.reach + ahead);
        let limit = skin * (1.0 - MARGIN);
        let largest = self.displacement(ahead) * (1.0 + MARGIN);
        let walls = wall_drift.is_none_or(|drift| largest + drift < limit);
        let pairs = 2.0 * largest < limit
            || self
                .diagonal
                .is_some_and(|b| (b + 2.0 * moved) * (1.0 + MARGIN) < limit);
        walls && pairs
    }

    /// A guess of the next step's reach [m], generous: the last one and half again.
    pub(crate) fn next_reach(&self) -> f64 {
        1.5 * self.last_reach
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bounds_rule_a_build_out_only_while_every_branch_is_below_the_skin() {
        // Skin 1 mm, no walls. After a build the pair branch needs 2 √3 R < 1 mm:
        // R < 0.2887 mm. Measured at L = 0.4 mm with a box of 0.5 mm, the box branch
        // allows 0.5 + 2 √3 R < 1 (R < 0.1443 mm) where 2 (0.4 + √3 R) < 1 no longer holds.
        let mut b = ReachBound::at_build(1.0);
        b.step(0.28e-3);
        assert!(b.rules_out(1e-3, None, 0.0));
        assert!(!b.rules_out(1e-3, None, 0.01e-3));
        b.measured(0.4e-3, Some(0.5e-3));
        b.step(0.14e-3);
        assert!(b.rules_out(1e-3, None, 0.0));
        b.step(0.005e-3);
        assert!(!b.rules_out(1e-3, None, 0.0));
        // Without the box the pair branch alone decides: 2 (0.4 + √3 R) < 1 needs
        // R < 0.0577 mm.
        b.measured(0.4e-3, None);
        b.step(0.05e-3);
        assert!(b.rules_out(1e-3, None, 0.0));
        b.step(0.01e-3);
        assert!(!b.rules_out(1e-3, None, 0.0));
        // Walls moved by 0.5 mm: L + √3 R + 0.5 < 1 with L = 0.2 mm needs R < 0.1732 mm.
        b.measured(0.2e-3, Some(0.0));
        b.step(0.17e-3);
        assert!(b.rules_out(1e-3, Some(0.5e-3), 0.0));
        b.step(0.01e-3);
        assert!(!b.rules_out(1e-3, Some(0.5e-3), 0.0));
    }

    #[test]
    fn a_forgotten_or_non_finite_bound_rules_nothing_out() {
        let mut b = ReachBound::at_build(1.0);
        b.forget();
        assert!(!b.rules_out(1.0, None, 0.0), "forgotten");
        b.measured(0.0, Some(0.0));
        assert!(!b.rules_out(1.0, None, 0.0), "a measure does not revive it");
        let mut b = ReachBound::at_build(1.0);
        b.step(f64::NAN);
        assert!(!b.rules_out(1.0, None, 0.0), "NaN reach");
        assert!(!ReachBound::at_build(f64::INFINITY).rules_out(1.0, None, 0.0));
    }
}
