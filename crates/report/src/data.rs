//! Loading a finished study (results table, profiles, flow series) and averaging replicas
//! into grid points: mean ± standard error over independent fills, before any fit.

use std::collections::BTreeMap;
use std::path::Path;

use analysis::profile::BinnedProfile;
use analysis::Estimate;

use files::ProfileRow;
use files::StudyFileError;
use files::DEFAULT_GRAVITY;
use files::{read_results_table, CaseStatus, ResultRow, StudyManifest, StudyPaths, SUMMARY_FILE};

/// Tolerance on s* for "the outlet is centred" (s* = 1); grid values are exact decimals.
const CENTRED_TOLERANCE: f64 = 1e-6;

/// Everything the report reads from a study directory.
#[derive(Debug, Clone, Default)]
pub struct StudyData {
    /// The manifest, when `study.json` exists.
    pub manifest: Option<StudyManifest>,
    /// Every row of `results.csv`.
    pub rows: Vec<ResultRow>,
    /// Replica-averaged grid points of the usable (complete, finite-W) cases.
    pub points: Vec<GridPoint>,
}

/// One grid point: the replicas of a case averaged.
#[derive(Debug, Clone, PartialEq)]
pub struct GridPoint {
    /// Identifier without the replica suffix.
    pub key: String,
    /// Series name.
    pub series: String,
    /// Orifice width D [m].
    pub outlet_width: f64,
    /// Hopper angle α [°].
    pub hopper_angle_deg: f64,
    /// Gap s between the left wall and the outlet [m].
    pub outlet_gap: f64,
    /// s* = 2s/(L − D) [-].
    pub dimensionless_gap: f64,
    /// Slab thickness Z [m].
    pub thickness: f64,
    /// Particle–wall friction μ_pw [-].
    pub wall_friction: f64,
    /// Hopper width L [m].
    pub width: f64,
    /// Particle diameter d [m].
    pub particle_diameter: f64,
    /// Particle density ρ_p [kg/m³].
    pub particle_density: f64,
    /// Particles in the fill.
    pub particles: usize,
    /// Replicas averaged.
    pub replicas: usize,
    /// W [kg/s]: replica mean ± error, the standard error over replicas floored at the
    /// runs' own blocking errors carried to the mean (one replica: its own blocking error).
    pub discharge_rate: Estimate,
    /// v_c [m/s], ± the standard error over replicas (NaN with one).
    pub centre_velocity: Estimate,
    /// φ_c [-].
    pub centre_area_fraction: Estimate,
    /// φ_max [-].
    pub max_area_fraction: Estimate,
    /// Mean settled bulk volume fraction φ_B [-].
    pub bulk_volume_fraction: f64,
    /// Mean velocity profile v(x*) [m/s], when profiles were saved.
    pub velocity_profile: Option<BinnedProfile>,
    /// Mean area-fraction profile φ(x*) [-].
    pub area_fraction_profile: Option<BinnedProfile>,
    /// Mean crossing number-density profile φ_n(x*) [-], when the profiles hold it (a
    /// study run before the column existed has none).
    pub crossing_area_fraction_profile: Option<BinnedProfile>,
    /// W(t) of the first replica: times [s] and rates [kg/s], when `flow.csv` was saved.
    pub flow: Option<(Vec<f64>, Vec<f64>)>,
    /// The geometry kind of the case (`geometry.kind`: "slab", "cylinder", "box", "mesh").
    pub kind: String,
    /// g [m/s²] of the case (`gravity`; its default when the case file omits it).
    pub gravity: f64,
    /// The first replica's radial profile fits (circular orifices only).
    pub radial_fit: Option<files::RadialFit>,
}

impl GridPoint {
    /// Outlet half-width R [m].
    pub fn radius(&self) -> f64 {
        0.5 * self.outlet_width
    }
    /// Whether the outlet is centred (s* = 1).
    pub fn is_centred(&self) -> bool {
        (self.dimensionless_gap - 1.0).abs() < CENTRED_TOLERANCE
    }
    /// Whether this point is a flat-bottomed (α = 90°) hopper.
    pub fn is_flat(&self) -> bool {
        (self.hopper_angle_deg - 90.0).abs() < 1e-9
    }
    /// Whether `other` has the same material, slab, hopper width and fill (so that one
    /// can be the reference of the other).
    pub fn same_conditions(&self, other: &GridPoint) -> bool {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-12);
        close(self.thickness, other.thickness)
            && close(self.wall_friction, other.wall_friction)
            && close(self.width, other.width)
            && close(self.particle_diameter, other.particle_diameter)
            && close(self.particle_density, other.particle_density)
            && self.particles == other.particles
    }
}

