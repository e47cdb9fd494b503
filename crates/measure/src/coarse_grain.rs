//! Coarse-grained continuum fields: mass density, volume fraction, velocity, and the
//! kinetic and contact stress tensors, on a grid in (x, z) for a slab or in (r, z) for an
//! axisymmetric silo, averaged over time windows (docs/physics.md §7.13).
//!
//! After Goldhirsch (Granular Matter 12, 239 (2010)) and Weinhart, Thornton, Luding and
//! Bokhove (Granular Matter 14, 289 (2012)): with a kernel W of unit integral,
//!
//! - ρ(r) = Σ_i m_i W(r − r_i) [kg/m³], φ(r) = Σ_i V_i W(r − r_i) [-];
//! - p(r) = Σ_i m_i v_i W(r − r_i) [kg/(m² s)], V = ⟨p⟩/⟨ρ⟩ [m/s], the ratio of the time
//!   averages (Goldhirsch's mass-weighted mean);
//! - kinetic stress σ^k = Σ_i m_i v'_i ⊗ v'_i W with v' = v − V, computed in the p/ρ form
//!   σ^k = ⟨Σ_i m_i v_i ⊗ v_i W⟩ − ⟨p⟩ ⊗ ⟨p⟩/⟨ρ⟩ [Pa]: frame by frame the same as the
//!   fluctuation about the local mean, and over a window the fluctuation about the window's
//!   mean velocity (so it holds the temporal fluctuations too, as a steady flow's stress should);
//! - contact stress σ^c = Σ_c f_c ⊗ b_c ∫_0^1 W(r − a_c − s b_c) ds [Pa], the force f_c on
//!   particle i of each contact and its branch b_c, from the partner's centre r_j to r_i for a
//!   pair (b = r_i − r_j), from the contact point c to r_i for a wall (b = r_i − c), the
//!   kernel integrated along the branch from its start a_c.
//!
//! **Sign convention: compression positive.** The tensors above are the negative of the
//! Cauchy stress (tension positive), as in soil mechanics: a bed at rest has σ_zz = +ρ g h at
//! depth h, and the pressure p = tr(σ)/3 is positive in compression.
//!
//! **Kernels** ([`CgKernel`]), of width w [m] given by the user, two-dimensional in the grid's
//! plane: the Gaussian exp(−r²/2w²)/(2π w²), cut at 3w and renormalised so that the cut
//! kernel keeps unit integral; Lucy's polynomial (Lucy, Astron. J. 82, 1013 (1977))
//! W = 5/(π c²) (1 + 3q)(1 − q)³, q = r/c < 1, compact, with the cutoff c = √(56/5) w ≈ 3.35 w
//! that gives it the Gaussian's standard deviation w along each axis, so that fields at the
//! same w resolve the same scales.
//!
//! **Grids** ([`CgGrid`]): square cells of side h; the fields are sampled at cell centres
//! (point values, not cell means; the space integral Σ field × cell volume is then the
//! midpoint rule, accurate to the kernel's quadrature error while h ≤ w).
//! - Slab: the (x, z) plane, each field averaged across the slab's thickness L_y: the 2D
//!   kernel in (x, z) divided by L_y, which is the 3D kernel integrated over y for a slab
//!   whose particles all lie between its walls. Densities are per unit volume [kg/m³].
//! - Axisymmetric: the (r, z) half plane about a vertical axis, cells being annuli of volume
//!   2π r h² (at their centre radius r). A particle at cylindrical radius r_i deposits
//!   W₂(r − r_i, z − z_i)/(2π r), the 3D kernel integrated over the azimuth in the limit
//!   w ≪ r_i (the ring through the cell is straight over the kernel's width); near the axis
//!   the part of the kernel at r < 0 is reflected (W₂(r + r_i, …) added), which keeps every
//!   particle's mass exactly while the shape there is approximate to O(w²/r_i²). Vectors
//!   and tensors are taken in the cylindrical basis (e_r, e_θ, e_z) at each particle's (each
//!   quadrature point's) azimuth.
//!
//! **Branch quadrature**: composite Gauss–Legendre, the branch cut into ⌈|b|/w⌉ equal
//! pieces of 4 points each (exact for polynomials of degree 7 on a piece no longer than w:
//! below 1e-5 of the Gaussian's integral, ample for w ≥ d/4). The weights sum to one, so
//! the space integral of σ^c is Σ f ⊗ b (the virial) to the grid's quadrature error alone.
//!
//! Frames are summed into blocks of a chosen duration (the averaging window), as
//! [`crate::VelocityFieldProbe`] does; [`CoarseGrainRecord::fields`] averages the blocks of
//! a time window.

use serde::{Deserialize, Serialize};

use super::error::MeasureError;
use super::snapshot::{Snapshot, TimeWindow};

/// Ratio of the Lucy kernel's cutoff to its width: c = √(56/5) w, so that its standard
/// deviation along each axis of the plane is w.
pub const LUCY_CUTOFF_PER_WIDTH: f64 = 3.346_640_106_136_302;
/// The Gaussian kernel's cut, in widths.
pub const GAUSSIAN_CUT_PER_WIDTH: f64 = 3.0;

/// The coarse-graining kernel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CgKernel {
    /// Lucy's compact polynomial (Lucy 1977), cutoff [`LUCY_CUTOFF_PER_WIDTH`] × w.
    Lucy,
    /// Gaussian of standard deviation w, cut at 3w and renormalised.
    Gaussian,
}

