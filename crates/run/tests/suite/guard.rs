//! A run directory is resumed only under the inputs that produced it: a summary, checkpoint
//! or case file of other inputs is refused, naming what changed, and the folder is left as
//! it was; stale temporary files are removed.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::run_dir::{files, interrupted};
use crate::tiny_hopper;

use files::CHECKPOINT_FILE;
use run::{check_run_dir, run_case, RunError, RunOptions, RunOutcome};

#[test]
fn resume_under_edited_inputs_names_each_changed_key_and_changes_nothing() {
    let dir = tempfile::tempdir().expect("temporary directory");
    interrupted(&tiny_hopper::tiny_case(&[]), dir.path());
    let before = files(dir.path());
    let edited = tiny_hopper::tiny_case(&["geometry.outlet_width=0.03", "seed=12"]);
    let err = run_case(&edited, dir.path(), &RunOptions::default()).unwrap_err();
    let RunError::OtherInputs {
        file,
        changes,
        found,
        expected,
        ..
    } = &err
    else {
        panic!("expected OtherInputs, got {err}");
    };
    assert_eq!(*file, CHECKPOINT_FILE);
    assert_ne!(found, expected);
    let named: Vec<(&str, Option<&str>, Option<&str>)> = changes
        .iter()
        .map(|c| (c.key.as_str(), c.old.as_deref(), c.new.as_deref()))
        .collect();
    assert!(
        named.contains(&("geometry.outlet_width", Some("0.018"), Some("0.03"))),
        "{named:?}"
    );
    assert!(
        named.contains(&("seed", Some("11"), Some("12"))),
        "{named:?}"
    );
    assert!(
        err.to_string()
            .contains("geometry.outlet_width: 0.018 -> 0.03"),
        "{err}"
    );
    assert!(
        before == files(dir.path()),
        "the refused resume changed the folder"
    );
    // The read-only check a study makes gives the same answer.
    assert!(matches!(
        check_run_dir(&edited, dir.path()),
        Err(RunError::OtherInputs { .. })
    ));
    assert!(check_run_dir(&tiny_hopper::tiny_case(&[]), dir.path()).is_ok());
}

#[test]
fn summary_or_case_file_of_other_inputs_is_refused() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let case = tiny_hopper::tiny_case(&[]);
    let edited = tiny_hopper::tiny_case(&["particles.count=240"]);

    // A folder whose run was killed before its first checkpoint holds only its case file.
    std::fs::write(
        dir.path().join("case.toml"),
        format!(
            "# Resolved by hopperflow 0.1.0; config hash x\n{}",
            case.to_toml_string()
        ),
    )
    .expect("write case.toml");
    match run_case(&edited, dir.path(), &RunOptions::default()) {
        Err(RunError::OtherInputs { file, changes, .. }) => {
            assert_eq!(file, "case.toml");
            assert_eq!(changes.len(), 1, "{changes:?}");
            assert_eq!(changes[0].key, "particles.count");
        }
        other => panic!("expected OtherInputs, got {other:?}"),
    }

    // A summary that does not parse as one is refused, not overwritten.
    let summary = serde_json::json!({"config_hash": "0123", "other": 1});
    std::fs::write(dir.path().join("summary.json"), summary.to_string()).expect("write");
    let before = files(dir.path());
    assert!(matches!(
        run_case(&case, dir.path(), &RunOptions::default()),
        Err(RunError::BadSummary { .. })
    ));
    assert!(
        before == files(dir.path()),
        "the refused run changed the folder"
    );
}

