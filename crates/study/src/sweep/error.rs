//! Why a study could not run or its results could not be read.

use std::path::PathBuf;

use files::{OutputError, StudyFileError};

/// A study-level failure. A single case failing is not one of these: it is recorded in
/// `failures.json` and the results table, and the other cases go on.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// A file of the study could not be read, written or parsed: its manifest, its results
    /// table, a directory, a summary.
    #[error(transparent)]
    File(#[from] StudyFileError),
    /// The output directory holds a different study, so resuming into it would mix results.
    #[error(
        "{path} holds study '{found_name}' with config hash {found_hash}, not '{expected_name}' \
         ({expected_hash}); choose another output directory or remove the old one"
    )]
    DifferentStudy {
        /// The manifest that disagrees.
        path: PathBuf,
        /// Name in the manifest.
        found_name: String,
        /// Config hash in the manifest.
        found_hash: String,
        /// Name of the sweep being run.
        expected_name: String,
        /// Config hash of the sweep being run.
        expected_hash: String,
    },
    /// A case's folder holds a run that this sweep must not continue: a summary, checkpoint
    /// or case file of other inputs, or a damaged checkpoint or summary.
    #[error("case {id}: {source}; remove that case folder to run the case afresh")]
    CaseFolder {
        /// The case.
        id: String,
        /// What is wrong with its folder.
        #[source]
        source: Box<run::RunError>,
    },
    /// A task names a case that the sweep does not have.
    #[error("the sweep has no case '{id}' (it has {known} cases)")]
    UnknownCase {
        /// The identifier asked for.
        id: String,
        /// How many cases the sweep has.
        known: usize,
    },
    /// Two cases of the plan share an identifier, so they would share a directory.
    #[error("the sweep has two cases named '{0}'")]
    DuplicateCase(String),
    /// The bed a study was to start from cannot be read.
    #[error(transparent)]
    Bed(Box<run::BedError>),
    /// A case of a study from a saved bed changes what made the bed.
    #[error("case {id}: {source}")]
    BedDoesNotFit {
        /// The case.
        id: String,
        /// What the bed refuses.
        #[source]
        source: Box<run::BedError>,
    },
    /// A study from one bed asked for replicas, which would all be the same run.
    #[error("replicas = {replicas}: a study from one saved bed runs each grid point once (replicas = 1), since the seed draws only the fill and every replica would repeat the same run; for independent replicas, run the sweep from fills, or one study per bed")]
    ReplicasFromOneBed {
        /// The replicas asked for.
        replicas: u32,
    },
}

impl StudyError {
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::File(StudyFileError::io(path, source))
    }

    /// A file of the study that was read but does not hold what it should.
    pub(crate) fn parse(path: impl Into<PathBuf>, reason: impl Into<String>) -> Self {
        Self::File(StudyFileError::Parse {
            path: path.into(),
            reason: reason.into(),
        })
    }
}

impl From<OutputError> for StudyError {
    fn from(e: OutputError) -> Self {
        Self::File(StudyFileError::Output(e))
    }
}
