//! The orientation of shaped grains (docs/physics.md §11.8): each grain's long axis (its
//! principal axis of least inertia) in the settled bed at the opening, and as it crosses the
//! orifice plane inside the outlet (counted once, as W counts it); their alignment with the
//! vertical and nematic order (`analysis::orientation`), and `orientations.csv` of the bed.

use dem::{DVec3, Watched};
use files::{AxesStatistics, Cell, OrientationSummary};
use measure::CrossingEvent;
use serde::{Deserialize, Serialize};

/// Columns of `orientations.csv`: each grain of the settled bed at the opening, its id (its
/// first member's), centre of mass [m] and long axis (a unit vector, sign arbitrary).
pub(crate) const ORIENTATION_COLUMNS: [&str; 7] = ["id", "x", "y", "z", "ux", "uy", "uz"];

/// The long axes recorded over a run of shaped grains; in checkpoints, so that a resumed run
/// measures what an uninterrupted one does.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub(crate) struct OrientationRecorder {
    /// The settled bed's grains at the opening: id, centre of mass [m], long axis.
    bed: Vec<(u64, [f64; 3], [f64; 3])>,
    /// The long axis of each grain crossing the orifice inside the outlet, in crossing
    /// order.
    outlet: Vec<[f64; 3]>,
}

/// Each clump's id (its first member's tag), centre of mass [m] and long axis in the world
/// frame: the first principal axis, whose moment is the least.
fn clump_axes(seen: &Watched<'_>) -> Vec<(u64, DVec3, DVec3)> {
    let clumps = seen.clumps();
    (0..clumps.len())
        .map(|c| {
            (
                clumps.first_tags()[c],
                clumps.positions()[c],
                clumps.orientations()[c] * DVec3::X,
            )
        })
        .collect()
}

impl OrientationRecorder {
    /// Records the settled bed's grains at the opening.
    pub(crate) fn record_bed(&mut self, seen: &Watched<'_>) {
        self.bed = clump_axes(seen)
            .into_iter()
            .map(|(id, x, u)| (id, x.to_array(), u.to_array()))
            .collect();
    }

    /// Records the long axes of the grains among `events` (the crossings just found) that
    /// crossed inside the outlet, looked up among the clumps `seen` now by their first tag.
    pub(crate) fn record_crossings(&mut self, events: &[CrossingEvent], seen: &Watched<'_>) {
        let clumps = seen.clumps();
        for e in events.iter().filter(|e| e.inside_outlet) {
            if let Some(c) = clumps.first_tags().iter().position(|&tag| tag == e.id) {
                self.outlet
                    .push((clumps.orientations()[c] * DVec3::X).to_array());
            }
        }
    }

    /// The summary's statistics.
    pub(crate) fn summary(&self) -> OrientationSummary {
        let bed: Vec<[f64; 3]> = self.bed.iter().map(|(_, _, u)| *u).collect();
        OrientationSummary {
            bed: statistics(&bed),
            outlet: statistics(&self.outlet),
        }
    }

    /// The rows of `orientations.csv`.
    pub(crate) fn bed_rows(&self) -> Vec<Vec<Cell>> {
        self.bed
            .iter()
            .map(|(id, x, u)| {
                vec![
                    Cell::Text(id.to_string()),
                    x[0].into(),
                    x[1].into(),
                    x[2].into(),
                    u[0].into(),
                    u[1].into(),
                    u[2].into(),
                ]
            })
            .collect()
    }
}

/// Alignment with the vertical and nematic order of `axes`; `None` for no axes.
fn statistics(axes: &[[f64; 3]]) -> Option<AxesStatistics> {
    let vertical = analysis::orientation::alignment(axes, [0.0, 0.0, 1.0])?;
    let order = analysis::orientation::nematic_order(axes)?;
    Some(AxesStatistics {
        grains: axes.len(),
        vertical_alignment: vertical,
        nematic_order: order.order,
        director: order.director,
    })
}
