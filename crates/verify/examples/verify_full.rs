//! Prints the verification table at full resolution (what `hopperflow verify` reports).
//!
//! Run with `cargo run -p hopperflow-verify --release --example verify_full`.

use verify::{run_all, Resolution};

fn main() {
    let rows = run_all(Resolution::Full);
    println!(
        "{:<6} {:<92} {:>13} {:>13} {:>10} pass",
        "test", "quantity", "expected", "measured", "tolerance"
    );
    for r in &rows {
        println!(
            "{:<6} {:<92} {:>13.6e} {:>13.6e} {:>10.3e} {}",
            r.test,
            r.quantity,
            r.expected,
            r.measured,
            r.tolerance,
            if r.pass { "yes" } else { "NO" }
        );
    }
    let failed = rows.iter().filter(|r| !r.pass).count();
    println!("{} rows, {} failed", rows.len(), failed);
    if failed > 0 {
        std::process::exit(1);
    }
}
