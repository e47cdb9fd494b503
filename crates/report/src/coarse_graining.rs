//! Coarse-grained parcels in a study (docs/physics.md §2.8): for cases that differ only in
//! their factor κ, the discharge rate W, the half-discharge time of N(t) and the settled
//! bed's pressure on the hopper wall against κ = 1, beside the ratio the Beverloo law
//! predicts from the parcels' larger empty annulus.
//!
//! Everything is read from saved files: κ and D/(κd) from each case's `summary.json`, N(t)
//! from its `remaining.csv`, the wall pressure from its `wall_pressure.csv`, W and the status
//! from `results.csv`, and what the cases share from their resolved `case.toml` (without its
//! seed, κ, `[measure]` and `[output]`).

use std::collections::BTreeMap;
use std::path::Path;

use analysis::Estimate;
use files::{CaseStatus, ResultRow, StudyPaths};

use super::data::{ratio, read_summary, replica_mean};

/// The Beverloo k of spheres through a circular orifice used for the predicted ratio: the
/// middle of the classic range 1.3–1.6 ([`super::silo::CLASSIC_K`]), as Nedderman (1992,
/// ch. 10) recommends for spheres.
pub const BEVERLOO_K: f64 = 1.5;

/// One run as this section reads it.
#[derive(Debug, Clone, PartialEq)]
pub struct ParcelRun {
    /// Case identifier.
    pub id: String,
    /// What it shares with the others of its table (the resolved case without its seed, κ,
    /// `[measure]` and `[output]`).
    pub conditions: String,
    /// κ [-], 1 for grains.
    pub factor: f64,
    /// D/(κd) [-].
    pub outlet_parcels: f64,
    /// D/d of the grains [-].
    pub outlet_grains: f64,
    /// Spheres simulated.
    pub parcels: usize,
    /// How the run ended.
    pub status: CaseStatus,
    /// W and its error [kg/s].
    pub rate: (f64, f64),
    /// Time from the opening at which half the settled mass had left [s]; NaN if it never
    /// did.
    pub half_time: f64,
    /// The settled bed's mean normal pressure on the hopper's cone [Pa]; NaN without a cone.
    pub pressure: f64,
}

/// The replicas of one κ in one table.
#[derive(Debug, Clone, PartialEq)]
pub struct ParcelLevel {
    /// κ [-].
    pub factor: f64,
    /// D/(κd) [-].
    pub outlet_parcels: f64,
    /// Spheres simulated (the first replica's).
    pub parcels: usize,
    /// Replicas run, and of them clogged.
    pub runs: usize,
    /// Clogged replicas.
    pub clogged: usize,
    /// W [kg/s] over the replicas that flowed.
    pub rate: Option<Estimate>,
    /// W/W(κ = 1), errors combined in quadrature.
    pub relative_rate: Option<Estimate>,
    /// ((D − kκd)/(D − kd))^{5/2}: the ratio Beverloo's law predicts with k = [`BEVERLOO_K`].
    pub beverloo_ratio: f64,
    /// W over [`ParcelLevel::beverloo_ratio`] [kg/s]: the grains' W that the parcels' W
    /// implies when Beverloo's law holds for both.
    pub corrected_rate: Option<Estimate>,
    /// The half-discharge time [s], replica mean.
    pub half_time: Option<Estimate>,
    /// The settled bed's mean pressure on the cone [Pa], replica mean.
    pub pressure: Option<Estimate>,
    /// It over κ = 1's.
    pub relative_pressure: Option<Estimate>,
}

/// One table: the levels of κ of cases that share everything else.
#[derive(Debug, Clone, PartialEq)]
pub struct ParcelTable {
    /// The grains' D/d [-].
    pub outlet_grains: f64,
    /// The levels in increasing κ.
    pub levels: Vec<ParcelLevel>,
}

