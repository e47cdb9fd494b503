//! Outlet crossings: discharge rate W(t) and the crossing velocity profile v(x) (docs/physics.md §7.1–7.2).
//!
//! The paper records "the vertical component v … as the particle passes through the aperture".
//! Each downward crossing of z = z_o by a particle centre between two consecutive observations
//! becomes an event; time, x and v_z at the crossing are linearly interpolated between the two
//! observations (a particle moves < 4 µm per step, so observing every k ≤ 100 steps is fine).
//! Events are kept, so the steady window is chosen after the run.
//!
//! Sign convention: v_z < 0 downward. Every *reported* speed is the downward speed −v_z > 0.

use std::collections::HashMap;

use serde::{Deserialize, Serialize};

use super::block_error::{BlockSums, ERROR_BLOCKS};
use super::error::MeasureError;
use super::geometry::{OutletBins, OutletGeometry};
use super::snapshot::{Snapshot, TimeWindow};

/// Default width of the time bins of W(t) [s]: docs/physics.md §7 asks for 0.02–0.05 s bins; the
/// short end keeps the rising and falling phases visible for a silo that empties in < 1 s.
pub const DEFAULT_DISCHARGE_BIN_WIDTH: f64 = 0.02;

/// One downward crossing of the outlet line by a particle centre.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CrossingEvent {
    /// Interpolated crossing time [s].
    pub time: f64,
    /// Interpolated horizontal position at the crossing [m].
    pub x: f64,
    /// Interpolated vertical velocity at the crossing [m/s] (negative downward).
    pub velocity_z: f64,
    /// Particle mass [kg].
    pub mass: f64,
    /// Whether the crossing lies within the orifice: x within [x_c − R, x_c + R] for a
    /// slot, (x, y) within R of the centre for a circular orifice.
    pub inside_outlet: bool,
    /// Interpolated horizontal velocity at the crossing [m/s].
    pub velocity_x: f64,
    /// Particle radius [m].
    pub radius: f64,
    /// The particle's stable identifier.
    pub id: u64,
    /// Interpolated position across the slab, or the second horizontal coordinate of a
    /// silo, at the crossing [m].
    #[serde(default)]
    pub y: f64,
}

/// A count of crossings and the mass they carried.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct CrossingTally {
    /// Number of crossings.
    pub count: u64,
    /// Mass carried [kg].
    pub mass: f64,
}

/// Everything the crossing probe recorded; serialisable, and analysed after the run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CrossingRecord {
    /// The outlet observed.
    pub geometry: OutletGeometry,
    /// Time of the first observation [s], if any.
    pub first_time: Option<f64>,
    /// Time of the last observation [s], if any.
    pub last_time: Option<f64>,
    /// Downward crossings in time order (inside and outside the orifice span).
    pub events: Vec<CrossingEvent>,
    /// Upward crossings (particles bouncing back through the line); not stored as events, so
    /// that W counts downward mass as docs/physics.md §7.1 says, but tallied to show they are rare.
    pub upward: CrossingTally,
}

/// Mean downward speed at the crossing in one x-bin.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ProfileBin {
    /// Bin centre in x* (dimensionless).
    pub x_star: f64,
    /// Bin centre in x [m].
    pub x: f64,
    /// Number of crossings in the bin and window.
    pub count: u64,
    /// Mean downward speed −v_z over the crossings [m/s]; `None` without crossings.
    pub mean_speed: Option<f64>,
    /// Standard error of that mean [m/s], from the spread between the window's time blocks
    /// (crossings come in clusters, so s/√n would understate it; see `block_error`);
    /// `None` unless two blocks saw crossings.
    pub standard_error: Option<f64>,
}

/// The crossing velocity profile v(x) over a window (flux-weighted, docs/physics.md §7.2:
/// ⟨v⟩_cross = ⟨v²⟩/⟨v⟩, 1–4 % above the snapshot mean).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VelocityProfile {
    /// Averaging window.
    pub window: TimeWindow,
    /// The x-bins.
    pub bins: OutletBins,
    /// One entry per bin, left to right.
    pub entries: Vec<ProfileBin>,
}

impl VelocityProfile {
    /// Centre speed v_c [m/s]: the mean of the central bins' speeds (see
    /// [`OutletBins::central_bins`]); `None` if none of them saw a crossing.
    pub fn centre_speed(&self) -> Option<f64> {
        mean_of(
            self.bins
                .central_bins()
                .into_iter()
                .filter_map(|i| self.entries[i].mean_speed),
        )
    }
}

