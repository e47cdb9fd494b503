//! `hopperflow report DIR` on a calibration folder (`hopperflow calibrate`, docs/physics.md
//! §12): the estimate, the targets, every round, and figures of the runs against the
//! parameters, from `calibration.json` and `runs.csv` alone.

use std::path::{Path, PathBuf};

use files::{
    plot_png, plot_svg, write_atomic, Axis, CalibrationRecord, Figure, Series, SeriesStyle,
    CALIBRATION_FILE, PALETTE, RUNS_FILE,
};

use super::build::ReportError;
use super::document::{Block, Document};

/// Figure size [px].
const FIGURE_SIZE: (u32, u32) = (900, 600);

/// The files a calibration report wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CalibrationReportFiles {
    /// `report/report.md`.
    pub markdown: PathBuf,
    /// `report/report.html`.
    pub html: PathBuf,
    /// Figure files (PNG and SVG).
    pub figures: Vec<PathBuf>,
}

/// Whether `dir` holds a calibration (its `calibration.json`).
pub fn is_calibration(dir: &Path) -> bool {
    dir.join(CALIBRATION_FILE).is_file()
}

/// runs.csv: headers and rows of text.
fn read_runs(path: &Path) -> Result<(Vec<String>, Vec<Vec<String>>), ReportError> {
    let io = |e: csv::Error| ReportError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(e.to_string()),
    };
    let mut reader = csv::Reader::from_path(path).map_err(io)?;
    let headers = reader
        .headers()
        .map_err(io)?
        .iter()
        .map(String::from)
        .collect();
    let mut rows = Vec::new();
    for record in reader.records() {
        rows.push(record.map_err(io)?.iter().map(String::from).collect());
    }
    Ok((headers, rows))
}

fn number(value: f64) -> String {
    if value == 0.0 || !value.is_finite() || (1e-3..1e4).contains(&value.abs()) {
        format!("{value:.4}")
    } else {
        format!("{value:.4e}")
    }
}

/// The last round's surface `surface` through the estimate, along parameter `k` over that
/// round's region, the other parameter held at its estimate; `first` is the first round,
/// whose region is the whole search range (which maps the parameters to unit coordinates).
fn surface_curve(
    record: &CalibrationRecord,
    first: &files::RoundRecord,
    last: &files::RoundRecord,
    surface: &files::SurfaceRecord,
    k: usize,
) -> Series {
    let unit = |j: usize, v: f64| (v - first.lower[j]) / (first.upper[j] - first.lower[j]);
    let (x, y): (Vec<f64>, Vec<f64>) = (0..=50)
        .map(|i| {
            let v = last.lower[k] + (last.upper[k] - last.lower[k]) * f64::from(i) / 50.0;
            let u: Vec<f64> = (0..record.estimate.len())
                .map(|j| {
                    if j == k {
                        unit(j, v)
                    } else {
                        unit(j, record.estimate[j].value)
                    }
                })
                .collect();
            (v, surface.value(&u))
        })
        .unzip();
    Series {
        label: format!("round {} surface", last.round),
        x,
        y,
        y_error: None,
        style: SeriesStyle::Line,
        color: Some(PALETTE[(record.rounds.len() - 1) % PALETTE.len()]),
    }
}

