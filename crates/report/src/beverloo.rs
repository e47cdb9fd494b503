//! Beverloo fits of a study: (W/Z)^{2/3} against D per series, per hopper angle and per
//! outlet gap, with C under the three normalisations of physics spec §8.2.

use analysis::beverloo::{fit_beverloo_2d, BeverlooFit, BeverlooNormalisation};

use super::data::GridPoint;
use super::{common_gravity, Fitted};

/// Confidence level of the reported intervals of k and C.
pub const BEVERLOO_CONFIDENCE: f64 = 0.95;

/// Label of the fit over the centred outlets of every hopper angle of a series, when the
/// series also holds off-centre outlets (otherwise its "all" group is that fit). The
/// paper's Fig. 2b fits one line through the W(D) points of all angles: C = 0.58,
/// k = 1.55.
pub const POOLED_ANGLES_LABEL: &str = "centred, all α";

/// One Beverloo fit over a group of grid points.
#[derive(Debug, Clone)]
pub struct BeverlooGroup {
    /// Series name.
    pub series: String,
    /// What the group holds, e.g. "α = 90°", "s = 0 mm", "all".
    pub label: String,
    /// Distinct outlet widths in the group.
    pub widths: usize,
    /// Distinct hopper angles in the group [°], ascending.
    pub hopper_angles: Vec<f64>,
    /// Whether every point of the group has a centred outlet.
    pub centred: bool,
    /// Bulk fraction φ_B used for ρ_b = φ_B ρ_p (mean measured over the group) [-].
    pub bulk_fraction: f64,
    /// Area fraction φ_2D used for ρ_p φ_2D (mean measured φ_c over the group) [-].
    pub area_fraction: f64,
    /// The fit.
    pub fit: Fitted<BeverlooFit>,
}

fn fit_group(series: &str, label: String, points: &[&GridPoint]) -> BeverlooGroup {
    let mut widths: Vec<f64> = points.iter().map(|p| p.outlet_width).collect();
    widths.sort_by(f64::total_cmp);
    widths.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    let mean = |f: fn(&GridPoint) -> f64| {
        let v: Vec<f64> = points
            .iter()
            .map(|p| f(p))
            .filter(|x| x.is_finite())
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    let mut hopper_angles: Vec<f64> = points.iter().map(|p| p.hopper_angle_deg).collect();
    hopper_angles.sort_by(f64::total_cmp);
    hopper_angles.dedup();
    let centred = points.iter().all(|p| p.is_centred());
    let bulk_fraction = mean(|p| p.bulk_volume_fraction);
    let area_fraction = mean(|p| p.centre_area_fraction.value);
    let fit = match points.first() {
        None => Err("no points".to_string()),
        Some(_) if widths.len() < 3 => Err(format!(
            "{} outlet width(s); the fit needs at least 3",
            widths.len()
        )),
        Some(first) => common_gravity(points.iter().copied()).and_then(|gravity| {
            let normalisation = BeverlooNormalisation {
                slab_thickness: first.thickness,
                particle_diameter: first.particle_diameter,
                particle_density: first.particle_density,
                bulk_fraction,
                area_fraction,
                gravity,
            };
            let d: Vec<f64> = points.iter().map(|p| p.outlet_width).collect();
            let w: Vec<f64> = points.iter().map(|p| p.discharge_rate.value).collect();
            let e: Vec<f64> = points
                .iter()
                .map(|p| p.discharge_rate.standard_error)
                .collect();
            let errors = e
                .iter()
                .all(|x| x.is_finite() && *x > 0.0)
                .then_some(&e[..]);
            fit_beverloo_2d(&d, &w, errors, &normalisation, BEVERLOO_CONFIDENCE)
                .map_err(|e| e.to_string())
        }),
    };
    BeverlooGroup {
        series: series.to_string(),
        label,
        widths: widths.len(),
        hopper_angles,
        centred,
        bulk_fraction,
        area_fraction,
        fit,
    }
}

/// Beverloo fits: for each series all its points with one material and slab, then per
/// hopper angle (centred outlets; with the centred outlets of all angles together first,
/// [`POOLED_ANGLES_LABEL`], when the series also holds off-centre ones) and per outlet gap
/// (off-centre outlets), and for off-centre series the paper's split s = 0 against s ≠ 0
/// (Fig. 15b).
pub fn fit_beverloo_groups(points: &[GridPoint]) -> Vec<BeverlooGroup> {
    let mut series: Vec<&str> = points.iter().map(|p| p.series.as_str()).collect();
    series.sort();
    series.dedup();
    let mut groups = Vec::new();
    for name in series {
        let members: Vec<&GridPoint> = points.iter().filter(|p| p.series == name).collect();
        groups.push(fit_group(name, "all".into(), &members));
        let mut angles: Vec<f64> = members
            .iter()
            .filter(|p| p.is_centred())
            .map(|p| p.hopper_angle_deg)
            .collect();
        angles.sort_by(f64::total_cmp);
        angles.dedup();
        if angles.len() > 1 {
            // Fig. 2b's pooled fit; the "all" group already is it when every point of the
            // series is centred.
            if members.iter().any(|p| !p.is_centred()) {
                let centred: Vec<&GridPoint> =
                    members.iter().copied().filter(|p| p.is_centred()).collect();
                groups.push(fit_group(name, POOLED_ANGLES_LABEL.into(), &centred));
            }
            for angle in angles {
                let group: Vec<&GridPoint> = members
                    .iter()
                    .copied()
                    .filter(|p| p.is_centred() && p.hopper_angle_deg == angle)
                    .collect();
                groups.push(fit_group(name, format!("α = {angle}°"), &group));
            }
        }
        let mut gaps: Vec<f64> = members
            .iter()
            .filter(|p| !p.is_centred())
            .map(|p| p.outlet_gap)
            .collect();
        gaps.sort_by(f64::total_cmp);
        gaps.dedup();
        if gaps.len() > 1 {
            for gap in &gaps {
                let group: Vec<&GridPoint> = members
                    .iter()
                    .copied()
                    .filter(|p| !p.is_centred() && p.outlet_gap == *gap)
                    .collect();
                groups.push(fit_group(name, format!("s = {} mm", gap * 1e3), &group));
            }
            if gaps[0] == 0.0 {
                let others: Vec<&GridPoint> = members
                    .iter()
                    .copied()
                    .filter(|p| !p.is_centred() && p.outlet_gap > 0.0)
                    .collect();
                groups.push(fit_group(name, "s ≠ 0".into(), &others));
            }
        }
    }
    groups
}

/// The fit of Fig. 2b in `series`: one line through the centred W(D) points of every
/// hopper angle, or why there is none (no centred points, a single angle).
pub fn pooled_angle_fit<'a>(
    groups: &'a [BeverlooGroup],
    series: &str,
) -> Result<&'a BeverlooGroup, String> {
    let in_series: Vec<&BeverlooGroup> = groups.iter().filter(|g| g.series == series).collect();
    if in_series.is_empty() {
        return Err(format!("no cases in series '{series}'"));
    }
    let pooled = in_series
        .iter()
        .find(|g| g.label == POOLED_ANGLES_LABEL)
        .or_else(|| in_series.iter().find(|g| g.label == "all" && g.centred))
        .copied()
        .ok_or_else(|| {
            format!("series '{series}' has no centred outlets at two or more hopper angles")
        })?;
    if pooled.hopper_angles.len() < 2 {
        return Err(format!(
            "centred outlets at one hopper angle only ({}°); the pooled fit needs two or more",
            pooled.hopper_angles.first().copied().unwrap_or(f64::NAN)
        ));
    }
    Ok(pooled)
}
