//! The report built from synthetic studies with known parameters: fits recover them,
//! comparison.json has exactly its keys, pass/fail follows the bands, and missing data
//! gives "not measured" rows rather than a failure.

use crate::study_fake;

use std::path::Path;

use case::{load_sweep, parse_sweep, SweepPlan, FAN2023_QUICK_SWEEP, FAN2023_SWEEP};
use report::{analyse_study, build_report, load_study, report_figures};
use serde_json::Value;
use study::{run_study, StudyEvent, StudyOptions};
use study_fake::FakeRunner;

fn quiet(_: &StudyEvent) {}

fn run_fake(sweep: &str, dir: &Path, fake: &FakeRunner) {
    run_fake_plan(&parse_sweep(sweep, "sweep", None, &[]).unwrap(), dir, fake);
}

fn run_fake_plan(plan: &SweepPlan, dir: &Path, fake: &FakeRunner) {
    run_study(plan, dir, fake, &StudyOptions { jobs: 2 }, &quiet).unwrap();
}

fn comparison(dir: &Path) -> Vec<Value> {
    let text = std::fs::read_to_string(dir.join("report/comparison.json")).unwrap();
    serde_json::from_str::<Value>(&text)
        .unwrap()
        .as_array()
        .unwrap()
        .clone()
}

fn item<'a>(items: &'a [Value], starts: &str) -> &'a Value {
    items
        .iter()
        .find(|i| i["item"].as_str().unwrap().starts_with(starts))
        .unwrap_or_else(|| panic!("no item {starts}"))
}

#[test]
fn fits_recover_the_known_laws_of_a_synthetic_fan2023_study() {
    let dir = tempfile::tempdir().unwrap();
    run_fake(FAN2023_SWEEP, dir.path(), &FakeRunner::new());
    let data = load_study(dir.path()).unwrap();
    let analysis = analyse_study(&data.points);

    let flat = analysis
        .angles
        .iter()
        .find(|f| f.series == "angle" && f.hopper_angle_deg == 90.0)
        .unwrap();
    // Profiles carry ±0.2 % noise, so exponents come back within 0.01 of the truth.
    assert!((flat.velocity_exponent.as_ref().unwrap().value - 0.39).abs() < 0.01);
    assert!((flat.packing_exponent.as_ref().unwrap().value - 0.39).abs() < 0.01);
    // v_c is the mean of the two central bins (x* = ±0.05), (1 − 0.0025)^a below the
    // peak: γ is low by about 2a·0.0025 ≈ 0.2 %, so 1 % covers it.
    let gamma = flat.centre_velocity.as_ref().unwrap().gamma.value;
    assert!((gamma / 1.66 - 1.0).abs() < 0.01, "γ = {gamma}");
    let phi = flat.saturation.as_ref().unwrap().phi_infinity.value;
    // φ_c carries the same 0.2 % noise on four points; 0.01 is a few σ of φ∞.
    assert!((phi - study_fake::PHI_INFINITY).abs() < 0.01, "φ∞ = {phi}");

    let k = analysis
        .beverloo
        .iter()
        .find(|g| g.series == "angle" && g.label == "α = 90°")
        .unwrap()
        .fit
        .as_ref()
        .unwrap()
        .k
        .value;
    // Rates are exact Beverloo values, so k is recovered to rounding.
    assert!((k - study_fake::BEVERLOO_K).abs() < 1e-6, "k = {k}");
    let c = analysis
        .beverloo
        .iter()
        .find(|g| g.series == "angle" && g.label == "α = 90°")
        .unwrap()
        .fit
        .as_ref()
        .unwrap()
        .coefficients
        .bulk_density
        .coefficient
        .value;
    assert!((c - study_fake::BEVERLOO_C).abs() < 1e-6, "C = {c}");

    // The σ_s1(s*) law of the fake is recovered by the per-case fits and the exponential
    // fit (0.2 % noise on 24 cases: limits within 0.02, rate within 20 %).
    let (_, fit) = analysis
        .eccentric
        .exponent_fits
        .iter()
        .find(|(s, _)| s == "eccentric")
        .unwrap();
    let fit = fit.as_ref().unwrap();
    assert!(
        (fit.limit.value - 0.39).abs() < 0.02,
        "c0 = {}",
        fit.limit.value
    );
    assert!(
        (fit.amplitude.value - 0.12).abs() < 0.02,
        "c1 = {}",
        fit.amplitude.value
    );
    assert!(
        (fit.rate.value / 3.74 - 1.0).abs() < 0.2,
        "c2 = {}",
        fit.rate.value
    );
    // W/W0 at s = 0 is the fake's gain exactly (same Beverloo rate times 1.3).
    for p in analysis
        .eccentric
        .points
        .iter()
        .filter(|p| p.point.outlet_gap == 0.0)
    {
        let ratio = p.relative_rate.as_ref().unwrap().value;
        assert!((ratio - study_fake::WALL_OUTLET_GAIN).abs() < 1e-9);
    }
}

