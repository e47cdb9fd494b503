//! The exit statuses of the command line (docs/user-guide.md): 0 done, 1 a failure of the
//! run or of the machine, 2 bad input, 3 a study with failed cases, 75 stopped by a signal
//! with its checkpoints written.

use study::StudyError;

/// Exit code for bad input (a malformed case file or override).
pub const EXIT_BAD_INPUT: i32 = 2;

/// Exit status of a run or study stopped by SIGTERM or Ctrl-C after writing its
/// checkpoints (BSD's EX_TEMPFAIL: the work is unfinished, try again later).
pub const EXIT_STOPPED: i32 = 75;

/// The exit status of a study-level error: 2 for what the user's inputs or folder cause
/// (another sweep in the folder, a case folder of other inputs, an unknown case), 1 else.
pub fn study_exit_code(e: &StudyError) -> i32 {
    match e {
        StudyError::DifferentStudy { .. }
        | StudyError::CaseFolder { .. }
        | StudyError::DuplicateCase(_)
        | StudyError::UnknownCase { .. }
        | StudyError::Bed(_)
        | StudyError::BedDoesNotFit { .. }
        | StudyError::ReplicasFromOneBed { .. } => 2,
        _ => 1,
    }
}