/// Identifier without its `-r<replica>` suffix.
fn point_key(id: &str) -> &str {
    match id.rfind("-r") {
        Some(i) if id[i + 2..].chars().all(|c| c.is_ascii_digit()) && i + 2 < id.len() => &id[..i],
        _ => id,
    }
}

/// Mean ± error of replica values, each `(value, its own error)` (NaN when the run gives
/// none).
///
/// The error is the larger of two estimates of the mean's uncertainty:
/// - the standard error over replicas, s/√n;
/// - each run's own error carried to the mean, √(Σe²)/n, when every run gives one.
///
/// With two or three replicas, s has one or two degrees of freedom and comes out near zero
/// whenever the runs happen to agree: in the three-replica study, two D = 18 mm runs at 90°
/// agreed to 0.03 % in one profile bin, and that bin then carried about 60 % of the weight
/// of the whole 90° shape fit. A run's own error (blocking error of W, a bin's error over
/// its crossings) is a floor that chance agreement cannot lower. With one value, its own
/// error is used.
pub(crate) fn replica_mean(samples: &[(f64, f64)]) -> Estimate {
    let finite: Vec<(f64, f64)> = samples
        .iter()
        .copied()
        .filter(|v| v.0.is_finite())
        .collect();
    let n = finite.len();
    if n == 0 {
        return Estimate::new(f64::NAN, f64::NAN);
    }
    let mean = finite.iter().map(|v| v.0).sum::<f64>() / n as f64;
    if n == 1 {
        return Estimate::new(mean, finite[0].1);
    }
    let variance = finite.iter().map(|v| (v.0 - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    let between = (variance / n as f64).sqrt();
    // NaN when some run has no error of its own; `max` then keeps the spread alone.
    let within = finite.iter().map(|v| v.1 * v.1).sum::<f64>().sqrt() / n as f64;
    Estimate::new(mean, between.max(within))
}

/// Ratio of two estimates, relative errors combined in quadrature (independent runs).
pub(crate) fn ratio(a: Estimate, b: Estimate) -> Estimate {
    let r = a.value / b.value;
    let e =
        r * ((a.standard_error / a.value).powi(2) + (b.standard_error / b.value).powi(2)).sqrt();
    Estimate::new(r, e)
}

/// Reads `profiles.csv` rows; `None` when absent or unreadable (the report then says the
/// profile was not measured rather than failing).
fn read_profiles(path: &Path) -> Option<Vec<ProfileRow>> {
    let mut reader = csv::Reader::from_path(path).ok()?;
    reader
        .deserialize::<ProfileRow>()
        .collect::<Result<_, _>>()
        .ok()
}

/// Reads `flow.csv` (time, rate, …); `None` when absent or unreadable.
fn read_flow(path: &Path) -> Option<(Vec<f64>, Vec<f64>)> {
    let mut reader = csv::Reader::from_path(path).ok()?;
    let (mut t, mut w) = (Vec::new(), Vec::new());
    for record in reader.records() {
        let record = record.ok()?;
        t.push(record.get(0)?.parse().ok()?);
        w.push(record.get(1)?.parse().ok()?);
    }
    Some((t, w))
}

/// Bin-wise replica average of profiles with equal bins: mean ± error ([`replica_mean`]) over
/// the replicas that populate a bin.
fn average_profiles(
    profiles: &[Vec<ProfileRow>],
    value: impl Fn(&ProfileRow) -> f64,
    error: impl Fn(&ProfileRow) -> f64,
    count: impl Fn(&ProfileRow) -> u64,
) -> Option<BinnedProfile> {
    let first = profiles.first()?;
    if profiles.iter().any(|p| p.len() != first.len()) {
        return None;
    }
    let (mut centres, mut values, mut counts, mut errors) = (vec![], vec![], vec![], vec![]);
    for (i, bin) in first.iter().enumerate() {
        let populated: Vec<&ProfileRow> = profiles
            .iter()
            .map(|p| &p[i])
            .filter(|row| count(row) > 0 && value(row).is_finite())
            .collect();
        let samples: Vec<(f64, f64)> = populated
            .iter()
            .map(|row| (value(row), error(row)))
            .collect();
        let mean = replica_mean(&samples);
        centres.push(bin.x_star);
        values.push(mean.value);
        counts.push(populated.iter().map(|row| count(row)).sum());
        errors.push(mean.standard_error);
    }
    BinnedProfile::new(centres, values, counts, errors).ok()
}

/// The geometry kind of a case from the resolved `case.toml` its run wrote (its
/// `geometry.kind`, which a slab leaves out; read as TOML, not resolved, so that a mesh case
/// whose STL files have moved is still told); a case folder without one is told by its row:
/// only a slab has a slab width.
/// The geometry kind (`geometry.kind`) and g [m/s²] of the case whose resolved
/// `case.toml` is in `dir`. Without a readable file, a row with a hopper width is a slab and
/// one without a cylinder, under the default g.
fn case_facts(dir: &Path, row: &ResultRow) -> (String, f64) {
    let table = std::fs::read_to_string(dir.join("case.toml"))
        .ok()
        .and_then(|text| text.parse::<toml::Table>().ok());
    let Some(table) = table else {
        let kind = if row.width.is_finite() {
            "slab"
        } else {
            "cylinder"
        };
        return (kind.to_string(), DEFAULT_GRAVITY);
    };
    let kind = table
        .get("geometry")
        .and_then(|g| g.get("kind"))
        .and_then(|k| k.as_str())
        .unwrap_or("slab")
        .to_string();
    (kind, case_gravity(&table))
}

/// g [m/s²] of a resolved case: a resolved case writes `gravity` only when it differs from
/// the default.
pub(crate) fn case_gravity(table: &toml::Table) -> f64 {
    match table.get("gravity") {
        Some(toml::Value::Float(g)) => *g,
        Some(toml::Value::Integer(g)) => *g as f64,
        _ => DEFAULT_GRAVITY,
    }
}

/// A case's `summary.json`, when it reads.
pub(crate) fn read_summary(dir: &Path) -> Option<files::CaseSummary> {
    let text = std::fs::read_to_string(dir.join(SUMMARY_FILE)).ok()?;
    serde_json::from_str(&text).ok()
}

/// Loads a study directory: `results.csv` (required), `study.json` and each case's
/// `profiles.csv` and `flow.csv` (optional).
pub fn load_study(root: &Path) -> Result<StudyData, StudyFileError> {
    let paths = StudyPaths::new(root);
    let manifest = StudyManifest::read(&paths.manifest())?;
    let rows = read_results_table(&paths.results())?;
    let mut groups: BTreeMap<String, Vec<&ResultRow>> = BTreeMap::new();
    for row in &rows {
        if row.status == CaseStatus::Complete && row.discharge_rate.is_finite() {
            groups
                .entry(point_key(&row.id).to_string())
                .or_default()
                .push(row);
        }
    }
    let mut points = Vec::new();
    for (key, replicas) in groups {
        let first = replicas[0];
        // Each replica's value of `f` with its own error `e`; results with none (the
        // centre values) get NaN, and their mean's error is the spread over replicas alone.
        let with_errors = |f: fn(&ResultRow) -> f64, e: fn(&ResultRow) -> f64| {
            replicas.iter().map(|r| (f(r), e(r))).collect::<Vec<_>>()
        };
        let values = |f: fn(&ResultRow) -> f64| with_errors(f, |_| f64::NAN);
        let profiles: Vec<Vec<ProfileRow>> = replicas
            .iter()
            .filter_map(|r| read_profiles(&paths.case_dir(&r.id).join("profiles.csv")))
            .collect();
        let usable = profiles.len() == replicas.len();
        let velocity_profile = usable
            .then(|| {
                average_profiles(
                    &profiles,
                    |r| r.velocity,
                    |r| r.velocity_error,
                    |r| r.crossings as u64,
                )
            })
            .flatten();
        let area_fraction_profile = usable
            .then(|| {
                average_profiles(
                    &profiles,
                    |r| r.area_fraction,
                    |r| r.area_fraction_error,
                    |r| u64::from(r.area_fraction.is_finite()),
                )
            })
            .flatten();
        // Every replica must carry the column: a bin left NaN by all of them is empty.
        let crossing_area_fraction_profile = (usable
            && profiles
                .iter()
                .all(|p| p.iter().any(|r| r.crossing_area_fraction.is_finite())))
        .then(|| {
            average_profiles(
                &profiles,
                |r| r.crossing_area_fraction,
                |r| r.crossing_area_fraction_error,
                |r| u64::from(r.crossing_area_fraction.is_finite()),
            )
        })
        .flatten();
        let (kind, gravity) = case_facts(&paths.case_dir(&first.id), first);
        points.push(GridPoint {
            key,
            series: first.series.clone(),
            outlet_width: first.outlet_width,
            hopper_angle_deg: first.hopper_angle_deg,
            outlet_gap: first.outlet_gap,
            dimensionless_gap: first.dimensionless_gap,
            thickness: first.thickness,
            wall_friction: first.wall_friction,
            width: first.width,
            particle_diameter: first.particle_diameter,
            particle_density: first.particle_density,
            particles: first.particles,
            replicas: replicas.len(),
            discharge_rate: replica_mean(&with_errors(
                |r| r.discharge_rate,
                |r| r.discharge_rate_error,
            )),
            centre_velocity: replica_mean(&values(|r| r.centre_velocity)),
            centre_area_fraction: replica_mean(&values(|r| r.centre_area_fraction)),
            max_area_fraction: replica_mean(&values(|r| r.max_area_fraction)),
            bulk_volume_fraction: replica_mean(&values(|r| r.bulk_volume_fraction)).value,
            velocity_profile,
            area_fraction_profile,
            crossing_area_fraction_profile,
            flow: read_flow(&paths.case_dir(&first.id).join("flow.csv")),
            kind,
            gravity,
            radial_fit: read_summary(&paths.case_dir(&first.id)).and_then(|s| s.radial_fit),
        });
    }
    Ok(StudyData {
        manifest,
        rows,
        points,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replica_suffix_is_removed_only_when_it_is_a_number() {
        assert_eq!(point_key("angle-a30-D045-r12"), "angle-a30-D045");
        assert_eq!(point_key("angle-rough"), "angle-rough");
    }

    #[test]
    fn replica_mean_gives_the_standard_error_of_the_mean() {
        // Values 1, 2, 3 with no errors of their own: sample standard deviation 1, so the
        // error is 1/√3 (to rounding: 1e-15 is a few ulps of numbers near 1).
        let nan = f64::NAN;
        let m = replica_mean(&[(1.0, nan), (2.0, nan), (3.0, nan)]);
        assert!((m.value - 2.0).abs() < 1e-15);
        assert!((m.standard_error - 1.0 / 3f64.sqrt()).abs() < 1e-15);
        // Own errors smaller than the spread change nothing: √(3 · 0.1²)/3 ≈ 0.058 < 0.577.
        let m = replica_mean(&[(1.0, 0.1), (2.0, 0.1), (3.0, 0.1)]);
        assert!((m.standard_error - 1.0 / 3f64.sqrt()).abs() < 1e-15);
        // One replica keeps the error it came with.
        assert_eq!(replica_mean(&[(4.0, 0.5)]).standard_error, 0.5);
    }

    #[test]
    fn replicas_that_agree_by_chance_keep_their_own_errors() {
        // Two runs 0.0003 apart, each ± 0.008 (the 90° D = 18 mm bin of the three-replica
        // study): the spread alone would give 0.00015, the runs' own errors give
        // √2 · 0.008/2 ≈ 0.00566, and the larger is the honest one.
        let m = replica_mean(&[(0.3051, 0.008), (0.3048, 0.008)]);
        assert!((m.value - 0.30495).abs() < 1e-12);
        assert!((m.standard_error - 0.008 / 2f64.sqrt()).abs() < 1e-12);
        // Identical runs: the spread is zero, the floor is not.
        let m = replica_mean(&[(1.0, 0.2), (1.0, 0.2)]);
        assert!(m.standard_error > 0.1);
    }
}
