//! Figures like the paper's Figs. 2–8 and 10–16, built from the analysis as plain
//! [`Figure`]s with captions that say what was measured and how.

use analysis::eccentric::{asymmetric_profile, exponential_approach};
use analysis::profile::BinnedProfile;
use analysis::selfsimilar::{packing_saturation, power_profile};

use super::comparison::{ANGLE_SERIES, ECCENTRIC_SERIES};
use super::{common_gravity, StudyAnalysis};
use files::{Axis, Figure, Series, PALETTE};

/// A figure with its file stem and caption.
pub struct ReportFigure {
    /// File stem under `figures/`.
    pub name: String,
    /// What was measured and how.
    pub caption: String,
    /// The plot.
    pub figure: Figure,
}

fn points_of(profile: &BinnedProfile, scale: f64) -> (Vec<f64>, Vec<f64>) {
    (0..profile.len())
        .filter(|&i| profile.counts[i] > 0 && profile.values[i].is_finite())
        .map(|i| (profile.centres[i], profile.values[i] / scale))
        .unzip()
}

fn curve(f: impl Fn(f64) -> f64) -> (Vec<f64>, Vec<f64>) {
    (0..=100)
        .map(|i| -1.0 + 0.02 * i as f64)
        .map(|x| (x, f(x)))
        .unzip()
}

/// The colour of group `g` of a figure: its points and its fit share it.
fn group_color(g: usize) -> [u8; 3] {
    PALETTE[g % PALETTE.len()]
}

/// The colour of a pooled fit drawn over the groups.
const POOLED: [u8; 3] = [0, 0, 0];

/// `figure` of W [g/s] against R with every series' ordinates raised to the 2/3 power (the
/// paper's Figs. 8b and 15b of its Figs. 8a and 15a), its error bars left out, under `title`.
fn two_thirds_power(figure: &Figure, title: &str) -> Figure {
    let mut powered = Figure::new(
        title,
        figure.x_axis.clone(),
        Axis::new("W^(2/3)", "(g/s)^(2/3)"),
    );
    for series in &figure.series {
        powered = powered.with_series(Series {
            y: series.y.iter().map(|w| w.powf(2.0 / 3.0)).collect(),
            y_error: None,
            ..series.clone()
        });
    }
    powered
}

fn push(out: &mut Vec<ReportFigure>, name: String, caption: String, figure: Figure) {
    if figure.series.iter().any(|s| !s.x.is_empty()) {
        out.push(ReportFigure {
            name,
            caption,
            figure,
        });
    }
}