/// Area fraction at the outlet from the number density of centres crossing it, per x-bin
/// (a second definition of φ(x) beside the strip's area fraction, physics spec §7.3).
///
/// Centres of areal number density n(x) falling at v(x) cross a length Δx of the outlet
/// line n v Δx times per unit time, so n = Σ 1/|v_z| / (T Δx) over the crossings of a
/// window of duration T, and with each centre's mid-plane disc π r² the area fraction is
/// φ_n = Σ π r²/|v_z| / (T Δx). It counts each grain once, at its centre, where the strip
/// spreads a grain's disc over the bins it covers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CrossingDensityProfile {
    /// Averaging window.
    pub window: TimeWindow,
    /// The x-bins.
    pub bins: OutletBins,
    /// φ_n per bin [-]; `None` without crossings.
    pub area_fraction: Vec<Option<f64>>,
    /// Standard error per bin [-]: the spread of the [`ERROR_BLOCKS`] equal time blocks'
    /// own φ_n over √(blocks) (empty blocks count as zero, as a rate should); `None`
    /// without crossings.
    pub standard_error: Vec<Option<f64>>,
}

/// Mass discharged per time bin.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DischargeSeries {
    /// Bin width [s].
    pub bin_width: f64,
    /// Start of the first bin: the first observation [s].
    pub start_time: f64,
    /// Bin centres [s].
    pub times: Vec<f64>,
    /// Mass crossing downward in each bin [kg].
    pub mass: Vec<f64>,
    /// Discharge rate W in each bin, mass / bin width [kg/s].
    pub rate: Vec<f64>,
    /// Cumulative discharged mass at the end of each bin [kg].
    pub cumulative_mass: Vec<f64>,
}

pub(crate) fn mean_of(values: impl Iterator<Item = f64>) -> Option<f64> {
    let (mut sum, mut n) = (0.0, 0usize);
    for v in values {
        sum += v;
        n += 1;
    }
    (n > 0).then(|| sum / n as f64)
}

impl CrossingRecord {
    /// Crossings whose x fell outside the orifice span (should be ~0: a centre at z_o
    /// outside the span would overlap the bottom plate).
    pub fn outside_outlet(&self) -> CrossingTally {
        let mut tally = CrossingTally::default();
        for e in self.events.iter().filter(|e| !e.inside_outlet) {
            tally.count += 1;
            tally.mass += e.mass;
        }
        tally
    }

    /// Total downward mass recorded [kg].
    pub fn discharged_mass(&self) -> f64 {
        self.events.iter().map(|e| e.mass).sum()
    }

    /// Downward mass crossing before time `t` [s] [kg].
    pub fn discharged_mass_before(&self, t: f64) -> f64 {
        self.events
            .iter()
            .filter(|e| e.time < t)
            .map(|e| e.mass)
            .sum()
    }

    /// Earliest crossing time [s] at which the cumulative discharged mass reaches `mass` [kg].
    pub fn time_when_discharged(&self, mass: f64) -> Result<f64, MeasureError> {
        let mut cumulative = 0.0;
        for e in &self.events {
            cumulative += e.mass;
            if cumulative >= mass {
                return Ok(e.time);
            }
        }
        Err(MeasureError::MassNotReached {
            mass,
            recorded: cumulative,
        })
    }

    /// Window between the moments `lower_mass` and `upper_mass` [kg] have been discharged, e.g.
    /// 15 % and 70 % of the initial load (docs/physics.md §7, steady window). Check the plateau of
    /// [`Self::discharged_mass_series`] before trusting it.
    pub fn window_between_discharged_masses(
        &self,
        lower_mass: f64,
        upper_mass: f64,
    ) -> Result<TimeWindow, MeasureError> {
        let start = self.time_when_discharged(lower_mass)?;
        let end = self.time_when_discharged(upper_mass)?;
        TimeWindow::new(start, end)
    }

    /// Mean discharge rate W over `window`: downward mass crossing in it / its duration [kg/s].
    pub fn mean_discharge_rate(&self, window: TimeWindow) -> f64 {
        self.window_mass(window, |_| true) / window.duration()
    }

