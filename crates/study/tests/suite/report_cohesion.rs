//! The report's cohesion section on a fake study written as a run leaves it (results.csv,
//! each case's resolved case.toml, a clogged case's summary.json with its arch): Bond
//! numbers, W against Bo with replicas averaged, the critical-width brackets, the arches.

use std::f64::consts::PI;
use std::path::Path;

use crate::fake_study::{Folder, RESULTS_HEADER};
use report::{analyse_cohesion, build_report, load_cohesion, CriticalWidth};

/// Table 1's grains: d = 3 mm, ρ_p = 2500 kg/m³, under the default g.
const D: f64 = 3e-3;
const DENSITY: f64 = 2500.0;
const G: f64 = 9.81;

/// One case: identifier, JKR w [J/m²] (None: dry), D [m], W [kg/s] (None: clogged).
type Fake = (&'static str, Option<f64>, f64, Option<f64>);

/// Writes the study: the 26 columns of results.csv, and per case the resolved case as a run
/// writes it (only the keys the report reads, plus one that all cases share) and, when
/// clogged, a summary.json whose arch stands 20.7 mm high at its apex.
fn write_study(root: &Path, cases: &[Fake]) {
    let mut csv = String::from(RESULTS_HEADER);
    for (i, &(id, w, width, rate)) in cases.iter().enumerate() {
        let series = if w.is_some() { "jkr" } else { "dry" };
        let replica = &id[id.len() - 1..];
        let (rate, error, clogged, status) = match rate {
            Some(r) => (r.to_string(), (0.03 * r).to_string(), false, "complete"),
            None => ("NaN".into(), "NaN".into(), true, "clogged"),
        };
        let gap = (0.06 - width) / 2.0;
        csv.push_str(&format!(
            "{id},{series},{replica},,{width},90,{gap},1,0.00303,0.5,0.06,{D},{DENSITY},600,{i},\
             {rate},{error},NaN,NaN,NaN,0.53,NaN,NaN,true,{clogged},{status}\n"
        ));
        let dir = root.join("cases").join(id);
        std::fs::create_dir_all(&dir).unwrap();
        let cohesion = w.map_or(String::new(), |w| {
            format!("cohesion = {{ law = \"jkr\", work_of_adhesion = {w} }}\n")
        });
        std::fs::write(
            dir.join("case.toml"),
            format!(
                "version = 1\nseed = {i}\n\n[geometry]\nwidth = 0.06\noutlet_width = {width}\n\
                 outlet_gap = {gap}\n\n[particles]\ncount = 600\ndiameter = {D}\n\n\
                 [particles.material]\ndensity = {DENSITY}\nshear_modulus = 1e8\n\
                 poisson_ratio = 0.25\n\n[wall]\nmaterial = \"same\"\nfriction = 0.5\n\n\
                 [contact]\nfriction = 0.5\n{cohesion}"
            ),
        )
        .unwrap();
        if clogged {
            std::fs::write(
                dir.join("summary.json"),
                r#"{"clogged": true, "arch": {"particles": 12, "apex_height": 0.0207,
                   "lowest_height": 0.0028, "mean_height": 0.0088}}"#,
            )
            .unwrap();
        }
    }
    std::fs::write(root.join("results.csv"), csv).unwrap();
}

/// Bo of JKR grains of work of adhesion `w` [J/m²], from the definition: the pull-off force
/// (3/2)π w R*, R* = d/4, over the weight ρ_p (π d³/6) g.
fn jkr_bond(w: f64) -> f64 {
    let pull_off = 1.5 * PI * w * D / 4.0;
    let weight = DENSITY * PI * D.powi(3) / 6.0 * G;
    pull_off / weight
}