impl CgKernel {
    /// The kernel's name in case files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            Self::Lucy => "lucy",
            Self::Gaussian => "gaussian",
        }
    }

    /// Radius beyond which the kernel of width `width` [m] is zero [m].
    pub fn support(self, width: f64) -> f64 {
        match self {
            Self::Lucy => LUCY_CUTOFF_PER_WIDTH * width,
            Self::Gaussian => GAUSSIAN_CUT_PER_WIDTH * width,
        }
    }

    /// The 2D kernel of width `width` [m] at squared distance `r2` [m²] [1/m²]: unit
    /// integral over the plane.
    #[inline]
    pub fn value(self, width: f64, r2: f64) -> f64 {
        match self {
            Self::Lucy => {
                let c = LUCY_CUTOFF_PER_WIDTH * width;
                let q = r2.sqrt() / c;
                if q >= 1.0 {
                    return 0.0;
                }
                let one = 1.0 - q;
                5.0 / (std::f64::consts::PI * c * c) * (1.0 + 3.0 * q) * one * one * one
            }
            Self::Gaussian => {
                let cut = GAUSSIAN_CUT_PER_WIDTH * width;
                if r2 > cut * cut {
                    return 0.0;
                }
                let kept = 1.0 - (-0.5 * GAUSSIAN_CUT_PER_WIDTH * GAUSSIAN_CUT_PER_WIDTH).exp();
                (-0.5 * r2 / (width * width)).exp()
                    / (2.0 * std::f64::consts::PI * width * width * kept)
            }
        }
    }
}

/// The shape a grid maps particles onto.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CgGeometry {
    /// A slab between walls at constant y: fields in (x, z), averaged across the thickness
    /// `thickness` L_y [m]; components in (x, y, z).
    Slab {
        /// Thickness L_y [m].
        thickness: f64,
    },
    /// A silo about the vertical axis through (x, y) = `axis` [m]: fields in (r, z);
    /// components in (r, θ, z).
    Axisymmetric {
        /// Where the axis meets the (x, y) plane [m].
        axis: [f64; 2],
    },
}

/// A regular grid of square cells in the (x, z) or (r, z) plane.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CgGrid {
    /// Slab or axisymmetric.
    pub geometry: CgGeometry,
    /// Left edge: x_min, or r_min ≥ 0 [m].
    pub first: f64,
    /// Bottom edge [m].
    pub z_min: f64,
    /// Cell side h [m].
    pub cell_size: f64,
    /// Cells along x (r).
    pub columns: usize,
    /// Cells along z.
    pub rows: usize,
}

/// The most cells a grid may have (a guard against a cell size given in the wrong unit).
pub const MAX_CELLS: usize = 4_000_000;

impl CgGrid {
    /// Cells of side `cell_size` [m] covering [first, last] × [z_min, z_max] [m] (the last
    /// column and row may overhang).
    pub fn new(
        geometry: CgGeometry,
        (first, last): (f64, f64),
        (z_min, z_max): (f64, f64),
        cell_size: f64,
    ) -> Result<Self, MeasureError> {
        let bad = |name, value, reason| MeasureError::InvalidParameter {
            name,
            value,
            reason,
        };
        if !(cell_size.is_finite() && cell_size > 0.0) {
            return Err(bad("cell_size", cell_size, "must be finite and positive"));
        }
        if !(first.is_finite() && last.is_finite() && last > first) {
            return Err(bad(
                "grid width",
                last - first,
                "must be finite and positive",
            ));
        }
        if !(z_min.is_finite() && z_max.is_finite() && z_max > z_min) {
            return Err(bad(
                "grid height",
                z_max - z_min,
                "must be finite and positive",
            ));
        }
        match geometry {
            CgGeometry::Slab { thickness } if !(thickness.is_finite() && thickness > 0.0) => {
                return Err(bad("thickness", thickness, "must be finite and positive"));
            }
            CgGeometry::Axisymmetric { .. } if !(first >= 0.0) => {
                return Err(bad("r_min", first, "must be ≥ 0"));
            }
            CgGeometry::Axisymmetric { axis } if !axis.iter().all(|a| a.is_finite()) => {
                return Err(bad("axis", axis[0], "must be finite"));
            }
            _ => {}
        }
        let columns = ((last - first) / cell_size).ceil();
        let rows = ((z_max - z_min) / cell_size).ceil();
        if !(columns * rows <= MAX_CELLS as f64) {
            return Err(bad(
                "cell_size",
                cell_size,
                "gives more than 4e6 cells over the region",
            ));
        }
        Ok(Self {
            geometry,
            first,
            z_min,
            cell_size,
            columns: columns as usize,
            rows: rows as usize,
        })
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.columns * self.rows
    }

    /// True for a grid without cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Centre (x or r, z) of cell (column, row) [m].
    pub fn cell_centre(&self, column: usize, row: usize) -> [f64; 2] {
        [
            self.first + (column as f64 + 0.5) * self.cell_size,
            self.z_min + (row as f64 + 0.5) * self.cell_size,
        ]
    }

    /// The volume a cell stands for [m³]: h² L_y for a slab, 2π r h² for an annulus of
    /// centre radius r.
    pub fn cell_volume(&self, column: usize) -> f64 {
        let h2 = self.cell_size * self.cell_size;
        match self.geometry {
            CgGeometry::Slab { thickness } => h2 * thickness,
            CgGeometry::Axisymmetric { .. } => {
                2.0 * std::f64::consts::PI * self.cell_centre(column, 0)[0] * h2
            }
        }
    }

    /// A point's place in the grid's plane (x or r, z) and the basis its vectors are taken
    /// in: (e_1, e_2, e_3) = (x, y, z) for a slab, (e_r, e_θ, e_z) at its azimuth for a silo
    /// (e_r = x on the axis itself).
    fn place(&self, x: [f64; 3]) -> ([f64; 2], Basis) {
        match self.geometry {
            CgGeometry::Slab { .. } => ([x[0], x[2]], Basis::Cartesian),
            CgGeometry::Axisymmetric { axis } => {
                let (dx, dy) = (x[0] - axis[0], x[1] - axis[1]);
                let r = dx.hypot(dy);
                let (c, s) = if r > 0.0 {
                    (dx / r, dy / r)
                } else {
                    (1.0, 0.0)
                };
                ([r, x[2]], Basis::Cylindrical { cos: c, sin: s })
            }
        }
    }
}

/// The basis vectors are taken in at one point.
#[derive(Debug, Clone, Copy)]
enum Basis {
    Cartesian,
    /// e_r = (cos, sin, 0), e_θ = (−sin, cos, 0), e_z.
    Cylindrical {
        cos: f64,
        sin: f64,
    },
}

