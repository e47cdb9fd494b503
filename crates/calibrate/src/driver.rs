//! The calibration loop: a study per round, the fits between them, the record after each.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use analysis::calibration::{converged, fit_round, Region, RoundFit, Target};
use case::CalibrationPlan;
use files::Cell;
use serde_json::Value;
use study::{run_study, CaseRunner, StudyEvent, StudyOptions};

use crate::error::CalibrationError;
use crate::measure::{has_measure, measure_value, numeric_measures};
use crate::round::{round_dir, round_plan, to_physical};
use files::{
    CalibrationRecord, ParameterEstimate, RoundRecord, SurfaceRecord, TargetMatch,
    CALIBRATION_FILE, RUNS_FILE,
};

/// How a calibration runs its rounds.
#[derive(Debug, Clone, Default)]
pub struct CalibrationOptions {
    /// Runs at the same time; 0 means one per available core.
    pub jobs: usize,
}

/// What a calibration reports while it runs.
#[derive(Debug)]
pub enum CalibrationEvent<'a> {
    /// A round's study starts: `runs` runs in `region` (lower and upper corners, unit of
    /// each key).
    RoundStarted {
        /// Round number, from 1.
        round: u32,
        /// Runs of the round.
        runs: usize,
        /// Lower corner of its region.
        lower: Vec<f64>,
        /// Upper corner of its region.
        upper: Vec<f64>,
    },
    /// Progress of the round's study.
    Study(&'a StudyEvent),
    /// A round was fitted.
    RoundFitted(&'a RoundRecord),
}

/// Hash of a calibration's inputs: its parameters, targets and replicates and the text of its
/// test cases (`max_rounds` is left out, so that a calibration may be continued with more).
pub fn plan_hash(plan: &CalibrationPlan) -> Result<String, CalibrationError> {
    let mut text = format!("calibration|{}|{}\n", plan.name, plan.replicates);
    for p in &plan.parameters {
        text.push_str(&format!("parameter|{}|{:?}|{:?}\n", p.key, p.min, p.max));
    }
    for t in &plan.targets {
        text.push_str(&format!(
            "target|{}|{}|{:?}|{:?}\n",
            plan.tests[t.test].name, t.measure, t.value, t.uncertainty
        ));
    }
    for test in &plan.tests {
        let case = std::fs::read_to_string(&test.path).map_err(|e| CalibrationError::Io {
            path: test.path.clone(),
            message: e.to_string(),
        })?;
        text.push_str(&format!("test|{}\n{case}\n", test.name));
    }
    Ok(files::hex_hash(&text))
}

fn io(path: &Path, e: impl std::fmt::Display) -> CalibrationError {
    CalibrationError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Refuses a folder that holds a calibration of other inputs; returns this plan's hash.
fn check_folder(plan: &CalibrationPlan, out: &Path) -> Result<String, CalibrationError> {
    let hash = plan_hash(plan)?;
    let record_path = out.join(CALIBRATION_FILE);
    if let Ok(text) = std::fs::read_to_string(&record_path) {
        let found = serde_json::from_str::<Value>(&text)
            .ok()
            .and_then(|v| {
                v.get("plan_hash")
                    .and_then(Value::as_str)
                    .map(str::to_string)
            })
            .unwrap_or_else(|| "unreadable".into());
        if found != hash {
            return Err(CalibrationError::DifferentCalibration {
                dir: out.to_path_buf(),
                found,
                expected: hash,
            });
        }
    }
    Ok(hash)
}

/// A round about to run.
pub struct NextRound {
    /// Its number, from 1.
    pub round: u32,
    /// Lower corner of its region (unit of each key).
    pub lower: Vec<f64>,
    /// Upper corner of its region.
    pub upper: Vec<f64>,
    /// Its study.
    pub sweep: case::SweepPlan,
}

/// A calibration between rounds: everything the next round depends on, rebuilt from the
/// finished runs alone.
pub struct Calibration<'a> {
    plan: &'a CalibrationPlan,
    out: std::path::PathBuf,
    targets: Vec<Target>,
    record: CalibrationRecord,
    rows: Vec<Vec<Cell>>,
    measurements: Vec<Vec<(Vec<f64>, f64)>>,
    region: Region,
    previous: Option<RoundFit>,
    done: bool,
}

impl<'a> Calibration<'a> {
    /// Starts (or, before its rounds are replayed, continues) `plan` in `out`, refusing a
    /// folder of another calibration.
    pub fn open(plan: &'a CalibrationPlan, out: &Path) -> Result<Self, CalibrationError> {
        let hash = check_folder(plan, out)?;
        let targets = plan
            .targets
            .iter()
            .map(|t| Target {
                value: t.value,
                uncertainty: t.uncertainty,
            })
            .collect();
        Ok(Self {
            plan,
            out: out.to_path_buf(),
            targets,
            record: CalibrationRecord {
                name: plan.name.clone(),
                plan_hash: hash,
                version: env!("CARGO_PKG_VERSION").to_string(),
                replicates: plan.replicates,
                rounds: Vec::new(),
                converged: false,
                runs: 0,
                failed_runs: 0,
                estimate: Vec::new(),
                correlation: None,
                matches: Vec::new(),
                targets_met: false,
            },
            rows: Vec::new(),
            measurements: vec![Vec::new(); plan.targets.len()],
            region: Region::whole(plan.parameters.len()),
            previous: None,
            done: false,
        })
    }

    /// The next round; `None` when the calibration has converged or used its rounds.
    pub fn next_round(&self) -> Result<Option<NextRound>, CalibrationError> {
        let round = self.record.rounds.len() as u32 + 1;
        if self.done || round > self.plan.max_rounds {
            return Ok(None);
        }
        let sweep = round_plan(self.plan, round, &self.region.design())
            .map_err(|source| CalibrationError::Case { round, source })?;
        Ok(Some(NextRound {
            round,
            lower: to_physical(self.plan, &self.region.lower()),
            upper: to_physical(self.plan, &self.region.upper()),
            sweep,
        }))
    }

    /// The record so far.
    pub fn record(&self) -> &CalibrationRecord {
        &self.record
    }

    /// Reads the finished runs of round `round` (whose study is `sweep`), fits it, writes
    /// `calibration.json` and `runs.csv`, and moves the region on. Runs without a summary
    /// count as failed.
    pub fn fit_round(
        &mut self,
        round: u32,
        sweep: &case::SweepPlan,
    ) -> Result<&RoundRecord, CalibrationError> {
        let plan = self.plan;
        let design = self.region.design();
        let dir = round_dir(&self.out, round);
        let mut failed = 0;
        let mut no_value = 0;
        for case in &sweep.cases {
            let point: usize = case.labels["point"].parse().unwrap_or(0);
            let replicate: u32 = case.labels["replica"].parse().unwrap_or(0);
            let test = plan
                .tests
                .iter()
                .position(|t| t.name == case.labels["test"])
                .unwrap_or(0);
            let summary_path = dir.join("cases").join(&case.id).join(files::SUMMARY_FILE);
            let summary: Option<Value> = std::fs::read_to_string(&summary_path)
                .ok()
                .and_then(|text| serde_json::from_str(&text).ok());
            let mut row = vec![
                Cell::Number(f64::from(round)),
                Cell::Number(point as f64),
                Cell::Text(plan.tests[test].name.clone()),
                Cell::Number(f64::from(replicate)),
                Cell::Text(case.case.seed.to_string()),
            ];
            row.extend(
                to_physical(plan, &design[point])
                    .into_iter()
                    .map(Cell::Number),
            );
            let mut without_value = false;
            for (index, target) in plan.targets.iter().enumerate() {
                let value = match &summary {
                    Some(summary) if target.test == test => {
                        if !has_measure(summary, &target.measure) {
                            return Err(CalibrationError::MissingMeasure {
                                run: summary_path,
                                measure: target.measure.clone(),
                                available: numeric_measures(summary).join(", "),
                            });
                        }
                        // A run without a value (a clogged run's rate) adds no measurement.
                        let value = measure_value(summary, &target.measure);
                        without_value |= value.is_none();
                        value
                    }
                    _ => None,
                };
                match value {
                    Some(value) => {
                        self.measurements[index].push((design[point].clone(), value));
                        row.push(Cell::Number(value));
                    }
                    None => row.push(Cell::Text(String::new())),
                }
            }
            failed += usize::from(summary.is_none());
            no_value += usize::from(without_value);
            let status = match (&summary, without_value) {
                (None, _) => "failed",
                (Some(_), true) => "no value",
                (Some(_), false) => "finished",
            };
            row.push(Cell::Text(status.into()));
            row.push(Cell::Text(format!(
                "rounds/round-{round:02}/cases/{}",
                case.id
            )));
            self.rows.push(row);
        }
        self.record.runs += sweep.cases.len();
        self.record.failed_runs += failed;

        let fit = fit_round(&self.measurements, &self.targets, &self.region).map_err(|e| {
            CalibrationError::Fit {
                round,
                reason: format!(
                    "the runs inside the region do not determine the response surfaces ({e}); \
                     more replicates or a narrower range may help"
                ),
            }
        })?;
        let mut round_record =
            describe_round(plan, round, &self.region, &design, sweep, failed, &fit);
        round_record.without_value = no_value;
        let done = self
            .previous
            .as_ref()
            .is_some_and(|p| converged(&p.solution, &fit.solution, &self.region));
        let record = &mut self.record;
        record.estimate = round_record.estimate.clone();
        record.correlation = round_record.correlation;
        record.matches = round_record.matches.clone();
        record.targets_met = round_record.targets_met;
        record.rounds.push(round_record);
        record.converged = done;
        std::fs::create_dir_all(&self.out).map_err(|e| io(&self.out, e))?;
        write_records(plan, &self.out, &self.record, &self.rows)?;
        self.done = done;
        self.region = self.region.next(&fit.solution);
        self.previous = Some(fit);
        Ok(self
            .record
            .rounds
            .last()
            .expect("a round was just recorded"))
    }
}

/// Runs (or continues) the calibration `plan` in the folder `out`.
///
/// Each round is the study [`round_plan`] in [`round_dir`]; its finished runs are kept, so
/// that a calibration run again after a kill repeats none of them and, its plans being
/// functions of the finished runs only, ends with the same files. `stop`, when set (by a
/// signal handler), ends the calibration after the running cases have checkpointed:
/// [`CalibrationError::Stopped`] is returned and the command may be run again.
pub fn run_calibration(
    plan: &CalibrationPlan,
    out: &Path,
    runner: &dyn CaseRunner,
    options: &CalibrationOptions,
    observer: &(dyn Fn(CalibrationEvent<'_>) + Sync),
    stop: Option<&AtomicBool>,
) -> Result<CalibrationRecord, CalibrationError> {
    let mut calibration = Calibration::open(plan, out)?;
    std::fs::create_dir_all(out).map_err(|e| io(out, e))?;
    while let Some(NextRound {
        round,
        lower,
        upper,
        sweep,
    }) = calibration.next_round()?
    {
        observer(CalibrationEvent::RoundStarted {
            round,
            runs: sweep.cases.len(),
            lower,
            upper,
        });
        let study_options = StudyOptions { jobs: options.jobs };
        run_study(
            &sweep,
            &round_dir(out, round),
            runner,
            &study_options,
            &|event| {
                observer(CalibrationEvent::Study(event));
            },
        )
        .map_err(|source| CalibrationError::Study {
            round,
            source: Box::new(source),
        })?;
        if stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
            return Err(CalibrationError::Stopped);
        }
        let fitted = calibration.fit_round(round, &sweep)?;
        observer(CalibrationEvent::RoundFitted(fitted));
    }
    Ok(calibration.record().clone())
}

/// Where a calibration run as Slurm jobs stands (docs/user-guide.md, "Calibration on a
/// cluster"): every round whose runs have all ended is fitted, in order.
pub enum SlurmStep {
    /// The calibration has converged or used its rounds: its record.
    Finished(Box<CalibrationRecord>),
    /// This round has runs to do (not started, or stopped with a checkpoint): its number
    /// and study. Failed runs are not retried; they count as failed in the fit.
    Run(u32, Box<case::SweepPlan>),
}

/// Replays the rounds of `plan` in `out` whose runs have all ended (finished or failed),
/// fitting each, and says what comes next.
pub fn slurm_step(plan: &CalibrationPlan, out: &Path) -> Result<SlurmStep, CalibrationError> {
    let mut calibration = Calibration::open(plan, out)?;
    while let Some(NextRound { round, sweep, .. }) = calibration.next_round()? {
        let dir = round_dir(out, round);
        let ended = dir.join("study.json").is_file()
            && study::case_states(&dir)
                .map_err(|source| CalibrationError::Study {
                    round,
                    source: Box::new(source),
                })?
                .iter()
                .all(|(_, state)| {
                    matches!(
                        state,
                        study::CaseState::Finished | study::CaseState::Failed(_)
                    )
                });
        if !ended {
            return Ok(SlurmStep::Run(round, Box::new(sweep)));
        }
        calibration.fit_round(round, &sweep)?;
    }
    Ok(SlurmStep::Finished(Box::new(calibration.record().clone())))
}

/// The round's record in physical units.
fn describe_round(
    plan: &CalibrationPlan,
    round: u32,
    region: &Region,
    design: &[Vec<f64>],
    sweep: &case::SweepPlan,
    failed: usize,
    fit: &RoundFit,
) -> RoundRecord {
    let solution = &fit.solution;
    let value = to_physical(plan, &solution.point);
    let errors = solution.standard_errors();
    let estimate = plan
        .parameters
        .iter()
        .zip(&value)
        .zip(&errors)
        .zip(&solution.point)
        .map(|(((p, v), e), u)| {
            let sigma = e * (p.max - p.min);
            ParameterEstimate {
                key: p.key.clone(),
                value: *v,
                standard_error: sigma,
                lower_95: v - 1.96 * sigma,
                upper_95: v + 1.96 * sigma,
                at_range_edge: *u <= 1e-6 || *u >= 1.0 - 1e-6,
            }
        })
        .collect();
    let correlation = (solution.point.len() == 2 && solution.identifiable())
        .then(|| solution.covariance[0][1] / (errors[0] * errors[1]));
    let matches: Vec<TargetMatch> = plan
        .targets
        .iter()
        .zip(&solution.predicted)
        .zip(&fit.surfaces)
        .map(|((t, p), s)| TargetMatch {
            test: plan.tests[t.test].name.clone(),
            measure: t.measure.clone(),
            lab: t.value,
            lab_uncertainty: t.uncertainty,
            predicted: p.value,
            predicted_error: p.standard_error,
            run_scatter: s.residual_sd,
        })
        .collect();
    let targets_met = matches.iter().all(|m: &TargetMatch| {
        (m.predicted - m.lab).abs()
            <= 2.0 * (m.lab_uncertainty.powi(2) + m.predicted_error.powi(2)).sqrt()
    });
    RoundRecord {
        targets_met,
        round,
        lower: to_physical(plan, &region.lower()),
        upper: to_physical(plan, &region.upper()),
        points: design.len(),
        runs: sweep.cases.len(),
        failed,
        without_value: 0,
        estimate,
        correlation,
        matches,
        chi_squared: solution.chi_squared,
        surfaces: fit.surfaces.iter().map(surface_record).collect(),
    }
}

/// A fitted surface as `calibration.json` keeps it.
fn surface_record(s: &analysis::calibration::ResponseSurface) -> SurfaceRecord {
    SurfaceRecord {
        centre: s.centre.clone(),
        scale: s.scale.clone(),
        coefficients: s.coefficients.clone(),
        covariance: s.covariance.clone(),
        residual_sd: s.residual_sd,
        points: s.points,
    }
}

/// Writes `calibration.json` and `runs.csv`, each atomically.
fn write_records(
    plan: &CalibrationPlan,
    out: &Path,
    record: &CalibrationRecord,
    rows: &[Vec<Cell>],
) -> Result<(), CalibrationError> {
    let mut headers: Vec<String> = ["round", "point", "test", "replicate", "seed"]
        .into_iter()
        .map(String::from)
        .collect();
    headers.extend(plan.parameters.iter().map(|p| p.key.clone()));
    headers.extend(
        plan.targets
            .iter()
            .map(|t| format!("{}:{}", plan.tests[t.test].name, t.measure)),
    );
    headers.extend(["status".to_string(), "folder".to_string()]);
    let headers: Vec<&str> = headers.iter().map(String::as_str).collect();
    let runs = out.join(RUNS_FILE);
    files::write_csv_table(&runs, &headers, rows).map_err(|e| io(&runs, e))?;
    let path = out.join(CALIBRATION_FILE);
    files::write_json_atomic(&path, record).map_err(|e| io(&path, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_saved_surface_evaluates_to_the_fitted_ones_bits() {
        // The report evaluates the saved surfaces; it must see the fit's own values.
        let data: Vec<(Vec<f64>, f64)> = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .map(|(i, j)| {
                let u = vec![0.2 + 0.1 * i as f64, 0.5 + 0.2 * j as f64];
                let y = 3.0 + u[0] * u[1] - 2.0 * u[1] * u[1] + 0.01 * (i * j) as f64;
                (u, y)
            })
            .collect();
        let fitted =
            analysis::calibration::ResponseSurface::fit(&data, &[0.3, 0.7], &[0.1, 0.2]).unwrap();
        let saved = surface_record(&fitted);
        for u in [[0.25, 0.6], [0.4, 0.9], [0.0, 0.0]] {
            assert_eq!(saved.value(&u).to_bits(), fitted.value(&u).to_bits());
        }
    }
}
