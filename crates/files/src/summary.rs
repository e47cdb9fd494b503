//! What one hopper run reports: `summary.json` and the rows of `profiles.csv`.

use serde::{Deserialize, Deserializer, Serialize};

/// JSON has no NaN: `summary.json` writes a quantity that could not be measured (W of a
/// clogged case, say) as `null`, and reading turns `null` back into NaN, so that a finished
/// summary always reads back.
fn nan_if_null<'de, D: Deserializer<'de>>(deserializer: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(deserializer)?.unwrap_or(f64::NAN))
}

/// NaN, the value of a quantity a summary does not hold.
fn nan() -> f64 {
    f64::NAN
}

/// [`nan_if_null`] for a pair.
fn nan_pair_if_null<'de, D: Deserializer<'de>>(deserializer: D) -> Result<[f64; 2], D::Error> {
    let pair = <[Option<f64>; 2]>::deserialize(deserializer)?;
    Ok(pair.map(|x| x.unwrap_or(f64::NAN)))
}

/// Why the discharge stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// Every particle left the hopper.
    Empty,
    /// No particle crossed the outlet for the clog timeout and particles span the orifice:
    /// an arch formed.
    Clogged,
    /// The flow stopped with particles left only beside the orifice (the stagnant zones of a
    /// flat or shallow bottom), none above it: the hopper drained as far as it can.
    Drained,
    /// The discharge time limit was reached with particles left.
    TimeLimit,
    /// The requested fraction of the fill had left (`protocol.stop_fraction`) and the
    /// steady window was complete.
    Fraction,
    /// A heap test's cylinder was lifted away and the heap came to rest (the mean kinetic
    /// energy per particle fell below `protocol.settle_kinetic_energy`).
    AtRest,
    /// A run that breaks its arches (`[protocol.unclog]`) collected the avalanches it was
    /// asked for, each ended by a clog.
    Avalanches,
}

/// Where the arch over a clogged orifice stands (`arch.csv` lists its grains): heights of
/// its grains' centres above the outlet line [m].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ArchSummary {
    /// Grains in the arch [-].
    pub particles: usize,
    /// The highest grain's centre above the outlet line, the apex [m].
    pub apex_height: f64,
    /// The lowest grain's centre above the outlet line, at the arch's feet [m].
    pub lowest_height: f64,
    /// The grains' mean centre height above the outlet line [m].
    pub mean_height: f64,
}