#[test]
fn report_of_a_paper_like_study_passes_every_item_and_writes_all_documents() {
    let dir = tempfile::tempdir().unwrap();
    run_fake(FAN2023_SWEEP, dir.path(), &FakeRunner::new());
    let files = build_report(dir.path()).unwrap();
    let items = comparison(dir.path());
    assert_eq!(items.len(), 12);
    for i in &items {
        let mut keys: Vec<&str> = i.as_object().unwrap().keys().map(|k| k.as_str()).collect();
        keys.sort();
        assert_eq!(keys, ["band", "item", "measured", "paper", "pass"]);
        if i["item"]
            .as_str()
            .unwrap()
            .starts_with("Beverloo k (α = 90°")
        {
            // The reference row: measured, with no band of its own.
            assert_eq!(i["pass"], Value::Null, "{i}");
            assert!(i["measured"].is_number(), "{i}");
        } else {
            // The fake follows the paper's laws, so every item must be measured and pass.
            assert_eq!(i["pass"], Value::Bool(true), "{i}");
        }
    }
    // The fake's W is Beverloo with k = 1.55 at every angle, times Brown's α factor, so the
    // 90° fit recovers 1.55 to rounding.
    let k90 = item(&items, "Beverloo k (α = 90°")["measured"]
        .as_f64()
        .unwrap();
    assert!((k90 - 1.55).abs() < 1e-6, "k(90°) = {k90}");

    let md = std::fs::read_to_string(&files.markdown).unwrap();
    let html = std::fs::read_to_string(&files.html).unwrap();
    for needle in [
        "Table 2",
        "Table 3",
        "Beverloo constants",
        "Comparison with the paper",
        "Config hash",
    ] {
        assert!(md.contains(needle), "markdown lacks {needle}");
        assert!(html.contains(needle), "html lacks {needle}");
    }
    // Paper values stand beside ours: Table 2's γ(15°) and Table 3's σ_s2(s = 0).
    assert!(md.contains("2.81") && md.contains("0.32"));
    // Self-contained: figures inline as SVG, no external image or stylesheet.
    assert!(html.contains("<svg"));
    assert!(!html.contains("<img") && !html.contains("<link"));
    assert!(
        files.figures.len() >= 20,
        "{} figure files",
        files.figures.len()
    );
    assert!(files.figures.iter().all(|f| f.exists()));
    assert!(dir
        .path()
        .join("report/figures/fig16-relative-rate.svg")
        .exists());
}

#[test]
fn a_missed_item_fails_and_the_report_says_by_how_much() {
    let dir = tempfile::tempdir().unwrap();
    // γ(90°) = 2.5 is 25.6 % above 1.66, beyond the ±20 % band (upper edge 1.992).
    let fake = FakeRunner {
        gamma_90: Some(2.5),
        ..FakeRunner::new()
    };
    run_fake(FAN2023_SWEEP, dir.path(), &fake);
    build_report(dir.path()).unwrap();
    let items = comparison(dir.path());
    let gamma = item(&items, "γ(90°)");
    assert_eq!(gamma["pass"], Value::Bool(false));
    let measured = gamma["measured"].as_f64().unwrap();
    // Within 1 % of the fake's value (see the recovery test for the bias).
    assert!((measured / 2.5 - 1.0).abs() < 0.01);
    // γ no longer stays flat from 55° to 90° (1.61, 1.64, 2.5: 2.5 is 31 % above the mean).
    assert_eq!(
        item(&items, "Table 2 trend: γ flat")["pass"],
        Value::Bool(false)
    );
    let md = std::fs::read_to_string(dir.path().join("report/report.md")).unwrap();
    let expected = format!("{:.3} above the band", measured - 1.66 * 1.2);
    assert!(md.contains(&expected), "report lacks '{expected}'");
}

