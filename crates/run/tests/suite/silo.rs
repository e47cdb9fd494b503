//! Runs of small cylindrical silos: the protocol works for the circular orifice, and what
//! it writes obeys the invariants of a discharge (docs/physics.md §5.6, §7.6).

use crate::run_dir::{self, table};
use std::path::Path;

use case::{parse_case, Case};
use files::{CaseSummary, StopReason};

/// A silo of 40 mm radius holding 400 spheres of 4 mm (the paper's soft material, so that
/// Δt = 5 µs is 0.15 Rayleigh times), a 20 mm orifice (5 d: at 4 d arches stop the flow
/// within a few hundred grains), filled from 60 mm up.
fn silo(extra: &str) -> Case {
    let extra = if extra.contains("outlet_diameter") {
        extra.to_string()
    } else {
        format!("outlet_diameter = 0.02\n{extra}")
    };
    let text = format!(
        "version = 1\nseed = 3\n[geometry]\nkind = \"cylinder\"\nradius = 0.04\nheight = 0.1\n\
         {extra}\n[particles]\ncount = 400\ndiameter = 0.004\n\
         [time]\ntime_step = 5.0e-6\n[protocol]\nfill_top = 0.06\ntime_limit = 1.5\n\
         settle_kinetic_energy = 1.0e-8\n[measure]\nrate_bin_width = 0.02\n\
         [output]\ncheckpoint_interval = 0.0\nvtu_interval = 0.0\n"
    );
    parse_case(&text, "silo.toml", &[]).expect("a valid silo case")
}

fn run(case: &Case, dir: &Path, threads: usize) -> CaseSummary {
    run_dir::finished(case, dir, threads, false)
}

/// The conical silo discharges: every crossing lies in the orifice disc, and N(t), the
/// particles above the orifice plane, falls by exactly the crossings counted before t (no
/// particle comes back up through an open orifice under gravity).
#[test]
fn conical_silo_discharge_conserves_its_particles() {
    let root = tempfile::tempdir().expect("temporary directory");
    let dir = root.path().join("cone");
    let summary = run(&silo("hopper_angle_deg = 45.0"), &dir, 1);
    // A 45° cone leaves no stagnant zone: the silo empties through a 5 d orifice.
    assert_eq!(summary.stop_reason, StopReason::Empty);
    let crossings = table(&dir.join("crossings.csv"));
    assert!(crossings.len() > 300, "only {} crossings", crossings.len());
    // Columns: time, x, vx, vz, radius, mass, density, id, y. A centre crossing the orifice
    // plane must lie within R of the axis.
    for c in &crossings {
        assert!(
            c[1].hypot(c[8]) <= 0.008,
            "crossing at ({}, {})",
            c[1],
            c[8]
        );
    }
    let remaining = table(&dir.join("remaining.csv"));
    assert_eq!(remaining[0][1], 400.0, "N(0) is the fill");
    let opened = summary.fill_time;
    for row in &remaining {
        let before = crossings.iter().filter(|c| c[0] - opened <= row[0]).count() as f64;
        // Samples and crossings come from the same looks; a crossing interpolated inside
        // the last interval before a sample is counted on both sides of it.
        assert!(
            (row[1] - (400.0 - before)).abs() <= 1.0,
            "N({}) = {} but 400 − {before} crossed",
            row[0],
            row[1]
        );
    }
    // The settled bed presses on the cone and on the cylinder only below its surface: a
    // zone wholly above the bed (plus one diameter for the surface's roughness) carries no
    // load, and the lowest cone zone carries some.
    let text = std::fs::read_to_string(dir.join("wall_pressure.csv")).expect("wall_pressure.csv");
    let settled: Vec<Vec<&str>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|r| r[1] == "settled")
        .collect();
    assert!(!settled.is_empty(), "no settled pressures");
    let number = |s: &str| s.parse::<f64>().unwrap();
    for r in &settled {
        let (low, pressure) = (number(r[3]), number(r[5]));
        assert!(pressure >= 0.0, "a negative pressure: {r:?}");
        if low > summary.bed_height + 0.004 {
            assert_eq!(pressure, 0.0, "load above the bed: {r:?}");
        }
    }
    let bottom = settled
        .iter()
        .filter(|r| r[2] == "hopper")
        .min_by(|a, b| number(a[3]).total_cmp(&number(b[3])))
        .expect("cone zones");
    assert!(
        number(bottom[5]) > 0.0,
        "the bed rests on the cone: {bottom:?}"
    );
    // The radial profiles are fitted, and the rate of the fitted profiles agrees with W: at
    // D/d = 5 the self-similar forms give W within 5 % on deep beds (docs/reproduction.md,
    // "3D Beverloo"); 10 % leaves room for this bed of 400 spheres, whose steady window
    // holds fewer crossings.
    let radial = summary.radial_fit.expect("the radial profiles are fitted");
    let w = summary.discharge_rate;
    assert!(
        (radial.profile_rate[0] - w).abs() <= 0.1 * w,
        "the fitted profiles give {} kg/s, W is {w} kg/s",
        radial.profile_rate[0]
    );
    // The bed does not reach the cylinder, so no zone of it lies in the bed: no Janssen fit,
    // and the summary says why.
    assert!(summary.janssen.is_none());
    let why = summary.janssen_not_fitted.expect("the reason for no fit");
    assert!(
        why.starts_with("0 zone(s) of the cylinder") && why.contains("needs at least 3"),
        "{why}"
    );
    // The settled bed's weight rests on the walls: in the last window before the opening,
    // the cylinder's, the cone's and the gate's vertical loads add up to −m g. The bed's
    // residual motion is all that may differ: with kinetic energy E its momentum is at most
    // √(2 M E), so over a window T the loads can differ from the weight by 2√(2 M E)/T.
    let loads = table(&dir.join("wall_forces.csv"));
    let text = std::fs::read_to_string(dir.join("wall_forces.csv")).expect("wall_forces.csv");
    let walls: Vec<&str> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap())
        .collect();
    let last = loads
        .iter()
        .map(|r| r[0])
        .filter(|t| *t < opened)
        .fold(f64::NEG_INFINITY, f64::max);
    let in_last: Vec<usize> = (0..loads.len()).filter(|&k| loads[k][0] == last).collect();
    let mut named: Vec<&str> = in_last.iter().map(|&k| walls[k]).collect();
    named.sort_unstable();
    assert_eq!(
        named,
        ["cylinder", "gate", "hopper"],
        "the walls that bear the bed"
    );
    let fz: f64 = in_last.iter().map(|&k| loads[k][4]).sum();
    let mass = 400.0 * 2500.0 * std::f64::consts::PI / 6.0 * 0.004f64.powi(3);
    let weight = mass * 9.81;
    let window = 2.0 * (opened - last);
    let slack = 2.0 * (2.0 * mass * summary.settled_kinetic_energy).sqrt() / window;
    assert!(
        (fz + weight).abs() <= slack,
        "the walls carry {fz} N of the bed's weight {weight} N (allowed {slack} N)"
    );
    // φ_B of a poured bed of spheres lies between loose random packing and the 0.64 of
    // random close packing, lowered a little by the wall layer of this narrow silo.
    assert!(
        summary.bulk_volume_fraction > 0.45 && summary.bulk_volume_fraction < 0.64,
        "φ_B = {}",
        summary.bulk_volume_fraction
    );
}