impl Basis {
    #[inline]
    fn components(self, v: [f64; 3]) -> [f64; 3] {
        match self {
            Self::Cartesian => v,
            Self::Cylindrical { cos, sin } => {
                [cos * v[0] + sin * v[1], -sin * v[0] + cos * v[1], v[2]]
            }
        }
    }
}

/// A particle pair's contact as the coarse graining needs it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CgPairContact {
    /// Index of particle i in the frame.
    pub i: usize,
    /// Index of particle j in the frame.
    pub j: usize,
    /// Force on i [N] (on j: its negative).
    pub force: [f64; 3],
}

/// A particle–wall contact as the coarse graining needs it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CgWallContact {
    /// Index of the particle in the frame.
    pub particle: usize,
    /// Force on the particle [N].
    pub force: [f64; 3],
    /// The contact point on the wall [m].
    pub point: [f64; 3],
}

/// The contacts of one frame, indexed into the frame's particles.
#[derive(Debug, Clone, Copy, Default)]
pub struct CgContacts<'a> {
    /// Particle pairs.
    pub pairs: &'a [CgPairContact],
    /// Particles on walls.
    pub walls: &'a [CgWallContact],
}

/// Per-cell sums of one block (each summed over its frames), row-major
/// (index row·columns + column).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CgBlock {
    /// Block index k: the block covers [origin + k·Δ, origin + (k+1)·Δ).
    pub index: u64,
    /// Frames summed.
    pub frames: u32,
    /// Σ ρ [kg/m³].
    pub density: Vec<f64>,
    /// Σ φ [-].
    pub volume_fraction: Vec<f64>,
    /// Σ p, 3 components per cell [kg/(m² s)].
    pub momentum: Vec<[f64; 3]>,
    /// Σ Σ_i m_i v_i ⊗ v_i W, 6 components per cell (11, 22, 33, 12, 13, 23) [Pa].
    pub second_moment: Vec<[f64; 6]>,
    /// Σ σ^c, 9 components per cell, row-major [Pa].
    pub contact_stress: Vec<[f64; 9]>,
}

impl CgBlock {
    fn new(index: u64, cells: usize) -> Self {
        Self {
            index,
            frames: 0,
            density: vec![0.0; cells],
            volume_fraction: vec![0.0; cells],
            momentum: vec![[0.0; 3]; cells],
            second_moment: vec![[0.0; 6]; cells],
            contact_stress: vec![[0.0; 9]; cells],
        }
    }
}

/// What one coarse-graining probe recorded.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CoarseGrainRecord {
    /// The grid.
    pub grid: CgGrid,
    /// The kernel.
    pub kernel: CgKernel,
    /// Its width w [m].
    pub width: f64,
    /// Block length Δ, the averaging window [s].
    pub block_duration: f64,
    /// Time of the first frame, the blocks' origin [s].
    pub origin: Option<f64>,
    /// Blocks in increasing index.
    pub blocks: Vec<CgBlock>,
}

/// One cell of a time-averaged field. Vectors in (x, y, z) for a slab, (r, θ, z) for a
/// silo; tensors row-major in the same basis; compression positive.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CgCell {
    /// Cell centre (x or r, z) [m].
    pub centre: [f64; 2],
    /// Mass density ⟨ρ⟩ [kg/m³].
    pub density: f64,
    /// Volume fraction ⟨φ⟩ [-].
    pub volume_fraction: f64,
    /// Velocity V = ⟨p⟩/⟨ρ⟩ [m/s]; zero where no mass was seen.
    pub velocity: [f64; 3],
    /// Kinetic stress σ^k [Pa].
    pub kinetic_stress: [f64; 9],
    /// Contact stress σ^c [Pa].
    pub contact_stress: [f64; 9],
}

impl CgCell {
    /// Total stress σ = σ^k + σ^c [Pa].
    pub fn stress(&self) -> [f64; 9] {
        std::array::from_fn(|k| self.kinetic_stress[k] + self.contact_stress[k])
    }

    /// Pressure p = tr(σ)/3 [Pa], positive in compression.
    pub fn pressure(&self) -> f64 {
        let s = self.stress();
        (s[0] + s[4] + s[8]) / 3.0
    }

    /// Shear stress τ = √(J₂) of the symmetric part of σ's deviator [Pa].
    pub fn shear_stress(&self) -> f64 {
        let s = self.stress();
        let p = (s[0] + s[4] + s[8]) / 3.0;
        let d = [s[0] - p, s[4] - p, s[8] - p];
        let sym = |a: usize, b: usize| 0.5 * (s[a] + s[b]);
        let (s12, s13, s23) = (sym(1, 3), sym(2, 6), sym(5, 7));
        (0.5 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) + s12 * s12 + s13 * s13 + s23 * s23).sqrt()
    }
}

/// A time-averaged coarse-grained field on a grid.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CgField {
    /// The grid.
    pub grid: CgGrid,
    /// The kernel.
    pub kernel: CgKernel,
    /// Its width w [m].
    pub width: f64,
    /// Frames averaged.
    pub frames: u64,
    /// Cells, row-major (index row·columns + column).
    pub cells: Vec<CgCell>,
}

impl CgField {
    /// The space integral Σ ρ × cell volume [kg]: the mass the field holds.
    pub fn mass(&self) -> f64 {
        self.integral(|c| c.density)
    }

    /// Σ f(cell) × cell volume over the grid.
    pub fn integral(&self, f: impl Fn(&CgCell) -> f64) -> f64 {
        self.cells
            .iter()
            .enumerate()
            .map(|(k, c)| f(c) * self.grid.cell_volume(k % self.grid.columns))
            .sum()
    }
}

