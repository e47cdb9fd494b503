//! A stand-in for the simulation: writes the files of a case run from known laws, so the
//! study runner and the report can be tested against parameters chosen in advance.
//!
//! Known laws of slab cases (paper values, so the report's comparison items should pass):
//! W = Z C ρ_b √g (D − k d)^{3/2} × Brown(α) × (1.3 at s = 0, else 1) with C = 0.58,
//! k = 1.55; v = v_c (1 − x*²)^a with v_c = √(2γgR); φ = φ_c (1 − x*²)^b with
//! φ_c = φ∞ (1 − τ₁ e^{−2τ₂R}), R in mm (Eq. 12); eccentric outlets follow Eqs. 16–17
//! with σ_s1 = 0.39 − 0.12 e^{−3.74 s*}.
//!
//! Known laws of cylinder cases (circular orifice of diameter D, inside the classic ranges
//! for spheres): W = C ρ_b √g (D − k d)^{5/2} with C = 0.58, k = 1.4, ρ_b = φ_B ρ_p and
//! seeded noise on W; radial profiles v(r) = v_c (1 − r*²)^a and φ(r) = φ_c (1 − r*²)^b
//! whose rate π R² ρ_p φ_c v_c/(1 + a + b) is the law's W. A silo case writes what a real
//! silo run writes for the report: `case.toml`, `flow.csv`, the radial `profiles.csv` and a
//! summary with `radial_fit`, the last two through the run's own writer and fit.

#![allow(dead_code)]

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use analysis::beverloo3d::beverloo_3d_rate;
use analysis::flowrate::brown_ratio;
use case::{CylinderGeometry, SweepCase};
use files::CASE_FILE;
use files::{write_csv_table, Cell};
use files::{CaseSummary, StopReason};
use measure::{RadialBin, RadialBins};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use run::{fit_radial, write_radial_profiles};
use study::CaseRunner;

/// Gravitational acceleration used by the fake [m/s²] (the analysis uses the same).
pub const GRAVITY: f64 = 9.81;
/// Beverloo constants of the fake.
pub const BEVERLOO_C: f64 = 0.58;
pub const BEVERLOO_K: f64 = 1.55;
/// Bulk volume fraction of every fake fill.
pub const BULK_FRACTION: f64 = 0.59;
/// W(s = 0)/W0 of the fake.
pub const WALL_OUTLET_GAIN: f64 = 1.3;
/// Eq. 12 constants of the fake (τ₂ per mm).
pub const PHI_INFINITY: f64 = 0.78;
pub const TAU1: f64 = 3.0;
pub const TAU2: f64 = 0.18;
/// Eq. 16–17 constants of the fake.
pub const EPSILON_S1: f64 = 1.3;
pub const SIGMA_S2: f64 = 0.42;

/// 3D Beverloo constants of the fake's cylinder cases.
pub const SILO_BEVERLOO_C: f64 = 0.58;
pub const SILO_BEVERLOO_K: f64 = 1.4;
/// Exponents a, b and centre volume fraction φ_c of the fake's radial profiles (near the
/// measured a ≈ 0.55, b ≈ 0.38 of docs/reproduction.md's 3D Beverloo study).
pub const SILO_VELOCITY_EXPONENT: f64 = 0.55;
pub const SILO_PACKING_EXPONENT: f64 = 0.38;
pub const SILO_CENTRE_FRACTION: f64 = 0.45;
/// Relative noise on a silo case's W (uniform in ±0.5 %, seeded by the case's seed): the fit
/// sees scatter, as it does in a real study, but less than a real run's blocking error
/// (1–5 % in docs/reproduction.md's 3D Beverloo study), so that C and k come back within
/// tight tolerances.
pub const SILO_RATE_NOISE: f64 = 0.005;

/// Table 2 of the paper: (α, a, γ, b).
pub const TABLE2: [(f64, f64, f64, f64); 5] = [
    (15.0, 0.20, 2.81, 0.16),
    (30.0, 0.32, 2.08, 0.19),
    (55.0, 0.35, 1.61, 0.30),
    (75.0, 0.33, 1.64, 0.38),
    (90.0, 0.39, 1.66, 0.39),
];

/// σ_s1(s*) of the fake (paper Fig. 11b).
pub fn sigma_s1(s_star: f64) -> f64 {
    0.39 - 0.12 * (-3.74 * s_star).exp()
}

/// δ_s1(s*) of the fake: −0.31 at the wall, vanishing towards the centre.
pub fn delta_s1(s_star: f64) -> f64 {
    -0.31 * (-4.0 * s_star).exp()
}

