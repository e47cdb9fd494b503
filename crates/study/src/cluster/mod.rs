//! Studies on a Slurm cluster: the batch scripts of an array job with one case per task and
//! of the report job that collects them, the options they carry, their submission
//! ([`write_jobs`]) and where each case stands ([`case_statuses`]). The tasks themselves are
//! [`crate::sweep::run_task`] and [`crate::sweep::collect_study`]; the command line only
//! prints what these return.

mod jobs;
mod queue;
mod script;
mod time_limit;

pub use jobs::{case_statuses, write_jobs, CaseStanding, Jobs, JobsError};
pub use queue::{known_partitions, on_path, queued_cases, sbatch, Submission, SUBMISSIONS_FILE};
pub use script::{array_script, job_name, report_script, shell_quote, SlurmOptions};
pub use time_limit::{TimeLimit, TIME_FORMATS};
