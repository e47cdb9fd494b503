//! The report's tables (ours beside the paper's), as document blocks.

use analysis::Estimate;

use super::centred::width_gamma;
use super::comparison::ComparisonItem;
use super::data::StudyData;
use super::document::Block;
use super::{Fitted, StudyAnalysis};

/// Table 2 of the paper: (α [°], a, γ, b, φ∞).
pub const PAPER_TABLE2: [(f64, f64, f64, f64, f64); 5] = [
    (15.0, 0.20, 2.81, 0.16, 0.79),
    (30.0, 0.32, 2.08, 0.19, 0.79),
    (55.0, 0.35, 1.61, 0.30, 0.78),
    (75.0, 0.33, 1.64, 0.38, 0.78),
    (90.0, 0.39, 1.66, 0.39, 0.78),
];

/// Table 3 of the paper: (s [mm], δ_s1, δ_s2, ε_s1, ε_s2, σ_s1, σ_s2).
pub const PAPER_TABLE3: [(f64, f64, f64, f64, f64, f64, f64); 6] = [
    (0.0, -0.31, -0.13, 1.46, 1.0, 0.28, 0.32),
    (6.0, -0.09, -0.02, 1.3, 1.0, 0.32, 0.44),
    (12.0, -0.06, -0.007, 1.3, 1.0, 0.37, 0.42),
    (18.0, -0.04, 0.008, 1.3, 1.0, 0.40, 0.40),
    (24.0, -0.01, -0.002, 1.3, 1.0, 0.38, 0.43),
    (30.0, -0.02, 0.002, 1.3, 1.0, 0.38, 0.41),
];

/// "value ± error" with three significant decimals, or the reason it is missing.
pub fn estimate(value: &Fitted<Estimate>) -> String {
    match value {
        Ok(e) if e.standard_error.is_finite() => {
            format!("{:.3} ± {:.3}", e.value, e.standard_error)
        }
        Ok(e) => format!("{:.3}", e.value),
        Err(why) => format!("not measured ({why})"),
    }
}

/// [`estimate`] of one field of a fit, or the fit's reason for missing.
fn estimate_of<T>(value: &Fitted<T>, field: impl FnOnce(&T) -> Estimate) -> String {
    estimate(&value.as_ref().map(field).map_err(Clone::clone))
}

