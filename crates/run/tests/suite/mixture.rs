//! Mixtures: the fill's draws realise the case's fractions, and a run of a mixture writes the
//! outflow composition over time (`composition.csv`, cases/README.md).
//!
//! The runs are small (300 spheres in a silo 32 mm wide), a few seconds each in the test
//! profile's optimised build.

use std::path::Path;

use case::{load_case, Case, Geometry};
use dem::{DVec3, MaterialId};
use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;
use run::insert_silo_batch;
use run::{case_simulation_by_component, ParticleDraws};
use run::{run_case, RunOptions, RunOutcome};

/// The preset `cases/mixture-1to2.toml` (2 mm and 4 mm spheres, 50/50 by mass) with `sets`.
fn preset(sets: &[&str]) -> Case {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases/mixture-1to2.toml");
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    load_case(&path, &sets).unwrap_or_else(|e| panic!("the preset is valid: {e}"))
}

/// The preset shrunk to a quick run: 300 spheres in a silo of R = 16 mm over a 45° cone to
/// a 16 mm orifice (4 large, 8 small diameters: wide enough that arches are rare), 50 mm
/// tall, so the fill needs no second batch and the silo empties in a few tenths of a second.
const SMALL_RUN: &[&str] = &[
    "particles.count=300",
    "geometry.radius=0.016",
    "geometry.height=0.05",
    "geometry.outlet_diameter=0.016",
    "time.time_step=2.5e-6",
    "protocol.settle_kinetic_energy=1e-8",
    "protocol.max_settle_time=0.15",
    "protocol.clog_timeout=0.1",
    "protocol.time_limit=0.5",
    "output.plots=false",
    "output.checkpoint_interval=0.0",
];