impl CoarseGrainRecord {
    /// Averages the blocks whose mid-time lies in `window` (window resolution: one block).
    pub fn fields(&self, window: TimeWindow) -> Result<CgField, MeasureError> {
        let n = self.grid.len();
        let mut sum = CgBlock::new(0, n);
        let mut frames = 0u64;
        let origin = self.origin.unwrap_or(0.0);
        for block in &self.blocks {
            let mid = origin + (block.index as f64 + 0.5) * self.block_duration;
            if !window.contains(mid) {
                continue;
            }
            frames += u64::from(block.frames);
            for c in 0..n {
                sum.density[c] += block.density[c];
                sum.volume_fraction[c] += block.volume_fraction[c];
                add(&mut sum.momentum[c], &block.momentum[c]);
                add(&mut sum.second_moment[c], &block.second_moment[c]);
                add(&mut sum.contact_stress[c], &block.contact_stress[c]);
            }
        }
        if frames == 0 {
            return Err(MeasureError::NoFramesInWindow {
                start: window.start,
                end: window.end,
            });
        }
        Ok(self.average(&sum, frames))
    }

    /// The average of every block recorded.
    pub fn all_fields(&self) -> Result<CgField, MeasureError> {
        let origin = self.origin.unwrap_or(0.0);
        let end = self.blocks.last().map_or(origin, |b| {
            origin + (b.index + 1) as f64 * self.block_duration
        });
        self.fields(TimeWindow::new(
            origin,
            end.max(origin + self.block_duration),
        )?)
    }

    fn average(&self, sum: &CgBlock, frames: u64) -> CgField {
        let f = frames as f64;
        let cells = (0..self.grid.len())
            .map(|c| {
                let rho = sum.density[c] / f;
                let p = sum.momentum[c].map(|x| x / f);
                let velocity = if rho > 0.0 {
                    p.map(|x| x / rho)
                } else {
                    [0.0; 3]
                };
                let m = sum.second_moment[c].map(|x| x / f);
                let full = [m[0], m[3], m[4], m[3], m[1], m[5], m[4], m[5], m[2]];
                // σ^k = ⟨Σ m v v W⟩ − ρ V V (the p/ρ form; module notes).
                let kinetic =
                    std::array::from_fn(|k| full[k] - rho * velocity[k / 3] * velocity[k % 3]);
                CgCell {
                    centre: self
                        .grid
                        .cell_centre(c % self.grid.columns, c / self.grid.columns),
                    density: rho,
                    volume_fraction: sum.volume_fraction[c] / f,
                    velocity,
                    kinetic_stress: kinetic,
                    contact_stress: sum.contact_stress[c].map(|x| x / f),
                }
            })
            .collect();
        CgField {
            grid: self.grid,
            kernel: self.kernel,
            width: self.width,
            frames,
            cells,
        }
    }
}

fn add<const N: usize>(a: &mut [f64; N], b: &[f64; N]) {
    for k in 0..N {
        a[k] += b[k];
    }
}

/// Gauss–Legendre nodes on [−1, 1] and weights of the 4-point rule.
const GL4: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
];

/// The most pieces a branch is cut into (a branch 16 widths long: far longer than any
/// contact's at the widths the case file allows).
const MAX_PIECES: usize = 16;

/// Sums coarse-grained fields on a grid, frame by frame, into blocks.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CoarseGrainProbe {
    record: CoarseGrainRecord,
    last_time: Option<f64>,
}

impl CoarseGrainProbe {
    /// A probe on `grid` with `kernel` of width `width` [m], summing blocks of
    /// `block_duration` [s].
    pub fn new(
        grid: CgGrid,
        kernel: CgKernel,
        width: f64,
        block_duration: f64,
    ) -> Result<Self, MeasureError> {
        if !(width.is_finite() && width > 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "width",
                value: width,
                reason: "must be finite and positive",
            });
        }
        if !(block_duration.is_finite() && block_duration > 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "block_duration",
                value: block_duration,
                reason: "must be finite and positive",
            });
        }
        if grid.is_empty() || !(grid.cell_size > 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "grid",
                value: grid.len() as f64,
                reason: "needs at least one cell of positive size",
            });
        }
        Ok(Self {
            record: CoarseGrainRecord {
                grid,
                kernel,
                width,
                block_duration,
                origin: None,
                blocks: Vec::new(),
            },
            last_time: None,
        })
    }

    /// What has been recorded so far.
    pub fn record(&self) -> &CoarseGrainRecord {
        &self.record
    }

    /// Ends observation and hands the record over.
    pub fn into_record(self) -> CoarseGrainRecord {
        self.record
    }

    /// Adds one frame: its particles and their contacts (indices into the frame).
    pub fn observe(
        &mut self,
        frame: &Snapshot<'_>,
        contacts: CgContacts<'_>,
    ) -> Result<(), MeasureError> {
        frame.validate()?;
        if let Some(previous) = self.last_time {
            if !(frame.time > previous) {
                return Err(MeasureError::TimeNotIncreasing {
                    previous,
                    current: frame.time,
                });
            }
        }
        let n = frame.len();
        for c in contacts.pairs {
            if c.i >= n || c.j >= n {
                return Err(MeasureError::LengthMismatch {
                    field: "contact particle index",
                    expected: n,
                    found: c.i.max(c.j),
                });
            }
            if !c.force.iter().all(|x| x.is_finite()) {
                return Err(MeasureError::NonFinite {
                    field: "contact force",
                    index: c.i,
                });
            }
        }
        for c in contacts.walls {
            if c.particle >= n {
                return Err(MeasureError::LengthMismatch {
                    field: "wall contact particle index",
                    expected: n,
                    found: c.particle,
                });
            }
            if !c.force.iter().chain(&c.point).all(|x| x.is_finite()) {
                return Err(MeasureError::NonFinite {
                    field: "wall contact",
                    index: c.particle,
                });
            }
        }
        self.last_time = Some(frame.time);
        let origin = *self.record.origin.get_or_insert(frame.time);
        let index = ((frame.time - origin) / self.record.block_duration).floor() as u64;
        let cells = self.record.grid.len();
        if self.record.blocks.last().map(|b| b.index) != Some(index) {
            self.record.blocks.push(CgBlock::new(index, cells));
        }
        let Self { record, .. } = self;
        let (grid, kernel, width) = (record.grid, record.kernel, record.width);
        let Some(block) = record.blocks.last_mut() else {
            return Ok(());
        };
        block.frames += 1;
        let depositor = Depositor {
            grid,
            kernel,
            width,
        };
        for i in 0..n {
            let m = frame.mass(i);
            let r = frame.radii[i];
            let volume = 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
            let (at, basis) = grid.place(frame.positions[i]);
            let v = basis.components(frame.velocities[i]);
            let second = [
                v[0] * v[0],
                v[1] * v[1],
                v[2] * v[2],
                v[0] * v[1],
                v[0] * v[2],
                v[1] * v[2],
            ];
            depositor.deposit(at, |c, w| {
                block.density[c] += m * w;
                block.volume_fraction[c] += volume * w;
                for (p, vk) in block.momentum[c].iter_mut().zip(v) {
                    *p += m * vk * w;
                }
                for (s, sk) in block.second_moment[c].iter_mut().zip(second) {
                    *s += m * sk * w;
                }
            });
        }
        let mut branch = |start: [f64; 3], end: [f64; 3], force: [f64; 3]| {
            let b = [end[0] - start[0], end[1] - start[1], end[2] - start[2]];
            let length = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
            let pieces = ((length / width).ceil() as usize).clamp(1, MAX_PIECES);
            for piece in 0..pieces {
                for (node, weight) in GL4 {
                    let s = (piece as f64 + 0.5 * (node + 1.0)) / pieces as f64;
                    let weight = 0.5 * weight / pieces as f64;
                    let x = [
                        start[0] + s * b[0],
                        start[1] + s * b[1],
                        start[2] + s * b[2],
                    ];
                    let (at, basis) = grid.place(x);
                    let (f, bb) = (basis.components(force), basis.components(b));
                    let t: [f64; 9] = std::array::from_fn(|k| weight * f[k / 3] * bb[k % 3]);
                    depositor.deposit(at, |c, w| {
                        for (s, tk) in block.contact_stress[c].iter_mut().zip(t) {
                            *s += tk * w;
                        }
                    });
                }
            }
        };
        for c in contacts.pairs {
            branch(frame.positions[c.j], frame.positions[c.i], c.force);
        }
        for c in contacts.walls {
            branch(c.point, frame.positions[c.particle], c.force);
        }
        Ok(())
    }
}