/// A fake simulation that counts its calls and can fail, panic or clog on chosen cases.
#[derive(Default)]
pub struct FakeRunner {
    /// Calls so far.
    pub calls: AtomicUsize,
    /// Identifiers run, in call order.
    pub ran: Mutex<Vec<String>>,
    /// Cases whose run returns an error.
    pub fail: Vec<String>,
    /// Cases whose run panics.
    pub panic: Vec<String>,
    /// Cases that clog.
    pub clog: Vec<String>,
    /// After this many calls every further call fails (a study killed part-way).
    pub stop_after: Option<usize>,
    /// Replace γ(90°) by this value (to make a comparison item fail).
    pub gamma_90: Option<f64>,
    /// Relative noise on the profile bins.
    pub noise: f64,
    /// Sleep per case [ms], to let parallel cases overlap.
    pub sleep_ms: u64,
    /// Cases running right now, and the most seen at once.
    pub active: AtomicUsize,
    pub max_active: AtomicUsize,
    /// When set, profiles.csv also holds the crossing number-density columns, following
    /// φ_c (1 − x*²)^b with b given by this function of α [°] (centred outlets only).
    pub crossing_exponent: Option<fn(f64) -> f64>,
    /// When set, the Beverloo k of each hopper angle α [°] (default [`BEVERLOO_K`] at all).
    pub beverloo_k: Option<fn(f64) -> f64>,
    /// The 3D Beverloo (C, k) of cylinder cases (default [`SILO_BEVERLOO_C`],
    /// [`SILO_BEVERLOO_K`]).
    pub silo_beverloo: Option<(f64, f64)>,
    /// Relative noise on a cylinder case's W (see [`SILO_RATE_NOISE`]).
    pub silo_rate_noise: f64,
    /// The rate of a cylinder case's radial profiles over its W (default 1: the profiles
    /// carry the measured rate).
    pub silo_profile_rate: Option<f64>,
    /// Cases whose run measured no settled bulk fraction (φ_B NaN, as when the bed's
    /// surface could not be found).
    pub no_bulk: Vec<String>,
}

impl FakeRunner {
    pub fn new() -> Self {
        Self {
            noise: 0.002,
            silo_rate_noise: SILO_RATE_NOISE,
            ..Self::default()
        }
    }

    fn laws(&self, alpha: f64) -> (f64, f64, f64) {
        let row = TABLE2
            .iter()
            .min_by(|p, q| (p.0 - alpha).abs().total_cmp(&(q.0 - alpha).abs()))
            .copied()
            .unwrap_or(TABLE2[4]);
        let gamma = match self.gamma_90 {
            Some(g) if alpha == 90.0 => g,
            _ => row.2,
        };
        (row.1, gamma, row.3)
    }
}

impl CaseRunner for FakeRunner {
    fn run(&self, case: &SweepCase, dir: &Path) -> Result<CaseSummary, String> {
        let call = self.calls.fetch_add(1, Ordering::SeqCst);
        if let Some(limit) = self.stop_after {
            if call >= limit {
                return Err("killed".to_string());
            }
        }
        let now = self.active.fetch_add(1, Ordering::SeqCst) + 1;
        self.max_active.fetch_max(now, Ordering::SeqCst);
        std::thread::sleep(std::time::Duration::from_millis(self.sleep_ms));
        self.active.fetch_sub(1, Ordering::SeqCst);
        self.ran.lock().unwrap().push(case.id.clone());
        if self.panic.contains(&case.id) {
            panic!("fake panic in {}", case.id);
        }
        if self.fail.contains(&case.id) {
            return Err(format!("fake failure in {}", case.id));
        }
        // The resolved case, as a real run writes it first: the report reads the geometry
        // kind and g from it.
        std::fs::write(dir.join(CASE_FILE), case.case.to_toml_string()).unwrap();
        Ok(match case.case.geometry.cylinder() {
            Some(silo) => write_silo_case(self, case, silo, dir),
            None => write_slab_case(self, case, dir),
        })
    }
}