/// The header and rows of a CSV file of numbers (text cells as NaN).
fn read_csv(dir: &Path, name: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
    let mut lines = text.lines();
    let header = lines
        .next()
        .expect("a header")
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| {
            l.split(',')
                .map(|c| c.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    (header, rows)
}

fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"))
}

#[test]
fn draws_pick_each_component_by_its_number_fraction() {
    let case = preset(&[]);
    let n = case.particles.number_fractions();
    assert!((n[1] - 1.0 / 9.0).abs() < 1e-15, "{n:?}");
    let draws = ParticleDraws::new(&case.particles, &[MaterialId(0), MaterialId(1)]);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    let draws_made = 100_000;
    let mut large = 0u64;
    for _ in 0..draws_made {
        let d = draws.draw(&mut rng);
        assert_eq!(d.material, MaterialId(d.component as u16));
        assert_eq!(d.radius, [0.001, 0.002][d.component as usize]);
        large += u64::from(d.component == 1);
    }
    // Each draw is a Bernoulli trial of p = 1/9: the count is binomial, σ = √(N p (1 − p))
    // = 99 of 11 111. Four σ: the seed is fixed, and a sampler off by 0.4 % of p fails.
    let expected = draws_made as f64 / 9.0;
    let sigma = (draws_made as f64 * (1.0 / 9.0) * (8.0 / 9.0)).sqrt();
    assert!(
        (large as f64 - expected).abs() < 4.0 * sigma,
        "{large} large draws of {draws_made}, expected {expected} ± {sigma}"
    );
}

#[test]
fn a_silo_fill_realises_the_mixtures_fractions_within_binomial_error() {
    // The preset's 20 000 spheres inserted at once into its silo: a random sequential
    // addition to 16 % solid volume, where a 4 mm sphere misses a free spot far more often
    // than a 2 mm one. Redrawing after each miss places fewer than 40 % of the large ones
    // the fractions ask for (856 of 2222 with this seed); the fill keeps each draw until it
    // is placed, so the placed particles are the first draws in order, and their component
    // counts are binomial about the fractions.
    let case = preset(&[]);
    let Geometry::Cylinder(silo) = &case.geometry else {
        panic!("the preset is a silo")
    };
    let (mut sim, _walls, materials) = case_simulation_by_component(&case, 1).unwrap();
    let draws = ParticleDraws::new(&case.particles, &materials);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(case.seed);
    let mut pending = None;
    let want = case.particles.count;
    let placed = insert_silo_batch(
        &mut sim,
        silo,
        &mut rng,
        want,
        &draws,
        &mut pending,
        (0.0, 0.2),
        DVec3::ZERO,
        20 * want + 1000,
    )
    .unwrap();
    let n = placed.len();
    assert_eq!(n, want, "every particle placed");
    let large = placed.iter().filter(|(_, c)| *c == 1).count() as f64;
    // Binomial: σ = √(n p (1 − p)) with p = 1/9, about 44 for n = 20 000. Three σ: the seed
    // is fixed, so this is one deterministic sample; 3σ is what a correct sampler passes
    // for 99.7 % of seeds, and a bias of 6 % of the large ones fails.
    let p = 1.0 / 9.0;
    let sigma = (n as f64 * p * (1.0 - p)).sqrt();
    assert!(
        (large - n as f64 * p).abs() < 3.0 * sigma,
        "{large} large of {n} placed, expected {} ± {sigma}",
        n as f64 * p
    );
    // The placed particles' masses: half of the fill's in the large ones, within the
    // binomial error of the count (a large sphere weighs 8 small ones).
    let masses = sim.particles().masses();
    let radii = sim.particles().radii();
    let large_mass: f64 = (0..masses.len())
        .filter(|&k| radii[k] > 0.0015)
        .map(|k| masses[k])
        .sum();
    let share = large_mass / masses.iter().sum::<f64>();
    // w = 8L/(8L + S): dw/dL = 8S/(8L + S)², with S = n − L.
    let (l, s) = (large, n as f64 - large);
    let share_sigma = 8.0 * s / (8.0 * l + s).powi(2) * sigma;
    assert!(
        (share - 0.5).abs() < 3.0 * share_sigma,
        "large mass share {share}, expected 0.5 ± {share_sigma}"
    );
}

#[test]
fn a_mixture_run_writes_the_outflow_composition_over_time() {
    let case = preset(SMALL_RUN);
    let dir = tempfile::tempdir().expect("temporary directory");
    let options = RunOptions {
        resume: false,
        ..RunOptions::default()
    };
    let outcome = run_case(&case, dir.path(), &options).expect("the mixture runs");
    let RunOutcome::Finished(summary) = outcome else {
        panic!("the run finished")
    };
    let (header, rows) = read_csv(dir.path(), "composition.csv");
    assert_eq!(
        header,
        [
            "time_s",
            "mass_kg",
            "count",
            "small_mass_kg",
            "small_count",
            "small_mass_fraction",
            "large_mass_kg",
            "large_count",
            "large_mass_fraction",
        ]
    );
    let (flow_header, flow) = read_csv(dir.path(), "flow.csv");
    assert_eq!(rows.len(), flow.len(), "the bins of flow.csv");
    let width = case.measure.rate_bin_width;
    let (rate, time) = (column(&flow_header, "rate"), column(&flow_header, "time"));
    let mut both = 0;
    let (mut total_mass, mut total_count) = (0.0, 0.0);
    for (row, f) in rows.iter().zip(&flow) {
        assert_eq!(row[0], f[time], "bin centres");
        // The bin's mass is the sum flow.csv divides by the bin width.
        assert!(
            (row[1] - f[rate] * width).abs() <= 1e-12 * row[1],
            "{row:?} against {f:?}"
        );
        // The components add up to the bin's mass and number (rounding of the sums only).
        assert!(
            (row[3] + row[6] - row[1]).abs() <= 1e-12 * row[1],
            "{row:?}"
        );
        assert_eq!(row[4] + row[7], row[2], "{row:?}");
        if row[1] > 0.0 {
            for fraction in [row[5], row[8]] {
                assert!((0.0..=1.0).contains(&fraction), "{row:?}");
            }
            assert!((row[5] + row[8] - 1.0).abs() < 1e-12, "{row:?}");
            both += usize::from(row[4] > 0.0 && row[7] > 0.0);
        } else {
            assert!(row[5].is_nan() && row[8].is_nan(), "{row:?}");
        }
        // Each component's mass is its count times its particles' mass (one size each).
        let small = 2500.0 * std::f64::consts::PI / 6.0 * 0.002f64.powi(3);
        assert!(
            (row[3] - row[4] * small).abs() <= 1e-9 * small.max(row[3]),
            "{row:?}"
        );
        assert!(
            (row[6] - row[7] * 8.0 * small).abs() <= 1e-9 * small.max(row[6]),
            "{row:?}"
        );
        total_mass += row[1];
        total_count += row[2];
    }
    assert!(both >= 3, "only {both} bins saw both sizes leave");
    // The bins hold what crossed the outlet, which is most of the fill.
    assert!(total_count > 0.8 * 300.0, "{total_count} crossings binned");
    assert!(
        (total_mass - summary.discharged_mass).abs() < 0.2 * summary.discharged_mass,
        "{total_mass} kg binned, {} kg discharged",
        summary.discharged_mass
    );
    // crossings.csv names each crossing's component.
    let text = std::fs::read_to_string(dir.path().join("crossings.csv")).unwrap();
    assert!(text.lines().next().unwrap().ends_with(",y_m,component"));
    let large = text.lines().filter(|l| l.ends_with(",large")).count();
    let small = text.lines().filter(|l| l.ends_with(",small")).count();
    assert_eq!(
        (small + large) as f64,
        total_count + (text.lines().count() - 1 - (small + large)) as f64,
        "every crossing has its component"
    );
}

#[test]
fn one_component_runs_write_no_composition() {
    // The tiny silo of one size: no composition.csv, and crossings.csv keeps its columns.
    let case = preset(&[
        "particles.components=[{diameter=0.004, fraction=1.0}]",
        "particles.count=100",
        "geometry.radius=0.016",
        "geometry.height=0.05",
        "geometry.outlet_diameter=0.016",
        "time.time_step=2.5e-6",
        "protocol.settle_kinetic_energy=1e-8",
        "protocol.max_settle_time=0.1",
        "protocol.clog_timeout=0.05",
        "protocol.time_limit=0.2",
        "output.plots=false",
        "output.checkpoint_interval=0.0",
    ]);
    assert!(!case.particles.is_mixture());
    let dir = tempfile::tempdir().expect("temporary directory");
    let options = RunOptions {
        resume: false,
        ..RunOptions::default()
    };
    run_case(&case, dir.path(), &options).expect("the silo runs");
    assert!(!dir.path().join("composition.csv").exists());
    let text = std::fs::read_to_string(dir.path().join("crossings.csv")).unwrap();
    assert!(text.lines().next().unwrap().ends_with(",id,y_m"));
}

/// Two materials of the benchmark's table (docs/physics.md §1.2): 2 mm spheres of M1 and
/// 4 mm spheres of M2, half the mass each, in the small silo of [`SMALL_RUN`] with steel walls.
fn two_material_case() -> Case {
    let text = r#"
version = 1
seed = 3

[geometry]
kind = "cylinder"
radius = 0.016
height = 0.05
outlet_diameter = 0.016
hopper_angle_deg = 45.0

[materials.M1]
density = 2500.0
youngs_modulus = 1.0e9
poisson_ratio = 0.2

[materials.M2]
density = 2000.0
youngs_modulus = 0.5e9
poisson_ratio = 0.2

[materials.steel]
density = 7200.0
youngs_modulus = 210.0e9
poisson_ratio = 0.2

[[pairs]]
materials = ["M1", "M1"]
restitution = 0.5
friction = 0.3

[[pairs]]
materials = ["M1", "M2"]
restitution = 0.45
friction = 0.2

[[pairs]]
materials = ["M2", "M2"]
restitution = 0.4
friction = 0.4

[[pairs]]
materials = ["M1", "steel"]
restitution = 0.4
friction = 0.2

[[pairs]]
materials = ["M2", "steel"]
restitution = 0.4
friction = 0.2

[particles]
count = 300
fraction_by = "mass"

[[particles.components]]
name = "small"
diameter = 0.002
material = "M1"
fraction = 0.5

[[particles.components]]
name = "large"
diameter = 0.004
material = "M2"
fraction = 0.5

[wall]
material = "steel"

[time]
time_step = 1.5e-6

[protocol]
settle_kinetic_energy = 1e-8
max_settle_time = 0.15
clog_timeout = 0.1
time_limit = 0.5

[output]
plots = false
checkpoint_interval = 0.0
"#;
    case::parse_case(text, "two-materials.toml", &[]).expect("a valid case")
}

#[test]
fn a_two_material_mixture_weighs_each_crossing_by_its_material_and_resumes_to_the_same_bits() {
    let case = two_material_case();
    // By mass with ρ 2500 and 2000 kg/m³: n_large = (0.5/(2000·8))/(0.5/2500 + 0.5/16000).
    let n = case.particles.number_fractions();
    assert!((n[1] - (1.0 / 16_000.0) / (1.0 / 2500.0 + 1.0 / 16_000.0)).abs() < 1e-15);
    let whole = tempfile::tempdir().expect("temporary directory");
    let fresh = RunOptions {
        resume: false,
        ..RunOptions::default()
    };
    run_case(&case, whole.path(), &fresh).expect("the mixture runs");
    let (header, rows) = read_csv(whole.path(), "composition.csv");
    let (small_mass, small_count) = (
        column(&header, "small_mass_kg"),
        column(&header, "small_count"),
    );
    let (large_mass, large_count) = (
        column(&header, "large_mass_kg"),
        column(&header, "large_count"),
    );
    let volume = |d: f64| std::f64::consts::PI / 6.0 * d * d * d;
    let (m1, m2) = (2500.0 * volume(0.002), 2000.0 * volume(0.004));
    let mut large = 0.0;
    for row in &rows {
        assert!(
            (row[small_mass] - row[small_count] * m1).abs() <= 1e-9 * m1,
            "{row:?}"
        );
        assert!(
            (row[large_mass] - row[large_count] * m2).abs() <= 1e-9 * m2,
            "{row:?}"
        );
        large += row[large_count];
    }
    assert!(large >= 10.0, "{large} large crossings");

    // Stopped in the fill and again in the discharge (chunks of 2.5 ms), then resumed: the
    // same files.
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(whole.path().join("summary.json")).unwrap()).unwrap();
    let opened = summary["fill_time"].as_f64().unwrap();
    let (first, second) = (10, 120);
    assert!(
        (first as f64) * 0.0025 < opened && ((first + second) as f64) * 0.0025 > opened + 0.02,
        "the gate opened at {opened} s"
    );
    let parts = tempfile::tempdir().expect("temporary directory");
    for limit in [Some(first), Some(second), None] {
        let options = RunOptions {
            resume: true,
            chunk_limit: limit,
            ..RunOptions::default()
        };
        let outcome = run_case(&case, parts.path(), &options).expect("the part runs");
        assert_eq!(
            matches!(outcome, RunOutcome::Finished(_)),
            limit.is_none(),
            "{limit:?}"
        );
    }
    for name in [
        "composition.csv",
        "crossings.csv",
        "flow.csv",
        "summary.json",
    ] {
        assert!(
            std::fs::read(whole.path().join(name)).unwrap()
                == std::fs::read(parts.path().join(name)).unwrap(),
            "{name} differs after resuming"
        );
    }
}
