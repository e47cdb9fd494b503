//! Cohesion in a study: the discharge rate W against the Bond number Bo for each outlet
//! width, the critical outlet width against Bo, and where the arches of the clogged cases
//! stand (docs/physics.md §7.9, §7.12).
//!
//! Everything is read from saved files: each case's Bo from its resolved `case.toml`
//! ([`super::bond`]), its arch from its `summary.json`, W and its status from
//! `results.csv`. Cases are grouped by what they share apart from their cohesion and their
//! outlet (the resolved case without its seed, outlet size and grain–grain cohesion, and
//! the row's s*), so that a dry series and a cohesive one over the same hopper form one
//! table whose dry rows are Bo = 0.

use std::collections::BTreeMap;
use std::path::Path;

use analysis::Estimate;
use files::{ArchSummary, CaseStatus, ResultRow, StudyPaths, SUMMARY_FILE};

use super::bond::{bond_number, case_grains, is_self_pair, read_cohesion, GrainCohesion};
use super::data::{case_gravity, ratio, replica_mean};

/// Relative tolerance under which two outlet widths are the same grid value.
const WIDTH_TOLERANCE: f64 = 1e-9;

/// One case as the cohesion section reads it.
#[derive(Debug, Clone, PartialEq)]
pub struct CohesionCase {
    /// Case identifier.
    pub id: String,
    /// Series name.
    pub series: String,
    /// What the case shares with the others of its table (see the module's text).
    pub conditions: String,
    /// The grains' cohesion with each other.
    pub cohesion: GrainCohesion,
    /// Bo [-] (zero when dry).
    pub bond: f64,
    /// The walls' cohesion law ("dry", "jkr", …, or "as [[pairs]]").
    pub walls: String,
    /// Outlet width D [m].
    pub outlet_width: f64,
    /// Grain diameter d [m].
    pub particle_diameter: f64,
    /// How the case ended.
    pub status: CaseStatus,
    /// W and its error [kg/s], as `results.csv` has them.
    pub rate: (f64, f64),
    /// The arch over the outlet when the case clogged (`summary.json`'s `arch`).
    pub arch: Option<ArchSummary>,
}

/// The cases of a study with their Bond numbers.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CohesionStudy {
    /// The cases whose Bo is defined.
    pub cases: Vec<CohesionCase>,
    /// The cases whose Bo is not, with the reason.
    pub undefined: Vec<(String, String)>,
    /// Whether some case's file names a cohesion law (other than "none").
    pub has_cohesion: bool,
}

/// Whether a TOML value holds a `cohesion` table whose law is not "none", at any depth.
fn names_cohesion(value: &toml::Value) -> bool {
    match value {
        toml::Value::Table(t) => t.iter().any(|(k, v)| {
            (k == "cohesion" && v.get("law").and_then(|l| l.as_str()) != Some("none"))
                || names_cohesion(v)
        }),
        toml::Value::Array(a) => a.iter().any(names_cohesion),
        _ => false,
    }
}

/// The resolved case without what a cohesion study varies: its seed, outlet size and
/// grain–grain cohesion (in `[contact]`, or in the self-pair of the particles' material).
fn conditions(case: &toml::Table, row: &ResultRow) -> String {
    let mut case = case.clone();
    case.remove("seed");
    if let Some(toml::Value::Table(g)) = case.get_mut("geometry") {
        for key in ["outlet_width", "outlet_diameter", "outlet_gap"] {
            g.remove(key);
        }
    }
    if let Some(toml::Value::Table(c)) = case.get_mut("contact") {
        c.remove("cohesion");
    }
    let material = case
        .get("particles")
        .and_then(|p| p.get("material"))
        .and_then(|m| m.as_str())
        .map(str::to_string);
    if let (Some(name), Some(toml::Value::Array(pairs))) = (material, case.get_mut("pairs")) {
        for pair in pairs.iter_mut().filter(|p| is_self_pair(p, &name)) {
            if let Some(t) = pair.as_table_mut() {
                t.remove("cohesion");
            }
        }
    }
    // The outlet's place, which `outlet_gap` gave with its size, as s*.
    format!(
        "{}s* = {:.6}",
        toml::to_string(&case).unwrap_or_default(),
        row.dimensionless_gap
    )
}

