//! The rows and the manifest that a study writes for its plan: `results.csv`'s row of each
//! case (its inputs from the case, its measurements from the summary) and `study.json`.

use files::{
    hex_hash, CaseStatus, CaseSummary, ManifestCase, ManifestSkipped, ResultRow, StudyManifest,
};
use sha2::{Digest, Sha256};

use case::{SlabGeometry, SweepCase, SweepPlan};

/// The manifest of a plan.
pub fn manifest_of_plan(plan: &SweepPlan) -> StudyManifest {
    let mut whole = Sha256::new();
    let cases = plan
        .cases
        .iter()
        .map(|case| {
            let text = case.case.to_toml_string();
            whole.update(case.id.as_bytes());
            whole.update([0u8]);
            whole.update(text.as_bytes());
            ManifestCase {
                id: case.id.clone(),
                seed: case.case.seed,
                config_hash: hex_hash(&text),
            }
        })
        .collect();
    // A study from a bed is another study than the same sweep's from fills; a study of
    // fills hashes as it always did.
    if let Some(start) = &plan.start {
        whole.update(format!("start|{:?}|{}", start.kind, start.sha256).as_bytes());
    }
    StudyManifest {
        name: plan.name.clone(),
        description: plan.description.clone(),
        version: env!("CARGO_PKG_VERSION").to_string(),
        config_hash: whole
            .finalize()
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect(),
        replicas: plan.replicas,
        cases,
        skipped: plan
            .skipped
            .iter()
            .map(|s| ManifestSkipped {
                id: s.id.clone(),
                reasons: s.reasons.clone(),
            })
            .collect(),
        start: plan.start.clone(),
    }
}

/// The row of a case whose run returned `summary`.
pub fn measured_row(case: &SweepCase, summary: &CaseSummary) -> ResultRow {
    let status = if summary.clogged {
        CaseStatus::Clogged
    } else {
        CaseStatus::Complete
    };
    ResultRow {
        discharge_rate: summary.discharge_rate,
        discharge_rate_error: summary.discharge_rate_error,
        centre_velocity: summary.centre_velocity,
        centre_area_fraction: summary.centre_area_fraction,
        max_area_fraction: summary.max_area_fraction,
        bulk_volume_fraction: summary.bulk_volume_fraction,
        flux_check_rate: summary.flux_check_rate,
        flux_check_ratio: summary.flux_check_rate / summary.discharge_rate,
        plateau_found: summary.plateau_found,
        clogged: summary.clogged,
        status,
        repose_angle_deg: summary.repose.map_or(f64::NAN, |r| r.angle_deg),
        repose_angle_error_deg: summary.repose.map_or(f64::NAN, |r| r.angle_error_deg),
        shelf_angle_deg: summary.draw_down.map_or(f64::NAN, |s| s.shelf_angle_deg),
        shelf_angle_error_deg: summary
            .draw_down
            .map_or(f64::NAN, |s| s.shelf_angle_error_deg),
        ..failed_row(case)
    }
}

/// The row of a case that produced no summary: inputs filled in, measurements NaN.
pub fn failed_row(case: &SweepCase) -> ResultRow {
    let geometry = &case.case.geometry;
    let of_slab = |f: fn(&SlabGeometry) -> f64| geometry.slab().map_or(f64::NAN, f);
    let labels = case
        .labels
        .iter()
        .filter(|(key, _)| key.as_str() != "series" && key.as_str() != "replica")
        .map(|(key, value)| format!("{key}={value}"))
        .collect::<Vec<_>>()
        .join(";");
    ResultRow {
        id: case.id.clone(),
        series: case.labels.get("series").cloned().unwrap_or_default(),
        replica: case
            .labels
            .get("replica")
            .and_then(|r| r.parse().ok())
            .unwrap_or(0),
        labels,
        outlet_width: geometry.outlet_size(),
        hopper_angle_deg: geometry.hopper_angle_deg(),
        outlet_gap: of_slab(|g| g.outlet_gap),
        dimensionless_gap: of_slab(|g| g.dimensionless_gap()),
        thickness: of_slab(|g| g.thickness),
        wall_friction: case.case.wall.interaction.friction,
        width: of_slab(|g| g.width),
        particle_diameter: case.case.particles.mean_diameter(),
        particle_density: case.case.particles.density(),
        particles: case.case.particles.count,
        seed: case.case.seed,
        discharge_rate: f64::NAN,
        discharge_rate_error: f64::NAN,
        centre_velocity: f64::NAN,
        centre_area_fraction: f64::NAN,
        max_area_fraction: f64::NAN,
        bulk_volume_fraction: f64::NAN,
        flux_check_rate: f64::NAN,
        flux_check_ratio: f64::NAN,
        repose_angle_deg: f64::NAN,
        repose_angle_error_deg: f64::NAN,
        shelf_angle_deg: f64::NAN,
        shelf_angle_error_deg: f64::NAN,
        plateau_found: false,
        clogged: false,
        status: CaseStatus::Failed,
    }
}
