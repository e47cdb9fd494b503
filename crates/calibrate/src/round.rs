//! One round of a calibration as a study: every test case at every design point, with
//! replicates.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use case::{CalibrationPlan, ConfigErrors, SweepCase, SweepPlan};

/// Unit coordinates u = (p − min)/(max − min) of physical parameter values.
pub fn to_unit(plan: &CalibrationPlan, values: &[f64]) -> Vec<f64> {
    plan.parameters
        .iter()
        .zip(values)
        .map(|(p, v)| (v - p.min) / (p.max - p.min))
        .collect()
}

/// Physical parameter values p = min + u (max − min) of unit coordinates.
pub fn to_physical(plan: &CalibrationPlan, unit: &[f64]) -> Vec<f64> {
    plan.parameters
        .iter()
        .zip(unit)
        .map(|(p, u)| p.min + u * (p.max - p.min))
        .collect()
}

/// The study folder of round `round` (from 1) in the calibration's folder `out`.
pub fn round_dir(out: &Path, round: u32) -> PathBuf {
    out.join("rounds").join(format!("round-{round:02}"))
}

/// The study of round `round`: each test case at each design point (unit coordinates), with
/// the plan's replicates. A run's identifier is `p<point>-<test>-r<replicate>`.
///
/// Replicate r of a test has the same seed at every design point of a round (common random
/// numbers: the same fill, whatever the parameters), so that the differences between
/// points, which the response surfaces fit, carry less of the fills' noise (Law 2015,
/// *Simulation Modeling and Analysis*, §11.2); the seeds of different replicates, tests and
/// rounds are independent, so that a point that two rounds share adds a new measurement.
pub fn round_plan(
    plan: &CalibrationPlan,
    round: u32,
    points: &[Vec<f64>],
) -> Result<SweepPlan, ConfigErrors> {
    let mut cases = Vec::new();
    for (index, unit) in points.iter().enumerate() {
        let values = to_physical(plan, unit);
        let sets = plan.sets_at(&values);
        for test in &plan.tests {
            let base = case::load_case(&test.path, &sets)?;
            for replicate in 0..plan.replicates {
                let mut case = base.clone();
                case.seed = case::replica_seed(
                    base.seed,
                    &format!("calibration|{}|round-{round}", test.name),
                    replicate,
                );
                let mut labels = BTreeMap::new();
                labels.insert("round".to_string(), round.to_string());
                labels.insert("point".to_string(), index.to_string());
                labels.insert("test".to_string(), test.name.clone());
                labels.insert("replica".to_string(), replicate.to_string());
                for (p, v) in plan.parameters.iter().zip(&values) {
                    labels.insert(p.key.clone(), format!("{v:?}"));
                }
                cases.push(SweepCase {
                    id: format!("p{index:02}-{}-r{replicate}", test.name),
                    case,
                    labels,
                });
            }
        }
    }
    Ok(SweepPlan {
        name: format!("{}-round-{round:02}", plan.name),
        description: format!("round {round} of the calibration {}", plan.name),
        replicas: plan.replicates,
        cases,
        skipped: Vec::new(),
        start: None,
    })
}
