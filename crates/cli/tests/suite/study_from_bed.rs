//! `hopperflow study SWEEP --from-bed DIR`: every case of a sweep over the outlet starts from
//! one saved bed, and each gives the bytes of a single `hopperflow run --from-bed` of that
//! case; a sweep that changes what made the bed, or asks for replicas, is refused with exit 2
//! and no study folder; a study folder from a bed is not continued from fills.

use crate::run_cli;
use run_cli::{hopperflow, utf8};
use std::path::Path;
use std::process::{Command, Output};

use crate::tiny;

/// Exit code the command line promises for bad input.
const EXIT_BAD_INPUT: i32 = 2;

/// The tiny hopper, its discharge cut to 50 ms: enough to measure a few crossings through
/// each outlet.
fn tiny_case() -> String {
    tiny::tiny_case(0.05)
}

/// A sweep of the tiny case over `axis` (`key`, `values`), `replicas` per point.
fn sweep(axis: (&str, &str), replicas: u32) -> String {
    format!(
        r#"version = 1
name = "tiny-bed"
description = "tiny hopper from one bed"
replicas = {replicas}
base = "tiny.toml"

[[axes]]
key = "{}"
values = {}
label = "v"
scale = 1000.0
digits = 3
"#,
        axis.0, axis.1
    )
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Writes the tiny case into `dir` and saves its settled bed there: the case file and the
/// bed folder.
fn case_and_bed(dir: &Path) -> (std::path::PathBuf, std::path::PathBuf) {
    let case = dir.join("tiny.toml");
    std::fs::write(&case, tiny_case()).expect("case file");
    let bed = dir.join("bed");
    let saved = hopperflow(&[
        "run",
        utf8(&case),
        "--save-bed",
        utf8(&bed),
        "--out",
        utf8(&dir.join("saving")),
        "--quiet",
    ]);
    assert!(saved.status.success(), "{}", stderr(&saved));
    (case, bed)
}

#[test]
fn a_study_from_one_bed_gives_each_case_the_bytes_of_its_own_run_from_that_bed() {
    let root = tempfile::tempdir().expect("temporary directory");
    let dir = root.path();
    let (case, bed) = case_and_bed(dir);

    let file = dir.join("outlets.toml");
    std::fs::write(&file, sweep(("geometry.outlet_width", "[0.015, 0.021]"), 1)).expect("sweep");
    let study = dir.join("study");
    let ran = hopperflow(&[
        "study",
        utf8(&file),
        "--from-bed",
        utf8(&bed),
        "--out",
        utf8(&study),
        "--jobs",
        "2",
        "--no-pictures",
        "--no-report",
    ]);
    assert!(ran.status.success(), "{}", stderr(&ran));
    let manifest: serde_json::Value =
        serde_json::from_slice(&std::fs::read(study.join("study.json")).expect("study.json"))
            .expect("JSON");
    assert_eq!(
        manifest["start"]["kind"],
        serde_json::json!("bed"),
        "{manifest}"
    );

    let mut ids: Vec<String> = std::fs::read_dir(study.join("cases"))
        .expect("case folders")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    ids.sort();
    assert_eq!(ids.len(), 2, "{ids:?}");
    for (id, width) in ids.iter().zip(["0.015", "0.021"]) {
        let single = dir.join(format!("single-{width}"));
        let run = hopperflow(&[
            "run",
            utf8(&case),
            "--from-bed",
            utf8(&bed),
            "--set",
            &format!("geometry.outlet_width={width}"),
            "--out",
            utf8(&single),
            "--quiet",
        ]);
        assert!(run.status.success(), "{}", stderr(&run));
        for name in ["summary.json", "flow.csv", "crossings.csv", "start.json"] {
            let a = std::fs::read(study.join("cases").join(id).join(name)).expect(name);
            let b = std::fs::read(single.join(name)).expect(name);
            assert!(
                a == b,
                "case {id}: {name} differs from the single run from the bed"
            );
        }
    }

    // The report says that the fits see one packing.
    let report = hopperflow(&["report", utf8(&study)]);
    assert!(report.status.success(), "{}", stderr(&report));
    let text = std::fs::read_to_string(study.join("report/report.md")).expect("report.md");
    assert!(
        text.contains("Every case started from one saved bed"),
        "the report does not say the cases share one bed"
    );

    // The folder holds a study from the bed: the same sweep from fills is another study.
    let again = hopperflow(&["study", utf8(&file), "--out", utf8(&study), "--no-report"]);
    assert_eq!(
        again.status.code(),
        Some(EXIT_BAD_INPUT),
        "{}",
        stderr(&again)
    );
    assert!(
        stderr(&again).contains("holds study 'tiny-bed'"),
        "{}",
        stderr(&again)
    );
}

#[test]
fn a_sweep_that_does_not_fit_the_bed_is_refused_before_anything_is_written() {
    let root = tempfile::tempdir().expect("temporary directory");
    let dir = root.path();
    let (_, bed) = case_and_bed(dir);

    let refused = |name: &str, text: String, fragments: &[&str]| {
        let file = dir.join(name);
        std::fs::write(&file, text).expect("sweep");
        let out = dir.join(format!("study-{name}"));
        let output = hopperflow(&[
            "study",
            utf8(&file),
            "--from-bed",
            utf8(&bed),
            "--out",
            utf8(&out),
            "--no-report",
        ]);
        let message = stderr(&output);
        assert_eq!(
            output.status.code(),
            Some(EXIT_BAD_INPUT),
            "{name}: {message}"
        );
        assert!(!message.contains("panicked"), "{name}: {message}");
        for fragment in fragments {
            assert!(
                message.contains(fragment),
                "{name}: `{fragment}` missing from {message}"
            );
        }
        assert!(
            !out.exists(),
            "{name}: a refused study created {}",
            out.display()
        );
    };
    refused(
        "count.toml",
        sweep(("particles.count", "[200, 250]"), 1),
        &["settled under other inputs", "particles.count: 250 -> 200"],
    );
    refused(
        "replicas.toml",
        sweep(("geometry.outlet_width", "[0.015, 0.021]"), 2),
        &["replicas = 2", "every replica would repeat the same run"],
    );
}

#[test]
fn the_array_tasks_of_a_study_from_a_bed_start_from_it_and_collect_the_local_table() {
    // The array's pieces without a scheduler, as `slurm_input.rs` runs them: the job script
    // names the bed, each task run by hand starts its case from it, and the collected table
    // is the local study's.
    let root = tempfile::tempdir().expect("temporary directory");
    let dir = root.path();
    let (_, bed) = case_and_bed(dir);
    let hf = |args: &[&str]| {
        let output = Command::new(env!("CARGO_BIN_EXE_hopperflow"))
            .args(args)
            .env("PATH", dir) // no Slurm tools: writing the jobs must not need them
            .output()
            .expect("runs");
        assert!(output.status.success(), "{args:?}: {}", stderr(&output));
        output
    };
    let file = dir.join("outlets.toml");
    std::fs::write(&file, sweep(("geometry.outlet_width", "[0.015, 0.021]"), 1)).expect("sweep");
    let (local, tasks) = (dir.join("local"), dir.join("tasks"));
    let study = |out: &Path, more: &[&str]| {
        let mut args = vec![
            "study",
            utf8(&file),
            "--from-bed",
            utf8(&bed),
            "--no-pictures",
            "--no-report",
            "--out",
            utf8(out),
        ];
        args.extend_from_slice(more);
        hf(&args);
    };
    study(&local, &[]);
    study(&tasks, &["--slurm"]);
    let script = std::fs::read_to_string(tasks.join("slurm/array-1.sh")).expect("array script");
    let absolute = std::path::absolute(&bed).expect("absolute path");
    assert!(
        script.contains(&format!("--from-bed {}", absolute.display())),
        "the array script does not name the bed:\n{script}"
    );
    let list = tasks.join("slurm/tasks-1.txt");
    for index in ["0", "1"] {
        study(&tasks, &["--task-list", utf8(&list), "--task-index", index]);
    }
    study(&tasks, &["--collect"]);
    let read = |d: &Path| std::fs::read(d.join("results.csv")).expect("results.csv");
    assert!(
        read(&local) == read(&tasks),
        "collected table differs from the local study from the bed"
    );
}