/// The walls' cohesion law of a resolved case.
fn walls(case: &toml::Table) -> String {
    let wall = case.get("wall");
    match wall
        .and_then(|w| w.get("material"))
        .and_then(|m| m.as_str())
    {
        Some(name) if name != "same" && name != "rigid" => "as [[pairs]]".into(),
        _ => read_cohesion(wall.and_then(|w| w.get("cohesion")))
            .map_or_else(|why| why, |c| c.law().to_string()),
    }
}

/// The arch of a case's `summary.json`, when it has one (read alone, so that a summary
/// written by another version still gives it).
fn read_arch(dir: &Path) -> Option<ArchSummary> {
    let text = std::fs::read_to_string(dir.join(SUMMARY_FILE)).ok()?;
    let value: serde_json::Value = serde_json::from_str(&text).ok()?;
    serde_json::from_value(value.get("arch")?.clone()).ok()
}

/// Reads the Bond number of every case of `rows` from its folder under `root`.
pub fn load_cohesion(root: &Path, rows: &[ResultRow]) -> CohesionStudy {
    let paths = StudyPaths::new(root);
    let mut study = CohesionStudy::default();
    for row in rows {
        let dir = paths.case_dir(&row.id);
        let case = std::fs::read_to_string(dir.join("case.toml"))
            .ok()
            .and_then(|text| text.parse::<toml::Table>().ok());
        let Some(case) = case else {
            study
                .undefined
                .push((row.id.clone(), "no readable case.toml".into()));
            continue;
        };
        study.has_cohesion |= names_cohesion(&toml::Value::Table(case.clone()));
        match case_grains(&case, case_gravity(&case)) {
            Ok(grains) => study.cases.push(CohesionCase {
                id: row.id.clone(),
                series: row.series.clone(),
                conditions: conditions(&case, row),
                cohesion: grains.cohesion,
                bond: bond_number(&grains),
                walls: walls(&case),
                outlet_width: row.outlet_width,
                particle_diameter: grains.diameter,
                status: row.status,
                rate: (row.discharge_rate, row.discharge_rate_error),
                arch: read_arch(&dir),
            }),
            Err(why) => study.undefined.push((row.id.clone(), why)),
        }
    }
    study
}

/// The replicas of one Bond number at one outlet width.
#[derive(Debug, Clone, PartialEq)]
pub struct BondCell {
    /// Outlet width D [m].
    pub outlet_width: f64,
    /// Replicas that ran to an end (complete or clogged).
    pub runs: usize,
    /// Of them, those that clogged.
    pub clogged: usize,
    /// Replicas that failed (left out of everything).
    pub failed: usize,
    /// W [kg/s] over the replicas that flowed: mean ± error as elsewhere in the report.
    pub rate: Option<Estimate>,
    /// W/W(Bo = 0) at the same width, errors of the two combined in quadrature (none for
    /// the dry level, the reference).
    pub relative_rate: Option<Estimate>,
}

impl BondCell {
    /// The fraction of the runs that clogged.
    pub fn clogging_fraction(&self) -> f64 {
        self.clogged as f64 / self.runs as f64
    }
}

/// Where the critical outlet width D_c of one Bond number lies among the widths run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CriticalWidth {
    /// No run clogged: D_c is at most the smallest width run [m].
    Below(f64),
    /// D_c lies between the largest width at which a run clogged and the smallest larger
    /// width at which every run flowed [m].
    Between {
        /// The largest width that clogged [m].
        clogged: f64,
        /// The smallest larger width that flowed in every run [m].
        flowed: f64,
    },
    /// A run clogged at the largest width run [m]: D_c is above it.
    Above(f64),
    /// No run ended (all failed).
    Unknown,
}

