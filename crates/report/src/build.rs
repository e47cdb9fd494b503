//! `hopperflow report DIR`: reads a finished study and writes `report/report.md`,
//! `report/report.html`, `report/comparison.json` and `report/figures/*.{png,svg}`.

use std::path::{Path, PathBuf};

use super::cohesion::{analyse_cohesion, cohesion_blocks, load_cohesion};
use super::comparison::compare_with_paper;
use super::data::load_study;
use super::document::{Block, Document};
use super::figures::{cohesion_figures, report_figures};
use super::{analyse_study, tables};
use files::StudyFileError;
use files::{plot_png, plot_svg, write_atomic, write_json_atomic, OutputError};
use files::{CaseStatus, StudyPaths};

/// Figure size [px]: wide enough for legends beside six series.
const FIGURE_SIZE: (u32, u32) = (900, 600);

/// Why a report could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// The directory holds no study: no `results.csv` (a folder that `hopperflow study`
    /// never wrote to, or a mistyped path).
    #[error(
        "{} holds no study: {} is missing; give the directory a `hopperflow study` run wrote \
         to (its --out, or study-<sweep name> by default)",
        dir.display(),
        results.display()
    )]
    NoStudy {
        /// The directory given.
        dir: PathBuf,
        /// The results table it lacks.
        results: PathBuf,
    },
    /// The study could not be read.
    #[error(transparent)]
    Study(#[from] StudyFileError),
    /// A report file could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The report directory could not be created or a figure read back.
    #[error("cannot access {path}: {source}")]
    Io {
        /// The path involved.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
}

/// The files a report wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReportFiles {
    /// `report/report.md`.
    pub markdown: PathBuf,
    /// `report/report.html`.
    pub html: PathBuf,
    /// `report/comparison.json`.
    pub comparison: PathBuf,
    /// Figure files (PNG and SVG).
    pub figures: Vec<PathBuf>,
}