    /// Like [`Self::mean_discharge_rate`], counting only crossings inside the orifice span [kg/s].
    pub fn mean_discharge_rate_inside(&self, window: TimeWindow) -> f64 {
        self.window_mass(window, |e| e.inside_outlet) / window.duration()
    }

    fn window_mass(&self, window: TimeWindow, keep: impl Fn(&CrossingEvent) -> bool) -> f64 {
        self.events
            .iter()
            .filter(|e| window.contains(e.time) && keep(e))
            .map(|e| e.mass)
            .sum()
    }

    /// W(t): downward mass per bin of `bin_width` [s] from the first to the last observation.
    pub fn discharged_mass_series(&self, bin_width: f64) -> Result<DischargeSeries, MeasureError> {
        if !(bin_width.is_finite() && bin_width > 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "bin_width",
                value: bin_width,
                reason: "must be finite and positive",
            });
        }
        let (start, end) = match (self.first_time, self.last_time) {
            (Some(s), Some(e)) => (s, e),
            _ => (0.0, 0.0),
        };
        // A span that is a whole number of bins up to round-off gets no extra empty bin.
        let count = (((end - start) / bin_width - 1e-9).ceil() as usize).max(1);
        let mut mass = vec![0.0; count];
        for e in &self.events {
            let k = (((e.time - start) / bin_width).floor().max(0.0) as usize).min(count - 1);
            mass[k] += e.mass;
        }
        let times = (0..count)
            .map(|k| start + (k as f64 + 0.5) * bin_width)
            .collect();
        let rate = mass.iter().map(|m| m / bin_width).collect();
        let cumulative_mass = mass
            .iter()
            .scan(0.0, |acc, m| {
                *acc += m;
                Some(*acc)
            })
            .collect();
        Ok(DischargeSeries {
            bin_width,
            start_time: start,
            times,
            mass,
            rate,
            cumulative_mass,
        })
    }

    /// Mean downward speed at the crossing per x*-bin over the crossings in `window`.
    pub fn velocity_profile(&self, window: TimeWindow, bins: &OutletBins) -> VelocityProfile {
        let mut sum = vec![0.0; bins.count];
        let mut count = vec![0u64; bins.count];
        let mut blocks = BlockSums::new(bins.count, window);
        for e in self.events.iter().filter(|e| window.contains(e.time)) {
            if let Some(i) = bins.index_of(e.x) {
                let speed = -e.velocity_z;
                sum[i] += speed;
                count[i] += 1;
                blocks.add(i, e.time, speed);
            }
        }
        let entries = (0..bins.count)
            .map(|i| {
                let mean = (count[i] > 0).then(|| sum[i] / count[i] as f64);
                let standard_error = mean.and_then(|m| blocks.standard_error(i, m));
                ProfileBin {
                    x_star: bins.x_star_centre(i),
                    x: bins.x_centre(i),
                    count: count[i],
                    mean_speed: mean,
                    standard_error,
                }
            })
            .collect();
        VelocityProfile {
            window,
            bins: *bins,
            entries,
        }
    }
}

