//! A study refuses a case folder that holds a run of other inputs before it writes anything.

use case::parse_sweep;
use run::RunError;
use study::{check_study_dir, StudyError};

use crate::run_dir::{files, interrupted};

#[test]
fn study_refuses_a_case_folder_of_other_inputs_before_writing() {
    let sweep = r#"
version = 1
name = "guard"
[base]
version = 1
seed = 11
[base.geometry]
width = 0.05
height = 0.1
outlet_width = 0.018
[base.particles]
count = 250
[base.protocol]
fill_bottom = 0.07
[base.output]
checkpoint_interval = 0.05
plots = false
[[axes]]
key = "geometry.outlet_width"
values = [0.018, 0.024]
label = "D"
scale = 1000.0
digits = 3
"#;
    let plan = parse_sweep(sweep, "guard.toml", None, &[]).expect("sweep");
    let root = tempfile::tempdir().expect("temporary directory");
    assert!(
        check_study_dir(&plan, root.path()).is_ok(),
        "an empty folder"
    );
    // Plant a checkpoint of the first case's hopper with another seed in its folder.
    let first = &plan.cases[0];
    let mut other = first.case.clone();
    other.seed += 1;
    let case_dir = root.path().join("cases").join(&first.id);
    interrupted(&other, &case_dir);
    let before = files(root.path());
    match check_study_dir(&plan, root.path()) {
        Err(StudyError::CaseFolder { id, source }) => {
            assert_eq!(id, first.id);
            assert!(
                matches!(*source, RunError::OtherInputs { ref changes, .. }
                    if changes.iter().any(|c| c.key == "seed")),
                "{source}"
            );
        }
        other => panic!("expected CaseFolder, got {other:?}"),
    }
    let err = study::run_study(
        &plan,
        root.path(),
        &study::SimulationRunner {
            pictures: false,
            ..Default::default()
        },
        &study::StudyOptions::default(),
        &|_| {},
    )
    .unwrap_err();
    assert!(matches!(err, StudyError::CaseFolder { .. }), "{err}");
    assert!(
        before == files(root.path()),
        "the refused study changed its folder"
    );
}