/// The summary of one run (`summary.json`). Rates in kg/s for the whole slab.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaseSummary {
    /// hopperflow version that produced it.
    pub version: String,
    /// Seed of the fill.
    pub seed: u64,
    /// Hash of the resolved case file (hex SHA-256), to tie results to inputs.
    pub config_hash: String,
    /// Outlet width D [m].
    #[serde(deserialize_with = "nan_if_null")]
    pub outlet_width: f64,
    /// Hopper angle α from the vertical [°].
    #[serde(deserialize_with = "nan_if_null")]
    pub hopper_angle_deg: f64,
    /// Gap s between the left wall and the outlet [m].
    #[serde(deserialize_with = "nan_if_null")]
    pub outlet_gap: f64,
    /// Dimensionless eccentricity s* = 2s/(L − D) [-].
    #[serde(deserialize_with = "nan_if_null")]
    pub dimensionless_gap: f64,
    /// Hopper width L [m].
    #[serde(deserialize_with = "nan_if_null")]
    pub width: f64,
    /// Slab thickness Z [m].
    #[serde(deserialize_with = "nan_if_null")]
    pub thickness: f64,
    /// Mean particle diameter d [m].
    #[serde(deserialize_with = "nan_if_null")]
    pub particle_diameter: f64,
    /// Particle density ρ_p [kg/m³].
    #[serde(deserialize_with = "nan_if_null")]
    pub particle_density: f64,
    /// Particles in the fill.
    pub particles: usize,
    /// Mean discharge rate W over the steady window [kg/s].
    #[serde(deserialize_with = "nan_if_null")]
    pub discharge_rate: f64,
    /// Standard error of W from block averaging of the binned rate [kg/s].
    #[serde(deserialize_with = "nan_if_null")]
    pub discharge_rate_error: f64,
    /// Steady window [s, s], measured from the gate opening.
    #[serde(deserialize_with = "nan_pair_if_null")]
    pub steady_window: [f64; 2],
    /// Whether W(t) showed a plateau in the window (see `analysis::series`).
    pub plateau_found: bool,
    /// W from the snapshot flux (2/3) ρ_p d ∫ ⟨φ v⟩ dx over the window [kg/s] (docs/physics.md §7.4).
    #[serde(deserialize_with = "nan_if_null")]
    pub flux_check_rate: f64,
    /// W from the crossing v(x) times the strip φ(x) [kg/s].
    #[serde(deserialize_with = "nan_if_null")]
    pub flux_check_rate_profiles: f64,
    /// Settled bulk volume fraction φ_B (3D) [-].
    #[serde(deserialize_with = "nan_if_null")]
    pub bulk_volume_fraction: f64,
    /// Settled mid-plane area fraction of the bed [-].
    #[serde(deserialize_with = "nan_if_null")]
    pub bulk_area_fraction: f64,
    /// Settled bed height above the outlet [m].
    #[serde(deserialize_with = "nan_if_null")]
    pub bed_height: f64,
    /// Centre velocity v_c (downward, mean of |x*| < 0.1) [m/s].
    #[serde(deserialize_with = "nan_if_null")]
    pub centre_velocity: f64,
    /// Centre area fraction φ_c [-].
    #[serde(deserialize_with = "nan_if_null")]
    pub centre_area_fraction: f64,
    /// Largest binned area fraction φ_max [-].
    #[serde(deserialize_with = "nan_if_null")]
    pub max_area_fraction: f64,
    /// Where φ_max sits, x* [-].
    #[serde(deserialize_with = "nan_if_null")]
    pub max_area_fraction_position: f64,
    /// Whether the outlet clogged.
    pub clogged: bool,
    /// Why the discharge stopped.
    pub stop_reason: StopReason,
    /// Mass discharged through the outlet [kg].
    #[serde(deserialize_with = "nan_if_null")]
    pub discharged_mass: f64,
    /// Simulated time from gate opening to stop [s].
    #[serde(deserialize_with = "nan_if_null")]
    pub discharge_time: f64,
    /// Simulated time of filling and settling [s].
    #[serde(deserialize_with = "nan_if_null")]
    pub fill_time: f64,
    /// Mean kinetic energy per particle when the gate opened [J].
    #[serde(deserialize_with = "nan_if_null")]
    pub settled_kinetic_energy: f64,
    /// Whether the settling threshold was reached before the settle time limit.
    pub settled: bool,
    /// Exponent b of φ/φ_c = (1 − x*²)^b (paper Eq. 11) fitted to this run's strip
    /// area-fraction profile (bins |x*| ≤ 0.9, divided by the centre value) [-]; `null`
    /// when the profile is missing or the fit fails.
    #[serde(default)]
    pub area_fraction_exponent: Option<f64>,
    /// The same exponent for the crossing number-density profile [-]; `null` as above.
    #[serde(default)]
    pub crossing_area_fraction_exponent: Option<f64>,
    /// The self-similar fits of a circular orifice's radial profiles (absent for a slot).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radial_fit: Option<RadialFit>,
    /// Janssen's law fitted to the settled bed's pressure on a silo's cylinder (absent for
    /// a slab, or when too few zones lie in the bed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub janssen: Option<JanssenSummary>,
    /// Why a silo's settled bed gives no Janssen fit (too few zones of the cylinder in the
    /// bed, or the fit failed); absent where the fit exists or the container has no
    /// cylinder.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub janssen_not_fitted: Option<String>,
    /// What the run started from instead of its own fill: a saved bed or a packing file,
    /// by SHA-256 (`run::StartRecord`); absent for a run that filled its container.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<crate::StartRecord>,
    /// The arch over the orifice when the run clogged; absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub arch: Option<ArchSummary>,
    /// The angle of repose of a heap test (`geometry.kind = "heap"`, docs/physics.md §7.10);
    /// absent for the other kinds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub repose: Option<ReposeSummary>,
    /// The shelf angles of a draw-down test (`geometry.kind = "draw_down"`, docs/physics.md
    /// §7.11); absent for the other kinds. Its discharge rate is `discharge_rate`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub draw_down: Option<DrawDownSummary>,
    /// The coarse-grained fields (`[output.fields]`, docs/physics.md §7.13): their
    /// kernel, the mass check and the check of the width; absent without the section.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fields: Option<FieldsSummary>,
    /// The avalanches between clogs of a run that breaks its arches (`[protocol.unclog]`,
    /// `avalanches.csv`, docs/physics.md §7.14); absent without the section.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub avalanches: Option<AvalancheSummary>,
    /// The grains that coarse-grained parcels stand for (`particles.coarse_graining`,
    /// docs/physics.md §2.8); absent when the grains are simulated as they are. Then
    /// `particles` and `particle_diameter` above are the parcels'; masses and rates are the
    /// grains' as they are.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coarse_graining: Option<CoarseGrainingSummary>,
    /// The orientation of shaped grains' long axes in the settled bed and at the outlet
    /// (`particles.shape`, `orientations.csv`, docs/physics.md §11.8); absent for spheres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation: Option<OrientationSummary>,
    /// How long the grains stayed after the opening (`residence.csv`, docs/physics.md
    /// §7.15); absent for a run that never opened or that no grain left.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub residence: Option<ResidenceSummary>,
}

