//! `wall_forces.csv` of a whole tiny-hopper run: its columns and windows, and the physics
//! of the loads in it. Before the gate opens the walls hold the settled bed up, so their
//! vertical loads add up to its weight and their sideways loads cancel; once the gate is
//! removed it has no more rows.

use crate::tiny_hopper;

use std::collections::BTreeMap;

use run::{run_case, RunOptions, RunOutcome};

/// Gravity of the hopper runs [m/s²] (the engine's default, along −z).
const G: f64 = 9.81;

/// One row of wall_forces.csv.
#[derive(Debug, Clone)]
struct Row {
    time: f64,
    wall: String,
    force: [f64; 3],
    torque: [f64; 3],
}

fn parse(text: &str) -> (Vec<String>, Vec<Row>) {
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .expect("a header line")
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|line| {
            let cells: Vec<&str> = line.split(',').collect();
            assert_eq!(cells.len(), 8, "row {line:?} has 8 cells");
            let num = |k: usize| -> f64 {
                cells[k]
                    .parse()
                    .unwrap_or_else(|e| panic!("cell {k} of {line:?}: {e}"))
            };
            Row {
                time: num(0),
                wall: cells[1].to_string(),
                force: [num(2), num(3), num(4)],
                torque: [num(5), num(6), num(7)],
            }
        })
        .collect();
    (header, rows)
}