#[test]
fn quick_study_report_builds_with_not_measured_rows() {
    let dir = tempfile::tempdir().unwrap();
    run_fake(FAN2023_QUICK_SWEEP, dir.path(), &FakeRunner::new());
    build_report(dir.path()).unwrap();
    let items = comparison(dir.path());
    assert_eq!(items.len(), 12);
    // Two widths only: no Beverloo fit (needs 3) and no Eq. 12 fit (needs 4).
    for name in [
        "Beverloo k (all α pooled",
        "Beverloo k (α = 90°",
        "φ∞(90°)",
        "Table 2 trend: γ flat",
    ] {
        let i = item(&items, name);
        assert_eq!(i["measured"], Value::String("not measured".into()), "{i}");
        assert_eq!(i["pass"], Value::Null);
    }
    // What two widths can measure is measured: γ(90°), a, b, the 30° rise, W(s=0)/W0.
    for name in [
        "γ(90°)",
        "a(90°)",
        "b(90°)",
        "Table 2 trend: γ rises",
        "Table 2 trend: b rises",
        "W(s = 0)/W0",
    ] {
        assert_eq!(item(&items, name)["pass"], Value::Bool(true), "{name}");
    }
    // The b trend from the strip profiles at 30° and 90° (the fake's 0.19 and 0.39); the
    // fake writes no crossing profiles, and the item says so instead of failing.
    let trend = item(&items, "Table 2 trend: b rises")["measured"]
        .as_str()
        .unwrap()
        .to_string();
    assert!(trend.contains("strip area fraction: 0.1"), "{trend}");
    assert!(
        trend.contains("crossing number density: not measured"),
        "{trend}"
    );
    let md = std::fs::read_to_string(dir.path().join("report/report.md")).unwrap();
    assert!(
        md.contains("not measured (1 outlet width(s); the fit needs at least 3)")
            || md.contains("not measured (2 outlet width(s); the fit needs at least 3)")
    );
}

#[test]
fn report_survives_failed_cases_and_missing_profiles() {
    let dir = tempfile::tempdir().unwrap();
    let fake = FakeRunner {
        fail: vec!["angle-a90-D030-r0".into()],
        ..FakeRunner::new()
    };
    run_fake(FAN2023_QUICK_SWEEP, dir.path(), &fake);
    std::fs::remove_file(dir.path().join("cases/angle-a90-D018-r0/profiles.csv")).unwrap();
    build_report(dir.path()).unwrap();
    let items = comparison(dir.path());
    assert_eq!(
        item(&items, "a(90°)")["measured"],
        Value::String("not measured".into())
    );
    let md = std::fs::read_to_string(dir.path().join("report/report.md")).unwrap();
    assert!(md.contains("1 failed"));
}

