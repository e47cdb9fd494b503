//! Sweep files: expansion of the built-in fan2023 programme, replicas, skipping and errors.

use std::collections::BTreeSet;
use std::path::Path;

use case::{
    builtin_sweep, load_case, load_sweep, parse_sweep, Case, FAN2023_QUICK_SWEEP,
    FAN2023_SENSITIVITY_SWEEP, FAN2023_SWEEP,
};

/// The paper's programme and the sensitivity series, as one plan.
fn fan2023() -> case::SweepPlan {
    let mut plan = parse_sweep(FAN2023_SWEEP, "fan2023", None, &[]).expect("fan2023 must expand");
    let extra = parse_sweep(FAN2023_SENSITIVITY_SWEEP, "fan2023-sensitivity", None, &[])
        .expect("fan2023-sensitivity must expand");
    plan.cases.extend(extra.cases);
    plan.skipped.extend(extra.skipped);
    plan
}

#[test]
fn fan2023_is_the_papers_44_cases() {
    // Table 1 of the paper: 5 angles × 4 widths and 6 gaps × 4 widths.
    let plan = parse_sweep(FAN2023_SWEEP, "fan2023", None, &[]).unwrap();
    assert_eq!(plan.cases.len(), 44);
    assert!(plan
        .cases
        .iter()
        .all(|c| ["angle", "eccentric"].contains(&c.labels["series"].as_str())));
}

#[test]
fn fan2023_expands_to_the_papers_grid_plus_sensitivity_runs() {
    let plan = fan2023();
    let count = |series: &str| {
        plan.cases
            .iter()
            .filter(|c| c.labels["series"] == series)
            .count()
    };
    // 5 angles × 4 widths; 6 gaps × 4 widths (all fit: s + D ≤ 90 mm < L); 4 widths at
    // low wall friction; 2 thicknesses × 4 widths. One replica each.
    assert_eq!(count("angle"), 20);
    assert_eq!(count("eccentric"), 24);
    assert_eq!(count("wallfriction"), 4);
    assert_eq!(count("thickness"), 8);
    assert_eq!(plan.cases.len(), 56);
    assert!(plan.skipped.is_empty());
    let ids: BTreeSet<&str> = plan.cases.iter().map(|c| c.id.as_str()).collect();
    assert_eq!(ids.len(), plan.cases.len(), "identifiers must be unique");
}

