//! What a run and a study leave on disk, and the writers that put it there.
//!
//! - [`CaseSummary`] (`summary.json`), [`StartRecord`] (`start.json`), [`StudyManifest`]
//!   (`study.json`) and [`ResultRow`] (`results.csv`): the saved records, with the names of
//!   their files ([`SUMMARY_FILE`], [`StudyPaths`], …). The report reads these and nothing
//!   else; this crate does not depend on the engine or the run.
//!
//! Every writer takes plain data (slices of `f64`, `[f64; 3]`, the small structs defined here),
//! never engine types, and every file appears atomically (temporary file in the same
//! directory, fsync, rename), so a crash or an error never leaves a half-written output.
//!
//! - [`write_atomic`], [`write_json_atomic`], [`AtomicFile`]: the atomic primitive.
//! - [`write_csv_table`], [`write_csv_columns`]: tables of numbers and text.
//! - [`write_particles_vtu`], [`write_walls_vtu`]: VTK XML unstructured grids for ParaView
//!   (particles as vertices with id, radius, velocity, angular velocity and speed; walls as
//!   polygons), and [`PvdCollection`], the time series that ties them together.
//! - [`plot_png`], [`plot_svg`], [`render_plot`]: line/point plots with error bars and shaded
//!   x bands from a [`Figure`]; [`discharge_rate_figure`], [`velocity_profile_figure`] and
//!   [`area_fraction_profile_figure`] build the study's standard figures.
//! - [`render_frame`], [`write_frame_png`]: snapshots of the hopper in the x–z plane, discs
//!   coloured by speed with the [`viridis`] colour map, walls, colour bar and time label.
//! - [`RgbImage`]: the in-memory picture behind both PNG writers, readable pixel by pixel.
//!
//! Text uses the embedded DejaVu Sans font, so images look the same on every machine.
//! Functions that render in memory report errors with an empty path; the file writers fill
//! in their target.

#![warn(missing_docs)]

mod atomic;
mod calibration;
mod colormap;
mod defaults;
mod error;
mod figures;
mod font;
mod frame;
mod image;
mod layout;
mod manifest;
#[cfg(feature = "parquet")]
mod parquet;
mod plot;
mod pvd;
mod results;
mod start;
mod study_file_error;
mod summary;
mod table;
mod vtu;

pub use atomic::{
    is_temporary_name, remove_stale_temporaries, write_atomic, write_json_atomic, AtomicFile,
};
pub use calibration::{
    CalibrationRecord, ParameterEstimate, RoundRecord, SurfaceRecord, TargetMatch,
    CALIBRATION_FILE, RUNS_FILE,
};
pub use colormap::viridis;
pub use error::OutputError;
pub use figures::{
    area_fraction_profile_figure, discharge_rate_figure, velocity_profile_figure,
    wall_pressure_figure, FittedCurve, Profile,
};
pub use frame::{
    render_frame, write_frame_png, FrameLayout, FrameParticle, FrameViewport, WallSegment,
};
pub use image::RgbImage;
#[cfg(feature = "parquet")]
pub use parquet::write_parquet_table;
pub use plot::{
    plot_png, plot_svg, render_plot, Axis, Figure, Series, SeriesStyle, ShadedRange, PALETTE,
};
pub use pvd::{PvdCollection, PvdEntry};
pub use table::{write_csv_columns, write_csv_table, Cell};
pub use vtu::{
    write_grid_vti, write_particles_vtu, write_walls_vtu, GridArray, GridFields, ParticleFields,
};

pub use defaults::DEFAULT_GRAVITY;
pub use layout::{
    StudyPaths, BED_CASE_FILE, BED_FILE, CASE_FILE, CHECKPOINT_FILE, FAILURE_FILE, START_FILE,
    SUMMARY_FILE,
};
pub use manifest::{hex_hash, CaseFailure, ManifestCase, ManifestSkipped, StudyManifest};
pub use results::{read_results_table, write_results_table, CaseStatus, ResultRow, RESULT_COLUMNS};
pub use start::{describe_start, StartKind, StartRecord};
pub use study_file_error::StudyFileError;
pub use summary::{
    ArchSummary, AvalancheSummary, AxesStatistics, CaseSummary, CoarseGrainingSummary,
    DrawDownSummary, FieldsSummary, JanssenSummary, OrientationSummary, ProfileRow, RadialFit,
    ReposeSummary, ResidenceSummary, StopReason, TailFitSummary, WidthChange,
};