#[test]
fn each_angle_s_points_and_fit_share_a_colour_and_the_pooled_fit_is_drawn() {
    // Figs. 2b, 4, 7, 8a and 8b of a synthetic paper study: every labelled series of points is
    // followed by its fit, unlabelled (one legend entry), in the same colour, and no two
    // angles share a colour; Fig. 2b also draws the pooled fit, in its own colour and named;
    // every title says which figure it is.
    let dir = tempfile::tempdir().unwrap();
    run_fake(FAN2023_SWEEP, dir.path(), &FakeRunner::new());
    let analysis = analyse_study(&load_study(dir.path()).unwrap().points);
    let figures = report_figures(&analysis);
    for name in [
        "fig02b-beverloo",
        "fig04-centre-velocity",
        "fig07-centre-fraction",
        "fig08a-rate-eq14",
        "fig08b-rate-two-thirds",
    ] {
        let figure = &figures
            .iter()
            .find(|f| f.name == name)
            .unwrap_or_else(|| panic!("{name}"))
            .figure;
        assert!(figure.title.starts_with("Fig."), "{name}: {}", figure.title);
        let mut colours = Vec::new();
        for pair in figure.series.windows(2) {
            let (points, fit) = (&pair[0], &pair[1]);
            if points.style == files::SeriesStyle::Points && fit.label.is_empty() {
                assert!(
                    points.color.is_some() && points.color == fit.color,
                    "{name}: {}",
                    points.label
                );
                colours.push(points.color);
            }
        }
        assert!(colours.len() >= 2, "{name}: fits drawn for several angles");
        let distinct: std::collections::BTreeSet<_> = colours.iter().collect();
        assert_eq!(distinct.len(), colours.len(), "{name}: one colour an angle");
    }
    let beverloo = &figures
        .iter()
        .find(|f| f.name == "fig02b-beverloo")
        .unwrap()
        .figure;
    // Figs. 8b and 15b are Figs. 8a and 15a to the 2/3 power, series for series.
    let by_name = |n: &str| &figures.iter().find(|f| f.name == n).unwrap().figure;
    for (linear, powered) in [
        ("fig08a-rate-eq14", "fig08b-rate-two-thirds"),
        ("fig15-rate-eq18", "fig15b-rate-two-thirds"),
    ] {
        let (a, b) = (by_name(linear), by_name(powered));
        assert_eq!(a.series.len(), b.series.len(), "{powered}");
        for (sa, sb) in a.series.iter().zip(&b.series) {
            assert_eq!((sa.color, &sa.label), (sb.color, &sb.label), "{powered}");
            for (wa, wb) in sa.y.iter().zip(&sb.y) {
                assert!(
                    (wa.powf(2.0 / 3.0) - wb).abs() <= 1e-12 * wb.abs(),
                    "{wa} {wb}"
                );
            }
        }
    }
    let pooled = beverloo
        .series
        .iter()
        .find(|s| s.label.contains("pooled"))
        .expect("the pooled fit");
    assert_eq!(pooled.style, files::SeriesStyle::Line);
    assert!(beverloo
        .series
        .iter()
        .filter(|s| s.label != pooled.label)
        .all(|s| s.color != pooled.color));
}

#[test]
fn pooled_beverloo_k_fits_every_angle_together_and_differs_from_the_flat_bottom_fit() {
    // k rising as the hopper steepens, 1.55 at 90° to 2.3 at 15°: one line through all
    // angles then has an intercept unlike the 90° line's. (With one k at every angle, the
    // pooled intercept equals it: Brown's factor scales each angle's line about the same
    // root D = kd.)
    let dir = tempfile::tempdir().unwrap();
    let fake = FakeRunner {
        beverloo_k: Some(|alpha| 1.55 + (90.0 - alpha) / 100.0),
        ..FakeRunner::new()
    };
    run_fake(FAN2023_SWEEP, dir.path(), &fake);
    build_report(dir.path()).unwrap();
    let items = comparison(dir.path());
    // Fig. 2b fits one line through the points of all angles. Recompute it independently:
    // every centred angle-series case of results.csv in one Beverloo fit.
    let data = load_study(dir.path()).unwrap();
    let points: Vec<_> = data
        .points
        .iter()
        .filter(|p| p.series == "angle" && p.is_centred())
        .collect();
    let angles: std::collections::BTreeSet<u64> =
        points.iter().map(|p| p.hopper_angle_deg as u64).collect();
    assert_eq!(angles.len(), 5, "all five angles enter the pooled fit");
    let analysis = analyse_study(&data.points);
    let pooled = report::beverloo::pooled_angle_fit(&analysis.beverloo, "angle").unwrap();
    assert_eq!(pooled.hopper_angles, [15.0, 30.0, 55.0, 75.0, 90.0]);
    let normalisation = analysis::beverloo::BeverlooNormalisation {
        slab_thickness: points[0].thickness,
        particle_diameter: points[0].particle_diameter,
        particle_density: points[0].particle_density,
        bulk_fraction: pooled.bulk_fraction,
        area_fraction: pooled.area_fraction,
        gravity: points[0].gravity,
    };
    let d: Vec<f64> = points.iter().map(|p| p.outlet_width).collect();
    let w: Vec<f64> = points.iter().map(|p| p.discharge_rate.value).collect();
    let e: Vec<f64> = points
        .iter()
        .map(|p| p.discharge_rate.standard_error)
        .collect();
    let expected =
        analysis::beverloo::fit_beverloo_2d(&d, &w, Some(&e), &normalisation, 0.95).unwrap();
    let k = item(&items, "Beverloo k (all α pooled")["measured"]
        .as_f64()
        .unwrap();
    // The same points in a different order: equal to summation round-off (1e-9 of k).
    assert!(
        (k - expected.k.value).abs() < 1e-9,
        "{k} vs {}",
        expected.k.value
    );
    // The 90° row keeps the 90° line's own k (1.55 to rounding), and the pooled item is
    // not it: the other angles' larger k pull it up by a few hundredths at least.
    let k90 = item(&items, "Beverloo k (α = 90°")["measured"]
        .as_f64()
        .unwrap();
    assert!((k90 - 1.55).abs() < 1e-6, "k(90°) = {k90}");
    assert!(k - k90 > 0.05, "pooled {k} against the 90° fit {k90}");
    // The report states the other codes' 90° values beside ours.
    let md = std::fs::read_to_string(dir.path().join("report/report.md")).unwrap();
    assert!(md.contains("LIGGGHTS 3.8") && md.contains("2.12") && md.contains("2.19"));
}