impl CrossingRecord {
    /// φ_n(x), the area fraction from the number density of centres crossing the outlet
    /// line over `window` (see [`CrossingDensityProfile`]). Crossings with v_z = 0 cannot
    /// occur (a centre that crosses moves), but one would add nothing rather than ∞.
    pub fn crossing_density_profile(
        &self,
        window: TimeWindow,
        bins: &OutletBins,
    ) -> CrossingDensityProfile {
        let mut sum = vec![0.0; bins.count];
        let mut count = vec![0u64; bins.count];
        let mut blocks = vec![0.0; bins.count * ERROR_BLOCKS];
        let block_duration = window.duration() / ERROR_BLOCKS as f64;
        for e in self.events.iter().filter(|e| window.contains(e.time)) {
            let speed = -e.velocity_z;
            if let (Some(i), true) = (bins.index_of(e.x), speed > 0.0) {
                let area = std::f64::consts::PI * e.radius * e.radius / speed;
                sum[i] += area;
                count[i] += 1;
                let block = (((e.time - window.start) / block_duration).floor().max(0.0) as usize)
                    .min(ERROR_BLOCKS - 1);
                blocks[i * ERROR_BLOCKS + block] += area;
            }
        }
        let scale = 1.0 / (window.duration() * bins.width());
        let block_scale = 1.0 / (block_duration * bins.width());
        let area_fraction: Vec<Option<f64>> = (0..bins.count)
            .map(|i| (count[i] > 0).then(|| sum[i] * scale))
            .collect();
        let standard_error = (0..bins.count)
            .map(|i| {
                let mean = area_fraction[i]?;
                let g = ERROR_BLOCKS as f64;
                let spread: f64 = blocks[i * ERROR_BLOCKS..(i + 1) * ERROR_BLOCKS]
                    .iter()
                    .map(|b| (b * block_scale - mean).powi(2))
                    .sum();
                Some((spread / (g - 1.0) / g).sqrt())
            })
            .collect();
        CrossingDensityProfile {
            window,
            bins: *bins,
            area_fraction,
            standard_error,
        }
    }
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
struct Observation {
    time: f64,
    x: f64,
    #[serde(default)]
    y: f64,
    z: f64,
    velocity_z: f64,
    generation: u64,
    velocity_x: f64,
}

/// Detects crossings of the outlet line between consecutive observations.
///
/// Call [`CrossingProbe::observe`] every k steps (k ≤ 100 at Δt = 2.5 µs). The probe keeps
/// each id's previous (t, x, z, v_z); ids that vanish (removed particles) are forgotten.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CrossingProbe {
    record: CrossingRecord,
    previous: HashMap<u64, Observation>,
    generation: u64,
}

impl CrossingProbe {
    /// A probe for the outlet `geometry`.
    pub fn new(geometry: OutletGeometry) -> Result<Self, MeasureError> {
        geometry.validate()?;
        Ok(Self {
            record: CrossingRecord {
                geometry,
                first_time: None,
                last_time: None,
                events: Vec::new(),
                upward: CrossingTally::default(),
            },
            previous: HashMap::new(),
            generation: 0,
        })
    }

    /// Observes one frame; returns the number of downward crossings found since the last one.
    pub fn observe(&mut self, frame: &Snapshot<'_>) -> Result<usize, MeasureError> {
        frame.validate()?;
        if let Some(previous) = self.record.last_time {
            if !(frame.time > previous) {
                return Err(MeasureError::TimeNotIncreasing {
                    previous,
                    current: frame.time,
                });
            }
        }
        self.generation += 1;
        let generation = self.generation;
        let z_o = self.record.geometry.outlet_height;
        let first_new_event = self.record.events.len();
        for i in 0..frame.len() {
            let [x, y, z] = frame.positions[i];
            let [velocity_x, _, velocity_z] = frame.velocities[i];
            let now = Observation {
                time: frame.time,
                x,
                y,
                z,
                velocity_z,
                generation,
                velocity_x,
            };
            if let Some(before) = self.previous.insert(frame.ids[i], now) {
                if before.z > z_o && z <= z_o {
                    // Linear interpolation between the two observations.
                    let s = (before.z - z_o) / (before.z - z);
                    let x_cross = before.x + s * (x - before.x);
                    let y_cross = before.y + s * (y - before.y);
                    self.record.events.push(CrossingEvent {
                        time: before.time + s * (frame.time - before.time),
                        x: x_cross,
                        velocity_z: before.velocity_z + s * (velocity_z - before.velocity_z),
                        mass: frame.mass(i),
                        inside_outlet: self.record.geometry.contains(x_cross, y_cross),
                        velocity_x: before.velocity_x + s * (velocity_x - before.velocity_x),
                        radius: frame.radii[i],
                        id: frame.ids[i],
                        y: y_cross,
                    });
                } else if before.z <= z_o && z > z_o {
                    self.record.upward.count += 1;
                    self.record.upward.mass += frame.mass(i);
                }
            }
        }
        self.previous.retain(|_, o| o.generation == generation);
        // Interpolated times are not ordered across particles within one interval.
        self.record.events[first_new_event..].sort_by(|a, b| a.time.total_cmp(&b.time));
        self.record.first_time.get_or_insert(frame.time);
        self.record.last_time = Some(frame.time);
        Ok(self.record.events.len() - first_new_event)
    }

    /// What has been recorded so far.
    pub fn record(&self) -> &CrossingRecord {
        &self.record
    }

    /// Ends observation and hands the record over.
    pub fn into_record(self) -> CrossingRecord {
        self.record
    }
}