/// The half-clogging width D_50 of one Bond number: where the fraction of runs that clog
/// falls through one half as the outlet widens. Clogging has no sharp threshold (Thomas &
/// Durian 2015: the clogging probability decays exponentially in the width, never to zero),
/// so a width at which a run of the study's length clogs half the time is the threshold
/// that more replicas sharpen rather than widen, unlike the bracket of [`CriticalWidth`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HalfClogging {
    /// Fewer than half the runs clogged at every width: D_50 lies below the smallest [m].
    Below(f64),
    /// Linear in the fraction between the widest width at which at least half the runs
    /// clogged and the next width run, at which fewer did [m].
    At(f64),
    /// At least half the runs clogged at the largest width run [m]: D_50 lies above it.
    Above(f64),
    /// No run ended (all failed).
    Unknown,
}

/// D_50 from the cells of one Bond number ([`HalfClogging`]).
fn half_clogging_width(cells: &[BondCell]) -> HalfClogging {
    let ran: Vec<&BondCell> = cells.iter().filter(|c| c.runs > 0).collect();
    let Some(first) = ran.first() else {
        return HalfClogging::Unknown;
    };
    let Some(k) = ran.iter().rposition(|c| c.clogging_fraction() >= 0.5) else {
        return HalfClogging::Below(first.outlet_width);
    };
    let Some(next) = ran.get(k + 1) else {
        return HalfClogging::Above(ran[k].outlet_width);
    };
    let (fa, fb) = (ran[k].clogging_fraction(), next.clogging_fraction());
    let (wa, wb) = (ran[k].outlet_width, next.outlet_width);
    HalfClogging::At(wa + (fa - 0.5) / (fa - fb) * (wb - wa))
}

/// One Bond number of a table.
#[derive(Debug, Clone, PartialEq)]
pub struct BondLevel {
    /// The grains' cohesion.
    pub cohesion: GrainCohesion,
    /// Bo [-].
    pub bond: f64,
    /// One cell per width of the table, in its order.
    pub cells: Vec<BondCell>,
    /// The bracket of D_c.
    pub critical: CriticalWidth,
    /// The half-clogging width D_50.
    pub half: HalfClogging,
}

/// The brackets of the critical width from the cells of one Bond number.
fn critical_width(cells: &[BondCell]) -> CriticalWidth {
    let ran: Vec<&BondCell> = cells.iter().filter(|c| c.runs > 0).collect();
    let Some(first) = ran.first() else {
        return CriticalWidth::Unknown;
    };
    let Some(largest) = ran
        .iter()
        .filter(|c| c.clogged > 0)
        .map(|c| c.outlet_width)
        .reduce(f64::max)
    else {
        return CriticalWidth::Below(first.outlet_width);
    };
    ran.iter()
        .filter(|c| c.outlet_width > largest && c.clogged == 0)
        .map(|c| c.outlet_width)
        .reduce(f64::min)
        .map_or(CriticalWidth::Above(largest), |flowed| {
            CriticalWidth::Between {
                clogged: largest,
                flowed,
            }
        })
}

/// The cases that share their conditions: W against Bo and width.
#[derive(Debug, Clone, PartialEq)]
pub struct CohesionGroup {
    /// Series of its cases.
    pub series: Vec<String>,
    /// The walls' cohesion law.
    pub walls: String,
    /// Grain diameter d [m].
    pub particle_diameter: f64,
    /// Outlet widths run [m], increasing.
    pub widths: Vec<f64>,
    /// Bond numbers, increasing.
    pub levels: Vec<BondLevel>,
    /// The clogged cases with their arches, by Bo then width.
    pub arches: Vec<(String, f64, f64, Option<ArchSummary>)>,
}

/// The cohesion section's content.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CohesionAnalysis {
    /// One table per group of cases with some cohesive case.
    pub groups: Vec<CohesionGroup>,
    /// Cases whose Bo is not defined, with the reason.
    pub undefined: Vec<(String, String)>,
    /// Whether the study has cohesion at all (the section is written only then).
    pub present: bool,
}

fn same_width(a: f64, b: f64) -> bool {
    (a - b).abs() <= WIDTH_TOLERANCE * a.abs().max(b.abs())
}

