//! Reading a calibration file (`hopperflow calibrate`, docs/physics.md §12): the material
//! parameters to find, each a case key with its search range, and the lab's targets, each a
//! measure of one test case with the value and uncertainty the lab gives it.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::document::parse_document;
use super::error::{ConfigError, ConfigErrors, ErrorKind, Location};
use super::reader::Section;
use super::sweep_file::is_identifier;

/// Most parameters one calibration searches: with noisy targets, a response surface in
/// more than two dimensions needs more runs than a material's calibration can afford.
pub const MAX_CALIBRATION_PARAMETERS: usize = 2;

/// Most targets one calibration matches.
pub const MAX_CALIBRATION_TARGETS: usize = 2;

/// Largest number of replicates per design point and test; a guard against typos.
const MAX_REPLICATES: i64 = 100;

/// Largest number of rounds; a guard against typos (a calibration that has not converged
/// in 20 rounds will not).
const MAX_ROUNDS: i64 = 20;

/// One parameter to find: a case key and the range searched.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibrationParameter {
    /// Dotted case key, as `--set` takes it (e.g. `contact.rolling_friction`).
    pub key: String,
    /// Lower end of the search range (unit of the key).
    pub min: f64,
    /// Upper end of the search range (unit of the key).
    pub max: f64,
}

/// One lab measurement to match.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibrationTarget {
    /// Index of the test (in [`CalibrationPlan::tests`]) that measures it.
    pub test: usize,
    /// Dotted name of the measure in each run's `summary.json` (e.g. `repose.angle_deg`,
    /// `discharge_rate`).
    pub measure: String,
    /// The lab's value (unit of the measure).
    pub value: f64,
    /// The lab's one-sigma uncertainty of it (unit of the measure, > 0).
    pub uncertainty: f64,
}

/// One test case the targets are measured in, run at every design point.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibrationTest {
    /// Name of its runs' folders: the case file's stem, made unique.
    pub name: String,
    /// The case file.
    pub path: PathBuf,
}

/// A validated calibration file.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibrationPlan {
    /// Name of the calibration.
    pub name: String,
    /// Free text from the file.
    pub description: String,
    /// Runs per design point and test, each with its own seed.
    pub replicates: u32,
    /// Most rounds of the search.
    pub max_rounds: u32,
    /// The parameters to find (1 or 2).
    pub parameters: Vec<CalibrationParameter>,
    /// The targets to match (at least as many as parameters, at most 2).
    pub targets: Vec<CalibrationTarget>,
    /// The distinct test cases of the targets, in order of first use.
    pub tests: Vec<CalibrationTest>,
}

/// Reads and validates a calibration file; relative case paths are taken from its folder.
///
/// Every test case is loaded with every parameter at both ends of its range, so that a key
/// the case does not know, or a range it refuses, is reported before anything runs.
pub fn load_calibration(path: &Path) -> Result<CalibrationPlan, ConfigErrors> {
    let name = path.display().to_string();
    let text = super::read_text(path, &name)?;
    parse_calibration(&text, &name, path.parent())
}

