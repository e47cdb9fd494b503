//! The comparison items of the report: each paper target with our value, the acceptance
//! band, pass or fail, and for a miss, by how much (physics spec §9 B3).

use analysis::Estimate;
use serde::Serialize;
use serde_json::{json, Value};

use super::centred::{AngleFit, AngleRatio};
use super::StudyAnalysis;

/// The series whose centred outlets give the paper's angle items.
pub const ANGLE_SERIES: &str = "angle";
/// The series whose off-centre outlets give the eccentric items.
pub const ECCENTRIC_SERIES: &str = "eccentric";
/// Relative spread allowed for "flat from 55° to 90°" (the paper's largest deviation in
/// Fig. 8c is 4.6 %; its γ values spread 3 %).
pub const FLAT_TOLERANCE: f64 = 0.10;

/// One row of `comparison.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ComparisonItem {
    /// What is compared.
    pub item: String,
    /// The paper's value (a number or, for trends, a text).
    pub paper: Value,
    /// Ours (a number, a text for trends, or "not measured").
    pub measured: Value,
    /// The acceptance band.
    pub band: String,
    /// Pass or fail; `null` when not measured.
    pub pass: Option<bool>,
    /// For a miss: by how much; for "not measured": why. Not written to the JSON.
    #[serde(skip)]
    pub note: String,
}

fn not_measured(item: &str, paper: Value, band: &str, why: String) -> ComparisonItem {
    ComparisonItem {
        item: item.into(),
        paper,
        measured: json!("not measured"),
        band: band.into(),
        pass: None,
        note: why,
    }
}

/// A value checked against [low, high].
fn in_range(
    item: &str,
    paper: f64,
    value: Result<Estimate, String>,
    low: f64,
    high: f64,
) -> ComparisonItem {
    let band = format!("[{}, {}]", trim(low), trim(high));
    match value {
        Err(why) => not_measured(item, json!(paper), &band, why),
        Ok(v) if !v.value.is_finite() => not_measured(
            item,
            json!(paper),
            &band,
            "the fit gave no finite value".into(),
        ),
        Ok(v) => {
            let pass = v.value >= low && v.value <= high;
            let note = if pass {
                String::new()
            } else if v.value < low {
                format!(
                    "{:.3} below the band ({:.1} % under {low})",
                    low - v.value,
                    100.0 * (low - v.value) / low
                )
            } else {
                format!(
                    "{:.3} above the band ({:.1} % over {high})",
                    v.value - high,
                    100.0 * (v.value - high) / high
                )
            };
            ComparisonItem {
                item: item.into(),
                paper: json!(paper),
                measured: json!(v.value),
                band,
                pass: Some(pass),
                note: if v.standard_error.is_finite() && !pass {
                    format!("{note}; ours is {:.3} ± {:.3}", v.value, v.standard_error)
                } else {
                    note
                },
            }
        }
    }
}

fn angle_fit(analysis: &StudyAnalysis, angle: f64) -> Result<&AngleFit, String> {
    analysis
        .angles
        .iter()
        .find(|f| f.series == ANGLE_SERIES && f.hopper_angle_deg == angle)
        .ok_or_else(|| format!("no centred {angle}° cases in series '{ANGLE_SERIES}'"))
}