/// W against Bo per width, the critical widths and the arches of `study`'s cases.
pub fn analyse_cohesion(study: &CohesionStudy) -> CohesionAnalysis {
    let mut by_conditions: BTreeMap<&str, Vec<&CohesionCase>> = BTreeMap::new();
    for case in &study.cases {
        by_conditions
            .entry(case.conditions.as_str())
            .or_default()
            .push(case);
    }
    let mut groups = Vec::new();
    for cases in by_conditions.into_values() {
        if cases.iter().all(|c| c.cohesion == GrainCohesion::Dry) {
            continue;
        }
        let mut widths: Vec<f64> = cases.iter().map(|c| c.outlet_width).collect();
        widths.sort_by(f64::total_cmp);
        widths.dedup_by(|a, b| same_width(*a, *b));
        let mut cohesions: Vec<(GrainCohesion, f64)> = Vec::new();
        for c in &cases {
            if !cohesions.iter().any(|(k, _)| *k == c.cohesion) {
                cohesions.push((c.cohesion, c.bond));
            }
        }
        cohesions.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.law().cmp(b.0.law())));
        let cell = |cohesion: GrainCohesion, width: f64| {
            let at: Vec<&&CohesionCase> = cases
                .iter()
                .filter(|c| c.cohesion == cohesion && same_width(c.outlet_width, width))
                .collect();
            let count = |s: CaseStatus| at.iter().filter(|c| c.status == s).count();
            let flowing: Vec<(f64, f64)> = at
                .iter()
                .filter(|c| c.status == CaseStatus::Complete && c.rate.0.is_finite())
                .map(|c| c.rate)
                .collect();
            BondCell {
                outlet_width: width,
                runs: count(CaseStatus::Complete) + count(CaseStatus::Clogged),
                clogged: count(CaseStatus::Clogged),
                failed: count(CaseStatus::Failed),
                rate: (!flowing.is_empty()).then(|| replica_mean(&flowing)),
                relative_rate: None,
            }
        };
        let mut levels: Vec<BondLevel> = cohesions
            .iter()
            .map(|&(cohesion, bond)| {
                let cells: Vec<BondCell> = widths.iter().map(|&w| cell(cohesion, w)).collect();
                BondLevel {
                    cohesion,
                    bond,
                    critical: critical_width(&cells),
                    half: half_clogging_width(&cells),
                    cells,
                }
            })
            .collect();
        if let Some(dry) = levels
            .iter()
            .find(|l| l.cohesion == GrainCohesion::Dry)
            .cloned()
        {
            // The dry level is the reference itself: no ratio of it with itself.
            for level in levels.iter_mut().filter(|l| l.bond > 0.0) {
                for (cell, reference) in level.cells.iter_mut().zip(&dry.cells) {
                    if let (Some(w), Some(w0)) = (cell.rate, reference.rate) {
                        cell.relative_rate = Some(ratio(w, w0));
                    }
                }
            }
        }
        let mut series: Vec<String> = cases.iter().map(|c| c.series.clone()).collect();
        series.sort();
        series.dedup();
        let mut arches: Vec<(String, f64, f64, Option<ArchSummary>)> = cases
            .iter()
            .filter(|c| c.status == CaseStatus::Clogged)
            .map(|c| (c.id.clone(), c.bond, c.outlet_width, c.arch))
            .collect();
        arches.sort_by(|a, b| {
            a.1.total_cmp(&b.1)
                .then(a.2.total_cmp(&b.2))
                .then(a.0.cmp(&b.0))
        });
        groups.push(CohesionGroup {
            series,
            walls: cases[0].walls.clone(),
            particle_diameter: cases[0].particle_diameter,
            widths,
            levels,
            arches,
        });
    }
    CohesionAnalysis {
        groups,
        undefined: study.undefined.clone(),
        present: study.has_cohesion,
    }
}