/// Builds the report of the study in `root` from its saved results (no simulation).
pub fn build_report(root: &Path) -> Result<ReportFiles, ReportError> {
    // Checked before anything is read or written: no `report/` folder is left in a
    // directory that holds no study.
    let results = StudyPaths::new(root).results();
    if !results.is_file() {
        return Err(ReportError::NoStudy {
            dir: root.to_path_buf(),
            results,
        });
    }
    let data = load_study(root)?;
    let analysis = analyse_study(&data.points);
    let items = compare_with_paper(&analysis);
    let dir = root.join("report");
    let figures_dir = dir.join("figures");
    std::fs::create_dir_all(&figures_dir).map_err(|source| ReportError::Io {
        path: figures_dir.clone(),
        source,
    })?;

    let mut doc = Document::default();
    let name = data
        .manifest
        .as_ref()
        .map_or("study".to_string(), |m| m.name.clone());
    doc.push(Block::Heading(1, format!("hopperflow report: {name}")));
    let count = |s: CaseStatus| data.rows.iter().filter(|r| r.status == s).count();
    match &data.manifest {
        Some(m) => doc.push(Block::Paragraph(format!(
            "Sweep '{}' ({}). Run by hopperflow {}, this report by hopperflow {}. Config hash {}. {} cases planned, {} replica(s) per grid point, {} grid point(s) skipped.",
            m.name, m.description, m.version, env!("CARGO_PKG_VERSION"), m.config_hash, m.cases.len(), m.replicas, m.skipped.len()
        ))),
        None => doc.push(Block::Paragraph("No study.json: version, config hash and seeds are unknown.".into())),
    }
    if let Some(start) = data.manifest.as_ref().and_then(|m| m.start.as_ref()) {
        // A study from one bed: its fits see the outlets of a single packing.
        doc.push(Block::Paragraph(format!(
            "Every case started from one saved bed (SHA-256 {}), not from a fill of its own: the cases differ in their outlets only, on one packing. The fits and their intervals below therefore leave out the scatter between fills, which independent beds would add (docs/user-guide.md §5).",
            start.sha256
        )));
    }
    let gravity = match super::common_gravity(&data.points) {
        Ok(g) => format!(" g = {g} m/s²."),
        Err(_) if data.points.is_empty() => String::new(),
        Err(why) => format!(" No fit mixes cases of different g: {why}."),
    };
    doc.push(Block::Paragraph(format!(
        "{} case(s) in results.csv: {} complete, {} clogged, {} failed. Clogged and failed cases are left out of every fit; replicas are averaged before fitting (mean ± standard error over replicas, floored at the runs' own errors carried to the mean where they have one). Uncertainties are one standard error unless an interval is given.{gravity}",
        data.rows.len(), count(CaseStatus::Complete), count(CaseStatus::Clogged), count(CaseStatus::Failed)
    )));

    // A study whose every case breaks its arches measures clogging: its rates hold the arrests
    // and the pulses, so the steady-flow sections (the paper's items, Beverloo, the profiles)
    // would fit what they do not describe.
    let clogging =
        super::clogging::analyse_clogging(&super::clogging::load_clogging(root, &data.rows));
    let finished = data
        .rows
        .iter()
        .filter(|r| r.status != CaseStatus::Failed)
        .count();
    let clogging_cases: usize = clogging.iter().flat_map(|g| &g.rows).map(|r| r.runs).sum();
    let steady_flow = !(finished > 0 && clogging_cases == finished);
    if !steady_flow {
        doc.push(Block::Paragraph("Every case breaks its arches ([protocol.unclog]) and goes on between clogs: its discharge rate holds the arrests and the pulses, so the steady-flow sections (the paper's items, the Beverloo fits, the outlet profiles and their figures) are left out; the clogging section below is this study's result.".into()));
    }
    if analysis.has_slabs && steady_flow {
        doc.push(Block::Heading(2, "Comparison with the paper".into()));
        doc.push(Block::Paragraph(format!(
        "Items of the acceptance list (physics spec §9 B3). The angle items use series '{}', the eccentric item series '{}'. 'not measured' means the study has too few cases for the fit (the reason is given).",
        super::ANGLE_SERIES, super::ECCENTRIC_SERIES
    )));
        doc.push(Block::Paragraph(format!(
        "Beverloo k: the paper's k = 1.55 (Fig. 2b) is one line through the W(D) points of all hopper angles together, so the compared item is our fit over the centred outlets of every angle of series '{}'. The flat-bottom (α = 90°) fit stands beside it as a reference row: the paper gives no 90°-only k, and {} with the same contact law give k = {} at 90°.",
        super::ANGLE_SERIES,
        super::OTHER_CODES_K_90.iter().map(|(c, _)| *c).collect::<Vec<_>>().join(" and "),
        super::OTHER_CODES_K_90.iter().map(|(_, k)| k.to_string()).collect::<Vec<_>>().join(" and "),
    )));
        doc.push(Block::Paragraph("Outlet fraction profile φ(x): its exponent b (φ/φ_c = (1 − x*²)^b, paper Eq. 11) depends on how φ is defined, so it is fitted under two definitions. Strip: the area of the bin covered by the particles' mid-plane discs in the strip |z − z_o| < h/2, averaged over frames (physics spec §7.3; the paper's image measure). Crossing: the number density of centres crossing the outlet line, Σ π r²/|v_z| over a bin's crossings divided by the window and the bin width (each grain counted once, at its centre). The paper's b can be compared only as a trend: it rises with α for α ≥ 30° (Table 2: 0.19, 0.30, 0.38, 0.39).".into()));
        if !analysis.silo.beverloo.is_empty() {
            // A study of slabs and silos: the table also holds the silo items, which the
            // paper has no value for.
            doc.push(Block::Paragraph("The study also holds silos with circular orifices: the items from '3D Beverloo' on are theirs. The paper (a slab hopper) has none of them, so C and k are set against the classic ranges for spheres and W from the radial profiles against the measured W (Janda et al. 2012, in 3D); their fits are in the sections '3D Beverloo constants' and 'Radial outlet profiles' below.".into()));
        }
        doc.push(tables::comparison_table(&items));

        doc.push(Block::Heading(
            2,
            "Table 2: centred outlets by hopper angle".into(),
        ));
        doc.push(Block::Paragraph("a and b: exponents of (1 − x*²)^p fitted to the velocity and area-fraction profiles of all widths of one angle, each divided by its centre value (|x*| < 0.1), bins |x*| ≤ 0.9, each bin weighted by its error (over replicas: the larger of their spread and the runs' own bin errors carried to the mean). γ: least squares of v_c = √(2γgR), equal weights. φ∞, τ₁, τ₂: Eq. 12 over φ_c(R), R in mm, equal weights (needs four widths).".into()));
        doc.push(tables::table2(&analysis));
        doc.push(Block::Paragraph("γ_D = v_c²/(2gR) of each width alone, beside the fitted γ (error from v_c's). Where γ_D rises with D, v_c grows faster than √R, and the fitted γ depends on which widths enter the fit.".into()));
        doc.push(tables::width_gamma_table(&analysis));
        doc.push(Block::Heading(2, "Beverloo constants".into()));
        doc.push(Block::Paragraph("Weighted straight line of (W/Z)^(2/3) against D (W's error over replicas: the larger of their spread and the runs' own blocking errors carried to the mean); k from the x-intercept, C from the slope under three densities (physics spec §8.2): bulk φ_B ρ_p (φ_B the measured settled fraction), particle ρ_p, and ρ_p φ_2D with φ_2D the mean measured centre area fraction. Intervals are 95 %.".into()));
        doc.push(tables::beverloo_table(&analysis));
        doc.push(Block::Heading(2, "Eq. 14 against the measured rate".into()));
        doc.push(tables::eq14_table(&analysis));
        doc.push(Block::Heading(2, "Hopper angle: W(α)/W(90°)".into()));
        doc.push(Block::Paragraph(format!(
            "Rose–Tanaka is evaluated at β_d = {}° (not stated in the paper).",
            super::centred::STAGNANT_ZONE_ANGLE_DEG
        )));
        doc.push(tables::angle_ratio_table(&analysis));
        doc.push(Block::Heading(2, "Table 3: off-centred outlets".into()));
        doc.push(Block::Paragraph("Eq. 16 on v/√(2gR) and Eq. 17 on φ/φ_max (ε_s2 held at 1), all widths of one gap pooled, bins |x*| ≤ 0.9, x* < 0 on the near-wall side.".into()));
        doc.push(tables::table3(&analysis));
        for block in tables::eccentric_fit_blocks(&analysis) {
            doc.push(block);
        }
        doc.push(Block::Heading(2, "Eq. 18 and W/W0".into()));
        doc.push(tables::eccentric_rate_table(&analysis));
    }
    if !analysis.has_slabs && steady_flow {
        doc.push(Block::Heading(2, "Comparison".into()));
        doc.push(Block::Paragraph("The paper's items (Fan et al. 2023) apply to the slab hopper; this study holds no slab case, so none of them is listed. The items below are those of silos with circular orifices.".into()));
        doc.push(tables::comparison_table(&items));
    }
    if steady_flow {
        for block in silo_blocks(&analysis.silo) {
            doc.push(block);
        }
    }
    // Cohesion: written only when some case's file names a cohesion law.
    let cohesion = analyse_cohesion(&load_cohesion(root, &data.rows));
    for block in cohesion_blocks(&cohesion) {
        doc.push(block);
    }
    // Clogging: written only when some case broke its arches ([protocol.unclog]).
    for block in super::clogging::clogging_blocks(&clogging) {
        doc.push(block);
    }
    // Coarse-grained parcels: written only when some case ran with κ > 1.
    let parcels = super::coarse_graining::load_parcels(root, &data.rows);
    for block in super::coarse_graining::parcel_blocks(parcels.as_deref()) {
        doc.push(block);
    }
    // The lab tests' angles: written only when the study holds heap or draw-down cases.
    for block in super::lab_tests::lab_test_blocks(&data.rows) {
        doc.push(block);
    }

    let mut figure_files = Vec::new();
    // The figures are the paper's (Figs. 2, 5, 8, 11): they need slab cases.
    let mut figures = if analysis.has_slabs && steady_flow {
        report_figures(&analysis)
    } else {
        Vec::new()
    };
    figures.extend(cohesion_figures(&cohesion));
    if !figures.is_empty() {
        doc.push(Block::Heading(2, "Figures".into()));
    }
    for figure in figures {
        let png = figures_dir.join(format!("{}.png", figure.name));
        let svg = figures_dir.join(format!("{}.svg", figure.name));
        plot_png(&figure.figure, &png, FIGURE_SIZE.0, FIGURE_SIZE.1)?;
        plot_svg(&figure.figure, &svg, FIGURE_SIZE.0, FIGURE_SIZE.1)?;
        let text = std::fs::read_to_string(&svg).map_err(|source| ReportError::Io {
            path: svg.clone(),
            source,
        })?;
        doc.push(Block::Figure {
            name: figure.name,
            caption: figure.caption,
            svg: text,
        });
        figure_files.push(png);
        figure_files.push(svg);
    }

    doc.push(Block::Heading(2, "Cases and seeds".into()));
    doc.push(tables::cases_table(&data));

    let files = ReportFiles {
        markdown: dir.join("report.md"),
        html: dir.join("report.html"),
        comparison: dir.join("comparison.json"),
        figures: figure_files,
    };
    write_json_atomic(&files.comparison, &items)?;
    write_atomic(&files.markdown, doc.to_markdown().as_bytes())?;
    write_atomic(
        &files.html,
        doc.to_html(&format!("hopperflow report: {name}"))
            .as_bytes(),
    )?;
    Ok(files)
}

