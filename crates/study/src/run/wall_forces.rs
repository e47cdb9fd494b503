//! The loads the particles exert on the hopper's walls, averaged over windows of the run:
//! what `wall_forces.csv` holds.
//!
//! Every step of the fill, the settling and the discharge adds the engine's load of that
//! step on each wall ([`dem::Simulation::wall_load`]) to the open window. A window holds
//! `measure.rate_bin_width` of simulated time (rounded to whole steps); the windows run
//! from the start of the run, one ends early when the gate opens, and from then on they
//! start at the opening, on the bins of the discharge rate W(t) in `flow.csv`. A window's
//! row holds the mean load over its steps. The last window of the run ends with the run
//! and may be shorter.
//!
//! Only walls that sum their load ([`dem::Wall::sums_load`]) are recorded: the side walls,
//! the bottom plates and, while it is closed, the gate; not the front and back faces.

use dem::{WallId, WallLoad, Watched};
use serde::{Deserialize, Serialize};

use crate::hopper::HopperWalls;
use crate::output::Cell;

/// Columns of `wall_forces.csv`; units in the module's and the docs' description.
pub(crate) const WALL_FORCE_COLUMNS: [&str; 8] =
    ["time", "wall", "fx", "fy", "fz", "tx", "ty", "tz"];

/// A hopper wall's name in `wall_forces.csv`.
const NAMES: [&str; 5] = ["left", "right", "plate_left", "plate_right", "gate"];

/// One finished window of one wall.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
struct WallForceRow {
    /// Middle of the window [s from the start of the run].
    time: f64,
    /// Index into [`NAMES`].
    wall: u8,
    /// Mean force [N] then mean torque about the origin [N m] over the window's steps.
    load: [f64; 6],
}

/// The windows of wall loads of a run so far: the finished rows and the open window. Part
/// of the checkpointed run state, so that a resumed run writes the same file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WallForceRecorder {
    /// Steps of a whole window.
    window_steps: u64,
    /// The walls recorded: index into [`NAMES`] and the engine's id.
    walls: Vec<(u8, WallId)>,
    /// Finished rows, in time order and, within a window, in the order of `walls`.
    rows: Vec<WallForceRow>,
    /// The open window: its start [s], its last step's time [s], its steps.
    start: f64,
    end: f64,
    steps: u64,
    /// The open window's sums of force [N] and torque [N m] per entry of `walls`, and the
    /// steps each wall was present in (the gate leaves only when a window ends).
    sums: Vec<[f64; 6]>,
    present: Vec<u64>,
}

impl WallForceRecorder {
    /// A recorder for the walls of `walls` that sum their load in `sim`, with windows of
    /// `window` [s] at steps of `dt` [s] (at least one step).
    pub(crate) fn new(sim: &dem::Simulation, walls: &HopperWalls, window: f64, dt: f64) -> Self {
        let named = [
            Some(walls.sides[0]),
            Some(walls.sides[1]),
            walls.plates[0],
            walls.plates[1],
            Some(walls.gate),
        ];
        let walls: Vec<(u8, WallId)> = named
            .iter()
            .enumerate()
            .filter_map(|(k, id)| Some((k as u8, (*id)?)))
            .filter(|(_, id)| sim.wall(*id).is_some_and(|w| w.sums_load))
            .collect();
        let n = walls.len();
        Self {
            window_steps: (window / dt).round().max(1.0) as u64,
            walls,
            rows: Vec::new(),
            start: sim.time(),
            end: sim.time(),
            steps: 0,
            sums: vec![[0.0; 6]; n],
            present: vec![0; n],
        }
    }

    /// Adds the loads of the step `seen` shows; ends the window when it is whole.
    pub(crate) fn observe(&mut self, seen: &Watched<'_>) {
        for (k, (_, id)) in self.walls.iter().enumerate() {
            if let Some(load) = seen.wall_load(*id) {
                add(&mut self.sums[k], &load);
                self.present[k] += 1;
            }
        }
        self.steps += 1;
        self.end = seen.time();
        if self.steps >= self.window_steps {
            self.close();
        }
    }

    /// Ends the open window (when the gate opens): its rows are kept, and the next window
    /// starts at its end.
    pub(crate) fn close(&mut self) {
        let rows: Vec<WallForceRow> = self.open_rows().collect();
        self.rows.extend(rows);
        self.start = self.end;
        self.steps = 0;
        self.sums.iter_mut().for_each(|s| *s = [0.0; 6]);
        self.present.iter_mut().for_each(|p| *p = 0);
    }

    /// The rows of the open window: one per wall present in any of its steps.
    fn open_rows(&self) -> impl Iterator<Item = WallForceRow> + '_ {
        let time = 0.5 * (self.start + self.end);
        self.walls
            .iter()
            .zip(&self.sums)
            .zip(&self.present)
            .filter(|(_, &n)| n > 0)
            .map(move |(((wall, _), sum), &n)| WallForceRow {
                time,
                wall: *wall,
                load: sum.map(|s| s / n as f64),
            })
    }

    /// The table of `wall_forces.csv`: the finished windows and the open one.
    pub(crate) fn table(&self) -> Vec<Vec<Cell>> {
        self.rows
            .iter()
            .copied()
            .chain(self.open_rows())
            .map(|r| {
                let mut row: Vec<Cell> =
                    vec![r.time.into(), Cell::Text(NAMES[r.wall as usize].into())];
                row.extend(r.load.iter().map(|&v| Cell::from(v)));
                row
            })
            .collect()
    }
}

/// Adds a step's load to a window's sums.
fn add(sum: &mut [f64; 6], load: &WallLoad) {
    let values = [
        load.force.x,
        load.force.y,
        load.force.z,
        load.torque.x,
        load.torque.y,
        load.torque.z,
    ];
    for (s, v) in sum.iter_mut().zip(values) {
        *s += v;
    }
}
