//! Wall pressure against height in a silo (docs/physics.md §7.7): the normal and shear
//! stress on zones of the cylinder and of the bottom, from the engine's element loads
//! (`Simulation::take_surface_loads`, §5.5), on the settled bed and in windows of the
//! discharge; and the Janssen fit of the settled bed's cylinder pressures.
//!
//! A smooth cylinder or cone books its loads in bands of equal length along its axis, each
//! a zone; a meshed wall's triangles are grouped into zones of the same height by their
//! centroid's z. A zone's pressure is its normal impulse over the window's length and the
//! zone's area; its shear stress likewise from the magnitude of the tangential impulse.

use analysis::janssen::{fit_janssen, JanssenSilo};
use dem::{Simulation, WallId, WallShape};
use serde::{Deserialize, Serialize};

use crate::WALL_NAMES;
use files::Cell;

/// Columns of `wall_pressure.csv`: the window's middle [s from the opening; the settled
/// bed's window ends at the opening], the phase, the wall, the zone's heights [m], its mean
/// normal pressure [Pa] and shear stress [Pa].
pub(crate) const PRESSURE_COLUMNS: [&str; 7] = [
    "time", "phase", "wall", "z_low", "z_high", "pressure", "shear",
];

/// One wall's zones.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct ZonedWall {
    id: WallId,
    /// Index into [`WALL_NAMES`].
    name: u8,
    /// Each element's zone.
    element_zone: Vec<u32>,
    /// Each zone's heights [m] and area [m²].
    zones: Vec<(f64, f64, f64)>,
}

/// One zone's stresses over one window.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
struct PressureRow {
    time: f64,
    settled: bool,
    wall: u8,
    zone: (f64, f64),
    pressure: f64,
    shear: f64,
}

/// The recorder, part of the checkpointed run state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WallPressureRecorder {
    walls: Vec<ZonedWall>,
    /// Discharge window [s].
    interval: f64,
    /// When the gate opened [s] (NaN before).
    opened: f64,
    /// Windows of the discharge taken so far.
    windows: u64,
    /// The last window before the opening.
    settled: Vec<PressureRow>,
    /// The discharge's windows.
    rows: Vec<PressureRow>,
}

impl WallPressureRecorder {
    /// Zones of about `zone_height` [m] on the walls `walls` (id, name index) of `sim`, which
    /// are set to book in bands where they are cylinders or cones; windows of `interval` [s]
    /// during the discharge.
    pub(crate) fn new(
        sim: &mut Simulation,
        walls: &[(u8, WallId)],
        zone_height: f64,
        interval: f64,
    ) -> Result<Self, dem::DemError> {
        let mut zoned = Vec::new();
        for &(name, id) in walls {
            let Some(wall) = sim.wall(id) else { continue };
            let z = match wall.shape() {
                WallShape::Frustum(f) => {
                    let (z0, length) = (f.base().z, f.length());
                    let bands = ((length / zone_height).ceil() as usize).max(1);
                    let zones = (0..bands)
                        .map(|k| {
                            let (a, b) = (k as f64 / bands as f64, (k + 1) as f64 / bands as f64);
                            (z0 + a * length, z0 + b * length, f.band_area(k, bands))
                        })
                        .collect();
                    let element_zone = (0..bands as u32).collect();
                    sim.set_wall_bands(id, bands)?;
                    ZonedWall {
                        id,
                        name,
                        element_zone,
                        zones,
                    }
                }
                WallShape::Mesh(m) => {
                    let centroid_z =
                        |t: usize| m.triangle(t).iter().map(|p| p.z).sum::<f64>() / 3.0;
                    let zone_of = |t: usize| (centroid_z(t) / zone_height).floor() as i64;
                    let lowest = (0..m.len()).map(zone_of).min().unwrap_or(0);
                    let highest = (0..m.len()).map(zone_of).max().unwrap_or(0);
                    let count = (highest - lowest + 1) as usize;
                    let mut zones: Vec<(f64, f64, f64)> = (0..count)
                        .map(|k| {
                            let low = (lowest + k as i64) as f64 * zone_height;
                            (low, low + zone_height, 0.0)
                        })
                        .collect();
                    let element_zone: Vec<u32> = (0..m.len())
                        .map(|t| {
                            let k = (zone_of(t) - lowest) as usize;
                            zones[k].2 += m.triangle_area(t);
                            k as u32
                        })
                        .collect();
                    // A flat ring lies in one plane: its one zone spans only that height.
                    if count == 1 {
                        let z = centroid_z(0);
                        zones[0].0 = z;
                        zones[0].1 = z;
                    }
                    ZonedWall {
                        id,
                        name,
                        element_zone,
                        zones,
                    }
                }
                _ => continue,
            };
            zoned.push(z);
        }
        for w in &zoned {
            sim.take_surface_loads(w.id)?;
        }
        Ok(Self {
            walls: zoned,
            interval,
            opened: f64::NAN,
            windows: 0,
            settled: Vec::new(),
            rows: Vec::new(),
        })
    }

    /// The stresses of every zone over the window that ends now.
    fn take(&self, sim: &mut Simulation, time: f64, settled: bool) -> Vec<PressureRow> {
        let mut rows = Vec::new();
        for w in &self.walls {
            let Ok(loads) = sim.take_surface_loads(w.id) else {
                continue;
            };
            if loads.duration <= 0.0 {
                continue;
            }
            let mut normal = vec![0.0; w.zones.len()];
            let mut shear = vec![0.0; w.zones.len()];
            for (e, load) in loads.elements.iter().enumerate() {
                if let Some(&z) = w.element_zone.get(e) {
                    normal[z as usize] += load.normal_impulse;
                    shear[z as usize] += load.shear_impulse;
                }
            }
            for (k, &(low, high, area)) in w.zones.iter().enumerate() {
                let per = loads.duration * area;
                rows.push(PressureRow {
                    time,
                    settled,
                    wall: w.name,
                    zone: (low, high),
                    pressure: normal[k] / per,
                    shear: shear[k] / per,
                });
            }
        }
        rows
    }

