//! A stand-in for the simulation: writes the files of a case run from known laws, so the
//! study runner and the report can be tested against parameters chosen in advance.
//!
//! Known laws (paper values, so the report's comparison items should pass):
//! W = Z C ρ_b √g (D − k d)^{3/2} × Brown(α) × (1.3 at s = 0, else 1) with C = 0.58,
//! k = 1.55; v = v_c (1 − x*²)^a with v_c = √(2γgR); φ = φ_c (1 − x*²)^b with
//! φ_c = φ∞ (1 − τ₁ e^{−2τ₂R}), R in mm (Eq. 12); eccentric outlets follow Eqs. 16–17
//! with σ_s1 = 0.39 − 0.12 e^{−3.74 s*}.

#![allow(dead_code)]

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use analysis::flowrate::brown_ratio;
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use study::config::SweepCase;
use study::output::{write_csv_table, Cell};
use study::summary::{CaseSummary, StopReason};
use study::sweep::CaseRunner;

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
}

impl FakeRunner {
    pub fn new() -> Self {
        Self {
            noise: 0.002,
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
        Ok(write_case(self, case, dir))
    }
}

fn write_case(fake: &FakeRunner, case: &SweepCase, dir: &Path) -> CaseSummary {
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
    CaseSummary {
        version: "test".into(),
        seed: case.case.seed,
        config_hash: study::run::config_hash(&case.case.to_toml_string()),
        outlet_width: g.outlet_width,
        hopper_angle_deg: alpha,
        outlet_gap: g.outlet_gap,
        dimensionless_gap: s_star,
        width: g.width,
        thickness: g.thickness,
        particle_diameter: d,
        particle_density: rho,
        particles: case.case.particles.count,
        discharge_rate: rate,
        discharge_rate_error: 0.01 * rate,
        steady_window: [0.1, 0.7],
        plateau_found: true,
        flux_check_rate: 1.01 * rate,
        flux_check_rate_profiles: 0.99 * rate,
        bulk_volume_fraction: BULK_FRACTION,
        bulk_area_fraction: 0.885,
        bed_height: 0.24,
        centre_velocity: v_centre,
        centre_area_fraction: phi_centre,
        max_area_fraction: phi_max,
        max_area_fraction_position: phi_max_at,
        clogged,
        stop_reason: if clogged {
            StopReason::Clogged
        } else {
            StopReason::Empty
        },
        discharged_mass: mass,
        discharge_time: 1.0,
        fill_time: 0.5,
        settled_kinetic_energy: 1e-9,
        settled: true,
        area_fraction_exponent: (!eccentric).then_some(b),
        crossing_area_fraction_exponent: None,
        radial_fit: None,
        janssen: None,
        janssen_not_fitted: None,
        start: None,
    }
}