/// The summary fields every fake run fills alike, after writing its `flow.csv` at steady rate
/// `rate` [kg/s] (a rise over 0.05 s, halved after 0.8 s as the container empties): the
/// case's inputs, W ± `rate_error` [kg/s], the discharged mass, and `stop` unless the case
/// clogs. What belongs to one geometry (the slab's width, thickness and gap, the strip's
/// centre values, the radial fit) is NaN or absent, as in a silo's summary.
fn common_summary(
    fake: &FakeRunner,
    case: &SweepCase,
    dir: &Path,
    rate: f64,
    rate_error: f64,
    stop: StopReason,
) -> CaseSummary {
    let times: Vec<f64> = (0..50).map(|i| 0.02 * i as f64).collect();
    let rates: Vec<f64> = times
        .iter()
        .map(|t| rate * (1.0 - (-t / 0.05).exp()) * if *t > 0.8 { 0.5 } else { 1.0 })
        .collect();
    let mut mass = 0.0;
    let flow: Vec<Vec<Cell>> = times
        .iter()
        .zip(&rates)
        .map(|(t, w)| {
            mass += w * 0.02;
            vec![Cell::Number(*t), Cell::Number(*w), Cell::Number(mass)]
        })
        .collect();
    write_csv_table(
        dir.join("flow.csv"),
        &["time", "rate", "cumulative_mass"],
        &flow,
    )
    .unwrap();
    let clogged = fake.clog.contains(&case.id);
    let geometry = &case.case.geometry;
    CaseSummary {
        version: "test".into(),
        seed: case.case.seed,
        config_hash: run::config_hash(&case.case.to_toml_string()),
        outlet_width: geometry.outlet_size(),
        hopper_angle_deg: geometry.hopper_angle_deg(),
        outlet_gap: f64::NAN,
        dimensionless_gap: f64::NAN,
        width: f64::NAN,
        thickness: f64::NAN,
        particle_diameter: case.case.particles.mean_diameter(),
        particle_density: case.case.particles.density(),
        particles: case.case.particles.count,
        discharge_rate: rate,
        discharge_rate_error: rate_error,
        steady_window: [0.1, 0.7],
        plateau_found: true,
        flux_check_rate: f64::NAN,
        flux_check_rate_profiles: f64::NAN,
        bulk_volume_fraction: BULK_FRACTION,
        bulk_area_fraction: f64::NAN,
        bed_height: f64::NAN,
        centre_velocity: f64::NAN,
        centre_area_fraction: f64::NAN,
        max_area_fraction: f64::NAN,
        max_area_fraction_position: f64::NAN,
        clogged,
        stop_reason: if clogged { StopReason::Clogged } else { stop },
        discharged_mass: mass,
        discharge_time: 1.0,
        fill_time: 0.5,
        settled_kinetic_energy: 1e-9,
        settled: true,
        area_fraction_exponent: None,
        crossing_area_fraction_exponent: None,
        radial_fit: None,
        janssen: None,
        janssen_not_fitted: None,
        start: None,
        arch: None,
        repose: None,
        draw_down: None,
        fields: None,
        avalanches: None,
        coarse_graining: None,
        orientation: None,
        residence: None,
    }
}

/// A cylinder case: W from the 3D Beverloo law with noise, radial profiles whose rate is
/// the law's W (times `silo_profile_rate`) with their fit, and the settled bed's φ_B.
fn write_silo_case(
    fake: &FakeRunner,
    case: &SweepCase,
    silo: &CylinderGeometry,
    dir: &Path,
) -> CaseSummary {
    let d = case.case.particles.mean_diameter();
    let rho = case.case.particles.density();
    let gravity = case.case.gravity;
    let (c, k) = fake
        .silo_beverloo
        .unwrap_or((SILO_BEVERLOO_C, SILO_BEVERLOO_K));
    let law = beverloo_3d_rate(c, BULK_FRACTION * rho, silo.outlet_diameter, k, d, gravity);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(case.case.seed);
    let mut uniform = || rng.gen::<f64>() * 2.0 - 1.0;
    let rate = law * (1.0 + fake.silo_rate_noise * uniform());
    // v_c such that π R² ρ_p φ_c v_c/(1 + a + b) is the law's W (times the chosen factor).
    let (a, b, phi_c) = (
        SILO_VELOCITY_EXPONENT,
        SILO_PACKING_EXPONENT,
        SILO_CENTRE_FRACTION,
    );
    let radius = 0.5 * silo.outlet_diameter;
    let profile_rate = law * fake.silo_profile_rate.unwrap_or(1.0);
    let v_c = profile_rate * (1.0 + a + b) / (std::f64::consts::PI * radius * radius * rho * phi_c);
    let bins = RadialBins::with_width(
        [silo.outlet_offset, 0.0],
        radius,
        case.case.measure.x_bin_width,
    )
    .unwrap();
    let annuli: Vec<RadialBin> = (0..bins.count)
        .map(|i| {
            let r = bins.mean_radius(i);
            let base = 1.0 - (r / radius).powi(2);
            let velocity = v_c * base.powf(a) * (1.0 + fake.noise * uniform());
            let volume_fraction = phi_c * base.powf(b) * (1.0 + fake.noise * uniform());
            RadialBin {
                r_star: r / radius,
                r,
                velocity,
                velocity_error: 0.01 * velocity,
                crossings: 200,
                volume_fraction,
                volume_fraction_error: 0.01 * volume_fraction,
            }
        })
        .collect();
    write_radial_profiles(&dir.join("profiles.csv"), &annuli).unwrap();
    CaseSummary {
        bulk_volume_fraction: if fake.no_bulk.contains(&case.id) {
            f64::NAN
        } else {
            BULK_FRACTION
        },
        bed_height: 2.0 * silo.radius,
        radial_fit: fit_radial(&annuli, radius, rho),
        janssen_not_fitted: Some("the fake records no wall pressure".into()),
        // The standard deviation of the uniform noise, as the run's blocking error.
        ..common_summary(
            fake,
            case,
            dir,
            rate,
            fake.silo_rate_noise / 3f64.sqrt() * rate,
            StopReason::Fraction,
        )
    }
}