    /// Called at each settling check: the loads since the last one become the settled
    /// bed's window (the last before the opening is kept).
    pub(crate) fn observe_settling(&mut self, sim: &mut Simulation) {
        let t = sim.time();
        self.settled = self.take(sim, t, true);
    }

    /// The gate opens at `t` [s]: what was booked since the last settling check belongs to
    /// no window.
    pub(crate) fn open(&mut self, sim: &mut Simulation, t: f64) {
        self.opened = t;
        for w in &self.walls {
            let _ = sim.take_surface_loads(w.id);
        }
        // The settled window ends at the opening: time 0 of the discharge.
        for row in &mut self.settled {
            row.time = 0.0;
        }
    }

    /// Called after each discharge chunk: takes a window when one is due.
    pub(crate) fn observe_discharge(&mut self, sim: &mut Simulation) {
        if self.opened.is_nan() {
            return;
        }
        let since = sim.time() - self.opened;
        if since + 1e-12 < (self.windows + 1) as f64 * self.interval {
            return;
        }
        // The window's middle, from the opening.
        let middle = since - 0.5 * self.interval;
        let rows = self.take(sim, middle, false);
        self.rows.extend(rows);
        self.windows = (since / self.interval + 1e-9).floor() as u64;
    }

    /// The rows of `wall_pressure.csv`.
    pub(crate) fn table(&self) -> Vec<Vec<Cell>> {
        self.settled
            .iter()
            .chain(&self.rows)
            .map(|r| {
                vec![
                    r.time.into(),
                    Cell::Text(if r.settled { "settled" } else { "discharge" }.into()),
                    Cell::Text(WALL_NAMES[r.wall as usize].into()),
                    r.zone.0.into(),
                    r.zone.1.into(),
                    r.pressure.into(),
                    r.shear.into(),
                ]
            })
            .collect()
    }

    /// The settled window's rows of the wall named `cylinder`.
    fn settled_on_cylinder(&self) -> impl Iterator<Item = &PressureRow> {
        let cylinder = WALL_NAMES.iter().position(|n| *n == "cylinder");
        self.settled
            .iter()
            .filter(move |r| Some(usize::from(r.wall)) == cylinder)
    }

    /// The settled bed's zones of the wall named `cylinder` below its surface `bed_height`
    /// [m]: each zone's depth below the surface at its middle [m], its pressure and its shear
    /// stress [Pa], deepest last.
    pub(crate) fn settled_cylinder(&self, bed_height: f64) -> Vec<(f64, f64, f64)> {
        let mut zones: Vec<(f64, f64, f64)> = self
            .settled_on_cylinder()
            .filter(|r| r.zone.0 < bed_height)
            .map(|r| {
                let depth = bed_height - 0.5 * (r.zone.0 + r.zone.1);
                (depth, r.pressure, r.shear)
            })
            .collect();
        zones.sort_by(|a, b| a.0.total_cmp(&b.0));
        zones
    }

    /// Janssen's law fitted to the settled bed's pressures on the wall named `cylinder` of
    /// radius `radius` [m], over the zones that lie wholly between `bottom` [m] (the top of
    /// the cone) and two diameters `diameter` [m] below the bed's surface `bed_height` [m];
    /// or why there is no fit: fewer than three zones qualify, or the fit fails.
    pub(crate) fn janssen(
        &self,
        radius: f64,
        bottom: f64,
        (bed_height, diameter): (f64, f64),
        bulk_density: f64,
        gravity: f64,
    ) -> Result<files::JanssenSummary, String> {
        let top = bed_height - 2.0 * diameter;
        let (depths, pressures): (Vec<f64>, Vec<f64>) = self
            .settled_on_cylinder()
            .filter(|r| r.zone.0 >= bottom && r.zone.1 <= top)
            .map(|r| (bed_height - 0.5 * (r.zone.0 + r.zone.1), r.pressure))
            .unzip();
        if depths.len() < 3 {
            return Err(format!(
                "{} zone(s) of the cylinder lie between the cone's top (z = {:.4} m) and two \
                 diameters below the settled bed's surface (z = {:.4} m); the fit needs at \
                 least 3: a deeper bed gives them",
                depths.len(),
                bottom,
                top
            ));
        }
        let silo = JanssenSilo::cylinder(radius, bulk_density, gravity)
            .map_err(|e| format!("the silo's parameters are refused: {e}"))?;
        let fit = fit_janssen(&depths, &pressures, None, &silo).map_err(|e| {
            format!(
                "the fit of {} zones from depth {:.4} m to {:.4} m failed: {e}",
                depths.len(),
                depths.iter().cloned().fold(f64::INFINITY, f64::min),
                depths.iter().cloned().fold(0.0, f64::max)
            )
        })?;
        let pair = |e: analysis::Estimate| [e.value, e.standard_error];
        Ok(files::JanssenSummary {
            saturation_pressure: pair(fit.saturation_pressure),
            k_mu: pair(fit.k_mu),
            wall_friction: pair(fit.wall_friction),
            stress_ratio: pair(fit.stress_ratio),
            zones: depths.len(),
        })
    }
}
