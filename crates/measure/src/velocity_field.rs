//! Coarse-grained velocity field on a 2D grid around the outlet (paper Fig. 9-style maps).
//!
//! Coarse graining after Goldhirsch (Granular Matter 12, 239 (2010)) and Weinhart et al.
//! (Granular Matter 14, 289 (2012), MercuryDPM): with a kernel W(r) normalised to unit integral
//! in the (x, z) plane, the mass density is ρ(r) = Σ_k m_k W(r − r_k) and the momentum density
//! p(r) = Σ_k m_k v_k W(r − r_k), both evaluated at the cell centres; the velocity field is
//! V = ⟨p⟩/⟨ρ⟩, the ratio of time averages (the mass-weighted mean, which Goldhirsch
//! recommends over averaging instantaneous ratios). ρ here is mass per unit area of the
//! (x, z) plane [kg/m²] — the slab's mass per area, not a 3D density.
//!
//! Frames are accumulated into time blocks (default 0.02 s), so the averaging window can be
//! chosen after the run to block resolution while memory stays small.

use serde::{Deserialize, Serialize};

use super::error::MeasureError;
use super::geometry::OutletGeometry;
use super::snapshot::{Snapshot, TimeWindow};

/// Default time-block length [s], matching the W(t) bins.
pub const DEFAULT_BLOCK_DURATION: f64 = 0.02;

/// Coarse-graining kernel.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Kernel {
    /// Box kernel: a particle's mass goes wholly to the cell holding its centre
    /// (W = 1/cell area in that cell). Cheapest; resolution = cell size.
    Box,
    /// Gaussian W = exp(−r²/2w²)/(2π w²), cut at 3w and renormalised so the cut kernel still
    /// integrates to one (the cut drops exp(−4.5) ≈ 1.1 % of the weight). Sampled at cell
    /// centres, so the deposited mass matches m only to the quadrature error of a grid of
    /// spacing h against width w (negligible for h ≤ w).
    Gaussian {
        /// Standard deviation w [m]; w ≈ d/2 is the usual choice.
        width: f64,
    },
}

/// A regular grid in the (x, z) plane.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FieldGrid {
    /// Left edge [m].
    pub x_min: f64,
    /// Bottom edge [m].
    pub z_min: f64,
    /// Square cell side [m].
    pub cell_size: f64,
    /// Cells along x.
    pub columns: usize,
    /// Cells along z.
    pub rows: usize,
}

impl FieldGrid {
    /// Cells of side `cell_size` [m] covering [x_min, x_max] × [z_min, z_max] [m] (the last
    /// column/row may overhang).
    pub fn new(
        x_min: f64,
        x_max: f64,
        z_min: f64,
        z_max: f64,
        cell_size: f64,
    ) -> Result<Self, MeasureError> {
        if !(cell_size.is_finite() && cell_size > 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "cell_size",
                value: cell_size,
                reason: "must be finite and positive",
            });
        }
        if !(x_min.is_finite() && x_max.is_finite() && x_max > x_min) {
            return Err(MeasureError::InvalidParameter {
                name: "x_max",
                value: x_max,
                reason: "must be finite and above x_min",
            });
        }
        if !(z_min.is_finite() && z_max.is_finite() && z_max > z_min) {
            return Err(MeasureError::InvalidParameter {
                name: "z_max",
                value: z_max,
                reason: "must be finite and above z_min",
            });
        }
        Ok(Self {
            x_min,
            z_min,
            cell_size,
            columns: ((x_max - x_min) / cell_size).ceil() as usize,
            rows: ((z_max - z_min) / cell_size).ceil() as usize,
        })
    }

    /// The usual outlet window: x over the hopper width `hopper_width` L [m] centred on the
    /// axis x = 0, z from z_o − 3d to z_o + 2L, cells of side d.
    pub fn around_outlet(
        geometry: &OutletGeometry,
        hopper_width: f64,
    ) -> Result<Self, MeasureError> {
        geometry.validate()?;
        let d = geometry.particle_diameter;
        let z_o = geometry.outlet_height;
        Self::new(
            -0.5 * hopper_width,
            0.5 * hopper_width,
            z_o - 3.0 * d,
            z_o + 2.0 * hopper_width,
            d,
        )
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.columns * self.rows
    }

    /// True for a grid without cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Centre of cell (column, row) [m].
    pub fn cell_centre(&self, column: usize, row: usize) -> [f64; 2] {
        [
            self.x_min + (column as f64 + 0.5) * self.cell_size,
            self.z_min + (row as f64 + 0.5) * self.cell_size,
        ]
    }
}

