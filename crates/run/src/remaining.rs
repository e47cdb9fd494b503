//! The particles left in the container against time, N(t): the benchmark silo's output
//! (Dosta et al. 2024 count the centres above the orifice plane every 0.01 s), recorded for
//! every kind of container.

use dem::Watched;
use serde::{Deserialize, Serialize};

use files::Cell;

/// Columns of `remaining.csv`: time since the gate opened [s], the particles whose centre is
/// above the orifice plane, and their mass [kg].
pub(crate) const REMAINING_COLUMNS: [&str; 3] = ["time", "particles", "mass"];

/// N(t) sampled at the first look at or after each multiple of `interval` from the opening.
/// Part of the checkpointed run state, so that a resumed run writes the same file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RemainingRecorder {
    /// Time between samples [s].
    interval: f64,
    /// When the gate opened [s] (NaN before).
    opened: f64,
    /// Samples taken so far.
    samples: u64,
    /// Rows: time since the opening [s], particles, mass [kg].
    rows: Vec<(f64, u64, f64)>,
}

impl RemainingRecorder {
    /// A recorder sampling every `interval` [s] once the gate opens.
    pub(crate) fn new(interval: f64) -> Self {
        Self {
            interval,
            opened: f64::NAN,
            samples: 0,
            rows: Vec::new(),
        }
    }

    /// Starts the samples at the gate's opening, time `t` [s].
    pub(crate) fn open(&mut self, t: f64) {
        self.opened = t;
    }

    /// Takes a sample if one is due at the time `seen` shows.
    pub(crate) fn observe(&mut self, seen: &Watched<'_>) {
        if self.opened.is_nan() {
            return;
        }
        let since = seen.time() - self.opened;
        // Sample k is due at k·interval; the product, not a running sum, keeps long runs
        // on their grid.
        if since + 1e-12 < self.samples as f64 * self.interval {
            return;
        }
        // Grains by their centre (of mass), a clump's mass once.
        let above = seen.bodies(|x| x.z > 0.0);
        let (count, mass) = (above.len() as u64, above.masses.iter().sum::<f64>());
        self.rows.push((since, count, mass));
        // The next sample is the first multiple of the interval after this look.
        self.samples = (since / self.interval + 1e-9).floor() as u64 + 1;
    }

    /// The rows of `remaining.csv`; with `grains_per_parcel` (κ³ of coarse-grained parcels)
    /// a fourth column, the grains the parcels stand for.
    pub(crate) fn table(&self, grains_per_parcel: Option<f64>) -> Vec<Vec<Cell>> {
        self.rows
            .iter()
            .map(|&(t, n, m)| {
                let mut row = vec![t.into(), (n as f64).into(), m.into()];
                if let Some(k3) = grains_per_parcel {
                    row.push((n as f64 * k3).into());
                }
                row
            })
            .collect()
    }
}