/// [`load_calibration`] on text; `dir` resolves the relative case paths (`None`: the
/// current folder).
pub fn parse_calibration(
    text: &str,
    source_name: &str,
    dir: Option<&Path>,
) -> Result<CalibrationPlan, ConfigErrors> {
    let source: Arc<str> = Arc::from(source_name);
    let document = parse_document(text, &source)?;
    let mut errors = Vec::new();
    let mut root = Section::root(&document, &source);
    let version = root.integer_or("version", super::CASE_FORMAT_VERSION, &mut errors);
    if version.value != super::CASE_FORMAT_VERSION {
        errors.push(version.error(
            ErrorKind::Invalid,
            "this hopperflow reads calibration format version 1 only",
        ));
    }
    let name = match root.string("name", &mut errors) {
        Some(n) if is_identifier(&n.value) => n.value,
        Some(n) => {
            errors.push(n.error(
                ErrorKind::Invalid,
                "must be a non-empty name of letters, digits, `_` and `-`",
            ));
            String::new()
        }
        None => {
            errors.push(ConfigError::new(
                ErrorKind::Missing,
                Location::whole(&source),
                "name",
                None,
                "required: the calibration's name",
            ));
            String::new()
        }
    };
    let description = root
        .string("description", &mut errors)
        .map_or_else(String::new, |d| d.value);
    let replicates = root.integer_or("replicates", 3, &mut errors);
    if !(1..=MAX_REPLICATES).contains(&replicates.value) {
        errors.push(replicates.error(
            ErrorKind::Invalid,
            format!("must be an integer in [1, {MAX_REPLICATES}]"),
        ));
    }
    let max_rounds = root.integer_or("max_rounds", 6, &mut errors);
    if !(1..=MAX_ROUNDS).contains(&max_rounds.value) {
        errors.push(max_rounds.error(
            ErrorKind::Invalid,
            format!("must be an integer in [1, {MAX_ROUNDS}]"),
        ));
    }

    let mut parameters = Vec::new();
    let parameter_tables = root.tables("parameters", &mut errors).unwrap_or_default();
    for mut table in parameter_tables {
        let place = table.location().clone();
        let key = table.string("key", &mut errors);
        let min = table.float("min", "", &mut errors);
        let max = table.float("max", "", &mut errors);
        require(
            &table,
            &place,
            &[
                (
                    "key",
                    key.is_some(),
                    "the case key to find, e.g. contact.rolling_friction",
                ),
                ("min", min.is_some(), "the lower end of the search range"),
                ("max", max.is_some(), "the upper end of the search range"),
            ],
            &mut errors,
        );
        table.finish(&["key", "min", "max"], &mut errors);
        let (Some(key), Some(min), Some(max)) = (key, min, max) else {
            continue;
        };
        if key.value.trim().is_empty() || key.value.contains('=') {
            errors.push(key.error(
                ErrorKind::Invalid,
                "must be a dotted case key such as contact.rolling_friction",
            ));
            continue;
        }
        if !(min.value.is_finite() && max.value.is_finite() && min.value < max.value) {
            errors.push(max.error(
                ErrorKind::Invalid,
                format!("must be finite and above min = {}", min.value),
            ));
            continue;
        }
        if parameters
            .iter()
            .any(|p: &CalibrationParameter| p.key == key.value)
        {
            errors.push(key.error(ErrorKind::Conflict, "this key is already a parameter"));
            continue;
        }
        parameters.push(CalibrationParameter {
            key: key.value.clone(),
            min: min.value,
            max: max.value,
        });
    }
    count_tables(
        &root,
        &source,
        ("parameters", parameters.len(), MAX_CALIBRATION_PARAMETERS),
        "key, min and max",
        "can be calibrated",
        &mut errors,
    );

    let mut targets = Vec::new();
    let mut tests: Vec<CalibrationTest> = Vec::new();
    let target_tables = root.tables("targets", &mut errors).unwrap_or_default();
    for mut table in target_tables {
        let place = table.location().clone();
        let case = table.string("case", &mut errors);
        let measure = table.string("measure", &mut errors);
        let value = table.float("value", "", &mut errors);
        let uncertainty = table.float("uncertainty", "", &mut errors);
        require(
            &table,
            &place,
            &[
                ("case", case.is_some(), "the test's case file"),
                (
                    "measure",
                    measure.is_some(),
                    "the summary.json measure, e.g. repose.angle_deg",
                ),
                ("value", value.is_some(), "the lab's value"),
                (
                    "uncertainty",
                    uncertainty.is_some(),
                    "the lab's one-sigma uncertainty",
                ),
            ],
            &mut errors,
        );
        table.finish(&["case", "measure", "value", "uncertainty"], &mut errors);
        let (Some(case), Some(measure), Some(value), Some(uncertainty)) =
            (case, measure, value, uncertainty)
        else {
            continue;
        };
        let measure_ok = !measure.value.is_empty()
            && measure.value.split('.').all(|part| {
                !part.is_empty()
                    && part
                        .chars()
                        .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
            });
        if !measure_ok {
            errors.push(measure.error(
                ErrorKind::Invalid,
                "must be a dotted field of summary.json, e.g. repose.angle_deg or discharge_rate",
            ));
        }
        if !value.value.is_finite() {
            errors.push(value.error(ErrorKind::Invalid, "must be a finite number"));
        }
        if !(uncertainty.value.is_finite() && uncertainty.value > 0.0) {
            errors.push(uncertainty.error(
                ErrorKind::Invalid,
                "must be a finite number > 0: the lab's one-sigma uncertainty",
            ));
        }
        let path = dir.map_or_else(|| PathBuf::from(&case.value), |d| d.join(&case.value));
        let test = match tests.iter().position(|t| t.path == path) {
            Some(i) => i,
            None => {
                let stem = path
                    .file_stem()
                    .map(|s| s.to_string_lossy().to_string())
                    .unwrap_or_default();
                let stem: String = stem
                    .chars()
                    .map(|c| {
                        if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                            c
                        } else {
                            '_'
                        }
                    })
                    .collect();
                let stem = if stem.is_empty() {
                    "test".to_string()
                } else {
                    stem
                };
                let mut name = stem.clone();
                let mut n = 2;
                while tests.iter().any(|t| t.name == name) {
                    name = format!("{stem}-{n}");
                    n += 1;
                }
                // The case itself, then with the parameters at both ends of their ranges.
                let mut trials = vec![Vec::new()];
                if !parameters.is_empty() {
                    trials.push(sets(&parameters, |p| p.min));
                    trials.push(sets(&parameters, |p| p.max));
                }
                for (trial, set) in trials.iter().enumerate() {
                    if let Err(e) = super::load_case(&path, set) {
                        let which = [
                            "as written",
                            "with every parameter at its min",
                            "with every parameter at its max",
                        ][trial];
                        errors.push(case.error(
                            ErrorKind::Invalid,
                            format!("this test case cannot run {which}; its errors follow"),
                        ));
                        errors.extend(e.errors);
                        break;
                    }
                }
                tests.push(CalibrationTest { name, path });
                tests.len() - 1
            }
        };
        if targets
            .iter()
            .any(|t: &CalibrationTarget| t.test == test && t.measure == measure.value)
        {
            errors.push(measure.error(
                ErrorKind::Conflict,
                "this test's measure is already a target",
            ));
        }
        targets.push(CalibrationTarget {
            test,
            measure: measure.value,
            value: value.value,
            uncertainty: uncertainty.value,
        });
    }
    let counted = count_tables(
        &root,
        &source,
        ("targets", targets.len(), MAX_CALIBRATION_TARGETS),
        "case, measure, value and uncertainty",
        "can be matched",
        &mut errors,
    );
    if counted && !targets.is_empty() && targets.len() < parameters.len() {
        errors.push(ConfigError::new(
            ErrorKind::Invalid,
            Location::whole(&source),
            "targets",
            Some(targets.len().to_string()),
            format!(
                "{} parameters need at least as many targets: fewer cannot determine them",
                parameters.len()
            ),
        ));
    }
    root.finish(
        &[
            "version",
            "name",
            "description",
            "replicates",
            "max_rounds",
            "parameters",
            "targets",
        ],
        &mut errors,
    );
    if !errors.is_empty() {
        return Err(ConfigErrors { errors });
    }
    Ok(CalibrationPlan {
        name,
        description,
        replicates: replicates.value as u32,
        max_rounds: max_rounds.value as u32,
        parameters,
        targets,
        tests,
    })
}

