//! The report of a study whose every case breaks its arches: a fake slab study written as a
//! run leaves it (results.csv, each case's summary.json with its avalanches). Its rates hold
//! the arrests and pulses, so the report leaves out the steady-flow sections and keeps the
//! clogging one; a study that also holds a steady case keeps both.

use std::path::Path;

use crate::fake_study::{Folder, RESULTS_HEADER};
use report::build_report;

/// Writes a slab study of outlets `widths` [m] of 3 mm grains; the first `unclogged` cases
/// flow steadily (no avalanche section), the rest break their arches, with mean avalanche
/// sizes growing as exp(D/d).
fn write_study(root: &Path, widths: &[f64], unclogged: usize) {
    let mut csv = String::from(RESULTS_HEADER);
    for (i, &width) in widths.iter().enumerate() {
        let id = format!("slot-{i}-r0");
        let gap = (0.05 - width) / 2.0;
        csv.push_str(&format!(
            "{id},slot,0,,{width},90,{gap},1,0.00303,0.5,0.05,0.003,2500,1000,{i},\
             0.002,0.0002,NaN,NaN,NaN,0.53,NaN,NaN,true,false,complete\n"
        ));
        let dir = root.join("cases").join(&id);
        std::fs::create_dir_all(&dir).unwrap();
        let summary = if i < unclogged {
            r#"{"thickness": 0.00303}"#.to_string()
        } else {
            let mean = (width / 0.003f64).exp();
            format!(
                r#"{{"thickness": 0.00303, "avalanches": {{"count": 20, "mean_size": {mean},
                   "mean_size_error": {e}, "mean_size_censored": {mean},
                   "mean_size_censored_error": {e}, "mean_mass": 0.001, "mean_duration": 0.1,
                   "mean_arrest": 0.2, "pulses": 20, "failed_pulses": 0}}}}"#,
                e = 0.2 * mean
            )
        };
        std::fs::write(dir.join("summary.json"), summary).unwrap();
    }
    std::fs::write(root.join("results.csv"), csv).unwrap();
}

#[test]
fn a_study_that_only_breaks_arches_reports_clogging_without_the_steady_flow_sections() {
    let widths = [0.009, 0.0105, 0.012, 0.0135];
    let folder = Folder::new("clogging-only");
    write_study(&folder.0, &widths, 0);
    let files = build_report(&folder.0).expect("a report of the clogging study");
    let text = std::fs::read_to_string(&files.markdown).unwrap();
    assert!(
        text.contains("## Clogging: avalanche sizes against D/d"),
        "{text}"
    );
    for steady in ["## Comparison", "## Beverloo constants", "## Table 2"] {
        assert!(!text.contains(steady), "{steady} in a clogging-only report");
    }
    assert!(text.contains("steady-flow sections"), "{text}");
    // No figure is drawn for it, so no empty heading announces one.
    assert!(!text.contains("## Figures"), "{text}");

    // One steady case beside them: the steady-flow sections are back, clogging stays.
    let mixed = Folder::new("clogging-mixed");
    write_study(&mixed.0, &[0.015, 0.009, 0.0105, 0.012, 0.0135], 1);
    let files = build_report(&mixed.0).expect("a report of the mixed study");
    let text = std::fs::read_to_string(&files.markdown).unwrap();
    assert!(text.contains("## Clogging: avalanche sizes against D/d"));
    assert!(text.contains("## Comparison with the paper"));
}