/// The residence times of the grains that left, from the opening to their crossing of the
/// outlet (docs/physics.md §7.15).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ResidenceSummary {
    /// Grains in the bed at the opening [-].
    pub grains: usize,
    /// Grains that left through the outlet [-].
    pub left: usize,
    /// Mean residence time [s].
    #[serde(deserialize_with = "nan_if_null")]
    pub mean: f64,
    /// Residence times at 10 %, 50 % and 90 % of the grains that left [s].
    pub quantiles: [f64; 3],
    /// Spearman's rank correlation of the grains' heights at the opening with their
    /// residence times [-]: 1 first-in-first-out, near 0 or below for a core that carries
    /// the top down first; NaN (null) below three grains.
    #[serde(deserialize_with = "nan_if_null")]
    pub fifo_index: f64,
}

/// Orientation statistics of a set of grains' long axes (docs/physics.md §11.5): the
/// alignment with the vertical ⟨P₂(u·ẑ)⟩ = ⟨(3 (u·ẑ)² − 1)/2⟩ (1 all vertical, 0 random,
/// −1/2 all horizontal) and the nematic order S with its director.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AxesStatistics {
    /// Grains counted [-].
    pub grains: usize,
    /// ⟨P₂(u·ẑ)⟩ [-], in [−1/2, 1].
    pub vertical_alignment: f64,
    /// S [-], the order tensor's largest eigenvalue, in [0, 1].
    pub nematic_order: f64,
    /// The director (unit, sign arbitrary).
    pub director: [f64; 3],
}

/// The long axes of shaped grains: in the settled bed at the opening, and as each grain
/// crossed the orifice plane (counted once, as W counts it); `None` where there were none.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OrientationSummary {
    /// The settled bed at the opening.
    pub bed: Option<AxesStatistics>,
    /// The grains crossing the orifice inside the outlet.
    pub outlet: Option<AxesStatistics>,
}

/// The grains behind coarse-grained parcels (docs/physics.md §2.8).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CoarseGrainingSummary {
    /// κ [-]: a parcel's diameter over its grains'.
    pub factor: f64,
    /// κ³ [-]: the grains a parcel stands for.
    pub grains_per_parcel: f64,
    /// The grains' number-weighted mean diameter [m].
    pub grain_diameter: f64,
    /// The grains the case gives [-]; the parcels are this over κ³, rounded.
    pub grains: usize,
    /// The outlet size over the parcels' mean diameter, D/(κd) [-].
    pub outlet_parcels: f64,
    /// The outlet size over the grains' mean diameter, D/d [-].
    pub outlet_grains: f64,
    /// The discharged mass over a grain's mean mass: the grains that left [-].
    pub discharged_grains: f64,
}