#[test]
fn b_trend_shows_both_phi_definitions_and_fails_when_one_falls_with_angle() {
    // Crossing-density b falling with α (0.5 − α/300: 0.4 at 30°, 0.2 at 90°) while the
    // strip b follows Table 2 (rising): the item must show both and fail on the crossing one.
    let dir = tempfile::tempdir().unwrap();
    let fake = FakeRunner {
        crossing_exponent: Some(|alpha| 0.5 - alpha / 300.0),
        ..FakeRunner::new()
    };
    run_fake(FAN2023_SWEEP, dir.path(), &fake);
    build_report(dir.path()).unwrap();
    let items = comparison(dir.path());
    let trend = item(&items, "Table 2 trend: b rises");
    assert_eq!(trend["pass"], Value::Bool(false), "{trend}");
    let text = trend["measured"].as_str().unwrap();
    assert!(
        text.contains("strip area fraction: 0.19") && text.contains("crossing number density: 0.3"),
        "{text}"
    );
    let md = std::fs::read_to_string(dir.path().join("report/report.md")).unwrap();
    assert!(
        md.contains("crossing number density: b(55°)"),
        "the miss names the definition"
    );

    // Rising under both (α/300: 0.1 at 30° to 0.3 at 90°) passes, each value recovered
    // within 0.01 (0.2 % profile noise, as in the recovery test).
    let dir = tempfile::tempdir().unwrap();
    let fake = FakeRunner {
        crossing_exponent: Some(|alpha| alpha / 300.0),
        ..FakeRunner::new()
    };
    run_fake(FAN2023_SWEEP, dir.path(), &fake);
    build_report(dir.path()).unwrap();
    let analysis = analyse_study(&load_study(dir.path()).unwrap().points);
    for f in analysis.angles.iter().filter(|f| f.series == "angle") {
        let b = f.crossing_packing_exponent.as_ref().unwrap().value;
        assert!(
            (b - f.hopper_angle_deg / 300.0).abs() < 0.01,
            "b = {b} at {}°",
            f.hopper_angle_deg
        );
    }
    let items = comparison(dir.path());
    assert_eq!(
        item(&items, "Table 2 trend: b rises")["pass"],
        Value::Bool(true)
    );
}

/// The shipped 3D Beverloo study: a flat-bottomed cylindrical silo, orifices D/d = 4–12.
fn beverloo3d_sweep() -> SweepPlan {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases/beverloo3d.toml");
    load_sweep(&path, &[]).unwrap()
}

/// The profile item of the grid point of case `id` (its key: the id without `-r<replica>`).
fn profile_item<'a>(items: &'a [Value], id: &str) -> &'a Value {
    let key = id.rsplit_once("-r").map_or(id, |(key, _)| key);
    item(
        items,
        &format!("W from the fitted profiles / W measured ({key})"),
    )
}

/// Tolerances on the 3D Beverloo constants given back from the fake's silo study. The fake's
/// W carries ±0.5 % uniform noise (σ = 0.29 %, 0.12 % on W^(2/5)) over the seven orifices of
/// D/d = 4–12; the weighted fit then states σ_k ≈ 0.005 and σ_C ≈ 0.0017. The tolerances are
/// about 5σ, so that no plausible draw of the noise fails them, yet far below what a wrong law would give:
/// the 2D exponent 3/2, or ρ_p in place of ρ_b, moves C by tens of percent, and the classic
/// range of k is 0.3 wide.
const SILO_K_TOLERANCE: f64 = 0.03;
const SILO_C_TOLERANCE: f64 = 0.01;
/// Tolerance on W from the fitted radial profiles over W: the fake's profiles carry its W
/// before the ±0.5 % noise, and their bins ±0.2 % noise, so the ratio is 1 within about
/// 0.5 % + the profile fit's error (a few 0.1 %); 1 % covers both, a fifth of the item's 5 %
/// band.
const PROFILE_RATE_RATIO_TOLERANCE: f64 = 0.01;