fn number(value: &serde_json::Value) -> String {
    match value {
        serde_json::Value::Number(n) => n.as_f64().map_or(n.to_string(), |x| format!("{x:.4}")),
        serde_json::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

fn table(headers: &[&str], rows: Vec<Vec<String>>) -> Block {
    Block::Table {
        headers: headers.iter().map(|h| h.to_string()).collect(),
        rows,
    }
}

/// The comparison items with pass/fail and the size of each miss.
pub fn comparison_table(items: &[ComparisonItem]) -> Block {
    table(
        &["item", "paper", "ours", "band", "result", "miss / note"],
        items
            .iter()
            .map(|i| {
                vec![
                    i.item.clone(),
                    number(&i.paper),
                    number(&i.measured),
                    i.band.clone(),
                    match i.pass {
                        Some(true) => "pass".into(),
                        Some(false) => "FAIL".into(),
                        None if i.measured.is_number() => "reference".into(),
                        None => "not measured".into(),
                    },
                    i.note.clone(),
                ]
            })
            .collect(),
    )
}

/// Table 2, ours beside the paper's, per series and angle.
pub fn table2(analysis: &StudyAnalysis) -> Block {
    let rows = analysis
        .angles
        .iter()
        .map(|f| {
            let paper = PAPER_TABLE2.iter().find(|p| p.0 == f.hopper_angle_deg);
            let show = |x: Option<f64>| x.map_or("—".to_string(), |x| format!("{x}"));
            vec![
                f.series.clone(),
                format!("{}", f.hopper_angle_deg),
                f.points.len().to_string(),
                estimate(&f.velocity_exponent),
                show(paper.map(|p| p.1)),
                estimate_of(&f.centre_velocity, |c| c.gamma),
                show(paper.map(|p| p.2)),
                estimate(&f.packing_exponent),
                estimate(&f.crossing_packing_exponent),
                show(paper.map(|p| p.3)),
                estimate_of(&f.saturation, |s| s.phi_infinity),
                show(paper.map(|p| p.4)),
                estimate_of(&f.saturation, |s| s.tau1),
                estimate_of(&f.saturation, |s| s.tau2_per_millimetre),
            ]
        })
        .collect();
    table(
        &[
            "series",
            "α [°]",
            "widths",
            "a",
            "a paper",
            "γ",
            "γ paper",
            "b (strip)",
            "b (crossing)",
            "b paper",
            "φ∞",
            "φ∞ paper",
            "τ₁",
            "τ₂ [1/mm]",
        ],
        rows,
    )
}

/// γ_D = v_c²/(2gR) of each width beside the fitted γ, per series and angle.
pub fn width_gamma_table(analysis: &StudyAnalysis) -> Block {
    let mut widths: Vec<f64> = analysis
        .angles
        .iter()
        .flat_map(|f| f.points.iter().map(|p| p.outlet_width))
        .collect();
    widths.sort_by(f64::total_cmp);
    widths.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    let rows = analysis
        .angles
        .iter()
        .map(|f| {
            let mut row = vec![f.series.clone(), format!("{}", f.hopper_angle_deg)];
            row.extend(widths.iter().map(|&d| {
                f.points
                    .iter()
                    .find(|p| (p.outlet_width - d).abs() < 1e-12)
                    .map_or("—".to_string(), |p| estimate(&Ok(width_gamma(p))))
            }));
            row.push(estimate_of(&f.centre_velocity, |c| c.gamma));
            row
        })
        .collect();
    let labels: Vec<String> = widths
        .iter()
        .map(|d| format!("γ_D, D = {:.0} mm", d * 1e3))
        .collect();
    let mut headers = vec!["series", "α [°]"];
    headers.extend(labels.iter().map(String::as_str));
    headers.push("γ (fit)");
    table(&headers, rows)
}

/// Beverloo constants beside the paper's (C = 0.58, k = 1.55 overall; Fig. 8b, Fig. 15b).
pub fn beverloo_table(analysis: &StudyAnalysis) -> Block {
    let paper = |g: &super::beverloo::BeverlooGroup| match g.label.as_str() {
        // Fig. 2b: one line through the centred outlets of every angle.
        "all" if !(g.series == super::ANGLE_SERIES && g.centred) => "—",
        "α = 15°" => "C 0.72",
        "α = 30°" => "C 0.65",
        "α = 55°" | "α = 75°" => "C ≈ 0.55",
        "α = 90°" => "C ≈ 0.55; k: LIGGGHTS 3.8 2.12, LAMMPS 2.19",
        "s = 0 mm" => "C 0.60",
        "s ≠ 0" => "C 0.52",
        "all" | super::beverloo::POOLED_ANGLES_LABEL => "C 0.58, k 1.55 (all α pooled)",
        _ => "—",
    };
    let rows = analysis
        .beverloo
        .iter()
        .map(|g| {
            let mut row = vec![g.series.clone(), g.label.clone(), g.widths.to_string()];
            match &g.fit {
                Ok(f) => {
                    let c = |d: &analysis::beverloo::DischargeCoefficient| {
                        format!(
                            "{:.3} [{:.3}, {:.3}]",
                            d.coefficient.value, d.interval.lower, d.interval.upper
                        )
                    };
                    row.push(format!(
                        "{:.2} [{:.2}, {:.2}]",
                        f.k.value, f.k_interval.lower, f.k_interval.upper
                    ));
                    row.push(c(&f.coefficients.bulk_density));
                    row.push(c(&f.coefficients.particle_density));
                    row.push(c(&f.coefficients.area_fraction_density));
                }
                Err(why) => {
                    row.push(format!("not measured ({why})"));
                    row.extend(["—".to_string(), "—".to_string(), "—".to_string()]);
                }
            }
            row.push(format!("{:.3} / {:.3}", g.bulk_fraction, g.area_fraction));
            row.push(paper(g).to_string());
            row
        })
        .collect();
    table(
        &[
            "series",
            "group",
            "widths",
            "k (95 % CI)",
            "C, ρ = φ_B ρ_p",
            "C, ρ = ρ_p",
            "C, ρ = φ_2D ρ_p",
            "φ_B / φ_2D used",
            "paper",
        ],
        rows,
    )
}

/// Eq. 14 against the measured W for every centred point.
pub fn eq14_table(analysis: &StudyAnalysis) -> Block {
    let mut rows = Vec::new();
    for f in &analysis.angles {
        for (p, predicted) in f.points.iter().zip(&f.predicted_rates) {
            let ratio = match predicted {
                Ok(w) => format!("{:.3}", p.discharge_rate.value / w.value),
                Err(_) => "—".into(),
            };
            rows.push(vec![
                f.series.clone(),
                format!("{}", f.hopper_angle_deg),
                format!("{}", p.outlet_width * 1e3),
                format!(
                    "{:.1} ± {:.1}",
                    p.discharge_rate.value * 1e3,
                    p.discharge_rate.standard_error * 1e3
                ),
                match predicted {
                    Ok(w) => format!("{:.1} ± {:.1}", w.value * 1e3, w.standard_error * 1e3),
                    Err(why) => format!("not measured ({why})"),
                },
                ratio,
                estimate(&Ok(p.centre_velocity)),
            ]);
        }
    }
    table(
        &[
            "series",
            "α [°]",
            "D [mm]",
            "W measured [g/s]",
            "W Eq. 14 [g/s]",
            "measured/Eq. 14",
            "v_c [m/s]",
        ],
        rows,
    )
}

/// W(α)/W(90°) against Brown and Rose–Tanaka.
pub fn angle_ratio_table(analysis: &StudyAnalysis) -> Block {
    table(
        &[
            "series",
            "α [°]",
            "D [mm]",
            "W(α)/W(90°)",
            "Brown Eq. 3",
            "Rose–Tanaka",
        ],
        analysis
            .angle_ratios
            .iter()
            .map(|r| {
                vec![
                    r.series.clone(),
                    format!("{}", r.hopper_angle_deg),
                    format!("{}", r.outlet_width * 1e3),
                    format!("{:.3} ± {:.3}", r.measured.value, r.measured.standard_error),
                    format!("{:.3}", r.brown),
                    format!("{:.3}", r.rose_tanaka),
                ]
            })
            .collect(),
    )
}

/// Table 3, ours beside the paper's.
pub fn table3(analysis: &StudyAnalysis) -> Block {
    let rows = analysis
        .eccentric
        .gaps
        .iter()
        .map(|g| {
            let s_mm = g.outlet_gap * 1e3;
            let paper = PAPER_TABLE3.iter().find(|p| (p.0 - s_mm).abs() < 1e-9);
            let p = |x: Option<f64>| x.map_or("—".to_string(), |x| format!("{x}"));
            vec![
                g.series.clone(),
                format!("{s_mm}"),
                estimate_of(&g.fits.velocity, |f| f.asymmetry),
                p(paper.map(|r| r.1)),
                estimate_of(&g.fits.packing, |f| f.asymmetry),
                p(paper.map(|r| r.2)),
                estimate_of(&g.fits.velocity, |f| f.amplitude),
                p(paper.map(|r| r.3)),
                estimate_of(&g.fits.velocity, |f| f.exponent),
                p(paper.map(|r| r.5)),
                estimate_of(&g.fits.packing, |f| f.exponent),
                p(paper.map(|r| r.6)),
            ]
        })
        .collect();
    table(
        &[
            "series", "s [mm]", "δ_s1", "paper", "δ_s2", "paper", "ε_s1", "paper", "σ_s1", "paper",
            "σ_s2", "paper",
        ],
        rows,
    )
}

/// Eq. 18 and W/W0 for every off-centre point.
pub fn eccentric_rate_table(analysis: &StudyAnalysis) -> Block {
    table(
        &[
            "series",
            "s [mm]",
            "D [mm]",
            "s*",
            "W measured [g/s]",
            "W Eq. 18 [g/s]",
            "W/W0",
        ],
        analysis
            .eccentric
            .points
            .iter()
            .map(|p| {
                vec![
                    p.point.series.clone(),
                    format!("{}", p.point.outlet_gap * 1e3),
                    format!("{}", p.point.outlet_width * 1e3),
                    format!("{:.3}", p.point.dimensionless_gap),
                    format!("{:.1}", p.point.discharge_rate.value * 1e3),
                    match &p.predicted_rate {
                        Ok(w) => format!("{:.1} ± {:.1}", w.value * 1e3, w.standard_error * 1e3),
                        Err(why) => format!("not measured ({why})"),
                    },
                    estimate(&p.relative_rate.clone()),
                ]
            })
            .collect(),
    )
}

/// Fits of σ_s1(s*) and φ_max(R) beside the paper's.
pub fn eccentric_fit_blocks(analysis: &StudyAnalysis) -> Vec<Block> {
    let mut rows = Vec::new();
    for (series, fit) in &analysis.eccentric.exponent_fits {
        rows.push(match fit {
            Ok(f) => vec![
                series.clone(),
                "σ_s1 = c₀ − c₁ e^(−c₂ s*)".into(),
                format!(
                    "c₀ {}, c₁ {}, c₂ {}",
                    estimate(&Ok(f.limit)),
                    estimate(&Ok(f.amplitude)),
                    if f.rate_resolved {
                        estimate(&Ok(f.rate))
                    } else {
                        "not determined (σ_s1 reaches its plateau by the smallest s* > 0: a step at s* = 0)".into()
                    }
                ),
                "c₀ 0.39, c₁ 0.12, c₂ 3.74".into(),
            ],
            Err(why) => vec![
                series.clone(),
                "σ_s1(s*)".into(),
                format!("not measured ({why})"),
                "c₀ 0.39, c₁ 0.12, c₂ 3.74".into(),
            ],
        });
    }
    for (series, label, fit) in &analysis.eccentric.maximum_packing_fits {
        let paper = if label == "s = 0" {
            "τ₁ 3.74, τ₂ 0.18"
        } else {
            "τ₁ 5.34, τ₂ 0.19"
        };
        rows.push(match fit {
            Ok(f) => vec![
                series.clone(),
                format!("φ_max(R), {label}"),
                format!(
                    "φ∞ {}, τ₁ {}, τ₂ {} /mm",
                    estimate(&Ok(f.phi_infinity)),
                    estimate(&Ok(f.tau1)),
                    estimate(&Ok(f.tau2_per_millimetre))
                ),
                paper.into(),
            ],
            Err(why) => vec![
                series.clone(),
                format!("φ_max(R), {label}"),
                format!("not measured ({why})"),
                paper.into(),
            ],
        });
    }
    vec![table(&["series", "fit", "ours", "paper"], rows)]
}

/// Every case with its status and seed.
pub fn cases_table(data: &StudyData) -> Block {
    table(
        &["case", "status", "W [g/s]", "seed"],
        data.rows
            .iter()
            .map(|r| {
                vec![
                    r.id.clone(),
                    r.status.as_str().to_string(),
                    if r.discharge_rate.is_finite() {
                        format!("{:.2}", r.discharge_rate * 1e3)
                    } else {
                        "—".into()
                    },
                    r.seed.to_string(),
                ]
            })
            .collect(),
    )
}
