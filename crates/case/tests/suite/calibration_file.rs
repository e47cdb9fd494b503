//! Calibration files: a valid one is read whole, and every bad value is refused with the
//! file, the key, the value and what is allowed, all errors at once.

use std::path::Path;

use case::{parse_calibration, ConfigErrors};

/// A calibration of two parameters against two measures of one test case in `dir`.
fn text(parameters: &str, targets: &str) -> String {
    format!("version = 1\nname = \"glass\"\nreplicates = 2\n{parameters}\n{targets}\n")
}

const TWO_PARAMETERS: &str =
    "[[parameters]]\nkey = \"contact.rolling_friction\"\nmin = 0.0\nmax = 0.3\n\
    [[parameters]]\nkey = \"contact.friction\"\nmin = 0.2\nmax = 0.8\n";

const TWO_TARGETS: &str = "[[targets]]\ncase = \"test.toml\"\nmeasure = \"discharge_rate\"\nvalue = 0.05\nuncertainty = 0.002\n\
    [[targets]]\ncase = \"test.toml\"\nmeasure = \"bulk_volume_fraction\"\nvalue = 0.6\nuncertainty = 0.01\n";

fn dir_with_case() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("test.toml"),
        "version = 1\n[particles]\ncount = 200\n",
    )
    .unwrap();
    dir
}

fn errors(dir: &Path, text: &str) -> String {
    let e: ConfigErrors = parse_calibration(text, "cal.toml", Some(dir)).unwrap_err();
    e.to_string()
}

#[test]
fn a_valid_file_names_its_parameters_targets_and_one_shared_test() {
    let dir = dir_with_case();
    let plan = parse_calibration(
        &text(TWO_PARAMETERS, TWO_TARGETS),
        "cal.toml",
        Some(dir.path()),
    )
    .unwrap();
    assert_eq!(plan.parameters.len(), 2);
    assert_eq!(plan.parameters[0].key, "contact.rolling_friction");
    assert_eq!(plan.targets.len(), 2);
    // Both targets are measured in the same runs.
    assert_eq!(plan.tests.len(), 1);
    assert_eq!(plan.tests[0].name, "test");
    assert_eq!((plan.replicates, plan.max_rounds), (2, 6));
    assert_eq!(
        plan.sets_at(&[0.1, 0.5]),
        vec!["contact.rolling_friction=0.1", "contact.friction=0.5"]
    );
}

#[test]
fn bad_values_are_refused_with_key_value_and_range() {
    let dir = dir_with_case();
    let bad_parameters = "[[parameters]]\nkey = \"contact.friction\"\nmin = 0.8\nmax = 0.2\n";
    let bad_targets = "[[targets]]\ncase = \"test.toml\"\nmeasure = \"Discharge Rate\"\nvalue = 0.05\nuncertainty = -1.0\n";
    let text = format!(
        "{}replicates = 0\nmax_rounds = 99\ncolour = 3\n{bad_parameters}{bad_targets}",
        "version = 1\nname = \"glass\"\n"
    );
    let message = errors(dir.path(), &text);
    for expected in [
        "cal.toml:3",
        "replicates = 0: must be an integer in [1, 100]",
        "max_rounds = 99: must be an integer in [1, 20]",
        "colour: unknown key",
        "parameters[0].max = 0.2",
        "must be finite and above min = 0.8",
        "targets[0].measure",
        "targets[0].uncertainty = -1",
        "must be a finite number > 0",
    ] {
        assert!(
            message.contains(expected),
            "missing {expected:?} in:\n{message}"
        );
    }
}

#[test]
fn more_parameters_than_targets_are_refused() {
    let dir = dir_with_case();
    let one_target = "[[targets]]\ncase = \"test.toml\"\nmeasure = \"discharge_rate\"\nvalue = 0.05\nuncertainty = 0.002\n";
    let message = errors(dir.path(), &text(TWO_PARAMETERS, one_target));
    assert!(
        message.contains("targets = 1")
            && message.contains("2 parameters need at least as many targets"),
        "{message}"
    );
}

#[test]
fn a_key_the_test_case_refuses_is_reported_with_the_cases_own_error() {
    let dir = dir_with_case();
    // Restitution must lie in (0, 1]: the range's max is refused by the case.
    let parameters = "[[parameters]]\nkey = \"contact.restitution\"\nmin = 0.5\nmax = 1.5\n";
    let one_target = "[[targets]]\ncase = \"test.toml\"\nmeasure = \"discharge_rate\"\nvalue = 0.05\nuncertainty = 0.002\n";
    let message = errors(dir.path(), &text(parameters, one_target));
    assert!(
        message.contains("with every parameter at its max")
            && message.contains("contact.restitution"),
        "{message}"
    );
    // A key no case has.
    let parameters = "[[parameters]]\nkey = \"contact.stickiness\"\nmin = 0.0\nmax = 1.0\n";
    let message = errors(dir.path(), &text(parameters, one_target));
    assert!(message.contains("contact.stickiness"), "{message}");
    // A test case that does not exist.
    let missing = one_target.replace("test.toml", "nowhere.toml");
    let message = errors(
        dir.path(),
        &text(
            "[[parameters]]\nkey = \"contact.friction\"\nmin = 0.2\nmax = 0.8\n",
            &missing,
        ),
    );
    assert!(
        message.contains("nowhere.toml") && message.contains("cannot read"),
        "{message}"
    );
}