/// Reads every run of `rows` whose folder under `root` has a summary; `None` for a study
/// with no coarse-grained case.
pub fn load_parcels(root: &Path, rows: &[ResultRow]) -> Option<Vec<ParcelRun>> {
    let paths = StudyPaths::new(root);
    let mut runs = Vec::new();
    let mut any = false;
    for row in rows {
        let dir = paths.case_dir(&row.id);
        let Some(summary) = read_summary(&dir) else {
            continue;
        };
        let Some(conditions) = std::fs::read_to_string(dir.join("case.toml"))
            .ok()
            .and_then(|text| text.parse::<toml::Table>().ok())
            .map(|case| conditions(&case))
        else {
            continue;
        };
        any |= summary.coarse_graining.is_some();
        let outlet = summary.outlet_width;
        let (factor, outlet_parcels, outlet_grains) = match &summary.coarse_graining {
            Some(c) => (c.factor, c.outlet_parcels, c.outlet_grains),
            None => {
                let ratio = outlet / summary.particle_diameter;
                (1.0, ratio, ratio)
            }
        };
        runs.push(ParcelRun {
            id: row.id.clone(),
            conditions,
            factor,
            outlet_parcels,
            outlet_grains,
            parcels: summary.particles,
            status: row.status,
            rate: (row.discharge_rate, row.discharge_rate_error),
            half_time: half_time(&dir.join("remaining.csv")),
            pressure: cone_pressure(
                &dir.join("wall_pressure.csv"),
                outlet,
                summary.hopper_angle_deg,
            ),
        });
    }
    any.then_some(runs)
}

/// The resolved case without its seed, its κ and what only measures or writes the run
/// (`[measure]` and `[output]`, whose bin widths default to the parcels' diameter).
fn conditions(case: &toml::Table) -> String {
    let mut case = case.clone();
    for key in ["seed", "measure", "output"] {
        case.remove(key);
    }
    if let Some(toml::Value::Table(p)) = case.get_mut("particles") {
        p.remove("coarse_graining");
    }
    toml::to_string(&case).unwrap_or_default()
}

/// The first time in `remaining.csv` at which the mass above the orifice is at most half
/// its first value [s]; NaN when the file is missing or the mass never fell that far.
fn half_time(path: &Path) -> f64 {
    let Ok(mut reader) = csv::Reader::from_path(path) else {
        return f64::NAN;
    };
    let rows: Vec<(f64, f64)> = reader
        .records()
        .filter_map(|r| r.ok())
        .filter_map(|r| Some((r.get(0)?.parse().ok()?, r.get(2)?.parse().ok()?)))
        .collect();
    let Some(&(_, first)) = rows.first() else {
        return f64::NAN;
    };
    rows.iter()
        .find(|&&(_, m)| m <= 0.5 * first)
        .map_or(f64::NAN, |&(t, _)| t)
}

/// The settled bed's normal pressure on the cone of a hopper of outlet `outlet` [m] and
/// half-angle `angle_deg` [°], averaged over the cone's area [Pa]: each settled zone of the
/// wall `hopper` in `wall_pressure.csv` weighted by its area, ∝ its height times its mean
/// radius D/2 + z tan θ. NaN for a flat bottom or a missing file.
fn cone_pressure(path: &Path, outlet: f64, angle_deg: f64) -> f64 {
    // A flat bottom (90°) has no cone; NaN from an unreadable summary has none either.
    if angle_deg.is_nan() || angle_deg >= 90.0 {
        return f64::NAN;
    }
    let Ok(mut reader) = csv::Reader::from_path(path) else {
        return f64::NAN;
    };
    let tan = angle_deg.to_radians().tan();
    let (mut force, mut area) = (0.0, 0.0);
    for record in reader.records().filter_map(|r| r.ok()) {
        if record.get(1) != Some("settled") || record.get(2) != Some("hopper") {
            continue;
        }
        let number = |k: usize| record.get(k).and_then(|v| v.parse::<f64>().ok());
        let (Some(low), Some(high), Some(p)) = (number(3), number(4), number(5)) else {
            continue;
        };
        let weight = (high - low) * (0.5 * outlet + 0.5 * (low + high) * tan);
        force += p * weight;
        area += weight;
    }
    if area > 0.0 {
        force / area
    } else {
        f64::NAN
    }
}

