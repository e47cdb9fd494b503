//! Strip area fraction φ(x), the snapshot flux ⟨φ v⟩ and the snapshot v(x) at the outlet
//! (docs/physics.md §7.2–7.4).
//!
//! Per frame, the strip z ∈ [z_o − h/2, z_o + h/2] (h = d by default; d/2 for sensitivity) is
//! cut into x-bins. In each bin rectangle B the probe sums
//! - the exact area of B covered by the particles' mid-plane discs, Σ_k |D_k ∩ B|;
//! - Σ_k |D_k ∩ B| v_z,k, whose average over frames divided by |B| is ⟨φ v⟩ (docs/physics.md §7.4);
//! - Σ v_z and the count of centres with |z − z_o| < d/2 and x in the bin (snapshot v).
//!
//! Disc radius: the mid-plane section √(r² − (y − y_m)²) of each sphere when the slab
//! mid-plane y_m is given, otherwise r itself. In the paper's slab (Z = 1.01 d) centres stay
//! within ±15 µm of y_m, so the two differ by < 1e-4 r. Overlapping discs (contact overlaps of
//! 5–30 µm) are counted twice; this biases φ by O(δ/d) ≲ 1e-3 at the outlet, where grains are
//! dilute and contacts are few.
//!
//! Per-frame per-bin sums are stored, so the averaging window is chosen after the run.

use serde::{Deserialize, Serialize};

use super::block_error::BlockSums;
use super::crossing::mean_of;
use super::disc_area::{overlap_area, section_radius, Disc, Rectangle};
use super::error::MeasureError;
use super::geometry::{OutletBins, OutletGeometry};
use super::snapshot::{Snapshot, TimeWindow};

/// How the strip is laid out.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StripConfig {
    /// The outlet.
    pub geometry: OutletGeometry,
    /// The x-bins across the orifice.
    pub bins: OutletBins,
    /// Strip height h [m], centred on z_o.
    pub strip_height: f64,
    /// Slab mid-plane y_m [m] for the section radius; `None` uses the full radius.
    pub mid_plane: Option<f64>,
}

impl StripConfig {
    /// The default strip of docs/physics.md §7.3: h = d, full-radius discs.
    pub fn new(geometry: OutletGeometry, bins: OutletBins) -> Self {
        Self {
            geometry,
            bins,
            strip_height: geometry.particle_diameter,
            mid_plane: None,
        }
    }

    fn validate(&self) -> Result<(), MeasureError> {
        self.geometry.validate()?;
        if !(self.strip_height.is_finite() && self.strip_height > 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "strip_height",
                value: self.strip_height,
                reason: "must be finite and positive",
            });
        }
        if self.bins.count == 0 || !(self.bins.half_width > 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "bins",
                value: self.bins.count as f64,
                reason: "need at least one bin of positive width",
            });
        }
        if let Some(y) = self.mid_plane {
            if !y.is_finite() {
                return Err(MeasureError::InvalidParameter {
                    name: "mid_plane",
                    value: y,
                    reason: "must be finite",
                });
            }
        }
        Ok(())
    }
}

/// Per-bin sums of one frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StripFrame {
    /// Frame time [s].
    pub time: f64,
    /// Area of each bin rectangle covered by discs [m²].
    pub covered_area: Vec<f64>,
    /// Σ (covered area × v_z) per bin [m³/s] (negative for downward flow).
    pub area_velocity: Vec<f64>,
    /// Σ v_z of the centres with |z − z_o| < d/2 per bin [m/s].
    pub centre_velocity_sum: Vec<f64>,
    /// Number of such centres per bin.
    pub centre_count: Vec<u32>,
}

/// Everything the strip probe recorded.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StripRecord {
    /// The strip layout.
    pub config: StripConfig,
    /// One entry per observed frame, in time order.
    pub frames: Vec<StripFrame>,
}

/// Time-averaged strip quantities in one x-bin.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AreaFractionBin {
    /// Bin centre in x* (dimensionless).
    pub x_star: f64,
    /// Bin centre in x [m].
    pub x: f64,
    /// Area fraction φ_2D, covered area / bin area, averaged over frames.
    pub area_fraction: f64,
    /// Standard error of that average, from the spread between the window's time blocks
    /// (successive frames are correlated; see `block_error`); `None` unless two blocks hold
    /// frames.
    pub area_fraction_standard_error: Option<f64>,
    /// ⟨φ v⟩: frame average of Σ_k |D_k ∩ B| (−v_z,k) / |B| [m/s], downward positive.
    pub area_fraction_speed: f64,
    /// Snapshot mean downward speed of centres in |z − z_o| < d/2, pooled over frames [m/s];
    /// `None` if no centre was seen.
    pub snapshot_speed: Option<f64>,
    /// Number of centre samples behind `snapshot_speed`.
    pub snapshot_count: u64,
}

/// φ(x), ⟨φ v⟩(x) and the snapshot v(x) over a window.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AreaFractionProfile {
    /// Averaging window.
    pub window: TimeWindow,
    /// Number of frames averaged.
    pub frames: usize,
    /// The x-bins.
    pub bins: OutletBins,
    /// Strip height h [m].
    pub strip_height: f64,
    /// One entry per bin, left to right.
    pub entries: Vec<AreaFractionBin>,
}

impl AreaFractionProfile {
    /// φ_c: the mean area fraction of the central bins (|x*| < 0.1, docs/physics.md §7.5).
    pub fn centre_area_fraction(&self) -> Option<f64> {
        mean_of(
            self.bins
                .central_bins()
                .into_iter()
                .map(|i| self.entries[i].area_fraction),
        )
    }

