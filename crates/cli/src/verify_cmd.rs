//! `hopperflow verify`: the verification suite of physics.md §9, one row per checked quantity.

use clap::Args;
use verify::{run_all, Resolution};

#[derive(Args)]
pub struct VerifyArgs {
    /// Print the rows as a JSON array of objects.
    #[arg(long)]
    json: bool,
    /// Run at the coarser resolution used inside `cargo test`.
    #[arg(long)]
    fast: bool,
}

pub fn run(args: VerifyArgs) -> i32 {
    let rows = run_all(if args.fast {
        Resolution::Fast
    } else {
        Resolution::Full
    });
    let failed = rows.iter().filter(|r| !r.pass).count();
    if args.json {
        match serde_json::to_string_pretty(&rows) {
            Ok(s) => println!("{s}"),
            Err(e) => {
                eprintln!("error: {e}");
                return 1;
            }
        }
    } else {
        println!(
            "{:<6} {:<44} {:>13} {:>13} {:>11} {:>5}",
            "test", "quantity", "expected", "measured", "tolerance", "pass"
        );
        for r in &rows {
            println!(
                "{:<6} {:<44} {:>13.6e} {:>13.6e} {:>11.3e} {:>5}",
                r.test,
                r.quantity,
                r.expected,
                r.measured,
                r.tolerance,
                if r.pass { "ok" } else { "FAIL" }
            );
        }
        println!("{} rows, {} failed", rows.len(), failed);
    }
    if failed > 0 {
        1
    } else {
        0
    }
}