/// The statistics of the avalanches between clogs (docs/physics.md §7.14), over the
/// avalanches that a clog ended (the last one, cut by the run's stop, is left out).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AvalancheSummary {
    /// Avalanches ended by a clog [-].
    pub count: usize,
    /// Their mean size ⟨s⟩ [grains].
    #[serde(deserialize_with = "nan_if_null")]
    pub mean_size: f64,
    /// The standard error of ⟨s⟩, σ_s/√n [grains] (NaN below two avalanches).
    #[serde(deserialize_with = "nan_if_null")]
    pub mean_size_error: f64,
    /// ⟨s⟩ with the avalanches cut short before a clog (by the container draining or the
    /// time limit) counted as right-censored exponential sizes: all sizes over the clogs
    /// (docs/physics.md §7.14) [grains]; NaN without a clog, and in summaries written
    /// before it was reported.
    #[serde(default = "nan", deserialize_with = "nan_if_null")]
    pub mean_size_censored: f64,
    /// Its standard error, itself over √n [grains].
    #[serde(default = "nan", deserialize_with = "nan_if_null")]
    pub mean_size_censored_error: f64,
    /// Their mean mass [kg].
    #[serde(deserialize_with = "nan_if_null")]
    pub mean_mass: f64,
    /// Their mean duration, first grain to last [s].
    #[serde(deserialize_with = "nan_if_null")]
    pub mean_duration: f64,
    /// The mean arrest before an avalanche, last grain of the one before to its first [s]
    /// (set by `protocol.clog_timeout` and the pulse, as an experiment's wait is).
    #[serde(deserialize_with = "nan_if_null")]
    pub mean_arrest: f64,
    /// Pulses given in all [-].
    pub pulses: usize,
    /// Pulses after which no grain left before the next clog was declared [-].
    pub failed_pulses: usize,
    /// The exponential tail of the size distribution, where one was fitted.
    #[serde(default)]
    pub size_tail: Option<TailFitSummary>,
    /// The power-law tail of the time lapses between consecutive grains within the
    /// avalanches, where one was fitted.
    #[serde(default)]
    pub lapse_tail: Option<TailFitSummary>,
}

/// A maximum-likelihood fit of a distribution's tail above a threshold
/// (docs/physics.md §7.14).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TailFitSummary {
    /// The threshold the tail starts at, in the variable's unit (grains for sizes, s for
    /// lapses).
    pub threshold: f64,
    /// Samples at or above the threshold [-].
    pub samples: usize,
    /// The fitted parameter: the decay size s_c [grains] of an exponential tail
    /// exp(−s/s_c), the exponent α [-] of a power-law tail t^(−α).
    pub value: f64,
    /// Its standard error, in its unit.
    pub error: f64,
}

/// The angle of repose of a heap left by a lifted cylinder: the line h(r) = h₀ − r tan θ
/// fitted to the flank of its surface in each azimuthal sector (docs/physics.md §7.10).
/// `null` for what could not be measured (no sector with a flank to fit).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ReposeSummary {
    /// θ, the mean over the fitted sectors [°].
    #[serde(deserialize_with = "nan_if_null")]
    pub angle_deg: f64,
    /// Standard error of θ: the scatter over the sectors and the fits' own errors, in
    /// quadrature [°].
    #[serde(deserialize_with = "nan_if_null")]
    pub angle_error_deg: f64,
    /// The heap's height: its highest particle top above the plate [m].
    #[serde(deserialize_with = "nan_if_null")]
    pub height: f64,
    /// Where the fitted flanks meet the plate, averaged over the sectors whose line meets it
    /// near their grains; NaN (null) where none does (docs/physics.md §7.10) [m].
    #[serde(deserialize_with = "nan_if_null")]
    pub base_radius: f64,
    /// Azimuthal sectors fitted (of `sectors_total`).
    pub sectors: usize,
    /// Azimuthal sectors the surface was cut into.
    pub sectors_total: usize,
    /// Particles in the heap at the end (on the plate) [-].
    pub particles: usize,
}

/// The draw-down test's shelves: the lines fitted to the surface of the material left on
/// each shelf beside the slot, strip by strip across the depth (docs/physics.md §7.11).
/// `null` for what could not be measured.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DrawDownSummary {
    /// The mean over every fitted strip of both shelves [°].
    #[serde(deserialize_with = "nan_if_null")]
    pub shelf_angle_deg: f64,
    /// Its standard error: the scatter over the strips and the fits' own errors, in
    /// quadrature [°].
    #[serde(deserialize_with = "nan_if_null")]
    pub shelf_angle_error_deg: f64,
    /// The left shelf's angle (x < 0), the mean over its strips [°].
    #[serde(deserialize_with = "nan_if_null")]
    pub left_angle_deg: f64,
    /// The right shelf's angle (x > 0), the mean over its strips [°].
    #[serde(deserialize_with = "nan_if_null")]
    pub right_angle_deg: f64,
    /// Strips fitted, of both shelves.
    pub strips: usize,
    /// Mass left in the box when the flow stopped [kg].
    #[serde(deserialize_with = "nan_if_null")]
    pub residual_mass: f64,
}

