//! The study's results table, `results.csv`: one row per case, sorted by identifier.
//!
//! The table holds physics only (no wall-clock times), so a study that was killed and
//! resumed writes exactly the same table as one that ran without interruption.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::table::{write_csv_table, Cell};
use crate::StudyFileError;

/// How a case ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CaseStatus {
    /// The run finished and measured a discharge.
    Complete,
    /// The outlet clogged; the measurements cover the flow before the arch formed.
    Clogged,
    /// The run failed (error or panic); no measurement. See `failures.json`.
    Failed,
}

impl CaseStatus {
    /// The word written in the table.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Complete => "complete",
            Self::Clogged => "clogged",
            Self::Failed => "failed",
        }
    }

    /// How a case that ended so reads in a progress line: its discharge rate `rate` [kg/s]
    /// (before the arch, where it clogged), or the failure's `reason`.
    pub fn outcome_words(self, rate: f64, reason: Option<&str>) -> String {
        match self {
            Self::Complete => format!("W = {:.1} g/s", rate * 1e3),
            Self::Clogged => format!("CLOGGED (W before = {:.1} g/s)", rate * 1e3),
            Self::Failed => format!("FAILED: {}", reason.unwrap_or("unknown error")),
        }
    }
}

/// One row of `results.csv`. Numbers are SI; measurements of a failed case are NaN.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResultRow {
    /// Case identifier (its directory under `cases/`).
    pub id: String,
    /// Series name from the sweep.
    pub series: String,
    /// Replica index (independent fill).
    pub replica: u32,
    /// The other labels of the case, `key=value` joined by `;`.
    pub labels: String,
    /// Orifice width D [m].
    pub outlet_width: f64,
    /// Hopper angle α from the vertical [°].
    pub hopper_angle_deg: f64,
    /// Gap s between the left wall and the outlet [m].
    pub outlet_gap: f64,
    /// Dimensionless eccentricity s* = 2s/(L − D) [-].
    pub dimensionless_gap: f64,
    /// Slab thickness Z [m].
    pub thickness: f64,
    /// Particle–wall sliding friction μ_pw [-].
    pub wall_friction: f64,
    /// Hopper width L [m].
    pub width: f64,
    /// Mean particle diameter d [m].
    pub particle_diameter: f64,
    /// Particle density ρ_p [kg/m³].
    pub particle_density: f64,
    /// Particles in the fill.
    pub particles: usize,
    /// Seed of the fill.
    pub seed: u64,
    /// Mean discharge rate W over the steady window [kg/s].
    pub discharge_rate: f64,
    /// Standard error of W [kg/s].
    pub discharge_rate_error: f64,
    /// Centre velocity v_c [m/s].
    pub centre_velocity: f64,
    /// Centre area fraction φ_c [-].
    pub centre_area_fraction: f64,
    /// Largest binned area fraction φ_max [-].
    pub max_area_fraction: f64,
    /// Settled bulk volume fraction φ_B [-].
    pub bulk_volume_fraction: f64,
    /// W from the snapshot flux (physics spec §7.4) [kg/s].
    pub flux_check_rate: f64,
    /// Flux-check W divided by the counted W [-]; 1 ± 0.05 is the expected agreement.
    pub flux_check_ratio: f64,
    /// Whether W(t) showed a plateau in the steady window.
    pub plateau_found: bool,
    /// Whether the outlet clogged.
    pub clogged: bool,
    /// How the case ended.
    pub status: CaseStatus,
    /// A heap test's angle of repose (summary.json's `repose.angle_deg`) [°]; NaN for the
    /// other kinds, and in a table written before the column existed.
    #[serde(default = "not_measured")]
    pub repose_angle_deg: f64,
    /// Its standard error [°].
    #[serde(default = "not_measured")]
    pub repose_angle_error_deg: f64,
    /// A draw-down test's shelf angle (`draw_down.shelf_angle_deg`) [°]; NaN otherwise.
    #[serde(default = "not_measured")]
    pub shelf_angle_deg: f64,
    /// Its standard error [°].
    #[serde(default = "not_measured")]
    pub shelf_angle_error_deg: f64,
}

