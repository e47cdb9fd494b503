//! How finely the verification cases are resolved in time.

use serde::{Deserialize, Serialize};

/// The time resolution of a verification run.
///
/// `Full` is what `hopperflow verify` runs: 2000 steps per contact for the impact cases
/// (docs/physics.md §9 asks ≥ 100 and takes its model-reference numbers at ≥ 3000) and the
/// production Δt = 2.5 µs for the sliding/rolling cases. `Fast` is for `cargo test`: 1000
/// steps per contact and shorter observation windows where a case allows it.
///
/// Why not coarser: the scheme is first order in the dashpot (half-step velocities, §2.3), and
/// the engine's lever R − δ/2 (the Appendix-B reference uses R) already costs the CO-T Table-1
/// sliding line 0.011 of its 0.02 tolerance at V_n = 1 m/s. At 200 steps per contact that line
/// sits 0.030 off and CO5's tan θ_r at 70° 1.04 % off (tolerance 1 %); at 1000 steps both pass.
/// The impact cases are cheap (a single contact), so the whole fast suite still runs in about a second.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Resolution {
    /// The resolution of the reported verification table.
    Full,
    /// A coarser resolution for the automated tests.
    Fast,
}

impl Resolution {
    /// Time steps per elastic Hertz contact duration for the impact cases [-].
    pub fn steps_per_contact(self) -> f64 {
        match self {
            Resolution::Full => 2000.0,
            Resolution::Fast => 1000.0,
        }
    }
}