/// Builds `report/` in the calibration folder `dir`.
pub fn build_calibration_report(dir: &Path) -> Result<CalibrationReportFiles, ReportError> {
    let path = dir.join(CALIBRATION_FILE);
    let text = std::fs::read_to_string(&path).map_err(|source| ReportError::Io {
        path: path.clone(),
        source,
    })?;
    let record: CalibrationRecord = serde_json::from_str(&text).map_err(|e| ReportError::Io {
        path: path.clone(),
        source: std::io::Error::other(e.to_string()),
    })?;
    let (headers, rows) = read_runs(&dir.join(RUNS_FILE))?;
    let out = dir.join("report");
    let figures_dir = out.join("figures");
    std::fs::create_dir_all(&figures_dir).map_err(|source| ReportError::Io {
        path: figures_dir.clone(),
        source,
    })?;

    let mut doc = Document::default();
    doc.push(Block::Heading(
        1,
        format!("hopperflow calibration: {}", record.name),
    ));
    doc.push(Block::Paragraph(format!(
        "{} after {} round(s) of {} replicate(s): {} runs, {} failed. {} Run by hopperflow {}; inputs' hash {}. The method, its uncertainty and its checks: docs/physics.md §12.",
        if record.converged { "Converged" } else { "Not converged" },
        record.rounds.len(),
        record.replicates,
        record.runs,
        record.failed_runs,
        if record.targets_met {
            "Every target is met at the estimate."
        } else {
            "The targets are NOT all met at the estimate: the parameters cannot reach them within their ranges, or the targets contradict each other."
        },
        record.version,
        record.plan_hash
    )));

    doc.push(Block::Heading(2, "Estimate".into()));
    doc.push(Block::Table {
        headers: [
            "parameter",
            "value",
            "standard error",
            "95 % interval",
            "note",
        ]
        .map(String::from)
        .to_vec(),
        rows: record
            .estimate
            .iter()
            .map(|e| {
                vec![
                    e.key.clone(),
                    number(e.value),
                    number(e.standard_error),
                    format!("[{}, {}]", number(e.lower_95), number(e.upper_95)),
                    if e.at_range_edge {
                        "at an end of its range: widen it".into()
                    } else if !e.standard_error.is_finite() {
                        "not determined by the targets".into()
                    } else {
                        String::new()
                    },
                ]
            })
            .collect(),
    });
    if let Some(r) = record.correlation {
        doc.push(Block::Paragraph(format!(
            "Correlation of the two estimates' errors: {r:.3}."
        )));
    }
    doc.push(Block::Heading(2, "Targets".into()));
    doc.push(Block::Table {
        headers: [
            "test",
            "measure",
            "lab",
            "simulated at the estimate",
            "one run scatters by",
            "met",
        ]
        .map(String::from)
        .to_vec(),
        rows: record
            .matches
            .iter()
            .map(|m| {
                let met = (m.predicted - m.lab).abs()
                    <= 2.0 * (m.lab_uncertainty.powi(2) + m.predicted_error.powi(2)).sqrt();
                vec![
                    m.test.clone(),
                    m.measure.clone(),
                    format!("{} ± {}", number(m.lab), number(m.lab_uncertainty)),
                    format!("{} ± {}", number(m.predicted), number(m.predicted_error)),
                    number(m.run_scatter),
                    if met { "yes" } else { "no" }.into(),
                ]
            })
            .collect(),
    });

    doc.push(Block::Heading(2, "Rounds".into()));
    let keys: Vec<String> = record.estimate.iter().map(|e| e.key.clone()).collect();
    let mut round_headers = vec!["round".to_string()];
    round_headers.extend(keys.iter().map(|k| format!("{k}: region")));
    round_headers.extend(keys.iter().map(|k| format!("{k}: estimate")));
    round_headers.extend(["runs", "failed", "χ²"].map(String::from));
    doc.push(Block::Table {
        headers: round_headers,
        rows: record
            .rounds
            .iter()
            .map(|r| {
                let mut row = vec![r.round.to_string()];
                row.extend(
                    r.lower
                        .iter()
                        .zip(&r.upper)
                        .map(|(l, u)| format!("[{}, {}]", number(*l), number(*u))),
                );
                row.extend(
                    r.estimate
                        .iter()
                        .map(|e| format!("{} ± {}", number(e.value), number(e.standard_error))),
                );
                row.extend([
                    r.runs.to_string(),
                    r.failed.to_string(),
                    format!("{:.3}", r.chi_squared),
                ]);
                row
            })
            .collect(),
    });

    doc.push(Block::Heading(2, "Figures".into()));
    let column = |name: &str| headers.iter().position(|h| h == name);
    let value = |row: &Vec<String>, index: usize| row[index].parse::<f64>().ok();
    let round_col = column("round");
    let mut figures = Vec::new();
    for (t, m) in record.matches.iter().enumerate() {
        let Some(measure_col) = column(&format!("{}:{}", m.test, m.measure)) else {
            continue;
        };
        for (k, key) in keys.iter().enumerate() {
            let Some(key_col) = column(key) else { continue };
            let mut figure = Figure::new(
                format!("{}:{} against {key}", m.test, m.measure),
                Axis::new(key.clone(), ""),
                Axis::new(m.measure.clone(), ""),
            );
            for (r, round) in record.rounds.iter().enumerate() {
                let (x, y): (Vec<f64>, Vec<f64>) = rows
                    .iter()
                    .filter(|row| {
                        round_col.and_then(|c| value(row, c)) == Some(f64::from(round.round))
                    })
                    .filter_map(|row| Some((value(row, key_col)?, value(row, measure_col)?)))
                    .unzip();
                figure = figure.with_series(Series {
                    label: format!("round {} runs", round.round),
                    x,
                    y,
                    y_error: None,
                    style: SeriesStyle::Points,
                    color: Some(PALETTE[r % PALETTE.len()]),
                });
            }
            let (first, last) = (record.rounds.first(), record.rounds.last());
            if let (Some(first), Some(estimate)) = (first, record.estimate.get(k)) {
                let span = [first.lower[k], first.upper[k]];
                let line = |label: &str, y: f64, color: [u8; 3]| Series {
                    label: label.into(),
                    x: span.to_vec(),
                    y: vec![y, y],
                    y_error: None,
                    style: SeriesStyle::Line,
                    color: Some(color),
                };
                figure = figure
                    .with_series(line("lab value", m.lab, [0, 0, 0]))
                    .with_series(line("lab ± σ", m.lab + m.lab_uncertainty, [128, 128, 128]))
                    .with_series(line("", m.lab - m.lab_uncertainty, [128, 128, 128]));
                let ys: Vec<f64> = rows
                    .iter()
                    .filter_map(|row| value(row, measure_col))
                    .collect();
                let (low, high) = ys
                    .iter()
                    .fold((m.lab, m.lab), |(l, h), y| (l.min(*y), h.max(*y)));
                figure = figure.with_series(Series {
                    label: "estimate".into(),
                    x: vec![estimate.value, estimate.value],
                    y: vec![low, high],
                    y_error: None,
                    style: SeriesStyle::Line,
                    color: Some([214, 39, 40]),
                });
                // The last round's surface through the estimate, along this parameter over
                // its region (the other parameter held at its estimate).
                if let Some((last, surface)) = last.and_then(|l| Some((l, l.surfaces.get(t)?))) {
                    figure = figure.with_series(surface_curve(&record, first, last, surface, k));
                }
            }
            let name = format!(
                "{}-{}-vs-{}",
                m.test,
                m.measure.replace('.', "_"),
                key.replace('.', "_")
            );
            figures.push((
                name,
                format!(
                    "Each run's {} ({}) against {key}, coloured by round; the lab's value ± σ as horizontal lines, the estimate as a vertical one, and the last round's fitted surface over its region.{}",
                    m.measure,
                    m.test,
                    if keys.len() > 1 { " The other parameter varies between the runs at one abscissa." } else { "" }
                ),
                figure,
            ));
        }
    }
    if keys.len() == 2 {
        let mut figure = Figure::new(
            "design points and estimates".to_string(),
            Axis::new(keys[0].clone(), ""),
            Axis::new(keys[1].clone(), ""),
        );
        let (c0, c1) = (column(&keys[0]), column(&keys[1]));
        for (r, round) in record.rounds.iter().enumerate() {
            let (x, y): (Vec<f64>, Vec<f64>) = rows
                .iter()
                .filter(|row| round_col.and_then(|c| value(row, c)) == Some(f64::from(round.round)))
                .filter_map(|row| Some((value(row, c0?)?, value(row, c1?)?)))
                .unzip();
            figure = figure.with_series(Series {
                label: format!("round {} design", round.round),
                x,
                y,
                y_error: None,
                style: SeriesStyle::Points,
                color: Some(PALETTE[r % PALETTE.len()]),
            });
        }
        let (x, y): (Vec<f64>, Vec<f64>) = record
            .rounds
            .iter()
            .filter_map(|r| Some((r.estimate.first()?.value, r.estimate.get(1)?.value)))
            .unzip();
        figure = figure.with_series(Series {
            label: "estimate after each round".into(),
            x,
            y,
            y_error: None,
            style: SeriesStyle::LineAndPoints,
            color: Some([0, 0, 0]),
        });
        figures.push((
            "design".into(),
            "The design points of each round in the parameters' plane, and the estimate after each round: the search region shrinks around the estimate (docs/physics.md §12.1).".into(),
            figure,
        ));
    }
    let mut figure_files = Vec::new();
    for (name, caption, figure) in figures {
        let png = figures_dir.join(format!("{name}.png"));
        let svg = figures_dir.join(format!("{name}.svg"));
        plot_png(&figure, &png, FIGURE_SIZE.0, FIGURE_SIZE.1)?;
        plot_svg(&figure, &svg, FIGURE_SIZE.0, FIGURE_SIZE.1)?;
        let text = std::fs::read_to_string(&svg).map_err(|source| ReportError::Io {
            path: svg.clone(),
            source,
        })?;
        doc.push(Block::Figure {
            name,
            caption,
            svg: text,
        });
        figure_files.push(png);
        figure_files.push(svg);
    }
    let files = CalibrationReportFiles {
        markdown: out.join("report.md"),
        html: out.join("report.html"),
        figures: figure_files,
    };
    write_atomic(&files.markdown, doc.to_markdown().as_bytes())?;
    write_atomic(
        &files.html,
        doc.to_html(&format!("hopperflow calibration: {}", record.name))
            .as_bytes(),
    )?;
    Ok(files)
}
