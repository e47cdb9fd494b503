//! `hopperflow report DIR`: builds the report of a finished study, or of a calibration, from
//! its saved results.
//!
//! Exit status: 0 when the report is written; 2 when DIR holds no study (bad input: no
//! `results.csv` there); 1 when the study cannot be read or the report cannot be written.

use std::path::PathBuf;

use clap::Args;
use report::{build_report, ReportError};

use crate::exit_codes::EXIT_BAD_INPUT;

#[derive(Args)]
pub struct ReportArgs {
    /// The study directory (holding results.csv), or a calibration's (holding
    /// calibration.json).
    dir: PathBuf,
}

pub fn run(args: ReportArgs) -> i32 {
    if report::is_calibration(&args.dir) {
        return match report::build_calibration_report(&args.dir) {
            Ok(files) => {
                println!("report:     {}", files.markdown.display());
                println!("html:       {}", files.html.display());
                println!("figures:    {} files", files.figures.len());
                0
            }
            Err(e) => {
                eprintln!("error: {e}");
                1
            }
        };
    }
    match build_report(&args.dir) {
        Ok(files) => {
            println!("report:     {}", files.markdown.display());
            println!("html:       {}", files.html.display());
            println!("comparison: {}", files.comparison.display());
            println!("figures:    {} files", files.figures.len());
            0
        }
        Err(e) => {
            eprintln!("error: {e}");
            match e {
                ReportError::NoStudy { .. } => EXIT_BAD_INPUT,
                _ => 1,
            }
        }
    }
}