/// A `Missing` error for each `(key, found, what it is)` of `table` that was not found.
fn require(
    table: &Section<'_>,
    place: &Location,
    keys: &[(&str, bool, &str)],
    errors: &mut Vec<ConfigError>,
) {
    for (key, found, what) in keys {
        if !found {
            errors.push(ConfigError::new(
                ErrorKind::Missing,
                place.clone(),
                table.key(key),
                None,
                format!("required: {what}"),
            ));
        }
    }
}

/// Checks that the array of tables `key` was given and holds at most `most` entries
/// (`count` read); `with` lists each table's keys and `verb` says what is done with at most
/// `most` of them. Returns whether the count is within these bounds.
fn count_tables(
    root: &Section<'_>,
    source: &Arc<str>,
    (key, count, most): (&str, usize, usize),
    with: &str,
    verb: &str,
    errors: &mut Vec<ConfigError>,
) -> bool {
    if count == 0 && !root.has(key) {
        errors.push(ConfigError::new(
            ErrorKind::Missing,
            Location::whole(source),
            key,
            None,
            format!("required: one or two [[{key}]] tables, each with {with}"),
        ));
        false
    } else if count > most {
        errors.push(ConfigError::new(
            ErrorKind::Invalid,
            Location::whole(source),
            key,
            Some(count.to_string()),
            format!("at most {most} {key} {verb} at once"),
        ));
        false
    } else {
        true
    }
}

/// The `key=value` overrides that put every parameter at `value(parameter)`.
fn sets(
    parameters: &[CalibrationParameter],
    value: impl Fn(&CalibrationParameter) -> f64,
) -> Vec<String> {
    parameters
        .iter()
        .map(|p| format!("{}={:?}", p.key, value(p)))
        .collect()
}

impl CalibrationPlan {
    /// The `key=value` overrides of one design point, in physical values.
    pub fn sets_at(&self, values: &[f64]) -> Vec<String> {
        self.parameters
            .iter()
            .zip(values)
            .map(|(p, v)| format!("{}={v:?}", p.key))
            .collect()
    }
}