/// Spreads one point's weight over the grid's cells.
#[derive(Debug, Clone, Copy)]
struct Depositor {
    grid: CgGrid,
    kernel: CgKernel,
    width: f64,
}

impl Depositor {
    /// Calls `cell(index, W)` for every cell within the kernel's support of the point `at`
    /// (x or r, z) [m], W [1/m³] being the kernel per unit volume there (module notes).
    #[inline]
    fn deposit(&self, at: [f64; 2], mut cell: impl FnMut(usize, f64)) {
        let g = &self.grid;
        let support = self.kernel.support(self.width);
        let h = g.cell_size;
        let axisymmetric = matches!(g.geometry, CgGeometry::Axisymmetric { .. });
        let c0 = ((at[0] - support - g.first) / h - 0.5).ceil().max(0.0);
        let c1 = ((at[0] + support - g.first) / h - 0.5).floor();
        let r0 = ((at[1] - support - g.z_min) / h - 0.5).ceil().max(0.0);
        let r1 = ((at[1] + support - g.z_min) / h - 0.5).floor();
        if c1 < c0 || r1 < r0 || c0 >= g.columns as f64 || r0 >= g.rows as f64 {
            return;
        }
        let (c0, r0) = (c0 as usize, r0 as usize);
        let c1 = (c1 as usize).min(g.columns - 1);
        let r1 = (r1 as usize).min(g.rows - 1);
        for row in r0..=r1 {
            for column in c0..=c1 {
                let [a, z] = g.cell_centre(column, row);
                let dz2 = (z - at[1]) * (z - at[1]);
                let mut w = self
                    .kernel
                    .value(self.width, (a - at[0]) * (a - at[0]) + dz2);
                let per_volume = match g.geometry {
                    CgGeometry::Slab { thickness } => 1.0 / thickness,
                    CgGeometry::Axisymmetric { .. } => 1.0 / (2.0 * std::f64::consts::PI * a),
                };
                if axisymmetric {
                    // The kernel's part beyond the axis, reflected (module notes).
                    w += self
                        .kernel
                        .value(self.width, (a + at[0]) * (a + at[0]) + dz2);
                }
                if w > 0.0 {
                    cell(row * g.columns + column, w * per_volume);
                }
            }
        }
    }
}

/// How the fields change from one width to the next ([`width_scan`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WidthStep {
    /// The smaller width w [m].
    pub width: f64,
    /// The next width [m].
    pub next_width: f64,
    /// Relative change of ρ between the two, ‖Δρ‖₂/‖ρ‖₂ over the cells both hold [-].
    pub density_change: f64,
    /// Relative change of the pressure p [-].
    pub pressure_change: f64,
    /// Relative change of the velocity, ‖ΔV‖₂/‖V‖₂ [-].
    pub velocity_change: f64,
}

impl WidthStep {
    /// The larger of the density's and the pressure's changes [-] (the velocity's is left
    /// out: in a bed at rest it is the change of noise relative to noise).
    pub fn largest_change(&self) -> f64 {
        self.density_change.max(self.pressure_change)
    }
}

/// The check of the width: how much the fields change between consecutive widths, and
/// the plateau, the width at which they depend least on it (in ρ and p).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WidthScan {
    /// One row per pair of consecutive widths, in increasing width.
    pub steps: Vec<WidthStep>,
    /// The width of the step with the smallest largest change [m], where that change is at
    /// most [`PLATEAU_CHANGE`]; `None` where no step is that flat.
    pub plateau: Option<f64>,
    /// The smallest largest change of any step [-].
    pub least_change: Option<f64>,
}

/// The largest relative change between consecutive widths that still counts as a plateau.
pub const PLATEAU_CHANGE: f64 = 0.05;