/// What published studies say and what can be compared with them (docs/reproduction.md
/// carries the same paragraph with the numbers of the `cohesion-bond` study).
pub const PUBLISHED_TRENDS: &str = "Published studies. The DEM study closest to this one is A. Anand's thesis, Modeling granular hopper discharge and segregation for wet cohesive particles (University of Florida, 2009), with the paper of Anand, Curtis, Wassgren, Hancock & Ketterhagen on the same work (Chem. Eng. Sci. 64 (2009) 5268): wet cohesive grains discharged from a quasi-3D rectangular hopper, liquid bridges and the Bond number among its subjects. Only the thesis's title, subjects and the cohesionless part of its abstract could be read for this report, not the paper, so neither its trend of W with Bo nor its numbers are compared here. For dry grains, Zuriguel et al. (Phys. Rev. E 71 (2005) 051303) measured that the probability of an arch over the outlet falls as D/d grows (they fitted a divergence of the mean avalanche at a finite critical size), Janda et al. (EPL 84 (2008) 44002) found no size above which jamming cannot occur, and Thomas & Durian (Phys. Rev. Lett. 2015; arXiv:1410.0933) a fraction of clogging configurations that decays exponentially in the hole width to the power of the dimension, never zero: there is no sharp critical outlet. The brackets above are therefore those of this study's run length and number of replicas, an outlet above which a clog within one run became rare, not a sharp threshold; where cohesion moves them to wider outlets, it makes arches more likely, which those dry studies do not address (Zuriguel et al. found the dry beads' material left the arching probability unchanged).";

/// "D = 18 mm (6.0 d)".
fn width_label(width: f64, d: f64) -> String {
    format!("{:.1} mm ({:.1} d)", width * 1e3, width / d)
}

/// Bo to three significant digits ("0" when dry).
pub(crate) fn bond_label(bond: f64) -> String {
    if bond == 0.0 {
        return "0".into();
    }
    let digits = (2 - bond.abs().log10().floor() as i32).max(0) as usize;
    format!("{bond:.digits$}")
}