/// Time-block sums: Σ over frames of ρ, p_x, p_z at each cell (row-major, index row·columns + column).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FieldBlock {
    /// Block index k: the block covers [origin + k·Δ, origin + (k+1)·Δ).
    pub index: u64,
    /// Frames accumulated.
    pub frames: u32,
    /// Σ ρ [kg/m²].
    pub mass_density: Vec<f64>,
    /// Σ p_x [kg/(m s)].
    pub momentum_x: Vec<f64>,
    /// Σ p_z [kg/(m s)].
    pub momentum_z: Vec<f64>,
}

/// Everything the field probe recorded.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VelocityFieldRecord {
    /// Grid.
    pub grid: FieldGrid,
    /// Kernel.
    pub kernel: Kernel,
    /// Block length Δ [s].
    pub block_duration: f64,
    /// Time of the first frame, the block origin [s].
    pub origin: Option<f64>,
    /// Blocks in increasing index.
    pub blocks: Vec<FieldBlock>,
}

/// One cell of a time-averaged field.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FieldCell {
    /// Cell centre (x, z) [m].
    pub centre: [f64; 2],
    /// Mean mass per unit (x, z) area ⟨ρ⟩ [kg/m²].
    pub mass_density: f64,
    /// Velocity (v_x, v_z) = ⟨p⟩/⟨ρ⟩ [m/s]; `None` where no mass was seen.
    pub velocity: Option<[f64; 2]>,
}

/// A time-averaged coarse-grained field.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct VelocityField {
    /// Grid.
    pub grid: FieldGrid,
    /// Kernel.
    pub kernel: Kernel,
    /// Frames averaged.
    pub frames: u64,
    /// Cells, row-major (index row·columns + column).
    pub cells: Vec<FieldCell>,
}

impl VelocityFieldRecord {
    /// Averages the blocks whose mid-time lies in `window` (window resolution = one block).
    pub fn field(&self, window: TimeWindow) -> Result<VelocityField, MeasureError> {
        let n = self.grid.len();
        let mut rho = vec![0.0; n];
        let mut px = vec![0.0; n];
        let mut pz = vec![0.0; n];
        let mut frames = 0u64;
        let origin = self.origin.unwrap_or(0.0);
        for block in &self.blocks {
            let mid = origin + (block.index as f64 + 0.5) * self.block_duration;
            if !window.contains(mid) {
                continue;
            }
            frames += u64::from(block.frames);
            for c in 0..n {
                rho[c] += block.mass_density[c];
                px[c] += block.momentum_x[c];
                pz[c] += block.momentum_z[c];
            }
        }
        if frames == 0 {
            return Err(MeasureError::NoFramesInWindow {
                start: window.start,
                end: window.end,
            });
        }
        let f = frames as f64;
        let cells = (0..n)
            .map(|c| {
                let (row, column) = (c / self.grid.columns, c % self.grid.columns);
                FieldCell {
                    centre: self.grid.cell_centre(column, row),
                    mass_density: rho[c] / f,
                    velocity: (rho[c] > 0.0).then(|| [px[c] / rho[c], pz[c] / rho[c]]),
                }
            })
            .collect();
        Ok(VelocityField {
            grid: self.grid,
            kernel: self.kernel,
            frames,
            cells,
        })
    }
}

/// Accumulates coarse-grained ρ and p on the grid, frame by frame.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct VelocityFieldProbe {
    record: VelocityFieldRecord,
    last_time: Option<f64>,
}