#[test]
fn stale_temporaries_of_a_killed_write_are_removed_and_live_ones_kept() {
    let dir = tempfile::tempdir().expect("temporary directory");
    // A pid that no process has: above the kernel's largest (2^22).
    let stale = [
        ".summary.json.4194399-0.tmp",
        ".checkpoint.bin.4194399-17.tmp",
        ".flow_rate.png.4194399-3.tmp.png",
    ];
    for name in stale {
        std::fs::write(dir.path().join(name), b"half").expect("plant");
    }
    std::fs::create_dir_all(dir.path().join("snapshots")).expect("snapshots");
    std::fs::write(
        dir.path()
            .join("snapshots/.particles_000100.vtu.4194399-2.tmp"),
        b"half",
    )
    .expect("plant");
    // This process's own temporary (a writer still at work) and files that only look alike.
    let kept = [
        format!(".summary.json.{}-0.tmp", std::process::id()),
        "notes.tmp".to_string(),
        ".hidden".to_string(),
    ];
    for name in &kept {
        std::fs::write(dir.path().join(name), b"keep").expect("plant");
    }
    let options = RunOptions {
        chunk_limit: Some(1),
        ..RunOptions::default()
    };
    run_case(&tiny_hopper::tiny_case(&[]), dir.path(), &options).expect("runs");
    for name in stale {
        assert!(!dir.path().join(name).exists(), "{name} is left");
    }
    assert!(!dir
        .path()
        .join("snapshots/.particles_000100.vtu.4194399-2.tmp")
        .exists());
    for name in &kept {
        assert!(dir.path().join(name).exists(), "{name} was removed");
    }
}

#[test]
fn restart_equals_a_fresh_run() {
    let root = tempfile::tempdir().expect("temporary directory");
    let (fresh, reused) = (root.path().join("fresh"), root.path().join("reused"));
    interrupted(&tiny_hopper::tiny_case(&["seed=3"]), &reused);
    let case = tiny_hopper::tiny_case(&[]);
    let restart = RunOptions {
        resume: false,
        ..RunOptions::default()
    };
    run_case(&case, &reused, &restart).expect("restart");
    run_case(&case, &fresh, &restart).expect("fresh");
    let strip = |m: BTreeMap<PathBuf, Vec<u8>>, base: &Path| -> BTreeMap<PathBuf, Vec<u8>> {
        m.into_iter()
            .filter(|(p, _)| p.file_name() != Some("timing.json".as_ref()))
            .map(|(p, b)| (p.strip_prefix(base).expect("inside").to_path_buf(), b))
            .collect()
    };
    assert_eq!(
        tiny_hopper::read(&fresh, "case.toml"),
        tiny_hopper::read(&reused, "case.toml"),
        "the restart records the new inputs"
    );
    assert!(
        strip(files(&fresh), &fresh) == strip(files(&reused), &reused),
        "a restart over another case's checkpoint differs from a fresh run"
    );
}

#[test]
fn a_clogged_run_reads_back_as_finished() {
    // A 3.2 d outlet arches within a tenth of a second; W cannot be measured and
    // summary.json holds it as null (JSON has no NaN). A resume, and a study, must read
    // that summary back as the finished case it is, not refuse it or run it again.
    let case = tiny_hopper::tiny_case(&["geometry.outlet_width=0.0095"]);
    let dir = tempfile::tempdir().expect("temporary directory");
    let first = run_case(&case, dir.path(), &RunOptions::default()).expect("runs");
    let RunOutcome::Finished(first) = first else {
        panic!("the run finished")
    };
    assert!(first.clogged, "the 3.2 d outlet clogs, as this test needs");
    let text = String::from_utf8(tiny_hopper::read(dir.path(), "summary.json")).expect("utf-8");
    assert!(text.contains("\"discharge_rate\": null"), "{text}");
    // The arch stands over the 9.5 mm slot: at least two 3 mm grains span it, every
    // centre above the outlet line and below D + d, and arch.csv lists them.
    let arch = first
        .arch
        .expect("a clogged run says where its arch stands");
    assert!(arch.particles >= 2, "{arch:?}");
    assert!(
        arch.lowest_height > 0.0 && arch.apex_height < 0.0095 + 0.003,
        "{arch:?}"
    );
    assert!(arch.lowest_height <= arch.mean_height && arch.mean_height <= arch.apex_height);
    let listed = String::from_utf8(tiny_hopper::read(dir.path(), "arch.csv")).expect("utf-8");
    assert_eq!(listed.lines().count(), arch.particles + 1, "{listed}");
    let again = run_case(&case, dir.path(), &RunOptions::default()).expect("resume");
    let RunOutcome::Finished(again) = again else {
        panic!("read back as finished")
    };
    assert!(again.discharge_rate.is_nan() && again.clogged);
    assert_eq!(again.stop_reason, first.stop_reason);
    assert!(check_run_dir(&case, dir.path()).is_ok());
}
