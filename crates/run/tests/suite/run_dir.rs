//! What the guard tests of a run directory need in both crates that have them: the files of
//! a folder with their bytes, to show that a refusal changed nothing, and a run interrupted
//! after its first chunks. `run`'s tests use this module, and `study`'s include the same file
//! (`#[path]` in crates/study/tests/suite/main.rs): integration tests of two crates share no
//! other module.

// The study's tests include this file for its guard helpers alone.
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use files::CHECKPOINT_FILE;
use run::{run_case, RunOptions, RunOutcome};

/// Every file under `dir` with its bytes.
pub fn files(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).expect("read dir") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
            } else {
                out.insert(path.clone(), std::fs::read(&path).expect("read"));
            }
        }
    }
    out
}

/// Runs `case` in `dir` for a few protocol chunks, leaving a checkpoint in the fill.
pub fn interrupted(case: &case::Case, dir: &Path) {
    let options = RunOptions {
        chunk_limit: Some(3),
        resume: false,
        ..RunOptions::default()
    };
    let outcome = run_case(case, dir, &options).expect("the first chunks run");
    assert!(matches!(outcome, RunOutcome::Interrupted));
    assert!(dir.join(CHECKPOINT_FILE).is_file());
}

/// `case` run to its end in `dir` on `threads` threads, writing the snapshots (walls.vtu,
/// frames) when `pictures` is set; its summary.
pub fn finished(
    case: &case::Case,
    dir: &Path,
    threads: usize,
    pictures: bool,
) -> files::CaseSummary {
    let options = RunOptions {
        pictures,
        threads,
        ..RunOptions::default()
    };
    match run_case(case, dir, &options).expect("the case runs") {
        RunOutcome::Finished(summary) => *summary,
        RunOutcome::Interrupted => panic!("the run was interrupted"),
    }
}

/// Rows of a CSV file as numbers (the header dropped; a cell that is not a number is NaN).
pub fn table(path: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).expect("a written table");
    text.lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect()
}