/// The tables of `runs`: cases grouped by their conditions, with at least two levels of κ.
pub fn parcel_tables(runs: &[ParcelRun]) -> Vec<ParcelTable> {
    let mut groups: BTreeMap<&str, Vec<&ParcelRun>> = BTreeMap::new();
    for run in runs {
        groups.entry(&run.conditions).or_default().push(run);
    }
    let mut tables = Vec::new();
    for group in groups.values() {
        let mut by_factor: BTreeMap<u64, Vec<&ParcelRun>> = BTreeMap::new();
        for run in group {
            by_factor.entry(run.factor.to_bits()).or_default().push(run);
        }
        if by_factor.len() < 2 {
            continue;
        }
        let mut levels: Vec<ParcelLevel> = by_factor
            .values()
            .map(|runs| {
                let first = runs[0];
                let mean = |values: Vec<(f64, f64)>| {
                    let values: Vec<(f64, f64)> =
                        values.into_iter().filter(|v| v.0.is_finite()).collect();
                    (!values.is_empty()).then(|| replica_mean(&values))
                };
                // W over the replicas that flowed.
                let rate = mean(
                    runs.iter()
                        .filter(|r| r.status == CaseStatus::Complete)
                        .map(|r| r.rate)
                        .collect(),
                );
                // (D − kκd)/(D − kd) = (D/d − kκ)/(D/d − k).
                let (d_over_d, k) = (first.outlet_grains, BEVERLOO_K);
                let beverloo_ratio = ((d_over_d - k * first.factor) / (d_over_d - k))
                    .max(0.0)
                    .powf(2.5);
                ParcelLevel {
                    factor: first.factor,
                    outlet_parcels: first.outlet_parcels,
                    parcels: first.parcels,
                    runs: runs
                        .iter()
                        .filter(|r| r.status != CaseStatus::Failed)
                        .count(),
                    clogged: runs
                        .iter()
                        .filter(|r| r.status == CaseStatus::Clogged)
                        .count(),
                    rate,
                    relative_rate: None,
                    beverloo_ratio,
                    corrected_rate: rate.filter(|_| beverloo_ratio > 0.0).map(|w| {
                        Estimate::new(w.value / beverloo_ratio, w.standard_error / beverloo_ratio)
                    }),
                    half_time: mean(runs.iter().map(|r| (r.half_time, 0.0)).collect()),
                    pressure: mean(runs.iter().map(|r| (r.pressure, 0.0)).collect()),
                    relative_pressure: None,
                }
            })
            .collect();
        levels.sort_by(|a, b| a.factor.total_cmp(&b.factor));
        if levels[0].factor == 1.0 {
            let (rate, pressure) = (levels[0].rate, levels[0].pressure);
            for level in &mut levels[1..] {
                level.relative_rate = rate.zip(level.rate).map(|(r1, r)| ratio(r, r1));
                level.relative_pressure = pressure.zip(level.pressure).map(|(p1, p)| ratio(p, p1));
            }
        }
        tables.push(ParcelTable {
            outlet_grains: group[0].outlet_grains,
            levels,
        });
    }
    tables
}

