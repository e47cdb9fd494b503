//! The long validations: runs that take minutes to tens of minutes each, ignored by the test
//! command, that re-check the numbers `docs/reproduction.md` gives, to the digits it prints.
//! Run them all with the command that document gives:
//!
//! ```sh
//! cargo test --locked -p hopperflow --test validation -- --ignored --test-threads 1
//! ```
//!
//! A run's numbers depend only on its case, its seed and the build (bit-reproducible at any
//! thread count), so each documented value is met exactly up to its rounding: the tolerance
//! is half a unit of the last printed digit. When a change of physics moves them on purpose,
//! the documented numbers and these tests change together.

#[path = "suite/run_cli.rs"]
mod run_cli;

use std::path::Path;

use run_cli::{hopperflow, utf8};
use serde_json::Value;

/// The summary of the run in `dir`.
fn summary(dir: &Path) -> Value {
    let text = std::fs::read(dir.join("summary.json"))
        .unwrap_or_else(|e| panic!("{}/summary.json: {e}", dir.display()));
    serde_json::from_slice(&text).expect("summary.json is JSON")
}

/// `value` printed with `decimals` decimals, as the documentation prints it.
fn printed(value: f64, decimals: usize) -> String {
    format!("{value:.decimals$}")
}

/// Asserts that `value` in `unit_scale` units rounds to the documented `text`, whose decimals
/// give the precision: half a unit of its last digit.
fn assert_documented(what: &str, value: f64, unit_scale: f64, text: &str) {
    let decimals = text.split('.').nth(1).map_or(0, str::len);
    assert_eq!(
        printed(value * unit_scale, decimals),
        text,
        "{what}: {value} against the documented {text}"
    );
}

/// The `key` of a summary (or of one of its objects) as a number, or its `[value, error]`
/// pair's value.
fn number(summary: &Value, key: &str) -> f64 {
    let v = &summary[key];
    v.as_f64()
        .or_else(|| v[0].as_f64())
        .unwrap_or_else(|| panic!("summary key {key}: {v}"))
}

