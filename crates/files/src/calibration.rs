//! What a calibration leaves on disk (`hopperflow calibrate`, docs/physics.md §12):
//! `calibration.json` (the estimate, each round's fits) and `runs.csv` (every run it made).

use serde::{Deserialize, Serialize};

/// File name of the calibration's record in its output folder.
pub const CALIBRATION_FILE: &str = "calibration.json";

/// File name of the table of every run.
pub const RUNS_FILE: &str = "runs.csv";

/// One parameter's estimate (unit of its case key).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParameterEstimate {
    /// The case key.
    pub key: String,
    /// Best value.
    pub value: f64,
    /// One-sigma standard error; infinite when the targets do not determine it.
    pub standard_error: f64,
    /// value − 1.96 σ: the lower end of the 95 % interval of a normal estimate.
    pub lower_95: f64,
    /// value + 1.96 σ.
    pub upper_95: f64,
    /// Whether the estimate sits at an end of the search range: the lab's targets may need
    /// a value beyond it, so widen the range and run again.
    pub at_range_edge: bool,
}

/// How well one target is met at the estimate (unit of the measure).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TargetMatch {
    /// The test case's name.
    pub test: String,
    /// The measure.
    pub measure: String,
    /// The lab's value.
    pub lab: f64,
    /// The lab's one-sigma uncertainty.
    pub lab_uncertainty: f64,
    /// The response surface's prediction at the estimate.
    pub predicted: f64,
    /// Its standard error there.
    pub predicted_error: f64,
    /// Scatter of single runs about the surface: the test's noise, as a lab would see it
    /// in one repeat.
    pub run_scatter: f64,
}

/// One round: its region, runs and fits.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RoundRecord {
    /// Round number, from 1.
    pub round: u32,
    /// Lower corner of the region searched (unit of each key).
    pub lower: Vec<f64>,
    /// Upper corner of the region searched.
    pub upper: Vec<f64>,
    /// Design points.
    pub points: usize,
    /// Runs of the round (points × tests × replicates).
    pub runs: usize,
    /// Runs that failed and gave no measure.
    pub failed: usize,
    /// Measures that finished runs had no value for (a clogged run's discharge rate).
    pub without_value: usize,
    /// The estimate after this round.
    pub estimate: Vec<ParameterEstimate>,
    /// Correlation of the two parameters' errors (two parameters only).
    pub correlation: Option<f64>,
    /// The targets at the estimate.
    pub matches: Vec<TargetMatch>,
    /// χ² of the targets at the estimate (docs/physics.md §12.1).
    pub chi_squared: f64,
    /// Whether every target is met at the estimate: the prediction within twice the
    /// combined standard error (the lab's and the surface's) of the lab's value.
    pub targets_met: bool,
    /// The fitted surfaces, one per target (unit coordinates of the parameters).
    pub surfaces: Vec<SurfaceRecord>,
}

/// A calibration's record: its inputs, rounds and final estimate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CalibrationRecord {
    /// Name of the calibration.
    pub name: String,
    /// Hash of its inputs (the calibration file's parameters, targets and replicates, and
    /// the test cases' texts): a folder continues only the calibration it was made by.
    pub plan_hash: String,
    /// hopperflow version that wrote it.
    pub version: String,
    /// Replicates per design point and test.
    pub replicates: u32,
    /// The rounds run so far.
    pub rounds: Vec<RoundRecord>,
    /// Whether the last round's estimate moved less than its standard error.
    pub converged: bool,
    /// Runs made in all rounds.
    pub runs: usize,
    /// Runs that failed.
    pub failed_runs: usize,
    /// The estimate of the last round.
    pub estimate: Vec<ParameterEstimate>,
    /// Correlation of the two parameters' errors, in the last round.
    pub correlation: Option<f64>,
    /// The targets at the last round's estimate.
    pub matches: Vec<TargetMatch>,
    /// Whether the last round met every target (see [`RoundRecord::targets_met`]).
    pub targets_met: bool,
}

/// A fitted quadratic response surface y(u) of one target (docs/physics.md §12.1), in local
/// coordinates x = (u − centre)/scale of the parameters' unit coordinates u.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SurfaceRecord {
    /// Centre of the local coordinates (unit coordinates).
    pub centre: Vec<f64>,
    /// Scale of the local coordinates (unit coordinates).
    pub scale: Vec<f64>,
    /// Coefficients of (1, x, x²) or (1, x₁, x₂, x₁², x₁x₂, x₂²) (unit of the target).
    pub coefficients: Vec<f64>,
    /// Covariance of the coefficients, row-major.
    pub covariance: Vec<Vec<f64>>,
    /// Scatter of single runs about the surface (unit of the target).
    pub residual_sd: f64,
    /// Runs it was fitted to.
    pub points: usize,
}

impl SurfaceRecord {
    /// The surface's value at unit coordinates `u`.
    pub fn value(&self, u: &[f64]) -> f64 {
        let x: Vec<f64> = u
            .iter()
            .zip(&self.centre)
            .zip(&self.scale)
            .map(|((u, c), s)| (u - c) / s)
            .collect();
        let basis = match x.as_slice() {
            [a] => vec![1.0, *a, a * a],
            [a, b] => vec![1.0, *a, *b, a * a, a * b, b * b],
            _ => Vec::new(),
        };
        basis
            .iter()
            .zip(&self.coefficients)
            .map(|(b, c)| b * c)
            .sum()
    }
}
