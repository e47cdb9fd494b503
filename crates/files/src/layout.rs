//! The names of what a run and a study leave on disk: the files of a run directory, of a
//! saved bed and of a study directory. Every crate that writes or reads them names them here.

use std::path::PathBuf;

/// Name of a run's summary; its presence marks a finished run (and a finished study case).
pub const SUMMARY_FILE: &str = "summary.json";
/// Name of the resolved case inside a run directory.
pub const CASE_FILE: &str = "case.toml";
/// Name of the checkpoint file inside a run directory.
pub const CHECKPOINT_FILE: &str = "checkpoint.bin";
/// Name of the file in a run directory that says where a run started, when it did not fill
/// its container: the kind, the source's path and SHA-256, and for a bed the keys that
/// differ from the bed's case and the walls rebuilt for them.
pub const START_FILE: &str = "start.json";
/// The marker a failed study task leaves in its case folder: the case's id and the error.
pub const FAILURE_FILE: &str = "failure.json";
/// Name of the bed's state inside a bed folder.
pub const BED_FILE: &str = "bed.bin";
/// Name of the bed's resolved case inside a bed folder (for reading; `bed.bin` holds the
/// same text, which is what a reuse compares).
pub const BED_CASE_FILE: &str = "case.toml";

/// Paths inside a study directory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StudyPaths {
    /// The study directory.
    pub root: PathBuf,
}

impl StudyPaths {
    /// Paths of the study in `root`.
    pub fn new(root: impl Into<PathBuf>) -> Self {
        Self { root: root.into() }
    }
    /// `study.json`.
    pub fn manifest(&self) -> PathBuf {
        self.root.join("study.json")
    }
    /// `results.csv`.
    pub fn results(&self) -> PathBuf {
        self.root.join("results.csv")
    }
    /// `failures.json`.
    pub fn failures(&self) -> PathBuf {
        self.root.join("failures.json")
    }
    /// `cases/<id>/`.
    pub fn case_dir(&self, id: &str) -> PathBuf {
        self.root.join("cases").join(id)
    }
}