/// Compares fields of the same grid at several widths (any order): the relative L2 change
/// of ρ, p and V from each width to the next, over the cells where both have mass at least
/// 10 % of the largest density (the material, not its fringe), and the plateau.
pub fn width_scan(fields: &[CgField]) -> Result<WidthScan, MeasureError> {
    let mut order: Vec<&CgField> = fields.iter().collect();
    order.sort_by(|a, b| a.width.total_cmp(&b.width));
    // A width given twice is one width.
    order.dedup_by(|a, b| a.width == b.width);
    for f in &order {
        if f.grid != order[0].grid || f.cells.len() != order[0].cells.len() {
            return Err(MeasureError::BinsMismatch);
        }
    }
    let mut steps = Vec::new();
    for pair in order.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let top = a
            .cells
            .iter()
            .chain(&b.cells)
            .map(|c| c.density)
            .fold(0.0, f64::max);
        let mut sums = [[0.0f64; 2]; 3];
        for (x, y) in a.cells.iter().zip(&b.cells) {
            if !(x.density >= 0.1 * top && y.density >= 0.1 * top) {
                continue;
            }
            let dv: f64 = (0..3)
                .map(|k| (x.velocity[k] - y.velocity[k]).powi(2))
                .sum();
            let v: f64 = (0..3).map(|k| x.velocity[k].powi(2)).sum();
            for (s, (d, base)) in sums.iter_mut().zip([
                ((x.density - y.density).powi(2), x.density.powi(2)),
                ((x.pressure() - y.pressure()).powi(2), x.pressure().powi(2)),
                (dv, v),
            ]) {
                s[0] += d;
                s[1] += base;
            }
        }
        let rel = |s: [f64; 2]| {
            if s[1] > 0.0 {
                (s[0] / s[1]).sqrt()
            } else {
                0.0
            }
        };
        steps.push(WidthStep {
            width: a.width,
            next_width: b.width,
            density_change: rel(sums[0]),
            pressure_change: rel(sums[1]),
            velocity_change: rel(sums[2]),
        });
    }
    let best = steps
        .iter()
        .min_by(|a, b| a.largest_change().total_cmp(&b.largest_change()));
    Ok(WidthScan {
        plateau: best
            .filter(|s| s.largest_change() <= PLATEAU_CHANGE)
            .map(|s| s.width),
        least_change: best.map(WidthStep::largest_change),
        steps,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const D: f64 = 1.5e-3;
    const RHO_P: f64 = 2500.0;

    /// A frame of particles of diameter D at `positions` with `velocities`.
    struct Frame {
        ids: Vec<u64>,
        positions: Vec<[f64; 3]>,
        velocities: Vec<[f64; 3]>,
        radii: Vec<f64>,
    }

    impl Frame {
        fn new(positions: Vec<[f64; 3]>, velocity: impl Fn([f64; 3]) -> [f64; 3]) -> Self {
            Self {
                ids: (0..positions.len() as u64).collect(),
                velocities: positions.iter().map(|&x| velocity(x)).collect(),
                radii: vec![0.5 * D; positions.len()],
                positions,
            }
        }

        fn snapshot(&self, time: f64) -> Snapshot<'_> {
            Snapshot {
                time,
                ids: &self.ids,
                positions: &self.positions,
                velocities: &self.velocities,
                radii: &self.radii,
                density: RHO_P,
                masses: None,
            }
        }
    }

    fn mass() -> f64 {
        RHO_P * std::f64::consts::PI / 6.0 * D * D * D
    }

    fn field(
        grid: CgGrid,
        kernel: CgKernel,
        width: f64,
        frame: &Frame,
        contacts: CgContacts,
    ) -> CgField {
        let mut probe = CoarseGrainProbe::new(grid, kernel, width, 1.0).expect("valid probe");
        probe
            .observe(&frame.snapshot(0.0), contacts)
            .expect("valid frame");
        probe.into_record().all_fields().expect("one frame")
    }

    fn slab_grid(half: f64, cell: f64) -> CgGrid {
        let g = CgGeometry::Slab { thickness: 2.0 * D };
        CgGrid::new(g, (-half, half), (-half, half), cell).expect("valid grid")
    }

    #[test]
    fn one_particle_s_mass_integrates_to_its_mass_in_a_slab_and_in_a_silo() {
        // Cells of w/2 sample each kernel finely: the midpoint sum of the Gaussian's smooth
        // part is exact to far below 1e-9; what is left is its cut at 3w, a jump of 1.1 % of
        // the weight that cells of w/2 sample to within 1.5e-3 of the mass (the worst of 40
        // positions seen), and Lucy's C² edge, within 1e-5. Tolerances 3e-3 and 1e-4 (the
        // mass is off by half if the 1/L_y or the 1/(2π r) is lost, by 1.1 % if the Gaussian
        // is not renormalised). In the silo the particle lies off the axis (3d) and beside it
        // (0.1 w), where the reflected part of the kernel must keep the mass.
        let w = 0.5 * D;
        for (kernel, tolerance) in [(CgKernel::Gaussian, 3e-3), (CgKernel::Lucy, 1e-4)] {
            let frame = Frame::new(vec![[1.3e-4, 0.4e-3, -2.1e-4]], |_| [0.0; 3]);
            let f = field(
                slab_grid(6.0 * D, 0.5 * w),
                kernel,
                w,
                &frame,
                CgContacts::default(),
            );
            let error = (f.mass() - mass()).abs() / mass();
            assert!(
                error < tolerance,
                "{kernel:?} slab: relative error {error:e}"
            );
            for r in [3.0 * D, 0.1 * w] {
                let grid = CgGrid::new(
                    CgGeometry::Axisymmetric { axis: [0.0, 0.0] },
                    (0.0, 8.0 * D),
                    (-4.0 * D, 4.0 * D),
                    0.5 * w,
                )
                .expect("valid grid");
                let frame = Frame::new(vec![[0.6 * r, -0.8 * r, 2.0e-4]], |_| [0.0; 3]);
                let f = field(grid, kernel, w, &frame, CgContacts::default());
                let error = (f.mass() - mass()).abs() / mass();
                assert!(
                    error < tolerance,
                    "{kernel:?} silo at r = {r}: error {error:e}"
                );
            }
        }
    }

    /// A simple cubic lattice of spacing `a` filling [-half, half]² in (x, z) and `layers`
    /// planes in y.
    fn lattice(a: f64, half: f64, layers: usize) -> Vec<[f64; 3]> {
        let n = (2.0 * half / a).round() as usize;
        let mut out = Vec::new();
        for i in 0..n {
            for k in 0..n {
                for l in 0..layers {
                    out.push([
                        -half + (i as f64 + 0.5) * a,
                        (l as f64 + 0.5) * a,
                        -half + (k as f64 + 0.5) * a,
                    ]);
                }
            }
        }
        out
    }

    #[test]
    fn a_uniform_lattice_gives_its_volume_fraction_in_its_interior() {
        // A simple cubic lattice of spacing a = 1.1 d, two layers across a slab of 2a: φ =
        // (π/6) d³/a³ = 0.393, and ρ = ρ_p φ. A kernel of width w = a samples the lattice
        // finely: the Poisson sum of the Gaussian aliases at exp(−2π² w²/a²) ≈ 3e-9, its cut
        // adds 3e-4 (seen), Lucy's edge 1e-5. Tolerance 1e-3 at the cells at least 4w from
        // the lattice's edge (the interior); a lost 1/L_y would double φ.
        let a = 1.1 * D;
        let half = 12.0 * a;
        let frame = Frame::new(lattice(a, half, 2), |_| [0.0; 3]);
        let expected = std::f64::consts::PI / 6.0 * D * D * D / (a * a * a);
        for kernel in [CgKernel::Gaussian, CgKernel::Lucy] {
            let grid = CgGrid::new(
                CgGeometry::Slab { thickness: 2.0 * a },
                (-half, half),
                (-half, half),
                0.5 * a,
            )
            .expect("valid grid");
            let f = field(grid, kernel, a, &frame, CgContacts::default());
            let mut seen = 0;
            for c in &f.cells {
                if c.centre[0].abs() < half - 4.0 * a && c.centre[1].abs() < half - 4.0 * a {
                    seen += 1;
                    let e = (c.volume_fraction - expected).abs() / expected;
                    assert!(
                        e < 1e-3,
                        "{kernel:?}: φ {} at {:?}",
                        c.volume_fraction,
                        c.centre
                    );
                    let e = (c.density - RHO_P * expected).abs() / (RHO_P * expected);
                    assert!(e < 1e-3, "{kernel:?}: ρ {} at {:?}", c.density, c.centre);
                }
            }
            assert!(seen > 100, "the interior has cells");
        }
    }

    /// The space integral of each component of σ^c [N m].
    fn stress_integral(f: &CgField) -> [f64; 9] {
        std::array::from_fn(|k| f.integral(|c| c.contact_stress[k]))
    }

    #[test]
    fn a_loaded_pair_on_a_floor_gives_the_virial_and_a_symmetric_stress() {
        // Particle j rests on a floor z = 0, particle i on j along a tilted line of centres,
        // i pressed by an external load P along that line: in static equilibrium the pair's
        // contact pushes i with P along the branch b = r_i − r_j, and the floor pushes j with
        // P. The space integral of σ^c must be Σ f ⊗ b = P b̂ ⊗ b + P b̂ ⊗ (r_j − c): the branch
        // quadrature's weights sum to one, so only the grid's midpoint sum errs (as for the
        // mass, below 1e-3 with cells of w/2; tolerance 1e-3 of the largest component).
        // The pair's force is central (along its branch), so its σ^c must be symmetric in
        // every cell to round-off (1e-12 of the largest component anywhere), in the slab and
        // in the silo's cylindrical basis; the floor's force, tilted against its vertical
        // branch (friction), is not central, and is left out of that check.
        let load = 2.0;
        let tilt: f64 = 0.3;
        let rj = [2.0 * D, 0.0, 0.5 * D];
        let b = [D * tilt.sin(), 0.0, D * tilt.cos()];
        let ri = [rj[0] + b[0], rj[1] + b[1], rj[2] + b[2]];
        let floor = [rj[0], rj[1], 0.0];
        let frame = Frame::new(vec![ri, rj], |_| [0.0; 3]);
        let f_pair = b.map(|x| load * x / D);
        let pairs = [CgPairContact {
            i: 0,
            j: 1,
            force: f_pair,
        }];
        let walls = [CgWallContact {
            particle: 1,
            force: f_pair,
            point: floor,
        }];
        let contacts = CgContacts {
            pairs: &pairs,
            walls: &walls,
        };
        let to_floor = [rj[0] - floor[0], rj[1] - floor[1], rj[2] - floor[2]];
        let virial: [f64; 9] =
            std::array::from_fn(|k| f_pair[k / 3] * (b[k % 3] + to_floor[k % 3]));
        let w = 0.5 * D;
        for kernel in [CgKernel::Gaussian, CgKernel::Lucy] {
            let slab = CgGrid::new(
                CgGeometry::Slab { thickness: 2.0 * D },
                (-2.0 * D, 6.0 * D),
                (-4.0 * D, 6.0 * D),
                0.5 * w,
            )
            .expect("valid grid");
            let f = field(slab, kernel, w, &frame, contacts);
            let integral = stress_integral(&f);
            let scale = virial.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            for k in 0..9 {
                assert!(
                    (integral[k] - virial[k]).abs() < 1e-3 * scale,
                    "{kernel:?}: ∫σ {integral:?} against Σ f⊗b {virial:?}"
                );
            }
            // In the silo, about an axis through the floor point's x: the rotation into the
            // (r, θ, z) basis keeps the tensor symmetric.
            let silo = CgGrid::new(
                CgGeometry::Axisymmetric {
                    axis: [0.5 * D, 0.3 * D],
                },
                (0.0, 6.0 * D),
                (-4.0 * D, 6.0 * D),
                0.5 * w,
            )
            .expect("valid grid");
            let central = CgContacts {
                pairs: &pairs,
                walls: &[],
            };
            for f in [
                field(slab, kernel, w, &frame, central),
                field(silo, kernel, w, &frame, central),
            ] {
                let top = f
                    .cells
                    .iter()
                    .flat_map(|c| c.contact_stress)
                    .fold(0.0f64, |a, x| a.max(x.abs()));
                assert!(top > 0.0);
                for c in &f.cells {
                    let s = c.contact_stress;
                    for (p, q) in [(1, 3), (2, 6), (5, 7)] {
                        assert!((s[p] - s[q]).abs() <= 1e-12 * top, "not symmetric: {s:?}");
                    }
                }
            }
            // Compression positive: the vertical normal stress between the floor and i's top.
            let centre = f
                .cells
                .iter()
                .min_by(|x, y| {
                    let d = |c: &CgCell| (c.centre[0] - rj[0]).hypot(c.centre[1] - rj[2]);
                    d(x).total_cmp(&d(y))
                })
                .expect("cells");
            assert!(centre.contact_stress[8] > 0.0 && centre.pressure() > 0.0);
        }
    }

    #[test]
    fn a_rigid_rotation_s_velocity_field_is_recovered() {
        // The lattice turning about the y axis at ω: v = ω ŷ × r = ω (z, 0, −x). The field
        // V = ⟨p⟩/⟨ρ⟩ at a point is ω ŷ × (the kernel-weighted centroid of the lattice sites
        // near it), which is the point itself to the lattice's aliasing, through the Gaussian's
        // cut and Lucy's edge: 1.7e-3 a at worst (seen, both kernels). Tolerance 5e-3 ω a in
        // the interior, where the speeds reach 20 ω a.
        let omega = 3.0;
        let a = 1.1 * D;
        let half = 10.0 * a;
        let frame = Frame::new(lattice(a, half, 1), |x| [omega * x[2], 0.0, -omega * x[0]]);
        for kernel in [CgKernel::Gaussian, CgKernel::Lucy] {
            let grid = CgGrid::new(
                CgGeometry::Slab { thickness: a },
                (-half, half),
                (-half, half),
                0.5 * a,
            )
            .expect("valid grid");
            let f = field(grid, kernel, a, &frame, CgContacts::default());
            let mut seen = 0;
            for c in &f.cells {
                let [x, z] = c.centre;
                if x.abs() < half - 4.0 * a && z.abs() < half - 4.0 * a {
                    seen += 1;
                    let expected = [omega * z, 0.0, -omega * x];
                    for (v, e) in c.velocity.iter().zip(expected) {
                        assert!(
                            (v - e).abs() < 5e-3 * omega * a,
                            "{kernel:?}: V {:?} at {:?}",
                            c.velocity,
                            c.centre
                        );
                    }
                }
            }
            assert!(seen > 50);
        }
    }

    #[test]
    fn the_kinetic_stress_is_the_velocity_fluctuation_s_second_moment() {
        // Two particles at one place moving at ±u along x (no mean flow): σ^k_xx = Σ m u² W,
        // ρ = Σ m W, so σ^k_xx = ρ u² and every other component zero (tolerance 1e-12
        // relative: the same sums divide). A common drift U added to both must leave σ^k
        // unchanged (the p/ρ form removes the mean), to 1e-9 relative (U² ≫ u² cancels).
        let u = 0.2;
        for drift in [0.0, 1.5] {
            let mut frame = Frame::new(vec![[0.0; 3], [0.0; 3]], |_| [0.0; 3]);
            frame.velocities = vec![[drift + u, 0.0, 0.0], [drift - u, 0.0, 0.0]];
            let f = field(
                slab_grid(3.0 * D, 0.25 * D),
                CgKernel::Gaussian,
                0.5 * D,
                &frame,
                CgContacts::default(),
            );
            let c = f
                .cells
                .iter()
                .max_by(|a, b| a.density.total_cmp(&b.density))
                .expect("cells");
            let expected = c.density * u * u;
            assert!((c.kinetic_stress[0] - expected).abs() < 1e-9 * expected);
            for k in 1..9 {
                assert!(c.kinetic_stress[k].abs() < 1e-9 * expected);
            }
            assert!((c.velocity[0] - drift).abs() < 1e-12 + 1e-12 * drift);
        }
    }

    #[test]
    fn bad_inputs_are_refused_not_panicked_on() {
        // Every refusal names what was wrong.
        let slab = CgGeometry::Slab { thickness: D };
        assert!(CgGrid::new(slab, (0.0, 1.0), (0.0, 1.0), 0.0).is_err());
        assert!(
            CgGrid::new(slab, (0.0, 1.0), (0.0, 1.0), 1e-7).is_err(),
            "1e14 cells"
        );
        assert!(CgGrid::new(slab, (1.0, 0.0), (0.0, 1.0), 0.1).is_err());
        let silo = CgGeometry::Axisymmetric { axis: [0.0, 0.0] };
        assert!(CgGrid::new(silo, (-0.1, 1.0), (0.0, 1.0), 0.1).is_err());
        let grid = slab_grid(3.0 * D, D);
        assert!(CoarseGrainProbe::new(grid, CgKernel::Lucy, f64::NAN, 1.0).is_err());
        assert!(CoarseGrainProbe::new(grid, CgKernel::Lucy, D, 0.0).is_err());
        let mut probe = CoarseGrainProbe::new(grid, CgKernel::Lucy, D, 1.0).expect("valid");
        let frame = Frame::new(vec![[0.0; 3]], |_| [0.0; 3]);
        let pairs = [CgPairContact {
            i: 0,
            j: 5,
            force: [0.0; 3],
        }];
        let contacts = CgContacts {
            pairs: &pairs,
            walls: &[],
        };
        assert!(probe.observe(&frame.snapshot(0.0), contacts).is_err());
        // A point far outside the grid deposits nothing and does not fail.
        let far = Frame::new(vec![[1.0e3, 0.0, -1.0e3]], |_| [0.0; 3]);
        probe
            .observe(&far.snapshot(1.0), CgContacts::default())
            .expect("far away is fine");
    }
}
