//! The study report: analysis of a finished study's saved results (no re-simulation) and
//! the documents built from it.
//!
//! - [`load_study`] reads `results.csv`, `study.json` and each case's profiles, and
//!   averages replicas (mean ± standard error) into [`GridPoint`]s;
//! - [`analyse_study`] fits them: Beverloo per series, angle and gap ([`beverloo`]),
//!   Table 2 quantities and Eq. 14 ([`centred`]), Table 3 quantities and Eq. 18
//!   ([`eccentric`]); every function here is pure;
//! - [`compare_with_paper`] turns the fits into the paper's acceptance items;
//! - [`load_cohesion`] and [`analyse_cohesion`] read each case's Bond number ([`bond`])
//!   and tabulate W against Bo, the critical outlet width against Bo and the arches;
//! - [`load_clogging`] and [`analyse_clogging`] read the avalanches of runs that break
//!   their arches and fit the mean avalanche size against D/d;
//! - [`build_report`] writes `report/report.md`, `report/report.html` (self-contained),
//!   `report/comparison.json` and the figures;
//! - [`build_calibration_report`] writes the report of a calibration folder
//!   (`hopperflow calibrate`) from its `calibration.json` and `runs.csv`.

#![warn(missing_docs)]

pub mod beverloo;
pub mod bond;
mod build;
mod calibration;
pub mod centred;
mod clogging;
mod coarse_graining;
mod cohesion;
mod comparison;
mod data;
mod document;
pub mod eccentric;
mod figures;
mod lab_tests;
pub mod silo;
mod tables;

use analysis::Estimate;

pub use build::{build_report, ReportError, ReportFiles};
pub use calibration::{build_calibration_report, is_calibration, CalibrationReportFiles};
pub use clogging::{
    analyse_clogging, clogging_blocks, load_clogging, ClogCase, ClogGroup, ClogRow,
};
pub use coarse_graining::{
    load_parcels, parcel_tables, ParcelLevel, ParcelRun, ParcelTable, BEVERLOO_K,
};
pub use cohesion::{
    analyse_cohesion, load_cohesion, BondCell, BondLevel, CohesionAnalysis, CohesionCase,
    CohesionGroup, CohesionStudy, CriticalWidth, HalfClogging,
};
pub use comparison::{
    compare_with_paper, ComparisonItem, ANGLE_SERIES, B_TREND_FROM_DEG, ECCENTRIC_SERIES,
    FLAT_TOLERANCE, OTHER_CODES_K_90,
};
pub use data::{load_study, GridPoint, StudyData};
pub use document::{Block, Document};
pub use figures::{report_figures, ReportFigure};

/// A fitted value, or why it could not be measured (too few points, no profiles, a fit
/// that failed); the report prints the reason instead of failing.
pub type Fitted<T> = Result<T, String>;

/// The g [m/s²] that a fit over `points` uses: the one all of them ran under. Points of
/// several g are refused rather than fitted with one of them, since every law fitted here
/// (Beverloo, v_c = √(2γgR), the self-similar rate) carries √g.
pub fn common_gravity<'a>(points: impl IntoIterator<Item = &'a GridPoint>) -> Fitted<f64> {
    let mut values: Vec<f64> = points.into_iter().map(|p| p.gravity).collect();
    values.sort_by(f64::total_cmp);
    values.dedup();
    match values.as_slice() {
        [] => Err("no points".into()),
        [g] => Ok(*g),
        several => Err(format!(
            "the cases ran under different g ({} m/s²); fit each g in a study of its own",
            several
                .iter()
                .map(|g| g.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

/// All fits of a study.
#[derive(Debug, Clone)]
pub struct StudyAnalysis {
    /// Beverloo fits per series, angle and gap.
    pub beverloo: Vec<beverloo::BeverlooGroup>,
    /// Table 2 per (series, α).
    pub angles: Vec<centred::AngleFit>,
    /// W(α)/W(90°) per (series, α, D).
    pub angle_ratios: Vec<centred::AngleRatio>,
    /// Off-centre outlets.
    pub eccentric: eccentric::EccentricAnalysis,
    /// Silos with circular orifices.
    pub silo: silo::SiloAnalysis,
    /// Whether the study holds slab cases, to which the paper's items apply.
    pub has_slabs: bool,
}

/// Fits everything that the grid points allow: the paper's fits on the slab cases, the 3D
/// fits on the silos.
pub fn analyse_study(points: &[GridPoint]) -> StudyAnalysis {
    let slabs: Vec<GridPoint> = points
        .iter()
        .filter(|p| p.kind == "slab")
        .cloned()
        .collect();
    StudyAnalysis {
        beverloo: beverloo::fit_beverloo_groups(&slabs),
        angles: centred::fit_angles(&slabs),
        angle_ratios: centred::angle_ratios(&slabs),
        eccentric: eccentric::analyse_eccentric(&slabs),
        silo: silo::analyse_silos(points),
        has_slabs: !slabs.is_empty(),
    }
}

/// The standard errors of `values` when every one is finite and positive (fit weights);
/// otherwise `None`, so that the fit weights points equally.
pub(crate) fn errors_if_known(values: &[Estimate]) -> Option<Vec<f64>> {
    values
        .iter()
        .all(|e| e.standard_error.is_finite() && e.standard_error > 0.0)
        .then(|| values.iter().map(|e| e.standard_error).collect())
}