fn write_slab_case(fake: &FakeRunner, case: &SweepCase, dir: &Path) -> CaseSummary {
    let g = case.case.geometry.slab().expect("a slab case");
    let d = case.case.particles.mean_diameter();
    let rho = case.case.particles.density();
    let radius = 0.5 * g.outlet_width;
    let s_star = g.dimensionless_gap();
    let eccentric = (s_star - 1.0).abs() > 1e-9;
    let alpha = g.hopper_angle_deg;
    let (a, gamma, b) = fake.laws(alpha);
    let brown = brown_ratio(alpha.to_radians()).unwrap();
    let gain = if eccentric && g.outlet_gap == 0.0 {
        WALL_OUTLET_GAIN
    } else {
        1.0
    };
    let rate = g.thickness
        * BEVERLOO_C
        * BULK_FRACTION
        * rho
        * GRAVITY.sqrt()
        * (g.outlet_width - fake.beverloo_k.map_or(BEVERLOO_K, |k| k(alpha)) * d).powf(1.5)
        * brown
        * gain;
    let phi_c = PHI_INFINITY * (1.0 - TAU1 * (-2.0 * TAU2 * radius * 1000.0).exp());
    let free_fall = (2.0 * GRAVITY * radius).sqrt();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(case.case.seed);
    let mut noisy = |value: f64| value * (1.0 + fake.noise * (rng.gen::<f64>() * 2.0 - 1.0));
    let mut rows = Vec::new();
    let (mut v_centre, mut phi_centre, mut phi_max, mut phi_max_at) = (0.0, 0.0, 0.0, 0.0);
    for i in 0..20 {
        let x_star = -0.95 + 0.1 * i as f64;
        let base = 1.0 - x_star * x_star;
        let (v, phi) = if eccentric {
            (
                free_fall * (delta_s1(s_star) * x_star + EPSILON_S1 * base.powf(sigma_s1(s_star))),
                phi_c * (-0.1 * (-4.0 * s_star).exp() * x_star + base.powf(SIGMA_S2)),
            )
        } else {
            (
                (2.0 * gamma * GRAVITY * radius).sqrt() * base.powf(a),
                phi_c * base.powf(b),
            )
        };
        let (v, phi) = (noisy(v), noisy(phi));
        if x_star.abs() < 0.1 {
            v_centre += 0.5 * v;
            phi_centre += 0.5 * phi;
        }
        if phi > phi_max {
            phi_max = phi;
            phi_max_at = x_star;
        }
        let crossing = fake
            .crossing_exponent
            .map(|b_of| noisy(phi_c * base.powf(b_of(alpha))));
        let mut row = vec![
            Cell::Number(x_star),
            Cell::Number(g.outlet_centre() + x_star * radius),
            Cell::Number(v),
            Cell::Number(0.01 * v),
            Cell::Number(200.0),
            Cell::Number(phi),
            Cell::Number(0.01 * phi),
            Cell::Number(phi * v),
            Cell::Number(v),
        ];
        if let Some(c) = crossing {
            row.extend([Cell::Number(c), Cell::Number(0.01 * c)]);
        }
        rows.push(row);
    }
    write_csv_table(
        dir.join("profiles.csv"),
        &[
            "x_star",
            "x",
            "velocity",
            "velocity_error",
            "crossings",
            "area_fraction",
            "area_fraction_error",
            "area_fraction_velocity",
            "snapshot_velocity",
            "crossing_area_fraction",
            "crossing_area_fraction_error",
        ][..if fake.crossing_exponent.is_some() {
            11
        } else {
            9
        }],
        &rows,
    )
    .unwrap();
    CaseSummary {
        outlet_gap: g.outlet_gap,
        dimensionless_gap: s_star,
        width: g.width,
        thickness: g.thickness,
        flux_check_rate: 1.01 * rate,
        flux_check_rate_profiles: 0.99 * rate,
        bulk_area_fraction: 0.885,
        bed_height: 0.24,
        centre_velocity: v_centre,
        centre_area_fraction: phi_centre,
        max_area_fraction: phi_max,
        max_area_fraction_position: phi_max_at,
        area_fraction_exponent: (!eccentric).then_some(b),
        ..common_summary(fake, case, dir, rate, 0.01 * rate, StopReason::Empty)
    }
}