/// NaN: a measure the case did not make, or a column the table was written without.
fn not_measured() -> f64 {
    f64::NAN
}

/// Column names of `results.csv`, in order.
pub const RESULT_COLUMNS: [&str; 30] = [
    "id",
    "series",
    "replica",
    "labels",
    "outlet_width",
    "hopper_angle_deg",
    "outlet_gap",
    "dimensionless_gap",
    "thickness",
    "wall_friction",
    "width",
    "particle_diameter",
    "particle_density",
    "particles",
    "seed",
    "discharge_rate",
    "discharge_rate_error",
    "centre_velocity",
    "centre_area_fraction",
    "max_area_fraction",
    "bulk_volume_fraction",
    "flux_check_rate",
    "flux_check_ratio",
    "plateau_found",
    "clogged",
    "status",
    "repose_angle_deg",
    "repose_angle_error_deg",
    "shelf_angle_deg",
    "shelf_angle_error_deg",
];

impl ResultRow {
    fn cells(&self) -> Vec<Cell> {
        let flag = |b: bool| Cell::Text(b.to_string());
        vec![
            Cell::Text(self.id.clone()),
            Cell::Text(self.series.clone()),
            Cell::Text(self.replica.to_string()),
            Cell::Text(self.labels.clone()),
            Cell::Number(self.outlet_width),
            Cell::Number(self.hopper_angle_deg),
            Cell::Number(self.outlet_gap),
            Cell::Number(self.dimensionless_gap),
            Cell::Number(self.thickness),
            Cell::Number(self.wall_friction),
            Cell::Number(self.width),
            Cell::Number(self.particle_diameter),
            Cell::Number(self.particle_density),
            Cell::Text(self.particles.to_string()),
            // Seeds use all 63 bits: text keeps them exact where f64 would round.
            Cell::Text(self.seed.to_string()),
            Cell::Number(self.discharge_rate),
            Cell::Number(self.discharge_rate_error),
            Cell::Number(self.centre_velocity),
            Cell::Number(self.centre_area_fraction),
            Cell::Number(self.max_area_fraction),
            Cell::Number(self.bulk_volume_fraction),
            Cell::Number(self.flux_check_rate),
            Cell::Number(self.flux_check_ratio),
            flag(self.plateau_found),
            flag(self.clogged),
            Cell::Text(self.status.as_str().to_string()),
            Cell::Number(self.repose_angle_deg),
            Cell::Number(self.repose_angle_error_deg),
            Cell::Number(self.shelf_angle_deg),
            Cell::Number(self.shelf_angle_error_deg),
        ]
    }
}

/// Writes `rows` (keyed, hence sorted, by identifier) to `path` atomically.
pub fn write_results_table(
    path: &Path,
    rows: &BTreeMap<String, ResultRow>,
) -> Result<(), StudyFileError> {
    let cells: Vec<Vec<Cell>> = rows.values().map(ResultRow::cells).collect();
    write_csv_table(path, &RESULT_COLUMNS, &cells)?;
    #[cfg(feature = "parquet")]
    crate::parquet::write_parquet_table(path.with_extension("parquet"), &RESULT_COLUMNS, &cells)?;
    Ok(())
}

/// Reads a `results.csv` written by [`write_results_table`].
pub fn read_results_table(path: &Path) -> Result<Vec<ResultRow>, StudyFileError> {
    let parse = |reason: String| StudyFileError::Parse {
        path: path.to_path_buf(),
        reason,
    };
    let mut reader = csv::Reader::from_path(path).map_err(|e| parse(e.to_string()))?;
    let mut rows = Vec::new();
    for (index, record) in reader.deserialize::<ResultRow>().enumerate() {
        // Line index + 2: one header line, and lines count from 1.
        rows.push(record.map_err(|e| parse(format!("line {}: {e}", index + 2)))?);
    }
    Ok(rows)
}