/// Mean W(α)/W(90°) over the outlet widths of the angle series.
fn mean_ratio(ratios: &[AngleRatio], angle: f64) -> Option<f64> {
    let v: Vec<f64> = ratios
        .iter()
        .filter(|r| r.series == ANGLE_SERIES && r.hopper_angle_deg == angle)
        .map(|r| r.measured.value)
        .collect();
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

/// "Rises as α falls below 55°": the values at the measured angles below 55°, then the
/// reference (55° if measured, else the mean over 55–90°), must strictly decrease.
fn rises(item: &str, paper: &str, values: &[(f64, f64)]) -> ComparisonItem {
    let band = "strictly decreasing in α for α ≤ 55°".to_string();
    let below: Vec<(f64, f64)> = values.iter().copied().filter(|(a, _)| *a < 55.0).collect();
    let flat: Vec<(f64, f64)> = values.iter().copied().filter(|(a, _)| *a >= 55.0).collect();
    if below.is_empty() || flat.is_empty() {
        return not_measured(
            item,
            json!(paper),
            &band,
            "needs one angle below 55° and one from 55° to 90°".into(),
        );
    }
    // The reference is the 55° value when measured, else the mean over the measured
    // angles from 55° to 90°; its label says which.
    let (reference, reference_label) = match flat.iter().find(|(a, _)| *a == 55.0) {
        Some((_, v)) => (*v, "55°".to_string()),
        None => {
            let angles: Vec<String> = flat.iter().map(|(a, _)| format!("{a}°")).collect();
            (
                flat.iter().map(|(_, v)| v).sum::<f64>() / flat.len() as f64,
                format!("mean of {}", angles.join(", ")),
            )
        }
    };
    let mut chain: Vec<(String, f64)> = below.iter().map(|(a, v)| (format!("{a}°"), *v)).collect();
    chain.push((reference_label, reference));
    let text = chain
        .iter()
        .map(|(a, v)| format!("{v:.3} ({a})"))
        .collect::<Vec<_>>()
        .join(" > ");
    let misses: Vec<String> = chain
        .windows(2)
        .filter(|w| w[0].1 <= w[1].1)
        .map(|w| {
            format!(
                "{} is {:.3} not above {} ({:.3}), short by {:.1} %",
                w[0].0,
                w[0].1,
                w[1].0,
                w[1].1,
                100.0 * (w[1].1 - w[0].1) / w[1].1
            )
        })
        .collect();
    ComparisonItem {
        item: item.into(),
        paper: json!(paper),
        measured: json!(text),
        band,
        pass: Some(misses.is_empty()),
        note: misses.join("; "),
    }
}

/// "Flat from 55° to 90°": every value within ±[`FLAT_TOLERANCE`] of their mean.
fn flat(item: &str, paper: &str, values: &[(f64, f64)]) -> ComparisonItem {
    let band = format!(
        "within ±{:.0} % of their mean for 55° ≤ α ≤ 90°",
        100.0 * FLAT_TOLERANCE
    );
    let inside: Vec<(f64, f64)> = values.iter().copied().filter(|(a, _)| *a >= 55.0).collect();
    if inside.len() < 2 {
        return not_measured(
            item,
            json!(paper),
            &band,
            "needs two angles from 55° to 90°".into(),
        );
    }
    let mean = inside.iter().map(|(_, v)| v).sum::<f64>() / inside.len() as f64;
    let worst = inside
        .iter()
        .map(|(a, v)| (*a, (v - mean) / mean))
        .max_by(|x, y| x.1.abs().total_cmp(&y.1.abs()))
        .unwrap_or((0.0, 0.0));
    let pass = worst.1.abs() <= FLAT_TOLERANCE;
    ComparisonItem {
        item: item.into(),
        paper: json!(paper),
        measured: json!(inside
            .iter()
            .map(|(a, v)| format!("{v:.3} ({a}°)"))
            .collect::<Vec<_>>()
            .join(", ")),
        band,
        pass: Some(pass),
        note: if pass {
            String::new()
        } else {
            format!(
                "{}° deviates {:+.1} % from the mean, {:.1} points beyond ±{:.0} %",
                worst.0,
                100.0 * worst.1,
                100.0 * (worst.1.abs() - FLAT_TOLERANCE),
                100.0 * FLAT_TOLERANCE
            )
        },
    }
}

/// The comparison items of physics spec §9 B3 and the issue, in a fixed order.
pub fn compare_with_paper(analysis: &StudyAnalysis) -> Vec<ComparisonItem> {
    let mut items = Vec::new();
    let k = analysis
        .beverloo
        .iter()
        .find(|g| g.series == ANGLE_SERIES && g.label == "α = 90°")
        .ok_or_else(|| format!("no flat-bottom centred cases in series '{ANGLE_SERIES}'"))
        .and_then(|g| g.fit.as_ref().map(|f| f.k).map_err(Clone::clone));
    items.push(in_range("Beverloo k (α = 90°)", 1.55, k, 1.3, 1.8));

    let flat_fit = angle_fit(analysis, 90.0);
    let gamma = flat_fit.clone().and_then(|f| {
        f.centre_velocity
            .as_ref()
            .map(|c| c.gamma)
            .map_err(Clone::clone)
    });
    items.push(in_range("γ(90°)", 1.66, gamma, 1.66 * 0.8, 1.66 * 1.2));
    let a = flat_fit.clone().and_then(|f| f.velocity_exponent.clone());
    items.push(in_range("a(90°)", 0.39, a, 0.29, 0.49));
    let b = flat_fit.clone().and_then(|f| f.packing_exponent.clone());
    items.push(in_range("b(90°)", 0.39, b, 0.29, 0.49));
    let phi = flat_fit.and_then(|f| {
        f.saturation
            .as_ref()
            .map(|s| s.phi_infinity)
            .map_err(Clone::clone)
    });
    items.push(in_range("φ∞(90°)", 0.78, phi, 0.75, 0.81));

    let gammas: Vec<(f64, f64)> = analysis
        .angles
        .iter()
        .filter(|f| f.series == ANGLE_SERIES)
        .filter_map(|f| {
            f.centre_velocity
                .as_ref()
                .ok()
                .map(|c| (f.hopper_angle_deg, c.gamma.value))
        })
        .collect();
    items.push(rises(
        "Table 2 trend: γ rises as α falls below 55°",
        "2.81 (15°) > 2.08 (30°) > 1.61 (55°)",
        &gammas,
    ));
    items.push(flat(
        "Table 2 trend: γ flat from 55° to 90°",
        "1.61, 1.64, 1.66",
        &gammas,
    ));
    let mut ratios: Vec<(f64, f64)> = analysis
        .angles
        .iter()
        .filter(|f| f.series == ANGLE_SERIES)
        .filter_map(|f| {
            if f.hopper_angle_deg == 90.0 {
                Some((90.0, 1.0))
            } else {
                mean_ratio(&analysis.angle_ratios, f.hopper_angle_deg)
                    .map(|r| (f.hopper_angle_deg, r))
            }
        })
        .collect();
    ratios.sort_by(|x, y| x.0.total_cmp(&y.0));
    items.push(rises(
        "Table 2 trend: W rises as α falls below 55°",
        "W(α)/W(90°): 1.650 (15°) > 1.208 (30°) > 0.995 (55°) (Brown, Fig. 8c)",
        &ratios,
    ));
    items.push(flat(
        "Table 2 trend: W flat from 55° to 90°",
        "W(α)/W(90°): 0.995, 0.975, 1",
        &ratios,
    ));

    let wall: Vec<Estimate> = analysis
        .eccentric
        .points
        .iter()
        .filter(|p| p.point.series == ECCENTRIC_SERIES && p.point.outlet_gap == 0.0)
        .filter_map(|p| p.relative_rate.as_ref().ok().copied())
        .collect();
    let gain = if wall.is_empty() {
        Err(format!(
            "no s = 0 cases in series '{ECCENTRIC_SERIES}' with a centred flat-bottom case of the same width"
        ))
    } else {
        let n = wall.len() as f64;
        let mean = wall.iter().map(|e| e.value).sum::<f64>() / n;
        let error = wall
            .iter()
            .map(|e| e.standard_error.powi(2))
            .sum::<f64>()
            .sqrt()
            / n;
        Ok(Estimate::new(mean, error))
    };
    items.push(in_range("W(s = 0)/W0 (mean over D)", 1.3, gain, 1.15, 1.45));
    items
}

/// A band limit with round-off from its derivation removed (1.9919999999999998 → 1.992).
fn trim(x: f64) -> String {
    let s = format!("{x:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}
