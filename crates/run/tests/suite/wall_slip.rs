//! The wall slip of a settled silo bed (`protocol.wall_slip`, docs/physics.md §7.7): after the
//! cylinder has slipped up past the bed by a tenth of a diameter, the bed rests partly on
//! its walls, with their friction acting upward on it, as in Janssen's (1895) analysis.

use std::path::Path;

use case::{parse_case, Case};
use run::{run_case, RunOptions, RunOutcome};

/// A flat-bottomed cylinder of radius 12 mm (6 diameters) holding 400 spheres of 4 mm, about
/// 50 mm (four radii) deep, with the benchmark's M1 material and steel walls (Dosta et al.
/// 2024: μ = 0.3 between spheres, 0.2 at the wall), filled from 80 mm up.
fn silo(slip: f64) -> Case {
    let text = format!(
        "version = 1\nseed = 3\n[geometry]\nkind = \"cylinder\"\nradius = 0.012\n\
         height = 0.1\noutlet_diameter = 0.012\nhopper_angle_deg = 90.0\n\
         [particles]\ncount = 400\ndiameter = 0.004\n\
         [particles.material]\ndensity = 2500.0\nyoungs_modulus = 1.0e9\npoisson_ratio = 0.2\n\
         [wall]\nfriction = 0.2\nrestitution = 0.4\n\
         [wall.material]\ndensity = 7200.0\nyoungs_modulus = 210.0e9\npoisson_ratio = 0.2\n\
         [contact]\nfriction = 0.3\nrestitution = 0.5\n\
         [time]\ntime_step = 1.5e-6\n\
         [protocol]\nfill_top = 0.08\ntime_limit = 0.002\nwall_slip = {slip}\n\
         [output]\ncheckpoint_interval = 0.0\nvtu_interval = 0.0\n"
    );
    parse_case(&text, "silo.toml", &[]).expect("a valid silo case")
}

/// The vertical forces [N] of the bed on the cylinder and on the base (bottom and gate) in
/// the last window of `wall_forces.csv` before the gate opened.
fn settled_loads(dir: &Path) -> (f64, f64) {
    let text = std::fs::read_to_string(dir.join("wall_forces.csv")).expect("wall_forces.csv");
    let rows: Vec<Vec<&str>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    let time = |r: &Vec<&str>| r[0].parse::<f64>().expect("a time");
    let fz = |r: &Vec<&str>| r[4].parse::<f64>().expect("a force");
    let last = rows
        .iter()
        .filter(|r| r[1] == "gate")
        .map(time)
        .fold(f64::NEG_INFINITY, f64::max);
    let (mut cylinder, mut base) = (0.0, 0.0);
    for r in rows.iter().filter(|r| time(r) == last) {
        match r[1] {
            "cylinder" => cylinder += fz(r),
            "bottom" | "gate" => base += fz(r),
            other => panic!("unexpected wall {other}"),
        }
    }
    (cylinder, base)
}

/// After the slip the cylinder carries part of the bed's weight, and the base the rest.
///
/// Janssen's law puts the base's share of the weight of a bed h deep in a cylinder of radius
/// R at (1 − e^{−x})/x, x = 2Kμ_w h/R. With h/R ≈ 4 and the most cautious values the bed
/// admits (K ≥ 0.3, below Jaky's 1 − sin φ for any friction angle under 45°; μ_w ≥ 0.15,
/// three quarters of the wall's μ), x ≥ 0.36 and the share is at most 0.84: the test asks
/// for under 0.9, and for the cylinder to be pulled down (fz < 0) by at least a tenth of the
/// weight. The forces on the walls balance the weight to within 5 % (the bed is at rest: the
/// settling criterion leaves a mean kinetic energy of 1e-9 J a sphere).
#[test]
fn slipped_bed_hangs_partly_on_its_walls() {
    let root = tempfile::tempdir().expect("temporary directory");
    let dir = root.path().join("slip");
    let case = silo(4.0e-4);
    let options = RunOptions {
        pictures: true,
        threads: 1,
        ..RunOptions::default()
    };
    let summary = match run_case(&case, &dir, &options).expect("the silo runs") {
        RunOutcome::Finished(summary) => *summary,
        RunOutcome::Interrupted => panic!("the run was interrupted"),
    };
    assert!(summary.settled, "the bed settles again after the slip");
    let d: f64 = 0.004;
    let mass = 400.0 * 2500.0 * std::f64::consts::PI / 6.0 * d.powi(3);
    let weight = mass * case.gravity;
    let (cylinder, base) = settled_loads(&dir);
    let share = -base / weight;
    assert!(
        ((-base - cylinder) / weight - 1.0).abs() < 0.05,
        "the walls carry the weight: base {base} N, cylinder {cylinder} N, weight {weight} N"
    );
    assert!(share < 0.9, "the base carries {share} of the weight");
    assert!(
        cylinder < -0.1 * weight,
        "the cylinder is pulled down: fz = {cylinder} N, weight {weight} N"
    );
    // The run draws the settled bed's wall stresses against depth, beside its other plots.
    let png = std::fs::read(dir.join("wall_pressure.png")).expect("wall_pressure.png");
    assert!(png.starts_with(b"\x89PNG"), "wall_pressure.png is a PNG");
    let svg = std::fs::read_to_string(dir.join("wall_pressure.svg")).expect("wall_pressure.svg");
    assert!(
        svg.contains("ρ_b g h") && svg.contains("wall pressure"),
        "its legend"
    );
}