    /// φ_max and the x* of its bin (used for eccentric outlets, paper Fig. 13).
    pub fn max_area_fraction(&self) -> Option<(f64, f64)> {
        self.entries
            .iter()
            .map(|e| (e.area_fraction, e.x_star))
            .max_by(|a, b| a.0.total_cmp(&b.0))
    }
}

impl StripRecord {
    /// Averages the frames whose time lies in `window`.
    pub fn area_fraction_profile(
        &self,
        window: TimeWindow,
    ) -> Result<AreaFractionProfile, MeasureError> {
        let bins = self.config.bins;
        let n_bins = bins.count;
        let bin_area = bins.width() * self.config.strip_height;
        let mut phi_sum = vec![0.0; n_bins];
        let mut blocks = BlockSums::new(n_bins, window);
        let mut flux_sum = vec![0.0; n_bins];
        let mut velocity_sum = vec![0.0; n_bins];
        let mut velocity_count = vec![0u64; n_bins];
        let mut frames = 0usize;
        for frame in self.frames.iter().filter(|f| window.contains(f.time)) {
            frames += 1;
            for i in 0..n_bins {
                let phi = frame.covered_area[i] / bin_area;
                phi_sum[i] += phi;
                blocks.add(i, frame.time, phi);
                flux_sum[i] -= frame.area_velocity[i] / bin_area;
                velocity_sum[i] -= frame.centre_velocity_sum[i];
                velocity_count[i] += u64::from(frame.centre_count[i]);
            }
        }
        if frames == 0 {
            return Err(MeasureError::NoFramesInWindow {
                start: window.start,
                end: window.end,
            });
        }
        let n = frames as f64;
        let entries = (0..n_bins)
            .map(|i| {
                let mean = phi_sum[i] / n;
                let standard_error = blocks.standard_error(i, mean);
                AreaFractionBin {
                    x_star: bins.x_star_centre(i),
                    x: bins.x_centre(i),
                    area_fraction: mean,
                    area_fraction_standard_error: standard_error,
                    area_fraction_speed: flux_sum[i] / n,
                    snapshot_speed: (velocity_count[i] > 0)
                        .then(|| velocity_sum[i] / velocity_count[i] as f64),
                    snapshot_count: velocity_count[i],
                }
            })
            .collect();
        Ok(AreaFractionProfile {
            window,
            frames,
            bins,
            strip_height: self.config.strip_height,
            entries,
        })
    }
}

/// Observes frames (every ~1e-3 s, docs/physics.md §7.2) and stores per-bin strip sums.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StripProbe {
    record: StripRecord,
}

impl StripProbe {
    /// A probe with the given strip layout.
    pub fn new(config: StripConfig) -> Result<Self, MeasureError> {
        config.validate()?;
        Ok(Self {
            record: StripRecord {
                config,
                frames: Vec::new(),
            },
        })
    }

    /// Adds one frame's per-bin sums.
    pub fn observe(&mut self, frame: &Snapshot<'_>) -> Result<(), MeasureError> {
        frame.validate()?;
        if let Some(last) = self.record.frames.last() {
            if !(frame.time > last.time) {
                return Err(MeasureError::TimeNotIncreasing {
                    previous: last.time,
                    current: frame.time,
                });
            }
        }
        let config = &self.record.config;
        let bins = config.bins;
        let n_bins = bins.count;
        let z_o = config.geometry.outlet_height;
        let z_min = z_o - 0.5 * config.strip_height;
        let z_max = z_o + 0.5 * config.strip_height;
        let band = 0.5 * config.geometry.particle_diameter;
        let span_min = bins.left_edge(0);
        let span_max = bins.left_edge(n_bins);
        let width = bins.width();

        let mut out = StripFrame {
            time: frame.time,
            covered_area: vec![0.0; n_bins],
            area_velocity: vec![0.0; n_bins],
            centre_velocity_sum: vec![0.0; n_bins],
            centre_count: vec![0; n_bins],
        };
        for i in 0..frame.len() {
            let [x, y, z] = frame.positions[i];
            let velocity_z = frame.velocities[i][2];
            if (z - z_o).abs() < band {
                if let Some(b) = bins.index_of(x) {
                    out.centre_velocity_sum[b] += velocity_z;
                    out.centre_count[b] += 1;
                }
            }
            let radius = match config.mid_plane {
                Some(y_m) => section_radius(frame.radii[i], y - y_m),
                None => frame.radii[i],
            };
            if !(radius > 0.0)
                || z + radius <= z_min
                || z - radius >= z_max
                || x + radius <= span_min
                || x - radius >= span_max
            {
                continue;
            }
            let disc = Disc { x, z, radius };
            // Only the bins the disc's x-extent touches.
            let first = (((x - radius - span_min) / width).floor().max(0.0)) as usize;
            let last = ((((x + radius - span_min) / width).floor()) as usize).min(n_bins - 1);
            for b in first..=last {
                let rectangle = Rectangle {
                    x_min: bins.left_edge(b),
                    x_max: bins.left_edge(b + 1),
                    z_min,
                    z_max,
                };
                let area = overlap_area(disc, rectangle);
                out.covered_area[b] += area;
                out.area_velocity[b] += area * velocity_z;
            }
        }
        self.record.frames.push(out);
        Ok(())
    }

    /// What has been recorded so far.
    pub fn record(&self) -> &StripRecord {
        &self.record
    }

    /// Ends observation and hands the record over.
    pub fn into_record(self) -> StripRecord {
        self.record
    }
}