/// Asserts that the comparison of a study of `plan` (one silo group, series 'flat' at
/// θ = 90°) gives back `constants` (C, k) within their tolerances, and W from each case's
/// profiles over its W as `ratio`; that each of these items passes or fails as `pass` says;
/// returns C and k as given back.
fn assert_silo_items(
    items: &[Value],
    plan: &SweepPlan,
    constants: (f64, f64),
    ratio: f64,
    pass: bool,
) -> (f64, f64) {
    let c = item(items, "3D Beverloo C (series 'flat', θ = 90°)");
    let k = item(items, "3D Beverloo k (series 'flat', θ = 90°)");
    let c_value = c["measured"].as_f64().unwrap();
    let k_value = k["measured"].as_f64().unwrap();
    assert!(
        (c_value - constants.0).abs() < SILO_C_TOLERANCE,
        "C = {c_value}"
    );
    assert!(
        (k_value - constants.1).abs() < SILO_K_TOLERANCE,
        "k = {k_value}"
    );
    assert_eq!(c["pass"], Value::Bool(pass), "{c}");
    assert_eq!(k["pass"], Value::Bool(pass), "{k}");
    for case in &plan.cases {
        let i = profile_item(items, &case.id);
        let measured = i["measured"].as_f64().unwrap();
        assert!(
            (measured - ratio).abs() < PROFILE_RATE_RATIO_TOLERANCE,
            "{}: {measured}",
            case.id
        );
        assert_eq!(i["pass"], Value::Bool(pass), "{i}");
    }
    (c_value, k_value)
}

#[test]
fn silo_study_gives_back_the_3d_beverloo_c_and_k_of_its_cases() {
    let dir = tempfile::tempdir().unwrap();
    let plan = beverloo3d_sweep();
    run_fake_plan(&plan, dir.path(), &FakeRunner::new());
    let files = build_report(dir.path()).unwrap();
    let items = comparison(dir.path());
    // No slab case, so none of the paper's items: C and k of the one group (series 'flat',
    // θ = 90°), then one profile item per case.
    assert_eq!(items.len(), 2 + plan.cases.len());
    // The fake's C = 0.58 and k = 1.4 lie inside the classic ranges, by more than the
    // tolerances, and its profiles carry its W: every item passes.
    let (c_value, k_value) = assert_silo_items(
        &items,
        &plan,
        (study_fake::SILO_BEVERLOO_C, study_fake::SILO_BEVERLOO_K),
        1.0,
        true,
    );
    let c = item(&items, "3D Beverloo C (series 'flat', θ = 90°)");
    let k = item(&items, "3D Beverloo k (series 'flat', θ = 90°)");
    assert_eq!(c["band"], Value::String("[0.55, 0.65]".into()));
    assert_eq!(k["band"], Value::String("[1.3, 1.6]".into()));

    // The documents say why the paper's items are absent and show the silo sections, with
    // the fit's values as the comparison gives them.
    let md = std::fs::read_to_string(&files.markdown).unwrap();
    let html = std::fs::read_to_string(&files.html).unwrap();
    for needle in [
        "this study holds no slab case",
        "3D Beverloo constants",
        "Radial outlet profiles",
    ] {
        assert!(md.contains(needle), "markdown lacks {needle}");
        assert!(html.contains(needle), "html lacks {needle}");
    }
    assert!(!md.contains("Comparison with the paper") && !md.contains("Table 2"));
    assert!(md.contains(&format!("{c_value:.3} [")), "the C row");
    assert!(md.contains(&format!("{k_value:.2} [")), "the k row");
    // No figure applies to silos (the paper's figures are of slabs).
    assert!(files.figures.is_empty());
}