impl VelocityFieldProbe {
    /// A probe on `grid` with `kernel`, accumulating blocks of `block_duration` [s].
    pub fn new(grid: FieldGrid, kernel: Kernel, block_duration: f64) -> Result<Self, MeasureError> {
        if !(block_duration.is_finite() && block_duration > 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "block_duration",
                value: block_duration,
                reason: "must be finite and positive",
            });
        }
        if let Kernel::Gaussian { width } = kernel {
            if !(width.is_finite() && width > 0.0) {
                return Err(MeasureError::InvalidParameter {
                    name: "kernel width",
                    value: width,
                    reason: "must be finite and positive",
                });
            }
        }
        if grid.is_empty() || !(grid.cell_size > 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "grid",
                value: grid.len() as f64,
                reason: "needs at least one cell of positive size",
            });
        }
        Ok(Self {
            record: VelocityFieldRecord {
                grid,
                kernel,
                block_duration,
                origin: None,
                blocks: Vec::new(),
            },
            last_time: None,
        })
    }

    /// Adds one frame.
    pub fn observe(&mut self, frame: &Snapshot<'_>) -> Result<(), MeasureError> {
        frame.validate()?;
        if let Some(previous) = self.last_time {
            if !(frame.time > previous) {
                return Err(MeasureError::TimeNotIncreasing {
                    previous,
                    current: frame.time,
                });
            }
        }
        self.last_time = Some(frame.time);
        let origin = *self.record.origin.get_or_insert(frame.time);
        let index = ((frame.time - origin) / self.record.block_duration).floor() as u64;
        let grid = self.record.grid;
        let kernel = self.record.kernel;
        if self.record.blocks.last().map(|b| b.index) != Some(index) {
            self.record.blocks.push(FieldBlock {
                index,
                frames: 0,
                mass_density: vec![0.0; grid.len()],
                momentum_x: vec![0.0; grid.len()],
                momentum_z: vec![0.0; grid.len()],
            });
        }
        let last = self.record.blocks.len() - 1;
        let block = &mut self.record.blocks[last];
        block.frames += 1;
        let h = grid.cell_size;
        for i in 0..frame.len() {
            let [x, _, z] = frame.positions[i];
            let [vx, _, vz] = frame.velocities[i];
            let m = frame.mass(i);
            let mut deposit = |c: usize, weight: f64| {
                block.mass_density[c] += m * weight;
                block.momentum_x[c] += m * vx * weight;
                block.momentum_z[c] += m * vz * weight;
            };
            match kernel {
                Kernel::Box => {
                    let (s, t) = ((x - grid.x_min) / h, (z - grid.z_min) / h);
                    if s >= 0.0
                        && t >= 0.0
                        && (s as usize) < grid.columns
                        && (t as usize) < grid.rows
                    {
                        deposit(t as usize * grid.columns + s as usize, 1.0 / (h * h));
                    }
                }
                Kernel::Gaussian { width } => {
                    let cut = 3.0 * width;
                    let norm = 1.0
                        / (2.0 * std::f64::consts::PI * width * width * (1.0 - (-4.5f64).exp()));
                    let c0 = ((x - cut - grid.x_min) / h - 0.5).ceil().max(0.0) as usize;
                    let c1 = ((x + cut - grid.x_min) / h - 0.5).floor();
                    let r0 = ((z - cut - grid.z_min) / h - 0.5).ceil().max(0.0) as usize;
                    let r1 = ((z + cut - grid.z_min) / h - 0.5).floor();
                    if c1 < 0.0 || r1 < 0.0 {
                        continue;
                    }
                    let c1 = (c1 as usize).min(grid.columns.saturating_sub(1));
                    let r1 = (r1 as usize).min(grid.rows.saturating_sub(1));
                    for row in r0..=r1 {
                        for column in c0..=c1 {
                            let [cx, cz] = grid.cell_centre(column, row);
                            let d2 = (cx - x).powi(2) + (cz - z).powi(2);
                            if d2 <= cut * cut {
                                deposit(
                                    row * grid.columns + column,
                                    norm * (-0.5 * d2 / (width * width)).exp(),
                                );
                            }
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// What has been recorded so far.
    pub fn record(&self) -> &VelocityFieldRecord {
        &self.record
    }

    /// Ends observation and hands the record over.
    pub fn into_record(self) -> VelocityFieldRecord {
        self.record
    }
}
