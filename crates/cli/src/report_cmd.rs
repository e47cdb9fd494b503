//! `hopperflow report DIR`: builds the report of a finished study from its saved results.

use std::path::PathBuf;

use clap::Args;
use study::report::build_report;

#[derive(Args)]
pub struct ReportArgs {
    /// The study directory (holding results.csv).
    dir: PathBuf,
}

pub fn run(args: ReportArgs) -> i32 {
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
            1
        }
    }
}