#[test]
fn silo_items_give_back_other_constants_and_fail_outside_the_classic_ranges() {
    // C = 0.50 and k = 2.0 lie outside the classic ranges (0.55–0.65, 1.3–1.6); the profiles
    // carry 8 % more than the measured W, beyond the 5 % band.
    let dir = tempfile::tempdir().unwrap();
    let fake = FakeRunner {
        silo_beverloo: Some((0.50, 2.0)),
        silo_profile_rate: Some(1.08),
        ..FakeRunner::new()
    };
    let plan = beverloo3d_sweep();
    run_fake_plan(&plan, dir.path(), &fake);
    build_report(dir.path()).unwrap();
    let items = comparison(dir.path());
    // Given back within the same tolerances as the fake's default constants (the noise is
    // the same relative noise on W), and every item fails.
    assert_silo_items(&items, &plan, (0.50, 2.0), 1.08, false);
    let md = std::fs::read_to_string(dir.path().join("report/report.md")).unwrap();
    assert!(
        md.contains("outside the classic range"),
        "the miss is named"
    );
}

#[test]
fn silo_groups_that_cannot_be_fitted_say_why() {
    // Series 'few': two orifices, one short of the fit. Series 'two_g': three orifices under
    // each of two g, which no single law fits. Series 'no_bulk': three orifices, none with a
    // settled bulk fraction to give ρ_b. Each group is listed, not measured, with its
    // reason; the profile items of its cases are still measured.
    let three = "[0.018, 0.024, 0.030]";
    let sweep = [
        SILO_BASE.to_string(),
        series(
            "few",
            "",
            &[length_axis("geometry.outlet_diameter", "[0.018, 0.024]")],
        ),
        series(
            "two_g",
            "",
            &[
                axis("gravity", "[9.81, 4.0]", "g"),
                length_axis("geometry.outlet_diameter", three),
            ],
        ),
        series(
            "no_bulk",
            "",
            &[length_axis("geometry.outlet_diameter", three)],
        ),
    ]
    .concat();
    let dir = tempfile::tempdir().unwrap();
    let fake = FakeRunner {
        no_bulk: ["no_bulk-D018-r0", "no_bulk-D024-r0", "no_bulk-D030-r0"]
            .map(String::from)
            .to_vec(),
        ..FakeRunner::new()
    };
    run_fake(&sweep, dir.path(), &fake);
    build_report(dir.path()).unwrap();
    let items = comparison(dir.path());
    // C and k of the three groups, then the profile items of the 11 cases.
    assert_eq!(items.len(), 3 * 2 + 11);
    let md = std::fs::read_to_string(dir.path().join("report/report.md")).unwrap();
    for (series, why) in [
        ("few", "2 orifice diameter(s); the fit needs 3 or more"),
        ("two_g", "the cases ran under different g (4, 9.81 m/s²)"),
        ("no_bulk", "no settled bulk fraction was measured"),
    ] {
        for constant in ["C", "k"] {
            let i = item(
                &items,
                &format!("3D Beverloo {constant} (series '{series}', θ = 90°)"),
            );
            assert_eq!(i["measured"], Value::String("not measured".into()), "{i}");
            assert_eq!(i["pass"], Value::Null, "{i}");
        }
        assert!(md.contains(why), "the report lacks '{why}'");
    }
    let profiles: Vec<&Value> = items
        .iter()
        .filter(|i| i["item"].as_str().unwrap().starts_with("W from the fitted"))
        .collect();
    assert_eq!(profiles.len(), 11);
    assert!(profiles.iter().all(|i| i["pass"] == Value::Bool(true)));
}

/// A sweep's axis over `key` taking `values` (TOML array), identifiers labelled `label`.
fn axis(key: &str, values: &str, label: &str) -> String {
    format!("\n[[series.axes]]\nkey = \"{key}\"\nvalues = {values}\nlabel = \"{label}\"\n")
}

/// An axis over a length (outlet width or diameter) [m], labelled "D" in mm in identifiers.
fn length_axis(key: &str, values: &str) -> String {
    axis(key, values, "D") + "scale = 1000.0\ndigits = 3\n"
}

/// A `[[series]]` named `name` with the overrides `set` (a `set = { … }` line, or empty) and
/// the axes `axes`.
fn series(name: &str, set: &str, axes: &[String]) -> String {
    format!("\n[[series]]\nname = \"{name}\"\n{set}\n{}", axes.concat())
}

/// The base of the silo sweeps: the shipped 3D Beverloo silo (flat bottom, R = 15 d).
const SILO_BASE: &str = r#"
version = 1
name = "silo"
description = "cylindrical silo"

[base]
version = 1
seed = 7