/// The silo sections: the 3D Beverloo fits and the radial profile fits.
fn silo_blocks(silo: &super::silo::SiloAnalysis) -> Vec<Block> {
    use super::silo::{CLASSIC_C, CLASSIC_K};
    let mut blocks = Vec::new();
    if !silo.beverloo.is_empty() {
        blocks.push(Block::Heading(2, "3D Beverloo constants".into()));
        blocks.push(Block::Paragraph(format!(
            "W = C ρ_b √g (D − k d)^(5/2) for circular orifices: a weighted straight line of W^(2/5) against D (W's error over replicas, floored at the runs' own blocking errors); k from the x-intercept, C from the slope with ρ_b = φ_B ρ_p, φ_B the mean settled bulk fraction of the group's cases. Intervals are 95 %. The classic ranges for spheres are C ≈ {}–{} and k ≈ {}–{}.",
            CLASSIC_C.0, CLASSIC_C.1, CLASSIC_K.0, CLASSIC_K.1
        )));
        let rows = silo
            .beverloo
            .iter()
            .map(|g| {
                let (c, k) = match &g.fit {
                    Ok(f) => (
                        format!(
                            "{:.3} [{:.3}, {:.3}]",
                            f.coefficient.value,
                            f.coefficient_interval.lower,
                            f.coefficient_interval.upper
                        ),
                        format!(
                            "{:.2} [{:.2}, {:.2}]",
                            f.k.value, f.k_interval.lower, f.k_interval.upper
                        ),
                    ),
                    Err(why) => (why.clone(), String::new()),
                };
                let points = g
                    .points
                    .iter()
                    .map(|(d, w)| {
                        format!(
                            "{:.1} mm: {:.4} ± {:.4} kg/s",
                            d * 1e3,
                            w.value,
                            w.standard_error
                        )
                    })
                    .collect::<Vec<_>>()
                    .join("; ");
                vec![
                    g.series.clone(),
                    format!("{}", g.hopper_angle_deg),
                    format!("{:.0}", g.bulk_density),
                    c,
                    k,
                    points,
                ]
            })
            .collect();
        blocks.push(Block::Table {
            headers: [
                "series",
                "θ [°]",
                "ρ_b [kg/m³]",
                "C [95 %]",
                "k [95 %]",
                "D: W",
            ]
            .map(String::from)
            .to_vec(),
            rows,
        });
    }
    if !silo.profiles.is_empty() {
        blocks.push(Block::Heading(2, "Radial outlet profiles".into()));
        blocks.push(Block::Paragraph("v(r) = v_c (1 − r*²)^a from the crossings and φ(r) = φ_c (1 − r*²)^b from the volume fraction on the slab |z| ≤ h/2 at the orifice (annuli up to r* = 0.9, weighted by their errors), and the rate they give, W = π R² ρ_p φ_c v_c / (1 + a + b) (docs/physics.md §7.6). First replica of each point.".into()));
        let rows = silo
            .profiles
            .iter()
            .map(|p| {
                let pm = |v: [f64; 2], digits: usize| {
                    format!("{:.*} ± {:.*}", digits, v[0], digits, v[1])
                };
                vec![
                    p.key.clone(),
                    format!("{:.1}", p.outlet_diameter * 1e3),
                    pm(p.fit.centre_velocity, 3),
                    pm(p.fit.velocity_exponent, 2),
                    pm(p.fit.centre_volume_fraction, 3),
                    pm(p.fit.packing_exponent, 2),
                    format!("{:.4}", p.rate.value),
                    pm(p.fit.profile_rate, 4),
                    format!("{:+.1} %", 100.0 * p.relative_difference()),
                ]
            })
            .collect();
        blocks.push(Block::Table {
            headers: [
                "case",
                "D [mm]",
                "v_c [m/s]",
                "a",
                "φ_c",
                "b",
                "W [kg/s]",
                "W profiles [kg/s]",
                "difference",
            ]
            .map(String::from)
            .to_vec(),
            rows,
        });
    }
    blocks
}