/// `hopperflow run` with `args` into `dir`; panics with its error output when it fails.
fn run(args: &[&str], dir: &Path) {
    let mut all = vec!["run"];
    all.extend_from_slice(args);
    all.extend(["--out", utf8(dir), "--quiet"]);
    let output = hopperflow(&all);
    assert!(
        output.status.success(),
        "hopperflow {all:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// `hopperflow study` of `sweep` (a file or a built-in name) into `dir`, two cases at a time,
/// without pictures; panics with its error output when it fails.
fn study(sweep: &str, dir: &Path) {
    let output = hopperflow(&[
        "study",
        sweep,
        "--out",
        utf8(dir),
        "--jobs",
        "2",
        "--no-pictures",
    ]);
    assert!(
        output.status.success(),
        "the study of {sweep}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
}

/// The repository's root.
fn repository() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

#[test]
#[ignore = "long validation (minutes): docs/reproduction.md, \"Long validations\""]
fn the_base_case_gives_the_documented_rate_and_profiles() {
    // docs/reproduction.md, "Base case": W = 50.99 ± 0.78 g/s, flux checks 50.71 and
    // 51.63 g/s, v_c = 0.698 m/s, φ_c = 0.679, φ_B = 0.537, drained after 4.19 s; two
    // threads give the same bytes.
    let dir = tempfile::tempdir().expect("temporary directory");
    let (one, two) = (dir.path().join("one"), dir.path().join("two"));
    run(&["--threads", "1"], &one);
    let s = summary(&one);
    assert_documented("W [g/s]", number(&s, "discharge_rate"), 1e3, "50.99");
    assert_documented("σ_W [g/s]", number(&s, "discharge_rate_error"), 1e3, "0.78");
    assert_documented(
        "flux ⟨φv⟩ [g/s]",
        number(&s, "flux_check_rate"),
        1e3,
        "50.71",
    );
    assert_documented(
        "flux φ(x)v(x) [g/s]",
        number(&s, "flux_check_rate_profiles"),
        1e3,
        "51.63",
    );
    assert_documented("v_c [m/s]", number(&s, "centre_velocity"), 1.0, "0.698");
    assert_documented("φ_c", number(&s, "centre_area_fraction"), 1.0, "0.679");
    assert_documented("φ_B", number(&s, "bulk_volume_fraction"), 1.0, "0.537");
    assert_documented("discharge [s]", number(&s, "discharge_time"), 1.0, "4.19");
    run(&["--threads", "2"], &two);
    for name in ["summary.json", "flow.csv", "profiles.csv", "crossings.csv"] {
        let read = |d: &Path| std::fs::read(d.join(name)).expect(name);
        assert!(
            read(&one) == read(&two),
            "{name} differs between 1 and 2 threads"
        );
    }
}

#[test]
#[ignore = "long validation (minutes): docs/reproduction.md, \"Long validations\""]
fn the_reduced_benchmark_silo_gives_the_documented_rate_and_n_of_t() {
    // docs/reproduction.md, "Reduced silo, exact walls", run under g = 9.81 m/s² as
    // documented: W = 1.943 ± 0.023 kg/s, φ_B = 0.588, bed 73.8 mm; N(t) every 0.1 s;
    // the radial fits; W from the fitted profiles 1.936 kg/s.
    let dir = tempfile::tempdir().expect("temporary directory");
    let case = repository().join("cases/dosta2024-silo-reduced.toml");
    run(
        &[utf8(&case), "--set", "gravity=9.81", "--threads", "2"],
        dir.path(),
    );
    let s = summary(dir.path());
    assert_documented("W [kg/s]", number(&s, "discharge_rate"), 1.0, "1.943");
    assert_documented(
        "σ_W [kg/s]",
        number(&s, "discharge_rate_error"),
        1.0,
        "0.023",
    );
    assert_documented("φ_B", number(&s, "bulk_volume_fraction"), 1.0, "0.588");
    assert_documented("bed [mm]", number(&s, "bed_height"), 1e3, "73.8");
    let fit = &s["radial_fit"];
    for (what, key, documented) in [
        ("v_c [m/s]", "centre_velocity", "0.745"),
        ("a", "velocity_exponent", "0.365"),
        ("φ_c", "centre_volume_fraction", "0.541"),
        ("b", "packing_exponent", "0.106"),
        ("W from the profiles [kg/s]", "profile_rate", "1.936"),
    ] {
        assert_documented(what, number(fit, key), 1.0, documented);
    }
    let text = std::fs::read_to_string(dir.path().join("remaining.csv")).expect("remaining.csv");
    let documented = [
        20_000, 18_244, 15_868, 13_486, 11_134, 8834, 6598, 4444, 2420, 781, 113,
    ];
    // N(t) is sampled every 0.01 s from the first step after the opening; the documented
    // values are the samples nearest each tenth of a second.
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|c| c.parse::<f64>().unwrap()).collect())
        .collect();
    for (k, expected) in documented.iter().enumerate() {
        let t = 0.1 * k as f64;
        let row = rows
            .iter()
            .min_by(|a, b| (a[0] - t).abs().total_cmp(&(b[0] - t).abs()))
            .filter(|r| (r[0] - t).abs() < 0.005)
            .unwrap_or_else(|| panic!("no N(t) sample near t = {t} s"));
        assert_eq!(
            row[1],
            f64::from(*expected),
            "N({t} s), sampled at {} s",
            row[0]
        );
    }
}

#[test]
#[ignore = "long validation (tens of minutes): docs/reproduction.md, \"Long validations\""]
fn the_quick_3d_beverloo_study_gives_the_documented_table() {
    // docs/reproduction.md, "3D Beverloo", the reduced study: per orifice D [mm], W [g/s],
    // v_c [m/s], a, φ_c and b.
    let dir = tempfile::tempdir().expect("temporary directory");
    let sweep = repository().join("cases/beverloo3d-quick.toml");
    study(utf8(&sweep), dir.path());
    let documented = [
        ("15", "28.2", "0.371", "0.58", "0.380", "0.55"),
        ("21", "83.6", "0.449", "0.57", "0.437", "0.39"),
        ("27", "182.2", "0.526", "0.54", "0.477", "0.38"),
    ];
    let cases: Vec<_> = std::fs::read_dir(dir.path().join("cases"))
        .expect("the study's cases")
        .map(|e| e.expect("an entry").path())
        .collect();
    for (d, w, v_c, a, phi_c, b) in documented {
        let s = cases
            .iter()
            .map(|c| summary(c))
            .find(|s| printed(number(s, "outlet_width") * 1e3, 0) == d)
            .unwrap_or_else(|| panic!("no case of D = {d} mm"));
        let fit = &s["radial_fit"];
        assert_documented("W [g/s]", number(&s, "discharge_rate"), 1e3, w);
        assert_documented("v_c [m/s]", number(fit, "centre_velocity"), 1.0, v_c);
        assert_documented("a", number(fit, "velocity_exponent"), 1.0, a);
        assert_documented("φ_c", number(fit, "centre_volume_fraction"), 1.0, phi_c);
        assert_documented("b", number(fit, "packing_exponent"), 1.0, b);
    }
}

#[test]
#[ignore = "long validation (most of an hour on two cores): docs/reproduction.md, \"Long validations\""]
fn the_paper_study_gives_the_documented_comparison() {
    // docs/reproduction.md, "One replica per case": 44 cases, angle-a90-D018 and
    // eccentric-s12-D018 clogged, and the comparison items' measured values to the four
    // decimals the table prints.
    let dir = tempfile::tempdir().expect("temporary directory");
    study("fan2023", dir.path());
    let cases = dir.path().join("cases");
    let mut clogged: Vec<String> = std::fs::read_dir(&cases)
        .expect("the study's cases")
        .map(|e| e.expect("an entry").path())
        .filter(|c| summary(c)["clogged"] == Value::Bool(true))
        .map(|c| c.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    clogged.sort();
    // Case folders carry the replica: `-r0` for the one replica of each case.
    assert_eq!(clogged, ["angle-a90-D018-r0", "eccentric-s12-D018-r0"]);
    let text = std::fs::read_to_string(dir.path().join("report/comparison.json"))
        .expect("report/comparison.json");
    let items: Value = serde_json::from_str(&text).expect("comparison.json is JSON");
    let items = items.as_array().expect("an array of items");
    let measured = |starts: &str| {
        items
            .iter()
            .find(|i| i["item"].as_str().is_some_and(|t| t.starts_with(starts)))
            .unwrap_or_else(|| panic!("no item {starts}"))["measured"]
            .as_f64()
            .unwrap_or_else(|| panic!("item {starts} is not a number"))
    };
    // Each item by the start of its name, long enough to name one item: the pooled k
    // (the paper's Fig. 2b fit, three decimals in the summary) and the α = 90° reference.
    for (item, documented) in [
        ("Beverloo k (all α pooled", "1.437"),
        ("Beverloo k (α = 90°)", "2.4452"),
        ("γ(90°)", "1.8380"),
        ("a(90°)", "0.4162"),
        ("b(90°)", "0.2048"),
        ("W(s = 0)/W0", "1.2645"),
    ] {
        assert_documented(item, measured(item), 1.0, documented);
    }
}

/// The mean and standard error of `values`.
fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

/// One parameter of a round trip: its case key, true value and search range.
struct Unknown {
    key: &'static str,
    truth: f64,
    range: (f64, f64),
}

/// The calibration round trip of docs/physics.md §12.4: the two lab tests of the shipped
/// cases (the heap's angle of repose, the draw-down's shelf angle) run at the `unknowns`'
/// true values, four fills each, give the targets as a lab would (mean ± standard error);
/// `hopperflow calibrate` then searches the unknowns over their ranges with two replicates
/// a point. Returns the calibration's record.
fn round_trip(name: &str, unknowns: &[Unknown], max_rounds: u32) -> Value {
    const FILLS: u64 = 4;
    let dir = tempfile::tempdir().expect("temporary directory");
    let cases = repository().join("cases");
    let tests = [
        ("repose.toml", "repose", "angle_deg"),
        ("draw-down.toml", "draw_down", "shelf_angle_deg"),
    ];
    let sets: Vec<String> = unknowns
        .iter()
        .map(|u| format!("{}={}", u.key, u.truth))
        .collect();
    let mut targets = String::new();
    for (file, section, measure) in tests {
        let case = cases.join(file);
        let values: Vec<f64> = (0..FILLS)
            .map(|r| {
                let out = dir.path().join(format!("truth-{section}-{r}"));
                let seed = format!("seed={}", 1000 + r);
                let mut args = vec![utf8(&case), "--set", &seed, "--set", "output.plots=false"];
                for set in &sets {
                    args.extend(["--set", set.as_str()]);
                }
                run(&args, &out);
                number(&summary(&out)[section], measure)
            })
            .collect();
        let (mean, error) = mean_and_error(&values);
        eprintln!("truth {section}.{measure}: {values:?} → {mean:.3} ± {error:.3}");
        targets.push_str(&format!(
            "[[targets]]\ncase = \"{}\"\nmeasure = \"{section}.{measure}\"\nvalue = {mean}\nuncertainty = {error}\n",
            case.display()
        ));
    }
    let parameters: String = unknowns
        .iter()
        .map(|u| {
            format!(
                "[[parameters]]\nkey = \"{}\"\nmin = {}\nmax = {}\n",
                u.key, u.range.0, u.range.1
            )
        })
        .collect();
    let file = dir.path().join("round-trip.toml");
    std::fs::write(
        &file,
        format!(
            "version = 1\nname = \"{name}\"\nreplicates = 2\nmax_rounds = {max_rounds}\n{parameters}{targets}"
        ),
    )
    .expect("the calibration file is written");
    let out = dir.path().join("calibration");
    let started = std::time::Instant::now();
    let output = hopperflow(&["calibrate", utf8(&file), "--out", utf8(&out), "--jobs", "2"]);
    let seconds = started.elapsed().as_secs_f64();
    eprintln!("{}", String::from_utf8_lossy(&output.stdout));
    let record = summary_of(&out.join("calibration.json"));
    for (u, estimate) in unknowns
        .iter()
        .zip(record["estimate"].as_array().expect("estimates"))
    {
        let (value, error) = (
            estimate["value"].as_f64().expect("a value"),
            estimate["standard_error"].as_f64().unwrap_or(f64::INFINITY),
        );
        eprintln!(
            "round trip: {} = {value:.4} ± {error:.4} against {} ({:.2} σ)",
            u.key,
            u.truth,
            (value - u.truth) / error
        );
    }
    eprintln!(
        "{} runs in {} rounds, {seconds:.0} s of calibration on 2 jobs",
        record["runs"],
        record["rounds"].as_array().map_or(0, Vec::len)
    );
    record
}

/// Asserts that the calibration converged, met its targets and found every unknown within
/// two of its stated standard errors (a miss has probability 5 % per parameter for a
/// correct error).
fn assert_recovered(record: &Value, unknowns: &[Unknown]) {
    assert_eq!(record["converged"], true, "{record}");
    assert_eq!(record["targets_met"], true, "{record}");
    for (u, estimate) in unknowns
        .iter()
        .zip(record["estimate"].as_array().expect("estimates"))
    {
        let value = estimate["value"].as_f64().expect("a value");
        let error = estimate["standard_error"].as_f64().expect("an error");
        assert!(
            (value - u.truth).abs() <= 2.0 * error,
            "{} = {value} ± {error} misses {}",
            u.key,
            u.truth
        );
    }
}

#[test]
#[ignore = "long validation (tens of minutes): docs/physics.md §12.4"]
fn calibration_round_trip_recovers_the_rolling_friction() {
    let unknowns = [Unknown {
        key: "contact.rolling_friction",
        truth: 0.12,
        range: (0.02, 0.3),
    }];
    let record = round_trip("round-trip", &unknowns, 5);
    assert_recovered(&record, &unknowns);
}

#[test]
#[ignore = "long validation (tens of minutes): docs/physics.md §12.4"]
fn calibration_round_trip_of_rolling_and_sliding_friction_says_the_angles_cannot_separate_them() {
    // Two unknowns from the same two angles. Both angles rise with both frictions in the
    // same proportion: at the solution of the first round the two surfaces' gradients are
    // parallel to 1e-7 (docs/physics.md §12.4), so the targets fix one combination of μ_r
    // and μ_s only. The calibration must say so, with unbounded errors, rather than report
    // a spurious uncertainty. One round shows it.
    let unknowns = [
        Unknown {
            key: "contact.rolling_friction",
            truth: 0.12,
            range: (0.02, 0.3),
        },
        Unknown {
            key: "contact.friction",
            truth: 0.5,
            range: (0.2, 0.9),
        },
    ];
    let record = round_trip("round-trip-2", &unknowns, 1);
    for estimate in record["estimate"].as_array().expect("estimates") {
        // An infinite standard error is written as null.
        assert!(
            estimate["standard_error"].is_null(),
            "{}: the angles cannot determine it: {estimate}",
            estimate["key"]
        );
    }
    // The targets are still met: the estimate lies on the line of parameters they allow.
    assert_eq!(record["targets_met"], true, "{record}");
}

/// A JSON file.
fn summary_of(path: &Path) -> Value {
    let text = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_slice(&text).expect("JSON")
}