[base.geometry]
kind = "cylinder"
radius = 0.045
height = 0.12
outlet_diameter = 0.024
hopper_angle_deg = 90.0

[base.particles]
count = 2000
diameter = 0.003
"#;

/// A slab series of the paper's base hopper and a silo series of the shipped 3D Beverloo
/// silo, in one sweep or alone (same base seed and identifiers, so the same cases). The
/// base is the default case (a slab): the silo series sets its kind and dimensions.
fn mixed_sweep(slab: bool, silo: bool) -> String {
    let mut text = String::from(
        r#"
version = 1
name = "mixed"
description = "slab hopper and cylindrical silo"

[base]
version = 1
seed = 2023

[base.particles]
count = 3000
diameter = 0.003
"#,
    );
    if slab {
        text += &series(
            "angle",
            "",
            &[
                axis("geometry.hopper_angle_deg", "[30.0, 90.0]", "a"),
                length_axis("geometry.outlet_width", "[0.018, 0.030, 0.045]"),
            ],
        );
    }
    if silo {
        text += &series(
            "flat",
            r#"set = { "geometry.kind" = "cylinder", "geometry.radius" = 0.045, "geometry.height" = 0.12, "geometry.hopper_angle_deg" = 90.0 }"#,
            &[length_axis(
                "geometry.outlet_diameter",
                "[0.012, 0.015, 0.018, 0.021, 0.024, 0.030, 0.036]",
            )],
        );
    }
    text
}

#[test]
fn a_study_of_slabs_and_silos_lists_the_items_of_both() {
    let report_of = |slab: bool, silo: bool| {
        let dir = tempfile::tempdir().unwrap();
        run_fake(&mixed_sweep(slab, silo), dir.path(), &FakeRunner::new());
        let files = build_report(dir.path()).unwrap();
        let md = std::fs::read_to_string(&files.markdown).unwrap();
        let html = std::fs::read_to_string(&files.html).unwrap();
        let items = comparison(dir.path());
        (dir, items, md, html)
    };
    let (_, slab_items, slab_md, _) = report_of(true, false);
    let (_, silo_items, ..) = report_of(false, true);
    let (dir, items, md, html) = report_of(true, true);
    // Each kind is fitted on its own cases only: the mixed study's items are the slab
    // study's (the paper's, in their order) followed by the silo study's, value for value.
    assert_eq!(slab_items.len(), 12);
    assert_eq!(silo_items.len(), 2 + 7);
    let expected: Vec<Value> = slab_items.iter().chain(&silo_items).cloned().collect();
    assert_eq!(items, expected);
    // Both kinds are measured in the mixed study: the paper's 2D Beverloo k and γ(90°), the
    // silo's 3D C and k.
    for name in [
        "Beverloo k (all α pooled",
        "γ(90°)",
        "3D Beverloo C (series 'flat', θ = 90°)",
        "3D Beverloo k (series 'flat', θ = 90°)",
    ] {
        assert_eq!(item(&items, name)["pass"], Value::Bool(true), "{name}");
    }
    let k3 = item(&items, "3D Beverloo k (series 'flat', θ = 90°)")["measured"]
        .as_f64()
        .unwrap();
    assert!((k3 - study_fake::SILO_BEVERLOO_K).abs() < SILO_K_TOLERANCE);
    // The documents name both: the paper's sections and the silo's, and say which rows of
    // the comparison are the silos' (a slab study has no such sentence).
    let silo_rows = "The study also holds silos with circular orifices";
    for needle in [
        "Comparison with the paper",
        "Table 2",
        "Beverloo constants",
        "3D Beverloo constants",
        "Radial outlet profiles",
        silo_rows,
    ] {
        assert!(md.contains(needle), "markdown lacks {needle}");
        assert!(html.contains(needle), "html lacks {needle}");
    }
    assert!(md.contains("| 3D Beverloo k (series 'flat', θ = 90°) |"));
    assert!(!slab_md.contains(silo_rows));

    // A study whose case folders hold no case.toml (the kind then told by the hopper
    // width that only a slab has) gives the same items.
    for case in std::fs::read_dir(dir.path().join("cases")).unwrap() {
        std::fs::remove_file(case.unwrap().path().join("case.toml")).unwrap();
    }
    build_report(dir.path()).unwrap();
    assert_eq!(comparison(dir.path()), expected);
}