/// Every figure the analysis supports; figures without data are left out.
pub fn report_figures(analysis: &StudyAnalysis) -> Vec<ReportFigure> {
    let mut out = Vec::new();
    // Fig. 2a: W(t) of the flat-bottom case with D/d closest to 10.
    let flat = analysis
        .angles
        .iter()
        .filter(|f| f.series == ANGLE_SERIES && f.hopper_angle_deg == 90.0)
        .flat_map(|f| f.points.iter())
        .filter(|p| p.flow.is_some())
        .min_by(|a, b| {
            let target =
                |p: &&super::GridPoint| (p.outlet_width / p.particle_diameter - 10.0).abs();
            target(a).total_cmp(&target(b))
        });
    if let Some(p) = flat {
        if let Some((t, w)) = &p.flow {
            let figure = Figure::new("W(t)", Axis::new("t", "s"), Axis::new("W", "g/s"))
                .with_series(Series::line(
                    "instantaneous",
                    t.clone(),
                    w.iter().map(|x| x * 1e3).collect(),
                ))
                .with_series(Series::line(
                    "steady mean",
                    vec![t[0], *t.last().unwrap_or(&t[0])],
                    vec![p.discharge_rate.value * 1e3; 2],
                ));
            push(&mut out, "fig02a-flow-rate".into(), format!(
                "Fig. 2a: mass flow rate through the outlet against time since the gate opened, {} (D/d = {:.0}, α = 90°), binned crossings of the outlet line; the line is W, the mean over the steady window.",
                p.key, p.outlet_width / p.particle_diameter), figure);
        }
    }
    // Fig. 2b: (W/Z)^{2/3} against D per angle, with Beverloo lines.
    let mut beverloo = Figure::new(
        "Fig. 2b: (W/Z)^(2/3) against outlet width, per hopper angle",
        Axis::new("D", "mm"),
        Axis::new("(W/Z)^(2/3)", "(kg/(m·s))^(2/3)"),
    );
    let mut widest = 0.0f64;
    for (g, f) in analysis.angles.iter().enumerate() {
        let (x, y): (Vec<f64>, Vec<f64>) = f
            .points
            .iter()
            .map(|p| {
                (
                    p.outlet_width * 1e3,
                    (p.discharge_rate.value / p.thickness).powf(2.0 / 3.0),
                )
            })
            .unzip();
        widest = widest.max(x.iter().cloned().fold(0.0, f64::max));
        beverloo = beverloo.with_series(
            Series::points(format!("{} α = {}°", f.series, f.hopper_angle_deg), x, y)
                .with_color(group_color(g)),
        );
        let group = analysis
            .beverloo
            .iter()
            .find(|g| g.series == f.series && g.label == format!("α = {}°", f.hopper_angle_deg));
        if let Some(Ok(fit)) = group.map(|g| &g.fit) {
            let d: Vec<f64> = f.points.iter().map(|p| p.outlet_width).collect();
            let lo = fit
                .kd
                .value
                .min(d.iter().cloned().fold(f64::INFINITY, f64::min));
            let hi = d.iter().cloned().fold(0.0, f64::max);
            let xs = vec![lo * 1e3, hi * 1e3];
            let ys = vec![
                fit.line.slope.value * lo + fit.line.intercept.value,
                fit.line.slope.value * hi + fit.line.intercept.value,
            ];
            beverloo = beverloo.with_series(Series::line("", xs, ys).with_color(group_color(g)));
        }
    }
    // The pooled fit over every angle, which the comparison's k item uses.
    if let Ok(pooled) = super::beverloo::pooled_angle_fit(&analysis.beverloo, ANGLE_SERIES) {
        if let Ok(fit) = &pooled.fit {
            let (lo, hi) = (fit.kd.value, widest * 1e-3);
            if hi > lo {
                let line = |d: f64| fit.line.slope.value * d + fit.line.intercept.value;
                beverloo = beverloo.with_series(
                    Series::line(
                        format!("{ANGLE_SERIES}, all α pooled"),
                        vec![lo * 1e3, hi * 1e3],
                        vec![line(lo), line(hi)],
                    )
                    .with_color(POOLED),
                );
            }
        }
    }
    push(&mut out, "fig02b-beverloo".into(), "Fig. 2b: steady discharge rate per unit slab thickness to the 2/3 power against outlet width, per hopper angle; lines are weighted least-squares fits of Eq. 1 (2D), whose x-intercept is k·d, in each angle's colour; the black line is the fit to every angle pooled, whose k the comparison table uses.".into(), beverloo);

    // Figs. 3 and 6: raw and normalised profiles per angle.
    for f in &analysis.angles {
        let tag = format!("{}-a{}", f.series, f.hopper_angle_deg);
        for (kind, fitted, label, unit, number) in [
            ("velocity", &f.velocity_exponent, "v", "m/s", 3),
            ("packing", &f.packing_exponent, "φ", "-", 6),
        ] {
            let mut raw = Figure::new(
                format!("α = {}°", f.hopper_angle_deg),
                Axis::new("x*", "-"),
                Axis::new(label, unit),
            );
            let mut norm = Figure::new(
                format!("α = {}°", f.hopper_angle_deg),
                Axis::new("x*", "-"),
                Axis::new(format!("{label}/{label}_c"), "-"),
            );
            for p in &f.points {
                let profile = if kind == "velocity" {
                    &p.velocity_profile
                } else {
                    &p.area_fraction_profile
                };
                if let Some(profile) = profile {
                    let (x, y) = points_of(profile, 1.0);
                    raw = raw.with_series(Series::points(
                        format!("D = {} mm", p.outlet_width * 1e3),
                        x,
                        y,
                    ));
                    if let Ok(centre) = profile.centre_value(analysis::profile::CENTRE_HALF_WIDTH) {
                        let (x, y) = points_of(profile, centre.value);
                        norm = norm.with_series(Series::points(
                            format!("D = {} mm", p.outlet_width * 1e3),
                            x,
                            y,
                        ));
                    }
                }
            }
            if let Ok(e) = fitted {
                let (x, y) = curve(|x| power_profile(x, 1.0, e.value));
                norm = norm.with_series(Series::line(format!("(1 − x*²)^{:.2}", e.value), x, y));
            }
            let what = if kind == "velocity" {
                "vertical velocity of particles crossing the outlet line, averaged per x* bin over the steady window"
            } else {
                "2D area fraction of particle mid-plane discs in a strip one diameter high at the outlet, averaged over frames in the steady window"
            };
            push(
                &mut out,
                format!("fig{number:02}-{kind}-{tag}"),
                format!(
                    "Fig. {number}a–d: {what}, {} α = {}°, per outlet width.",
                    f.series, f.hopper_angle_deg
                ),
                raw,
            );
            push(&mut out, format!("fig{number:02}-{kind}-normalised-{tag}"), format!("Fig. {number}e–h: the same profiles divided by their centre value (mean of |x*| < 0.1); the line is (1 − x*²)^p fitted to all widths pooled (|x*| ≤ 0.9)."), norm);
        }
    }
    // Fig. 4: v_c against √R; Fig. 7: φ_c against R; Fig. 5: a, b, γ against α.
    let mut fig4 = Figure::new(
        "Fig. 4: centre velocity against √R, per hopper angle",
        Axis::new("√R", "√m"),
        Axis::new("v_c", "m/s"),
    );
    let mut fig7 = Figure::new(
        "Fig. 7: centre area fraction against R, per hopper angle",
        Axis::new("R", "mm"),
        Axis::new("φ_c", "-"),
    );
    let (mut alpha_a, mut a, mut alpha_b, mut b, mut alpha_g, mut g) =
        (vec![], vec![], vec![], vec![], vec![], vec![]);
    for (group, f) in analysis.angles.iter().enumerate() {
        let colour = group_color(group);
        let label = format!("{} α = {}°", f.series, f.hopper_angle_deg);
        let (x, y): (Vec<f64>, Vec<f64>) = f
            .points
            .iter()
            .map(|p| (p.radius().sqrt(), p.centre_velocity.value))
            .unzip();
        fig4 = fig4.with_series(Series::points(label.clone(), x.clone(), y).with_color(colour));
        // A fitted v_c implies one g over the group's points.
        if let (Ok(c), Ok(gravity)) = (&f.centre_velocity, common_gravity(&f.points)) {
            let xs: Vec<f64> = (0..=20)
                .map(|i| 0.05 * i as f64 * x.iter().cloned().fold(0.0, f64::max))
                .collect();
            let ys = xs
                .iter()
                .map(|s| (2.0 * c.gamma.value * gravity).sqrt() * s)
                .collect();
            fig4 = fig4.with_series(Series::line("", xs, ys).with_color(colour));
            if f.series == ANGLE_SERIES {
                alpha_g.push(f.hopper_angle_deg);
                g.push(c.gamma.value);
            }
        }
        let (x, y): (Vec<f64>, Vec<f64>) = f
            .points
            .iter()
            .map(|p| (p.radius() * 1e3, p.centre_area_fraction.value))
            .unzip();
        fig7 = fig7.with_series(Series::points(label, x.clone(), y).with_color(colour));
        if let Ok(s) = &f.saturation {
            let hi = x.iter().cloned().fold(0.0, f64::max);
            let xs: Vec<f64> = (1..=40).map(|i| hi * i as f64 / 40.0).collect();
            let ys = xs
                .iter()
                .map(|r| {
                    packing_saturation(
                        r * 1e-3,
                        s.phi_infinity.value,
                        s.tau1.value,
                        s.tau2_per_millimetre.value,
                    )
                })
                .collect();
            fig7 = fig7.with_series(Series::line("", xs, ys).with_color(colour));
        }
        if f.series == ANGLE_SERIES {
            if let Ok(e) = &f.velocity_exponent {
                alpha_a.push(f.hopper_angle_deg);
                a.push(e.value);
            }
            if let Ok(e) = &f.packing_exponent {
                alpha_b.push(f.hopper_angle_deg);
                b.push(e.value);
            }
        }
    }
    push(&mut out, "fig04-centre-velocity".into(), "Fig. 4: centre velocity v_c (mean of the |x*| < 0.1 bins) against √R; lines are v_c = √(2γgR) fitted per angle by least squares in v_c.".into(), fig4);
    let mut fig5 = Figure::new("exponents", Axis::new("α", "°"), Axis::new("a, b, γ", "-"))
        .with_series(Series::points("a", alpha_a, a))
        .with_series(Series::points("b", alpha_b, b))
        .with_series(Series::points("γ", alpha_g, g));
    let (pa, pg): (Vec<f64>, Vec<f64>) = super::tables::PAPER_TABLE2
        .iter()
        .map(|r| (r.0, r.2))
        .unzip();
    fig5 = fig5.with_series(Series::line("γ paper", pa.clone(), pg));
    fig5 = fig5.with_series(Series::line(
        "a paper",
        pa,
        super::tables::PAPER_TABLE2.iter().map(|r| r.1).collect(),
    ));
    push(&mut out, "fig05-exponents".into(), "Fig. 5: profile exponents a (velocity) and b (area fraction) and the free-fall factor γ against hopper angle, angle series; lines join the paper's Table 2 values.".into(), fig5);
    push(&mut out, "fig07-centre-fraction".into(), "Fig. 7: centre area fraction φ_c against outlet half-width R; lines are Eq. 12, φ_c = φ∞(1 − τ₁e^(−2τ₂R)) with R in mm.".into(), fig7);

    // Fig. 8a: W against R with Eq. 14; Fig. 8b: W^(2/3) against R, the same; Fig. 8c:
    // W(α)/W(90°).
    let mut fig8a = Figure::new(
        "Fig. 8a: discharge rate against R, with Eq. 14, per hopper angle",
        Axis::new("R", "mm"),
        Axis::new("W", "g/s"),
    );
    for (group, f) in analysis.angles.iter().enumerate() {
        let (x, y): (Vec<f64>, Vec<f64>) = f
            .points
            .iter()
            .map(|p| (p.radius() * 1e3, p.discharge_rate.value * 1e3))
            .unzip();
        let e: Vec<f64> = f
            .points
            .iter()
            .map(|p| p.discharge_rate.standard_error * 1e3)
            .map(|e| if e.is_finite() { e } else { 0.0 })
            .collect();
        let label = format!("{} α = {}°", f.series, f.hopper_angle_deg);
        fig8a = fig8a.with_series(
            Series::points(label, x.clone(), y)
                .with_y_error(e)
                .with_color(group_color(group)),
        );
        let predicted: Vec<(f64, f64)> = x
            .iter()
            .zip(&f.predicted_rates)
            .filter_map(|(r, w)| w.as_ref().ok().map(|w| (*r, w.value * 1e3)))
            .collect();
        if !predicted.is_empty() {
            let (x, y) = predicted.into_iter().unzip();
            fig8a = fig8a.with_series(Series::line("", x, y).with_color(group_color(group)));
        }
    }
    let fig8b = two_thirds_power(
        &fig8a,
        "Fig. 8b: discharge rate to the 2/3 power against R, with Eq. 14, per hopper angle",
    );
    push(&mut out, "fig08a-rate-eq14".into(), "Fig. 8a: measured steady discharge rate (replica mean ± standard error) against R; lines are Eq. 14 with the fitted a, b, γ and φ∞ of each angle.".into(), fig8a);
    push(&mut out, "fig08b-rate-two-thirds".into(), "Fig. 8b: the measured steady discharge rate to the 2/3 power against R, which Eq. 14 makes linear in R; lines are Eq. 14 with the fitted a, b, γ and φ∞ of each angle, to the same power.".into(), fig8b);
    let ratios: Vec<_> = analysis
        .angle_ratios
        .iter()
        .filter(|r| r.series == ANGLE_SERIES)
        .collect();
    if !ratios.is_empty() {
        let angles: Vec<f64> = (1..=90).map(|a| a as f64).collect();
        let brown = angles
            .iter()
            .map(|a| analysis::flowrate::brown_ratio(a.to_radians()).unwrap_or(f64::NAN))
            .collect();
        let rose = angles
            .iter()
            .map(|a| {
                analysis::flowrate::rose_tanaka_ratio(
                    a.to_radians(),
                    super::centred::STAGNANT_ZONE_ANGLE_DEG.to_radians(),
                )
                .unwrap_or(f64::NAN)
            })
            .collect();
        let fig = Figure::new(
            "W(α)/W(90°)",
            Axis::new("α", "°").with_range(0.0, 95.0),
            Axis::new("W(α)/W(90°)", "-"),
        )
        .with_series(Series::points(
            "DEM",
            ratios.iter().map(|r| r.hopper_angle_deg).collect(),
            ratios.iter().map(|r| r.measured.value).collect(),
        ))
        .with_series(Series::line("Brown Eq. 3", angles.clone(), brown))
        .with_series(Series::line(
            format!(
                "Rose–Tanaka β_d = {}°",
                super::centred::STAGNANT_ZONE_ANGLE_DEG
            ),
            angles,
            rose,
        ));
        push(&mut out, "fig08c-angle-ratio".into(), format!("Fig. 8c: discharge rate at hopper angle α divided by the flat-bottom rate at the same D (each point one width), with Brown's Eq. 3 and Rose–Tanaka at β_d = {}° (the paper does not state β_d).", super::centred::STAGNANT_ZONE_ANGLE_DEG), fig);
    }

    // Figs. 10 and 12: eccentric profiles per gap, scaled, with the pooled fits.
    for gap in analysis.eccentric.gaps.iter() {
        let members: Vec<_> = analysis
            .eccentric
            .points
            .iter()
            .filter(|p| p.point.series == gap.series && p.point.outlet_gap == gap.outlet_gap)
            .collect();
        let s_mm = gap.outlet_gap * 1e3;
        let mut v = Figure::new(
            format!("s = {s_mm} mm"),
            Axis::new("x*", "-"),
            Axis::new("v/√(2gR)", "-"),
        );
        let mut phi = Figure::new(
            format!("s = {s_mm} mm"),
            Axis::new("x*", "-"),
            Axis::new("φ/φ_max", "-"),
        );
        for p in &members {
            let label = format!("D = {} mm", p.point.outlet_width * 1e3);
            if let Some(profile) = &p.point.velocity_profile {
                let (x, y) = points_of(profile, (2.0 * p.point.gravity * p.point.radius()).sqrt());
                v = v.with_series(Series::points(label.clone(), x, y));
            }
            if let Some(profile) = &p.point.area_fraction_profile {
                if let Ok((max, _)) = profile.maximum() {
                    let (x, y) = points_of(profile, max.value);
                    phi = phi.with_series(Series::points(label, x, y));
                }
            }
        }
        if let Ok(f) = &gap.fits.velocity {
            let (x, y) = curve(|x| {
                asymmetric_profile(x, f.asymmetry.value, f.amplitude.value, f.exponent.value)
            });
            v = v.with_series(Series::line("Eq. 16", x, y));
        }
        if let Ok(f) = &gap.fits.packing {
            let (x, y) = curve(|x| {
                asymmetric_profile(x, f.asymmetry.value, f.amplitude.value, f.exponent.value)
            });
            phi = phi.with_series(Series::line("Eq. 17", x, y));
        }
        let tag = format!("{}-s{s_mm}", gap.series);
        push(&mut out, format!("fig10-velocity-{tag}"), format!("Fig. 10e–h: outlet velocity profiles scaled by √(2gR), {} s = {s_mm} mm, per width; x* = (x − x_c)/R with x* < 0 on the wall side; the line is Eq. 16 fitted to all widths pooled.", gap.series), v);
        push(&mut out, format!("fig12-packing-{tag}"), format!("Fig. 12e–h: outlet area-fraction profiles divided by their largest bin φ_max, {} s = {s_mm} mm; the line is Eq. 17 with ε_s2 = 1.", gap.series), phi);
    }
    // Figs. 11, 14: per-point δ and σ against s*; Fig. 13: φ_max(R); Figs. 15, 16.
    let series_of = |name: &'static str| {
        analysis
            .eccentric
            .points
            .iter()
            .filter(move |p| p.point.series == name)
    };
    let scatter =
        |pick: &dyn Fn(&super::eccentric::EccentricPoint) -> Option<f64>| -> (Vec<f64>, Vec<f64>) {
            series_of(ECCENTRIC_SERIES)
                .filter_map(|p| pick(p).map(|y| (p.point.dimensionless_gap, y)))
                .unzip()
        };
    let (x, y) = scatter(&|p| p.fits.velocity.as_ref().ok().map(|f| f.asymmetry.value));
    push(
        &mut out,
        "fig11a-delta-s1".into(),
        "Fig. 11a: δ_s1 of Eq. 16 fitted to each case alone, against s* = 2s/(L − D).".into(),
        Figure::new("δ_s1", Axis::new("s*", "-"), Axis::new("δ_s1", "-"))
            .with_series(Series::points("DEM", x, y)),
    );
    let (x, y) = scatter(&|p| p.fits.velocity.as_ref().ok().map(|f| f.exponent.value));
    let mut fig11b = Figure::new("σ_s1", Axis::new("s*", "-"), Axis::new("σ_s1", "-"))
        .with_series(Series::points("DEM", x, y));
    let (xs, ys): (Vec<f64>, Vec<f64>) = (0..=60)
        .map(|i| i as f64 / 50.0)
        .map(|s| (s, exponential_approach(s, 0.39, 0.12, 3.74)))
        .unzip();
    fig11b = fig11b.with_series(Series::line("paper 0.39 − 0.12e^(−3.74s*)", xs.clone(), ys));
    if let Some((_, Ok(f))) = analysis
        .eccentric
        .exponent_fits
        .iter()
        .find(|(s, _)| s == ECCENTRIC_SERIES)
    {
        let ys = xs
            .iter()
            .map(|s| exponential_approach(*s, f.limit.value, f.amplitude.value, f.rate.value))
            .collect();
        fig11b = fig11b.with_series(Series::line("fit", xs.clone(), ys));
    }
    push(&mut out, "fig11b-sigma-s1".into(), "Fig. 11b: σ_s1 of Eq. 16 per case against s*, with the exponential fit σ_s1 = c₀ − c₁e^(−c₂s*) and the paper's curve.".into(), fig11b);
    let (x, y) = scatter(&|p| p.fits.packing.as_ref().ok().map(|f| f.asymmetry.value));
    let (x2, y2) = scatter(&|p| p.fits.packing.as_ref().ok().map(|f| f.exponent.value));
    push(
        &mut out,
        "fig14-delta-sigma-s2".into(),
        "Fig. 14: δ_s2 and σ_s2 of Eq. 17 (ε_s2 = 1) fitted to each case alone, against s*.".into(),
        Figure::new("Eq. 17", Axis::new("s*", "-"), Axis::new("δ_s2, σ_s2", "-"))
            .with_series(Series::points("δ_s2", x, y))
            .with_series(Series::points("σ_s2", x2, y2)),
    );
    let mut fig13 = Figure::new(
        "Fig. 13: largest outlet area fraction against R, per outlet gap",
        Axis::new("R", "mm"),
        Axis::new("φ_max", "-"),
    );
    let mut fig15 = Figure::new(
        "Fig. 15a: discharge rate against R, with the corrected Eq. 18, per outlet gap",
        Axis::new("R", "mm"),
        Axis::new("W", "g/s"),
    );
    let mut fig16 = Figure::new(
        "Fig. 16: discharge rate over the centred rate against s*, per outlet width",
        Axis::new("s*", "-"),
        Axis::new("W/W0", "-"),
    );
    for (group, gap) in analysis
        .eccentric
        .gaps
        .iter()
        .filter(|g| g.series == ECCENTRIC_SERIES)
        .enumerate()
    {
        let members: Vec<_> = series_of(ECCENTRIC_SERIES)
            .filter(|p| p.point.outlet_gap == gap.outlet_gap)
            .collect();
        let label = format!("s = {} mm", gap.outlet_gap * 1e3);
        let (x, y): (Vec<f64>, Vec<f64>) = members
            .iter()
            .map(|p| (p.point.radius() * 1e3, p.point.max_area_fraction.value))
            .unzip();
        fig13 = fig13.with_series(Series::points(label.clone(), x, y));
        let (x, y): (Vec<f64>, Vec<f64>) = members
            .iter()
            .map(|p| (p.point.radius() * 1e3, p.point.discharge_rate.value * 1e3))
            .unzip();
        fig15 =
            fig15.with_series(Series::points(label.clone(), x, y).with_color(group_color(group)));
        let (x, y): (Vec<f64>, Vec<f64>) = members
            .iter()
            .filter_map(|p| {
                p.predicted_rate
                    .as_ref()
                    .ok()
                    .map(|w| (p.point.radius() * 1e3, w.value * 1e3))
            })
            .unzip();
        fig15 = fig15.with_series(Series::line("", x, y).with_color(group_color(group)));
    }
    let mut widths: Vec<f64> = series_of(ECCENTRIC_SERIES)
        .map(|p| p.point.outlet_width)
        .collect();
    widths.sort_by(f64::total_cmp);
    widths.dedup();
    for d in widths {
        let (x, y): (Vec<f64>, Vec<f64>) = series_of(ECCENTRIC_SERIES)
            .filter(|p| p.point.outlet_width == d)
            .filter_map(|p| {
                p.relative_rate
                    .as_ref()
                    .ok()
                    .map(|r| (p.point.dimensionless_gap, r.value))
            })
            .unzip();
        fig16 = fig16.with_series(Series::points(format!("D = {} mm", d * 1e3), x, y));
    }
    for (_, label, fit) in analysis
        .eccentric
        .maximum_packing_fits
        .iter()
        .filter(|(s, _, _)| s == ECCENTRIC_SERIES)
    {
        if let Ok(f) = fit {
            let xs: Vec<f64> = (1..=40).map(|i| 0.75 * i as f64).collect();
            let ys = xs.iter().map(|r| f.fraction(r * 1e-3)).collect();
            fig13 = fig13.with_series(Series::line(format!("Eq. 12 form, {label}"), xs, ys));
        }
    }
    push(&mut out, "fig13-maximum-fraction".into(), "Fig. 13: largest binned outlet area fraction φ_max against R per gap; lines are the Eq. 12 form fitted to s = 0 and to s > 0 separately.".into(), fig13);
    let fig15b = two_thirds_power(
        &fig15,
        "Fig. 15b: discharge rate to the 2/3 power against R, with Eq. 18, per outlet gap",
    );
    push(&mut out, "fig15-rate-eq18".into(), "Fig. 15a: measured steady discharge rate against R per gap; lines are the corrected Eq. 18 with the pooled Eq. 16–17 fits of each gap and φ_max from the Fig. 13 fit.".into(), fig15);
    push(&mut out, "fig15b-rate-two-thirds".into(), "Fig. 15b: the measured steady discharge rate to the 2/3 power against R per gap, which Eq. 18 makes close to linear in R; lines are the corrected Eq. 18 of Fig. 15a to the same power.".into(), fig15b);
    push(&mut out, "fig16-relative-rate".into(), "Fig. 16: discharge rate divided by W0, the centred flat-bottom rate of the same width, against s*.".into(), fig16);
    out
}