#[test]
fn a_cohesive_study_gets_w_against_bo_and_the_critical_width_bracket() {
    let folder = Folder::new("cohesion");
    let (w1, w2) = (0.098, 2.94);
    write_study(
        &folder.0,
        &[
            ("dry-D018-r0", None, 0.018, Some(0.0177)),
            ("dry-D030-r0", None, 0.030, Some(0.0495)),
            ("jkr-w0098-D018-r0", Some(w1), 0.018, Some(0.0169)),
            ("jkr-w0098-D030-r0", Some(w1), 0.030, Some(0.0456)),
            ("jkr-w0098-D030-r1", Some(w1), 0.030, Some(0.0462)),
            // At Bo = 30 and 6 d one replica arches and one flows; 10 d flows.
            ("jkr-w2940-D018-r0", Some(w2), 0.018, None),
            ("jkr-w2940-D018-r1", Some(w2), 0.018, Some(0.0120)),
            ("jkr-w2940-D030-r0", Some(w2), 0.030, Some(0.0376)),
        ],
    );
    let data = report::load_study(&folder.0).unwrap();
    let analysis = analyse_cohesion(&load_cohesion(&folder.0, &data.rows));
    assert!(analysis.present && analysis.undefined.is_empty());
    // Dry and JKR cases share everything but cohesion and outlet: one table.
    assert_eq!(analysis.groups.len(), 1);
    let group = &analysis.groups[0];
    assert_eq!(group.widths, vec![0.018, 0.030]);
    let bonds: Vec<f64> = group.levels.iter().map(|l| l.bond).collect();
    assert_eq!(bonds.len(), 3);
    assert_eq!(bonds[0], 0.0);
    // The report's Bo and the definition evaluated here differ by the order of the same
    // operations only: a few ulps, well inside 1e-12.
    for (got, w) in bonds[1..].iter().zip([w1, w2]) {
        let want = jkr_bond(w);
        assert!(
            (got - want).abs() < 1e-12 * want,
            "w = {w}: {got} vs {want}"
        );
    }
    // w = 0.098 J/m² is the preset's Bo ≈ 1 for these grains, 2.94 J/m² its Bo ≈ 30.
    assert!((bonds[1] - 1.0).abs() < 0.01 && (bonds[2] - 30.0).abs() < 0.1);

    // Replicas averaged: the mean of 45.6 and 46.2 g/s, over the dry 49.5 g/s.
    let cell = &group.levels[1].cells[1];
    assert_eq!((cell.runs, cell.clogged), (2, 0));
    let rate = cell.rate.unwrap();
    assert!((rate.value - 0.0459).abs() < 1e-12);
    let ratio = cell.relative_rate.unwrap();
    assert!((ratio.value - 0.0459 / 0.0495).abs() < 1e-12);
    assert!(ratio.value < 1.0 && ratio.standard_error > 0.0);
    // The dry level is the reference, not a ratio of itself.
    assert!(group.levels[0]
        .cells
        .iter()
        .all(|c| c.relative_rate.is_none()));
    // The half-clogged cell averages only the replica that flowed.
    let cell = &group.levels[2].cells[0];
    assert_eq!((cell.runs, cell.clogged), (2, 1));
    assert_eq!(cell.clogging_fraction(), 0.5);
    assert!((cell.rate.unwrap().value - 0.0120).abs() < 1e-15);

    // D_c: below 6 d when dry and at Bo = 1; between 6 d and 10 d at Bo = 30.
    assert_eq!(group.levels[0].critical, CriticalWidth::Below(0.018));
    assert_eq!(group.levels[1].critical, CriticalWidth::Below(0.018));
    assert_eq!(
        group.levels[2].critical,
        CriticalWidth::Between {
            clogged: 0.018,
            flowed: 0.030
        }
    );
    // The arch of the clogged case, where its summary put it.
    assert_eq!(group.arches.len(), 1);
    let (id, bond, width, arch) = &group.arches[0];
    assert_eq!((id.as_str(), *width), ("jkr-w2940-D018-r0", 0.018));
    assert_eq!(*bond, bonds[2]);
    assert_eq!(arch.unwrap().apex_height, 0.0207);

    // The written report carries the section, the bracket, the arch and the figure.
    let files = build_report(&folder.0).unwrap();
    let md = std::fs::read_to_string(&files.markdown).unwrap();
    assert!(md.contains("## Cohesion and the Bond number"));
    assert!(md.contains("| jkr | 30.0 | 18.0 mm: 1/2 (50 %); 30.0 mm: 0/1 (0 %) | 18.0 mm (6.0 d) < D_c ≤ 30.0 mm (10.0 d) |"));
    assert!(md.contains("| jkr-w2940-D018-r0 | 30.0 | 18.0 mm (6.0 d) | 12 | 20.7 mm (6.9 d) |"));
    assert!(md.contains("12.00 ± 0.36 (clogged 1/2)"));
    assert!(files
        .figures
        .iter()
        .any(|f| f.ends_with("cohesion-rate-ratio.svg")));
}

#[test]
fn a_dry_study_has_no_cohesion_section() {
    let folder = Folder::new("dry");
    write_study(
        &folder.0,
        &[
            ("dry-D018-r0", None, 0.018, Some(0.0177)),
            ("dry-D030-r0", None, 0.030, Some(0.0495)),
        ],
    );
    let files = build_report(&folder.0).unwrap();
    let md = std::fs::read_to_string(&files.markdown).unwrap();
    assert!(!md.contains("Bond number"));
    assert!(!files
        .figures
        .iter()
        .any(|f| f.to_string_lossy().contains("cohesion")));
}