/// The section's blocks: the definition, one W table, one critical-width table and one
/// arch table per group, the published trends; nothing when the study has no cohesion.
pub fn cohesion_blocks(analysis: &CohesionAnalysis) -> Vec<super::Block> {
    use super::Block;
    let mut blocks = Vec::new();
    if !analysis.present {
        return blocks;
    }
    blocks.push(Block::Heading(2, "Cohesion and the Bond number".into()));
    blocks.push(Block::Paragraph("Bo = F_c/(m g): the force that pulls two grains apart over one grain's weight, m = ρ_p π d³/6, R* = d/4 (docs/physics.md §7.12). JKR: the pull-off force F_c = (3/2)π w R*. Liquid bridge: its force at contact, F_c = 2π R γ cos θ. Simplified JKR: the least force of Hertz minus the attraction, F_c = (2/3)π³ k_c³ R*²/E*². Each case's Bo comes from its resolved case.toml. The cases that share everything but their grain–grain cohesion and their outlet width form one table, the dry ones its Bo = 0 rows. W: mean ± error over the replicas that flowed (as elsewhere in this report), in g/s; clogged replicas are counted, never averaged into W. W/W(Bo = 0): against the dry rate at the same width, the two errors combined in quadrature.".into()));
    for group in &analysis.groups {
        let d = group.particle_diameter;
        blocks.push(Block::Heading(
            3,
            format!(
                "Series {} (d = {:.2} mm, walls: {})",
                group.series.join(", "),
                d * 1e3,
                group.walls
            ),
        ));
        let mut headers = vec!["law".to_string(), "parameters".into(), "Bo".into()];
        headers.extend(
            group
                .widths
                .iter()
                .map(|&w| format!("W [g/s], D = {}", width_label(w, d))),
        );
        headers.extend(
            group
                .widths
                .iter()
                .map(|&w| format!("W/W(Bo = 0), D = {:.1} mm", w * 1e3)),
        );
        let rows = group
            .levels
            .iter()
            .map(|level| {
                let mut row = vec![
                    level.cohesion.law().to_string(),
                    level.cohesion.parameters(),
                    bond_label(level.bond),
                ];
                row.extend(level.cells.iter().map(|c| {
                    let clogs = format!("clogged {}/{}", c.clogged, c.runs);
                    match (c.rate, c.clogged) {
                        (Some(w), 0) => {
                            format!("{:.2} ± {:.2}", w.value * 1e3, w.standard_error * 1e3)
                        }
                        (Some(w), _) => format!(
                            "{:.2} ± {:.2} ({clogs})",
                            w.value * 1e3,
                            w.standard_error * 1e3
                        ),
                        (None, 0) if c.failed > 0 => format!("failed ({})", c.failed),
                        (None, 0) => "not run".into(),
                        (None, _) => clogs,
                    }
                }));
                row.extend(level.cells.iter().map(|c| match c.relative_rate {
                    Some(r) => format!("{:.3} ± {:.3}", r.value, r.standard_error),
                    None if level.cohesion == GrainCohesion::Dry && c.rate.is_some() => {
                        "1 (reference)".into()
                    }
                    None => "—".into(),
                }));
                row
            })
            .collect();
        blocks.push(Block::Table { headers, rows });
        blocks.push(Block::Paragraph("Critical outlet width D_c: the largest width at which a replica clogged and the smallest larger width at which every replica flowed bracket it; the clogging fraction is clogged runs over runs that ended (failed runs left out). The half-clogging width D_50 is where that fraction falls through one half as the outlet widens, linear between the widest width at which at least half the runs clogged and the next: clogging has no sharp threshold, and more replicas sharpen D_50 where they can only widen the bracket.".into()));
        let rows = group
            .levels
            .iter()
            .map(|level| {
                let fractions = level
                    .cells
                    .iter()
                    .filter(|c| c.runs > 0)
                    .map(|c| {
                        format!(
                            "{:.1} mm: {}/{} ({:.0} %)",
                            c.outlet_width * 1e3,
                            c.clogged,
                            c.runs,
                            100.0 * c.clogging_fraction()
                        )
                    })
                    .collect::<Vec<_>>()
                    .join("; ");
                let bracket = match level.critical {
                    CriticalWidth::Below(w) => {
                        format!("D_c ≤ {} (no run clogged)", width_label(w, d))
                    }
                    CriticalWidth::Between { clogged, flowed } => format!(
                        "{} < D_c ≤ {}",
                        width_label(clogged, d),
                        width_label(flowed, d)
                    ),
                    CriticalWidth::Above(w) => {
                        format!("D_c > {} (clogged at the largest width)", width_label(w, d))
                    }
                    CriticalWidth::Unknown => "no run ended".into(),
                };
                let half = match level.half {
                    HalfClogging::Below(w) => format!("D_50 < {}", width_label(w, d)),
                    HalfClogging::At(w) => format!("D_50 = {}", width_label(w, d)),
                    HalfClogging::Above(w) => format!("D_50 > {}", width_label(w, d)),
                    HalfClogging::Unknown => "no run ended".into(),
                };
                vec![
                    level.cohesion.law().to_string(),
                    bond_label(level.bond),
                    fractions,
                    bracket,
                    half,
                ]
            })
            .collect();
        blocks.push(Block::Table {
            headers: [
                "law",
                "Bo",
                "clogged/runs by D",
                "critical width",
                "half-clogging width",
            ]
            .map(String::from)
            .to_vec(),
            rows,
        });
        if !group.arches.is_empty() {
            blocks.push(Block::Paragraph("Where the arch of each clogged case stands (summary.json's `arch`, arch.csv lists its grains; docs/physics.md §7.9): heights of the grains' centres above the outlet line, at the apex, at the feet (the lowest) and on average.".into()));
            let mm = |h: f64| format!("{:.1} mm ({:.1} d)", h * 1e3, h / d);
            let rows = group
                .arches
                .iter()
                .map(|(id, bond, width, arch)| {
                    let mut row = vec![id.clone(), bond_label(*bond), width_label(*width, d)];
                    match arch {
                        Some(a) => row.extend([
                            a.particles.to_string(),
                            mm(a.apex_height),
                            mm(a.lowest_height),
                            mm(a.mean_height),
                        ]),
                        None => row.extend([
                            "not recorded".into(),
                            String::new(),
                            String::new(),
                            String::new(),
                        ]),
                    }
                    row
                })
                .collect();
            blocks.push(Block::Table {
                headers: ["case", "Bo", "D", "grains", "apex", "feet", "mean height"]
                    .map(String::from)
                    .to_vec(),
                rows,
            });
        }
    }
    if analysis.groups.is_empty() {
        blocks.push(Block::Paragraph("The study's cases name a cohesion law, but none has a Bond number, so no table is made.".into()));
    }
    if !analysis.undefined.is_empty() {
        blocks.push(Block::Paragraph(format!(
            "Cases without a Bond number, left out of the tables: {}.",
            analysis
                .undefined
                .iter()
                .map(|(id, why)| format!("{id} ({why})"))
                .collect::<Vec<_>>()
                .join("; ")
        )));
    }
    blocks.push(Block::Paragraph(PUBLISHED_TRENDS.into()));
    blocks
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell(width: f64, runs: usize, clogged: usize) -> BondCell {
        BondCell {
            outlet_width: width,
            runs,
            clogged,
            failed: 0,
            rate: None,
            relative_rate: None,
        }
    }

    #[test]
    fn the_critical_width_lies_above_the_largest_width_that_clogged() {
        // Clogs at 6 d and, by chance, at 8 d but not at 7 d: D_c lies above 8 d, below the
        // next width that never clogged.
        let cells = [
            cell(6.0, 3, 3),
            cell(7.0, 3, 0),
            cell(8.0, 3, 1),
            cell(10.0, 3, 0),
        ];
        assert_eq!(
            critical_width(&cells),
            CriticalWidth::Between {
                clogged: 8.0,
                flowed: 10.0
            }
        );
        assert_eq!(
            critical_width(&[cell(6.0, 2, 0), cell(8.0, 2, 0)]),
            CriticalWidth::Below(6.0)
        );
        assert_eq!(
            critical_width(&[cell(6.0, 2, 2), cell(8.0, 2, 1)]),
            CriticalWidth::Above(8.0)
        );
        // A width with no finished run brackets nothing.
        assert_eq!(
            critical_width(&[cell(6.0, 1, 1), cell(8.0, 0, 0)]),
            CriticalWidth::Above(6.0)
        );
        assert_eq!(critical_width(&[cell(6.0, 0, 0)]), CriticalWidth::Unknown);
    }

    #[test]
    fn the_half_clogging_width_is_where_the_fraction_falls_through_one_half() {
        // 4/5, 2/5, 2/5, 0/5 clog at 5, 6, 8, 10 d: the fraction falls through 1/2 between 5
        // and 6 d, three quarters of the way from 0.8 to 0.4, at 5.75 d (exact in binary to
        // the division's rounding).
        let cells = [
            cell(5.0, 5, 4),
            cell(6.0, 5, 2),
            cell(8.0, 5, 2),
            cell(10.0, 5, 0),
        ];
        match half_clogging_width(&cells) {
            HalfClogging::At(w) => assert!((w - 5.75).abs() < 1e-12, "{w}"),
            other => panic!("{other:?}"),
        }
        // Exactly half at one width: D_50 is that width.
        match half_clogging_width(&[cell(6.0, 4, 2), cell(8.0, 4, 0)]) {
            HalfClogging::At(w) => assert_eq!(w, 6.0),
            other => panic!("{other:?}"),
        }
        assert_eq!(
            half_clogging_width(&[cell(5.0, 5, 2), cell(6.0, 5, 0)]),
            HalfClogging::Below(5.0)
        );
        assert_eq!(
            half_clogging_width(&[cell(8.0, 5, 3), cell(10.0, 5, 3)]),
            HalfClogging::Above(10.0)
        );
        // A width with no finished run is skipped; none at all gives nothing.
        assert_eq!(
            half_clogging_width(&[cell(6.0, 2, 2), cell(8.0, 0, 0)]),
            HalfClogging::Above(6.0)
        );
        assert_eq!(
            half_clogging_width(&[cell(6.0, 0, 0)]),
            HalfClogging::Unknown
        );
    }
}
