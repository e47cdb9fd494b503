//! Residence times (docs/physics.md §7.15): each grain's place in the bed at the opening,
//! joined at the end with its crossing of the outlet, gives `residence.csv` and the summary's
//! `residence` (`analysis::residence`).

use std::collections::HashMap;

use dem::Watched;
use files::{Cell, ResidenceSummary};
use measure::CrossingRecord;
use serde::{Deserialize, Serialize};

/// Columns of `residence.csv`: each grain of the bed at the opening, its id (a clump's first
/// member's tag), its centre (of mass) then [m], and its residence time from the opening to
/// its crossing of the outlet [s], NaN for a grain that did not leave.
pub(crate) const RESIDENCE_COLUMNS: [&str; 5] = ["id", "x_m", "y_m", "z_m", "residence_s"];

/// The bed at the opening; in checkpoints and saved beds, so that a resumed run measures what
/// an uninterrupted one does.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub(crate) struct OpeningRecord {
    /// Each grain: id and centre [m], in the engine's order at the opening.
    grains: Vec<(u64, [f64; 3])>,
}

impl OpeningRecord {
    /// Records every grain of the bed as the gate opens.
    pub(crate) fn record(&mut self, seen: &Watched<'_>) {
        let bodies = seen.bodies(|_| true);
        self.grains = bodies
            .tags
            .iter()
            .zip(&bodies.positions)
            .map(|(&id, x)| (id, x.to_array()))
            .collect();
    }

    /// Whether a bed was recorded (a run that opened a gate).
    pub(crate) fn is_empty(&self) -> bool {
        self.grains.is_empty()
    }

    /// Each grain's residence time [s] from the opening at `opened` [s] to its first
    /// downward crossing of the outlet in `record`; NaN where it has none.
    fn times(&self, record: &CrossingRecord, opened: f64) -> Vec<f64> {
        let mut crossed: HashMap<u64, f64> = HashMap::with_capacity(record.events.len());
        for e in &record.events {
            crossed.entry(e.id).or_insert(e.time - opened);
        }
        self.grains
            .iter()
            .map(|(id, _)| crossed.get(id).copied().unwrap_or(f64::NAN))
            .collect()
    }

    /// The rows of `residence.csv` and the summary's statistics (`None` where no grain
    /// left).
    pub(crate) fn table(
        &self,
        record: &CrossingRecord,
        opened: f64,
    ) -> (Vec<Vec<Cell>>, Option<ResidenceSummary>) {
        let times = self.times(record, opened);
        let rows = self
            .grains
            .iter()
            .zip(&times)
            .map(|((id, x), &t)| {
                vec![
                    Cell::Text(id.to_string()),
                    x[0].into(),
                    x[1].into(),
                    x[2].into(),
                    t.into(),
                ]
            })
            .collect();
        let heights: Vec<f64> = self.grains.iter().map(|(_, x)| x[2]).collect();
        let summary =
            analysis::residence::residence_statistics(&heights, &times).map(|s| ResidenceSummary {
                grains: s.grains,
                left: s.left,
                mean: s.mean,
                quantiles: s.quantiles,
                fifo_index: s.fifo_index,
            });
        (rows, summary)
    }
}