/// Janssen's law p_w(h) = p_sat (1 − exp(−2Kμ_w h/R)) fitted to the settled bed's wall
/// pressure against depth h below the bed's surface (docs/physics.md §7.7), each value with
/// its standard error.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct JanssenSummary {
    /// Saturation pressure p_sat [Pa].
    pub saturation_pressure: [f64; 2],
    /// Kμ_w [-].
    pub k_mu: [f64; 2],
    /// μ_w = ρ_b g R/(2 p_sat) [-].
    pub wall_friction: [f64; 2],
    /// K = Kμ_w/μ_w [-].
    pub stress_ratio: [f64; 2],
    /// Zones of the cylinder fitted.
    pub zones: usize,
}

/// The self-similar fits v(r) = v_c (1 − r*²)^a and φ(r) = φ_c (1 − r*²)^b over a circular
/// orifice (Janda et al. 2012 in 3D, docs/physics.md §7.6), each value with its standard
/// error; `null` where the fit failed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RadialFit {
    /// Centre velocity v_c [m/s] and its error.
    pub centre_velocity: [f64; 2],
    /// Velocity exponent a [-] and its error.
    pub velocity_exponent: [f64; 2],
    /// Centre volume fraction φ_c [-] and its error.
    pub centre_volume_fraction: [f64; 2],
    /// Packing exponent b [-] and its error.
    pub packing_exponent: [f64; 2],
    /// W = π R² ρ_p φ_c v_c / (1 + a + b) from the fitted profiles [kg/s] and its error.
    pub profile_rate: [f64; 2],
}

/// One x-bin of the outlet profiles (`profiles.csv`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ProfileRow {
    /// Bin centre, normalised x* = (x − x_c)/R [-].
    pub x_star: f64,
    /// Bin centre x [m].
    pub x: f64,
    /// Mean downward velocity of crossings v(x) [m/s] (NaN if none).
    pub velocity: f64,
    /// Standard error of v [m/s].
    pub velocity_error: f64,
    /// Crossings counted in the bin.
    pub crossings: usize,
    /// Time-averaged 2D area fraction φ(x) [-].
    pub area_fraction: f64,
    /// Standard error of φ [-].
    pub area_fraction_error: f64,
    /// ⟨φ v⟩ from snapshots [m/s].
    pub area_fraction_velocity: f64,
    /// Snapshot mean downward velocity in the strip [m/s] (NaN if none).
    pub snapshot_velocity: f64,
    /// Area fraction from the number density of centres crossing the outlet line,
    /// Σ π r²/|v_z| over the bin's crossings / (window × bin width) [-] (NaN without
    /// crossings; see `measure::crossing`). A second definition of φ(x) beside the strip's.
    #[serde(default = "not_measured")]
    pub crossing_area_fraction: f64,
    /// Standard error of that fraction from time blocks [-] (NaN when unknown).
    #[serde(default = "not_measured")]
    pub crossing_area_fraction_error: f64,
}

/// NaN: the value of a column that a profiles table written before it existed lacks.
fn not_measured() -> f64 {
    f64::NAN
}

/// The coarse-grained fields of a run (`summary.json`'s `fields`, docs/physics.md §7.13).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FieldsSummary {
    /// Kernel: "lucy" or "gaussian".
    pub kernel: String,
    /// Kernel width w of `fields.vti` [m].
    pub width: f64,
    /// Grid cell side [m].
    pub cell_size: f64,
    /// Discharge frames averaged in `fields.vti`.
    pub frames: u64,
    /// The mass the field of the bed at rest holds, Σ ρ ΔV over the grid [kg] (`null` when
    /// no settled frame was taken).
    pub settled_field_mass: Option<f64>,
    /// The particles' mass when the gate opened [kg].
    pub settled_particle_mass: Option<f64>,
    /// The check of the width (`field_widths.csv`): one row per pair of consecutive widths;
    /// empty where no `widths` were given.
    pub widths: Vec<WidthChange>,
    /// The width at which the fields depend least on it [m], where the largest relative
    /// change of ρ and p to the next width is at most 5 %; `null` otherwise.
    pub plateau_width: Option<f64>,
    /// That smallest largest change [-]; `null` without widths.
    pub least_change: Option<f64>,
}

/// How the fields change from one kernel width to the next.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WidthChange {
    /// The width [m].
    pub width: f64,
    /// The next width [m].
    pub next_width: f64,
    /// Relative L2 change of the density [-].
    pub density_change: f64,
    /// Relative L2 change of the pressure [-].
    pub pressure_change: f64,
    /// Relative L2 change of the velocity [-].
    pub velocity_change: f64,
}