#[test]
fn wall_loads_of_the_settled_bed_carry_its_weight_and_the_gate_leaves_with_the_opening() {
    // The paper's time step (0.1 Rayleigh times): the settled bed's balance is physics, and
    // the tiny case's longer step leaves it 3 % off its weight in the last window.
    let case = tiny_hopper::tiny_case(&["time.time_step=2.5e-6"]);
    let dir = tempfile::tempdir().expect("temporary directory");
    let options = RunOptions {
        resume: false,
        ..RunOptions::default()
    };
    let outcome = run_case(&case, dir.path(), &options).expect("the tiny hopper runs");
    let RunOutcome::Finished(summary) = outcome else {
        panic!("the run finished")
    };
    assert!(summary.settled, "the bed settled before the gate opened");
    let opened = summary.fill_time;
    let bin = case.measure.rate_bin_width;
    let dt = case.time_step;

    let text = String::from_utf8(tiny_hopper::read(dir.path(), "wall_forces.csv"))
        .expect("wall_forces.csv is UTF-8");
    let (header, rows) = parse(&text);
    assert_eq!(
        header,
        ["time", "wall", "fx", "fy", "fz", "tx", "ty", "tz"],
        "the documented columns"
    );
    // Every window has one row per wall that sums its load: the side walls, both plates of
    // the flat bottom and, before the opening, the gate; never the faces.
    let mut windows: BTreeMap<u64, Vec<&Row>> = BTreeMap::new();
    for r in &rows {
        windows.entry(r.time.to_bits()).or_default().push(r);
    }
    let before: Vec<(f64, &Vec<&Row>)> = windows
        .values()
        .map(|w| (w[0].time, w))
        .filter(|(t, _)| *t < opened)
        .collect();
    let after: Vec<(f64, &Vec<&Row>)> = windows
        .values()
        .map(|w| (w[0].time, w))
        .filter(|(t, _)| *t > opened)
        .collect();
    assert!(
        !before.is_empty() && !after.is_empty(),
        "windows before and after the opening at {opened} s"
    );
    fn names<'a>(w: &[&'a Row]) -> Vec<&'a str> {
        w.iter().map(|r| r.wall.as_str()).collect()
    }
    for (t, w) in &before {
        assert_eq!(
            names(w),
            ["left", "right", "plate_left", "plate_right", "gate"],
            "walls of the window at {t} s"
        );
    }
    for (t, w) in &after {
        assert_eq!(
            names(w),
            ["left", "right", "plate_left", "plate_right"],
            "walls of the window at {t} s, the gate removed"
        );
    }
    // Windows of one W(t) bin from the start of the run; the one the opening cuts short
    // ends at it, and from there they lie on the bins of flow.csv, centred on
    // opened + (k + ½) bin. The tolerance is a few steps of rounding of the step times.
    let whole = (bin / dt).round() * dt;
    assert!(
        (before[0].0 - 0.5 * whole).abs() < 2.0 * dt,
        "the first window is centred on half a bin"
    );
    assert_eq!(before.len(), (opened / whole).ceil() as usize);
    for (k, (t, _)) in after.iter().enumerate().take(after.len() - 1) {
        let centre = opened + (k as f64 + 0.5) * whole;
        assert!(
            (t - centre).abs() < 2.0 * dt,
            "discharge window {k} at {t} s, expected {centre} s"
        );
    }
    assert!(
        after.len() as f64 >= (summary.discharge_time / whole).floor(),
        "the discharge is covered to its end"
    );

    // The settled bed, in the last window before the opening: its weight m g rests on the
    // walls that sum their load. The faces of this 1.01 d slab press on the spheres only
    // where a contact pushes them sideways, so the friction they add is small; and the
    // bed's residual motion (mean kinetic energy below 1e-8 J) changes its momentum by far
    // less. Measured: the walls carry 0.9978 of m g; 1 % leaves room for the face friction
    // of another fill while a missing wall (each carries over 5 %) still fails.
    let d = case.particles.mean_diameter();
    let mass =
        case.particles.count as f64 * case.particles.density() * std::f64::consts::PI * d.powi(3)
            / 6.0;
    let weight = mass * G;
    let (_, settled) = before.last().expect("windows before the opening");
    let vertical: f64 = settled.iter().map(|r| r.force[2]).sum();
    println!(
        "settled bed: weight {weight:.6e} N, walls' vertical load {vertical:.6e} N ({:.5} of -m g); \
         by wall: {:?}",
        -vertical / weight,
        settled
            .iter()
            .map(|r| (r.wall.as_str(), r.force[2]))
            .collect::<Vec<_>>()
    );
    assert!(
        (vertical + weight).abs() < 0.01 * weight,
        "walls carry {vertical} N of a {weight} N bed (the loads on the walls point down)"
    );
    for r in settled.iter() {
        assert!(
            r.force[2] <= 0.0,
            "{} is pressed down or not at all: fz = {}",
            r.wall,
            r.force[2]
        );
    }
    let get = |name: &str| settled.iter().find(|r| r.wall == name).expect(name);
    let gate = get("gate");
    // The gate carries the part of the bed over the outlet. The floor under a bed about as
    // tall as it is wide carries nearly all of it (the side walls' friction holds only
    // a few per cent), roughly in proportion to width, so the gate's share is of the
    // order of D/L; the middle of the floor is pressed harder than its edges, near the side
    // walls that hold part of the bed. Measured: 1.37 D/L. Half to twice D/L fails for a
    // gate that misses its load or takes another wall's.
    let share = case.geometry.slab().unwrap().outlet_width / case.geometry.slab().unwrap().width;
    println!(
        "gate: fz = {:.6e} N, {:.4} of m g (outlet share of the width {share:.3})",
        gate.force[2],
        -gate.force[2] / weight
    );
    assert!(
        -gate.force[2] > 0.5 * share * weight && -gate.force[2] < 2.0 * share * weight,
        "the gate carries {} N of a {weight} N bed",
        gate.force[2]
    );
    // Sideways, the bed pushes the left wall to −x and the right wall to +x with equal
    // forces: nothing else takes a force along x except friction on the faces and floor.
    let (left, right) = (get("left"), get("right"));
    assert!(
        left.force[0] < 0.0 && right.force[0] > 0.0,
        "the bed pushes the side walls apart"
    );
    let fx: f64 = settled.iter().map(|r| r.force[0]).sum();
    assert!(
        fx.abs() < 0.1 * right.force[0],
        "sideways loads balance: sum {fx} N against {} N on the right wall",
        right.force[0]
    );
    // The torque about the origin of a horizontal floor's load: τ_x = y F_z − z F_y and
    // τ_y = z F_x − x F_z, with the gate in z = 0 and the load's line of action in the
    // slab (0 < y < Z) and over the gate (|x − x_c| < D/2).
    let (y, x) = (
        gate.torque[0] / gate.force[2],
        -gate.torque[1] / gate.force[2],
    );
    println!("gate's line of action: x = {x:.6e} m, y = {y:.6e} m");
    assert!(
        y > 0.0 && y < case.geometry.slab().unwrap().thickness,
        "the gate's load acts in the slab: y = {y} m"
    );
    let centre = case.geometry.slab().unwrap().outlet_centre();
    assert!(
        (x - centre).abs() < 0.5 * case.geometry.slab().unwrap().outlet_width,
        "the gate's load acts over it: x = {x} m"
    );
}