#[test]
fn fan2023_identifiers_name_the_grid_values() {
    let plan = fan2023();
    let find = |id: &str| {
        plan.cases
            .iter()
            .find(|c| c.id == id)
            .unwrap_or_else(|| panic!("no case {id}"))
    };
    let angle = find("angle-a30-D045-r0");
    // Exact: the values are copied from the sweep file, not computed.
    assert_eq!(angle.case.geometry.slab().unwrap().hopper_angle_deg, 30.0);
    assert_eq!(angle.case.geometry.slab().unwrap().outlet_width, 0.045);
    assert_eq!(angle.case.geometry.slab().unwrap().outlet_offset(), 0.0);
    assert_eq!(angle.labels["geometry.hopper_angle_deg"], "30");

    let eccentric = find("eccentric-s06-D018-r0");
    assert_eq!(eccentric.case.geometry.slab().unwrap().outlet_gap, 0.006);
    assert_eq!(
        eccentric.case.geometry.slab().unwrap().hopper_angle_deg,
        90.0
    );

    let wall = find("wallfriction-D030-r0");
    assert_eq!(wall.case.wall.interaction.friction, 0.01);
    assert_eq!(wall.labels["wall.friction"], "0.01");
    // The sensitivity series changes only the wall friction of the base case.
    assert_eq!(wall.case.contact.particle.friction, 0.5);

    let thick = find("thickness-Z45-D060-r0");
    assert_eq!(thick.case.geometry.slab().unwrap().thickness, 0.0045);
    for case in &plan.cases {
        assert!(case
            .id
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_'));
        assert_eq!(case.case.particles.count, 3000);
    }
}

#[test]
fn quick_preset_is_small_and_every_case_fits() {
    let plan = parse_sweep(FAN2023_QUICK_SWEEP, "fan2023-quick", None, &[]).unwrap();
    assert_eq!(plan.cases.len(), 6);
    for sweep_case in &plan.cases {
        let case = &sweep_case.case;
        assert_eq!(case.particles.count, 600);
        // The fill must leave head room below H for the particles to rain in.
        let fill = case.fill_height().expect("quick cases must fit");
        assert!(
            fill < 0.8 * case.geometry.slab().unwrap().height,
            "{}: fill {fill}",
            sweep_case.id
        );
    }
    assert_eq!(builtin_sweep("quick"), Some(FAN2023_QUICK_SWEEP));
    assert_eq!(builtin_sweep("fan2023"), Some(FAN2023_SWEEP));
    assert_eq!(builtin_sweep("nonesuch"), None);
}

#[test]
fn replicas_get_distinct_reproducible_seeds() {
    let text = r#"
version = 1
name = "rep"
replicas = 3
[[axes]]
key = "geometry.outlet_width"
values = [0.018, 0.03]
label = "D"
scale = 1000.0
digits = 3
"#;
    let plan = parse_sweep(text, "rep.toml", None, &[]).unwrap();
    assert_eq!(plan.cases.len(), 6);
    let seeds: BTreeSet<u64> = plan.cases.iter().map(|c| c.case.seed).collect();
    assert_eq!(
        seeds.len(),
        6,
        "every replica of every point needs its own fill"
    );
    let again = parse_sweep(text, "rep.toml", None, &[]).unwrap();
    assert_eq!(plan, again);
    assert_eq!(plan.cases[0].id, "rep-D018-r0");
    assert_eq!(plan.cases[2].id, "rep-D018-r2");
    // Seeds stay writable as TOML integers.
    assert!(seeds.iter().all(|s| *s <= i64::MAX as u64));
}

#[test]
fn grid_points_whose_outlet_does_not_fit_are_skipped_with_reasons() {
    let text = r#"
version = 1
name = "fit"
[[axes]]
key = "geometry.outlet_gap"
values = [0.05, 0.08]
label = "s"
scale = 1000.0
[[axes]]
key = "geometry.outlet_width"
values = [0.018, 0.03]
label = "D"
scale = 1000.0
"#;
    let plan = parse_sweep(text, "fit.toml", None, &[]).unwrap();
    // s + D = 0.11 m > L = 0.1 m only for s = 80 mm, D = 30 mm.
    assert_eq!(plan.cases.len(), 3);
    assert_eq!(plan.skipped.len(), 1);
    assert_eq!(plan.skipped[0].id, "fit-s80-D30");
    assert!(plan.skipped[0].reasons[0].contains("the outlet does not fit"));
}

#[test]
fn a_bad_axis_value_is_reported_at_its_line_in_the_sweep_file() {
    let text = "version = 1\nname = \"bad\"\n[[axes]]\nkey = \"geometry.outlet_width\"\nvalues = [0.03,\n  \"wide\"]\n";
    let errors = parse_sweep(text, "bad.toml", None, &[]).unwrap_err();
    let report = errors.to_string();
    assert!(
        report.contains("bad.toml:6:3: geometry.outlet_width = \"wide\": expected a number"),
        "{report}"
    );
    assert!(
        report.contains("(in sweep case bad-outlet_widthwide)"),
        "{report}"
    );
}

#[test]
fn sweep_errors_in_the_file_itself_are_all_reported() {
    let text = "version = 1\nreplicas = 0\nbogus = 1\n[[series]]\nset = 3\n";
    let errors = parse_sweep(text, "s.toml", None, &[]).unwrap_err();
    let report = errors.to_string();
    for fragment in [
        "s.toml: name: required",
        "s.toml:2:1: replicas = 0: must be an integer in [1, 10000]",
        "s.toml:3:1: bogus: unknown key",
        "series[0].set = 3: expected a table",
        "series[0].name: required",
    ] {
        assert!(report.contains(fragment), "lacks `{fragment}`:\n{report}");
    }
}

#[test]
fn sweep_base_can_be_a_case_file_next_to_the_sweep() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("narrow.toml"),
        "version = 1\n[geometry]\nwidth = 0.06\n[particles]\ncount = 500\n",
    )
    .unwrap();
    let sweep = dir.path().join("sweep.toml");
    std::fs::write(
        &sweep,
        "version = 1\nname = \"n\"\nbase = \"narrow.toml\"\n[[axes]]\nkey = \"geometry.hopper_angle_deg\"\nvalues = [45, 90]\nlabel = \"a\"\n",
    )
    .unwrap();
    let plan = load_sweep(&sweep, &["seed=7".to_string()]).unwrap();
    assert_eq!(plan.cases.len(), 2);
    assert_eq!(plan.cases[0].id, "n-a45-r0");
    assert_eq!(plan.cases[0].case.geometry.slab().unwrap().width, 0.06);
    assert_eq!(plan.cases[1].case.particles.count, 500);
    // The --set seed feeds the replica seeds, so they differ from the default-seed plan.
    let default_seed = load_sweep(&sweep, &[]).unwrap();
    assert_ne!(plan.cases[0].case.seed, default_seed.cases[0].case.seed);
}

#[test]
fn shipped_case_files_match_the_built_ins_and_are_valid() {
    let cases = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases");
    let read = |name: &str| std::fs::read_to_string(cases.join(name)).unwrap();
    assert_eq!(read("fan2023.toml"), FAN2023_SWEEP);
    assert_eq!(read("fan2023-sensitivity.toml"), FAN2023_SENSITIVITY_SWEEP);
    assert_eq!(read("fan2023-quick.toml"), FAN2023_QUICK_SWEEP);
    assert_eq!(read("base.toml"), case::CASE_TEMPLATE);
    assert_eq!(
        load_case(&cases.join("base.toml"), &[]).unwrap(),
        Case::paper_base()
    );
    let alpha = load_case(&cases.join("alpha30.toml"), &[]).unwrap();
    assert_eq!(alpha.geometry.slab().unwrap().hopper_angle_deg, 30.0);
    // Plates of run 35 mm at 30° rise 35/tan 30° = 60.6 mm (0.1 mm tolerance: printed).
    assert!((alpha.geometry.slab().unwrap().funnel_height() - 0.0606).abs() < 1e-4);
    let wall = load_case(&cases.join("eccentric-s0.toml"), &[]).unwrap();
    assert_eq!(wall.geometry.slab().unwrap().outlet_gap, 0.0);
    // x_c = −e = −(L − D)/2 = −35 mm, to rounding.
    assert!((wall.geometry.slab().unwrap().outlet_centre() + 0.035).abs() < 1e-15);
}