/// An off-centre orifice in a flat bottom: the crossings gather about its centre.
#[test]
fn off_centre_orifice_discharges_around_its_centre() {
    let root = tempfile::tempdir().expect("temporary directory");
    let dir = root.path().join("flat");
    // 6 d: a flat bottom's orifice of 4 d arches within a few dozen grains.
    let case = silo("hopper_angle_deg = 90.0\noutlet_offset = 0.015\noutlet_diameter = 0.024");
    let summary = run(&case, &dir, 1);
    assert!(summary.discharged_mass > 0.0);
    let crossings = table(&dir.join("crossings.csv"));
    // A flat bottom drains only the funnel above the orifice: a few dozen of the 400.
    assert!(crossings.len() > 30, "only {} crossings", crossings.len());
    let n = crossings.len() as f64;
    let mean_x = crossings.iter().map(|c| c[1]).sum::<f64>() / n;
    // Crossings spread over the 12 mm radius: the spread of their mean is below
    // R/(2√30) ≈ 1.1 mm for 30 or more, so 3.5 mm is more than three of those.
    assert!((mean_x - 0.015).abs() < 0.0035, "mean x = {mean_x}");
    for c in &crossings {
        assert!((c[1] - 0.015).hypot(c[8]) <= 0.012);
    }
}

/// The same silo with meshed walls runs on one and on two threads to the same bits.
#[test]
fn meshed_silo_is_the_same_on_one_and_two_threads() {
    let root = tempfile::tempdir().expect("temporary directory");
    let case = silo("hopper_angle_deg = 45.0\nwalls = \"meshed\"\nmesh_segments = 48");
    run(&case, &root.path().join("one"), 1);
    run(&case, &root.path().join("two"), 2);
    // The summaries hold NaN (no slab width), so they are compared as written.
    for file in [
        "summary.json",
        "flow.csv",
        "crossings.csv",
        "remaining.csv",
        "wall_forces.csv",
    ] {
        let a = std::fs::read(root.path().join("one").join(file)).unwrap();
        let b = std::fs::read(root.path().join("two").join(file)).unwrap();
        assert!(a == b, "{file} differs between 1 and 2 threads");
    }
}