/// W/W(Bo = 0) against log₁₀ Bo, one series per outlet width, for each group of the
/// cohesion section with a dry reference (the plot has linear axes: log₁₀ Bo is the
/// abscissa, and the dry points, Bo = 0, are the reference, not points).
pub fn cohesion_figures(analysis: &super::cohesion::CohesionAnalysis) -> Vec<ReportFigure> {
    let mut out = Vec::new();
    let several = analysis.groups.len() > 1;
    for (i, group) in analysis.groups.iter().enumerate() {
        let mut figure = Figure::new(
            "W/W(Bo = 0) against the Bond number",
            Axis::new("log₁₀ Bo", ""),
            Axis::new("W/W(Bo = 0)", "-"),
        );
        for (k, &width) in group.widths.iter().enumerate() {
            let points: Vec<(f64, f64, f64)> = group
                .levels
                .iter()
                .filter(|l| l.bond > 0.0)
                .filter_map(|l| {
                    l.cells[k]
                        .relative_rate
                        .map(|r| (l.bond.log10(), r.value, r.standard_error))
                })
                .collect();
            if points.is_empty() {
                continue;
            }
            let errors = points
                .iter()
                .map(|p| if p.2.is_finite() { p.2 } else { 0.0 })
                .collect();
            figure = figure.with_series(
                Series {
                    style: files::SeriesStyle::LineAndPoints,
                    ..Series::points(
                        format!(
                            "D = {:.1} mm ({:.1} d)",
                            width * 1e3,
                            width / group.particle_diameter
                        ),
                        points.iter().map(|p| p.0).collect(),
                        points.iter().map(|p| p.1).collect(),
                    )
                }
                .with_y_error(errors),
            );
        }
        // The dry reference across the Bond numbers plotted.
        let xs: Vec<f64> = group
            .levels
            .iter()
            .filter(|l| l.bond > 0.0)
            .map(|l| l.bond.log10())
            .collect();
        if let (Some(lo), Some(hi)) = (
            xs.iter().copied().reduce(f64::min),
            xs.iter().copied().reduce(f64::max),
        ) {
            figure = figure.with_series(
                Series::line("dry (Bo = 0)", vec![lo, hi], vec![1.0, 1.0]).with_color([120; 3]),
            );
        }
        let name = if several {
            format!("cohesion-rate-ratio-{}", i + 1)
        } else {
            "cohesion-rate-ratio".into()
        };
        push(&mut out, name, format!(
            "Discharge rate over the dry rate at the same outlet width against the Bond number Bo = F_c/(m g) (log₁₀ Bo on the axis), series {}; error bars one standard error, the two rates' errors combined in quadrature. A width that clogged at some Bo has no point there (see the table).",
            group.series.join(", ")
        ), figure);
    }
    out
}
