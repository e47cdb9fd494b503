//! Studies on a Slurm cluster: the batch scripts of an array job with one case per task and
//! of the report job that collects them, and the options they carry. Submitting and asking
//! the queue are the command line's business; the tasks themselves are
//! [`crate::sweep::run_task`] and [`crate::sweep::collect_study`].

mod script;
mod time_limit;

pub use script::{array_script, job_name, report_script, shell_quote, SlurmOptions};
pub use time_limit::{TimeLimit, TIME_FORMATS};