/// The report's section: nothing for a study without coarse-grained cases.
pub fn parcel_blocks(runs: Option<&[ParcelRun]>) -> Vec<super::Block> {
    use super::Block;
    let Some(runs) = runs else {
        return Vec::new();
    };
    let mut blocks = vec![
        Block::Heading(2, "Coarse-grained parcels".into()),
        Block::Paragraph(format!(
            "Parcels of κ grains' diameter, of the grains' material, each standing for κ³ grains (docs/physics.md §2.8). The cases that share everything but κ form one table. W: mean ± error over the replicas that flowed, in g/s; W/W(κ = 1) with the errors combined in quadrature. Beverloo: the ratio ((D − kκd)/(D − kd))^(5/2) that the parcels' wider empty annulus predicts, k = {BEVERLOO_K}; W/Beverloo: the grains' W that the parcels' W implies where that law holds. t₁/₂: the time from the opening at which half the settled mass had left (remaining.csv). p_cone: the settled bed's normal pressure on the hopper's cone, averaged over its area (wall_pressure.csv); the replicas' spread is its error."
        )),
    ];
    let tables = parcel_tables(runs);
    if tables.is_empty() {
        blocks.push(Block::Paragraph(
            "No two cases differ in κ alone: nothing to compare.".into(),
        ));
    }
    let estimate = |e: Option<Estimate>, scale: f64, digits: usize| match e {
        Some(e) if e.standard_error > 0.0 => format!(
            "{:.digits$} ± {:.digits$}",
            e.value * scale,
            e.standard_error * scale
        ),
        Some(e) => format!("{:.digits$}", e.value * scale),
        None => "—".into(),
    };
    for table in &tables {
        blocks.push(Block::Heading(
            3,
            format!("Grains at D/d = {:.1}", table.outlet_grains),
        ));
        let headers = [
            "κ",
            "D/(κd)",
            "parcels",
            "W [g/s]",
            "W/W(κ = 1)",
            "Beverloo",
            "W/Beverloo [g/s]",
            "t₁/₂ [s]",
            "p_cone [Pa]",
            "p_cone/p_cone(κ = 1)",
            "clogged",
        ]
        .map(String::from)
        .to_vec();
        let rows = table
            .levels
            .iter()
            .map(|l| {
                vec![
                    format!("{}", l.factor),
                    format!("{:.2}", l.outlet_parcels),
                    l.parcels.to_string(),
                    estimate(l.rate, 1e3, 1),
                    match (l.factor == 1.0, l.relative_rate) {
                        (true, _) => "1 (reference)".into(),
                        (false, r) => estimate(r, 1.0, 3),
                    },
                    format!("{:.3}", l.beverloo_ratio),
                    estimate(l.corrected_rate, 1e3, 1),
                    estimate(l.half_time, 1.0, 3),
                    estimate(l.pressure, 1.0, 0),
                    match (l.factor == 1.0, l.relative_pressure) {
                        (true, _) => "1 (reference)".into(),
                        (false, r) => estimate(r, 1.0, 3),
                    },
                    format!("{}/{}", l.clogged, l.runs),
                ]
            })
            .collect();
        blocks.push(Block::Table { headers, rows });
    }
    blocks
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(factor: f64, rate: f64, pressure: f64) -> ParcelRun {
        ParcelRun {
            id: format!("k{factor}"),
            conditions: "silo".into(),
            factor,
            outlet_parcels: 15.0 / factor,
            outlet_grains: 15.0,
            parcels: (20_000.0 / factor.powi(3)) as usize,
            status: CaseStatus::Complete,
            rate: (rate, 0.01 * rate),
            half_time: 1.0,
            pressure,
        }
    }

    #[test]
    fn levels_are_compared_with_kappa_one_and_the_beverloo_ratio() {
        // D/d = 15, κ = 3, k = 1.5: ((15 − 4.5)/(15 − 1.5))^{5/2} = (10.5/13.5)^{2.5}.
        let runs = [
            run(1.0, 0.5, 800.0),
            run(3.0, 0.4, 820.0),
            run(2.0, 0.45, 790.0),
        ];
        let tables = parcel_tables(&runs);
        assert_eq!(tables.len(), 1);
        let levels = &tables[0].levels;
        let factors: Vec<f64> = levels.iter().map(|l| l.factor).collect();
        assert_eq!(factors, [1.0, 2.0, 3.0]);
        let three = &levels[2];
        assert!((three.beverloo_ratio - (10.5f64 / 13.5).powf(2.5)).abs() < 1e-12);
        let r = three.relative_rate.unwrap();
        assert!((r.value - 0.8).abs() < 1e-12);
        // 1 % on each W: √2 % on the ratio.
        assert!((r.standard_error - 0.8 * 2f64.sqrt() * 0.01).abs() < 1e-12);
        assert!((three.relative_pressure.unwrap().value - 820.0 / 800.0).abs() < 1e-12);
        assert!(levels[0].relative_rate.is_none());
        // W/Beverloo: 0.4 kg/s over the ratio, the error scaled alike.
        let corrected = three.corrected_rate.unwrap();
        assert!((corrected.value - 0.4 / three.beverloo_ratio).abs() < 1e-12);
    }

    #[test]
    fn the_cone_pressure_is_the_settled_zones_weighted_by_their_area() {
        // Zones 0–10 mm at 100 Pa and 10–20 mm at 200 Pa on a 45° cone over a 20 mm
        // orifice: areas ∝ 10 mm × 15 mm and 10 mm × 25 mm, so (100·15 + 200·25)/40 Pa. The
        // discharge row and the cylinder's zone are not the settled cone's.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("wall_pressure.csv");
        std::fs::write(
            &path,
            "time,phase,wall,z_low,z_high,pressure,shear
             0,settled,hopper,0,0.01,100,1
0,settled,hopper,0.01,0.02,200,1
             0,settled,cylinder,0.02,0.03,900,1
0.1,discharge,hopper,0,0.01,5000,1
",
        )
        .unwrap();
        let p = cone_pressure(&path, 0.02, 45.0);
        assert!((p - 162.5).abs() < 1e-9, "{p}");
        assert!(cone_pressure(&path, 0.02, 90.0).is_nan());
        assert!(cone_pressure(&dir.path().join("none.csv"), 0.02, 45.0).is_nan());
    }

    #[test]
    fn a_group_of_one_kappa_makes_no_table() {
        let mut other = run(2.0, 0.45, 790.0);
        other.conditions = "another silo".into();
        assert!(parcel_tables(&[run(1.0, 0.5, 800.0), other]).is_empty());
        assert!(parcel_blocks(None).is_empty());
    }
}
