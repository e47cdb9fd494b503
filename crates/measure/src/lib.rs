//! Outlet and bulk measurements on particle snapshots (docs/physics.md §7; paper Secs. 2–4).
//!
//! Probes observe a plain [`Snapshot`] and never touch the engine. Each probe stores a
//! serialisable record (`*Record`) from which the window-dependent results are derived
//! after the run, once the steady window is known:
//!
//! - [`CrossingProbe`] → [`CrossingRecord`]: W(t), the steady-window rate, the crossing
//!   velocity profile v(x) (docs/physics.md §7.1–7.2).
//! - [`StripProbe`] → [`StripRecord`]: φ(x), ⟨φ v⟩(x) and the snapshot v(x) (§7.3–7.4).
//! - [`OutletSummary`]: v_c, φ_c, φ_max and the flux check W = (2/3) ρ_p d ∫ φ v dx (§7.4).
//! - [`VelocityFieldProbe`] → [`VelocityFieldRecord`]: coarse-grained velocity maps (Fig. 9).
//! - [`CoarseGrainProbe`] → [`CoarseGrainRecord`]: coarse-grained density, volume fraction,
//!   velocity and kinetic and contact stress on an (x, z) or (r, z) grid (§7.13), and
//!   [`width_scan`], the check of the kernel's width.
//! - [`BulkProbe`]: settled φ_B and bed height.
//! - [`find_arch`]: the arch over a clogged orifice.
//! - [`heap_angle`]: the angle of repose of a heap, fitted to its surface by sector (§7.10).
//! - [`shelf_angles`]: the angles of the material left on a draw-down box's shelves (§7.11).
//!
//! Sign convention: v_z < 0 is downward; every reported speed is downward positive.

// Validation is written as `!(x > 0.0)` on purpose: NaN must fail it, and `x <= 0.0` would let
// NaN through.
#![warn(missing_docs)]
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod arch;
mod block_error;
mod bulk;
mod coarse_grain;
mod crossing;
mod disc_area;
mod error;
mod geometry;
mod heap_surface;
mod radial;
mod shelf_angle;
mod silo_bulk;
mod snapshot;
mod strip;
mod summary;
mod surface_fit;
mod velocity_field;
mod x_profile;

pub use arch::{find_arch, Arch, ArchMember};
pub use block_error::ERROR_BLOCKS;
pub use bulk::{sphere_volume_below, BulkMeasurement, BulkProbe, ContainerOutline, CrossSection};
pub use coarse_grain::{
    width_scan, CgBlock, CgCell, CgContacts, CgField, CgGeometry, CgGrid, CgKernel, CgPairContact,
    CgWallContact, CoarseGrainProbe, CoarseGrainRecord, WidthScan, WidthStep,
    GAUSSIAN_CUT_PER_WIDTH, LUCY_CUTOFF_PER_WIDTH, MAX_CELLS, PLATEAU_CHANGE,
};
pub use crossing::{
    CrossingDensityProfile, CrossingEvent, CrossingProbe, CrossingRecord, CrossingTally,
    DischargeSeries, ProfileBin, VelocityProfile, DEFAULT_DISCHARGE_BIN_WIDTH,
};
pub use disc_area::{overlap_area, section_radius, Disc, Rectangle};
pub use error::MeasureError;
pub use geometry::{OutletBins, OutletGeometry, OutletShape, CENTRE_HALF_WIDTH};
pub use heap_surface::{heap_angle, HeapAngle, HeapBinning, HeapSector, HEAP_SECTORS};
pub use radial::{radial_profiles, RadialBin, RadialBins, RadialPackingProbe};
pub use shelf_angle::{shelf_angles, Shelf, ShelfAngles, ShelfBinning, ShelfStrip, MIN_STRIP_BINS};
pub use silo_bulk::{bed_bulk, silo_bulk};
pub use snapshot::{Snapshot, TimeWindow};
pub use strip::{
    AreaFractionBin, AreaFractionProfile, StripConfig, StripFrame, StripProbe, StripRecord,
};
pub use summary::{flux_from_area_velocity, flux_from_profiles, OutletSummary};
pub use surface_fit::{FlankFit, SurfaceBin, FLANK_BAND, MIN_FLANK_BINS};
pub use velocity_field::{
    FieldBlock, FieldCell, FieldGrid, Kernel, VelocityField, VelocityFieldProbe,
    VelocityFieldRecord, DEFAULT_BLOCK_DURATION,
};
pub use x_profile::{x_profiles, XProfileBin};
