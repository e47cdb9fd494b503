//! The loads the particles exert on the hopper's walls, averaged over windows of the run:
//! what `wall_forces.csv` holds.
//!
//! The engine integrates each wall's load over every step of the fill, the settling and the
//! discharge ([`dem::Simulation::wall_impulse`]); a window's mean load is the difference of
//! two readings over the time between them, so the run reads the walls only where it looks
//! at the bodies anyway (after each chunk of the fill and settling, at each outlet check of
//! the discharge) and its steps stay those of a plain run. A window holds
//! `measure.rate_bin_width` of simulated time: it ends at the first look at or after that
//! span; the windows run from the start of the run, one ends early when the gate opens, and
//! from then on they start at the opening, on the bins of the discharge rate W(t) in
//! `flow.csv` (the outlet checks divide the bins). The last window of the run ends with the
//! run and may be shorter.
//!
//! Only walls that sum their load ([`dem::Wall::sums_load`]) are recorded: the side walls,
//! the bottom plates and, while it is closed, the gate; not the front and back faces.

use dem::{WallId, WallLoad, Watched};
use serde::{Deserialize, Serialize};

use crate::ContainerWalls;
use files::Cell;

/// Columns of `wall_forces.csv`; units in the module's and the docs' description.
pub(crate) const WALL_FORCE_COLUMNS: [&str; 8] =
    ["time", "wall", "fx", "fy", "fz", "tx", "ty", "tz"];

/// One finished window of one wall.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
struct WallForceRow {
    /// Middle of the window [s from the start of the run].
    time: f64,
    /// Index into the case's wall names (`crate::wall_names`).
    wall: u8,
    /// Mean force [N] then mean torque about the origin [N m] over the window's steps.
    load: [f64; 6],
}

/// The windows of wall loads of a run so far: the finished rows and where the open window
/// began. Part of the checkpointed run state, so that a resumed run writes the same file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WallForceRecorder {
    /// Steps of a whole window.
    window_steps: u64,
    /// The walls recorded: index into the case's wall names and the engine's id.
    walls: Vec<(u8, WallId)>,
    /// Finished rows, in time order and, within a window, in the order of `walls`.
    rows: Vec<WallForceRow>,
    /// The open window: its start [s] and step, the last look's time [s].
    start: f64,
    start_step: u64,
    end: f64,
    /// Each wall's impulse (force [N s], torque [N m s]) when the open window began, and the
    /// last look's (`None` once the wall is gone: the gate leaves only when a window ends).
    at_start: Vec<Option<[f64; 6]>>,
    at_end: Vec<Option<[f64; 6]>>,
}

impl WallForceRecorder {
    /// A recorder for the walls of `walls` that sum their load in `sim`, with windows of
    /// `window` [s] at steps of `dt` [s] (at least one step).
    pub(crate) fn new(sim: &dem::Simulation, walls: &ContainerWalls, window: f64, dt: f64) -> Self {
        let walls: Vec<(u8, WallId)> = walls
            .named()
            .into_iter()
            .filter_map(|(k, id)| Some((k, id?)))
            .filter(|(_, id)| sim.wall(*id).is_some_and(|w| w.sums_load))
            .collect();
        let start = sim.watched();
        let at_start: Vec<Option<[f64; 6]>> = walls
            .iter()
            .map(|(_, id)| start.wall_impulse(*id).map(|l| numbers(&l)))
            .collect();
        Self {
            window_steps: (window / dt).round().max(1.0) as u64,
            walls,
            rows: Vec::new(),
            start: sim.time(),
            start_step: sim.steps(),
            end: sim.time(),
            at_end: at_start.clone(),
            at_start,
        }
    }

    /// Reads the walls' impulses at the step `seen` shows (`step` of the run); ends the
    /// window when it is whole.
    pub(crate) fn observe(&mut self, seen: &Watched<'_>, step: u64) {
        for ((_, id), end) in self.walls.iter().zip(&mut self.at_end) {
            *end = seen.wall_impulse(*id).map(|l| numbers(&l));
        }
        self.end = seen.time();
        if step >= self.start_step + self.window_steps {
            self.close(step);
        }
    }

    /// Ends the open window at the last look, `step` of the run (when the gate opens, after
    /// an [`WallForceRecorder::observe`] of that step): its rows are kept, and the next
    /// window starts there.
    pub(crate) fn close(&mut self, step: u64) {
        let rows: Vec<WallForceRow> = self.open_rows().collect();
        self.rows.extend(rows);
        self.start = self.end;
        self.start_step = step;
        self.at_start.clone_from(&self.at_end);
    }

    /// The rows of the open window: one per wall present at both of its ends, the mean load
    /// the difference of the impulses over the window's length.
    fn open_rows(&self) -> impl Iterator<Item = WallForceRow> + '_ {
        let time = 0.5 * (self.start + self.end);
        let span = self.end - self.start;
        self.walls
            .iter()
            .zip(self.at_start.iter().zip(&self.at_end))
            .filter(move |_| span > 0.0)
            .filter_map(move |((wall, _), (a, b))| {
                let (a, b) = (a.as_ref()?, b.as_ref()?);
                Some(WallForceRow {
                    time,
                    wall: *wall,
                    load: std::array::from_fn(|k| (b[k] - a[k]) / span),
                })
            })
    }

    /// The table of `wall_forces.csv`: the finished windows and the open one, each wall
    /// under its name in `names` (`crate::wall_names`).
    pub(crate) fn table(&self, names: &[String]) -> Vec<Vec<Cell>> {
        self.rows
            .iter()
            .copied()
            .chain(self.open_rows())
            .map(|r| {
                let mut row: Vec<Cell> =
                    vec![r.time.into(), Cell::Text(names[r.wall as usize].clone())];
                row.extend(r.load.iter().map(|&v| Cell::from(v)));
                row
            })
            .collect()
    }
}

/// A load's six numbers: force, then torque.
fn numbers(load: &WallLoad) -> [f64; 6] {
    [
        load.force.x,
        load.force.y,
        load.force.z,
        load.torque.x,
        load.torque.y,
        load.torque.z,
    ]
}
