//! The lab tests of a study (`geometry.kind = "heap"` and `"draw_down"`, docs/physics.md §5.9–
//! 5.10, §7.10–7.11): each grid point's angle of repose or shelf angle, averaged over its
//! replicas, from `results.csv` alone.

use std::collections::BTreeMap;

use files::{CaseStatus, ResultRow};

use super::document::Block;

/// Mean and standard error over replicas: the standard error of the mean when there are
/// several, the run's own fitted error when there is one.
fn mean_and_error(values: &[(f64, f64)]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().map(|v| v.0).sum::<f64>() / n;
    if values.len() == 1 {
        return (mean, values[0].1);
    }
    let variance = values.iter().map(|v| (v.0 - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

/// The identifier without its replica suffix (`-r<n>`).
fn point_of(id: &str) -> &str {
    match id.rfind("-r") {
        Some(i) if i + 2 < id.len() && id[i + 2..].chars().all(|c| c.is_ascii_digit()) => &id[..i],
        _ => id,
    }
}

/// A grid point's labels, its replicas' (angle, error) [°] and their rates W [kg/s].
type Point = (String, Vec<(f64, f64)>, Vec<f64>);

/// One table per test kind present: grid point, its labels, replicas, the angle (mean ±
/// error) and, for the draw-down test, W. Nothing when the study has no lab test.
pub fn lab_test_blocks(rows: &[ResultRow]) -> Vec<Block> {
    let mut blocks = Vec::new();
    type Angle = fn(&ResultRow) -> (f64, f64);
    let kinds: [(&str, &str, Angle, bool); 2] = [
        (
            "Angle of repose (heap)",
            "angle of repose [°]",
            |r| (r.repose_angle_deg, r.repose_angle_error_deg),
            false,
        ),
        (
            "Shelf angle (draw-down)",
            "shelf angle [°]",
            |r| (r.shelf_angle_deg, r.shelf_angle_error_deg),
            true,
        ),
    ];
    for (title, column, angle, with_rate) in kinds {
        let mut points: BTreeMap<&str, Point> = BTreeMap::new();
        for row in rows
            .iter()
            .filter(|r| r.status != CaseStatus::Failed && angle(r).0.is_finite())
        {
            let entry = points
                .entry(point_of(&row.id))
                .or_insert_with(|| (row.labels.clone(), Vec::new(), Vec::new()));
            entry.1.push(angle(row));
            if row.discharge_rate.is_finite() {
                entry.2.push(row.discharge_rate);
            }
        }
        if points.is_empty() {
            continue;
        }
        let mut headers = vec!["point", "labels", "replicas", column];
        if with_rate {
            headers.push("W [g/s]");
        }
        let table_rows = points
            .iter()
            .map(|(point, (labels, angles, rates))| {
                let (mean, error) = mean_and_error(angles);
                let mut row = vec![
                    point.to_string(),
                    labels.clone(),
                    angles.len().to_string(),
                    format!("{mean:.2} ± {error:.2}"),
                ];
                if with_rate {
                    row.push(if rates.is_empty() {
                        "—".into()
                    } else {
                        let w: Vec<(f64, f64)> = rates.iter().map(|w| (*w, f64::NAN)).collect();
                        let (mean, error) = mean_and_error(&w);
                        format!("{:.1} ± {:.1}", mean * 1e3, error * 1e3)
                    });
                }
                row
            })
            .collect();
        blocks.push(Block::Heading(2, title.into()));
        blocks.push(Block::Paragraph(format!(
            "Each grid point's {column} over its replicas: their mean ± the standard error of the mean (one replica: its own fitted error, docs/physics.md §7.10–7.11).{}",
            if with_rate { " W: the draw-down's discharge rate, mean ± standard error over the replicas." } else { "" }
        )));
        blocks.push(Block::Table {
            headers: headers.into_iter().map(String::from).collect(),
            rows: table_rows,
        });
    }
    blocks
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A results table of three heap runs (two replicas of one point, one of another) and a
    /// silo run, read back as a study's.
    fn rows() -> Vec<ResultRow> {
        let dir = std::env::temp_dir().join(format!("hopperflow-lab-tests-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("results.csv");
        let mut text = files::RESULT_COLUMNS.join(",");
        text.push('\n');
        for (id, labels, angle, error) in [
            ("mu-r0", "mu_r=0.1", "18.0", "0.5"),
            ("mu-r1", "mu_r=0.1", "20.0", "0.7"),
            ("low-r0", "mu_r=0.05", "12.0", "0.4"),
            ("silo-r0", "", "NaN", "NaN"),
        ] {
            let cells: Vec<String> = files::RESULT_COLUMNS
                .iter()
                .map(|c| match *c {
                    "id" => id.into(),
                    "series" => "s".into(),
                    "replica" => "0".into(),
                    "labels" => labels.into(),
                    "particles" | "seed" => "1".into(),
                    "plateau_found" | "clogged" => "false".into(),
                    "status" => "complete".into(),
                    "repose_angle_deg" => angle.into(),
                    "repose_angle_error_deg" => error.into(),
                    "shelf_angle_deg" | "shelf_angle_error_deg" => "NaN".into(),
                    _ => "0.01".into(),
                })
                .collect();
            text.push_str(&cells.join(","));
            text.push('\n');
        }
        std::fs::write(&path, text).unwrap();
        let rows = files::read_results_table(&path).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        rows
    }

    #[test]
    fn replicas_are_averaged_per_point_and_other_kinds_left_out() {
        let blocks = lab_test_blocks(&rows());
        // Heaps only: one heading, one paragraph, one table.
        assert_eq!(blocks.len(), 3);
        let Block::Table { rows, .. } = &blocks[2] else {
            panic!("a table");
        };
        assert_eq!(rows.len(), 2);
        // The point of two replicas: mean 19.00, standard error of the mean |20 − 18|/2 = 1.
        assert_eq!(rows[1][0], "mu");
        assert_eq!(rows[1][3], "19.00 ± 1.00");
        // One replica keeps its own fitted error.
        assert_eq!(rows[0][3], "12.00 ± 0.40");
        assert!(lab_test_blocks(&[]).is_empty());
    }
}
