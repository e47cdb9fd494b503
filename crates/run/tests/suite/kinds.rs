//! Runs of small rectangular silos (`kind = "box"`) and of STL walls (`kind = "mesh"`): the
//! protocol works for each, what it writes obeys the invariants of a discharge, and STL files
//! of the cylindrical silo's own triangles give that silo's walls and physics bit for bit
//! (docs/physics.md §5.7–5.8, §7.8).

use crate::run_dir::{self, table};
use std::path::Path;

use case::{load_case, parse_case, Case};
use files::{CaseSummary, StopReason};
use glam::DVec3;
use run::case_simulation;
use run::{run_case, RunOptions, RunOutcome};

/// The run settings of every case here: 400 spheres of 4 mm (the paper's soft material, so
/// Δt = 5 µs is 0.15 Rayleigh times) poured from `fill_top` [m], a discharge of at most
/// `time_limit` [s], no checkpoints or pictures.
fn settings(fill_top: f64, time_limit: f64) -> String {
    format!(
        "[particles]\ncount = 400\ndiameter = 0.004\n[time]\ntime_step = 5.0e-6\n\
         [protocol]\ntime_limit = {time_limit:?}\nsettle_kinetic_energy = 1.0e-8\nfill_top = {fill_top:?}\n\
         [measure]\nrate_bin_width = 0.02\n\
         [output]\ncheckpoint_interval = 0.0\nvtu_interval = 0.0\n"
    )
}

fn run(case: &Case, dir: &Path, threads: usize) -> CaseSummary {
    run_dir::finished(case, dir, threads, false)
}

/// N(t) in remaining.csv falls by exactly the crossings counted before t: no particle comes
/// back up through an open orifice under gravity.
fn remaining_matches_crossings(dir: &Path, summary: &CaseSummary, total: f64) {
    let crossings = table(&dir.join("crossings.csv"));
    let remaining = table(&dir.join("remaining.csv"));
    assert_eq!(remaining[0][1], total, "N(0) is the fill");
    for row in &remaining {
        let before = crossings
            .iter()
            .filter(|c| c[0] - summary.fill_time <= row[0])
            .count() as f64;
        // A crossing interpolated inside the last interval before a sample is counted on both
        // sides of it.
        assert!(
            (row[1] - (total - before)).abs() <= 1.0,
            "N({}) = {} but {total} − {before} crossed",
            row[0],
            row[1]
        );
    }
}

/// A box 50 mm × 24 mm over a 30° wedge to a 20 mm slot (5 d) empties: every crossing lies in
/// the slot, N(t) falls by the crossings, the poured bed's bulk fraction is that of a random
/// packing, and the slot's x-profile holds the crossings, fastest near its middle.
#[test]
fn box_wedge_discharges_through_its_slot() {
    let text = format!(
        "version = 1\nseed = 5\n[geometry]\nkind = \"box\"\nwidth = 0.05\ndepth = 0.024\n\
         height = 0.1\noutlet_width = 0.02\nhopper_angle_deg = 30.0\n{}",
        settings(0.08, 1.5)
    );
    let case = parse_case(&text, "box.toml", &[]).expect("a valid box case");
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("wedge");
    let summary = run_dir::finished(&case, &dir, 1, true);
    // walls.vtu holds the six faces (two side walls above the plates, front and back, two
    // plates); the frames of the vertical cut are drawn.
    let walls = std::fs::read_to_string(dir.join("snapshots/walls.vtu")).unwrap();
    assert!(walls.contains("NumberOfCells=\"6\""), "{walls}");
    assert!(dir.join("snapshots/frame_0000.png").is_file());
    assert_eq!(summary.stop_reason, StopReason::Empty);
    let crossings = table(&dir.join("crossings.csv"));
    assert_eq!(crossings.len(), 400);
    // Columns: time, x, vx, vz, radius, mass, density, id, y.
    for c in &crossings {
        assert!(c[1].abs() <= 0.01, "crossing at x = {}", c[1]);
        // Within the depth less a radius, up to the spheres' overlap with the front and back
        // walls (a few µm; the engine's guard stops a run at 10 % of r).
        assert!(
            c[8].abs() <= 0.012 - 0.002 + 2e-5,
            "crossing at y = {}",
            c[8]
        );
        assert!(c[3] < 0.0);
    }
    remaining_matches_crossings(&dir, &summary, 400.0);
    assert!(
        summary.bulk_volume_fraction > 0.45 && summary.bulk_volume_fraction < 0.64,
        "φ_B = {}",
        summary.bulk_volume_fraction
    );
    assert!(summary.bed_height > 0.02 && summary.bed_height < 0.06);
    // profiles.csv: x*, x, v, error, crossings, φ, error, over the 10 bins of d/2.
    let profiles = table(&dir.join("profiles.csv"));
    assert_eq!(profiles.len(), 10);
    let counted: f64 = profiles.iter().map(|r| r[4]).sum();
    assert!(counted > 50.0, "{counted} crossings in the window");
    let centre = 0.5 * (profiles[4][2] + profiles[5][2]);
    // No centre crosses within r of the plates' edges: the outer bins stay empty (NaN), and
    // the outermost bins with crossings are slower than the middle.
    let seen: Vec<&Vec<f64>> = profiles.iter().filter(|r| r[4] > 0.0).collect();
    assert!(profiles[0][2].is_nan() && profiles[9][2].is_nan());
    let edge = 0.5 * (seen[0][2] + seen[seen.len() - 1][2]);
    assert!(centre > edge, "v centre {centre} ≤ v edge {edge}");
    // v_c is the mean of the central bins (`OutletBins::central_bins`): one or both of these.
    let (v4, v5) = (profiles[4][2], profiles[5][2]);
    assert!(
        summary.centre_velocity >= v4.min(v5) && summary.centre_velocity <= v4.max(v5),
        "v_c = {}",
        summary.centre_velocity
    );
    // The volume fraction from the flux of centres is a density of centres times a sphere's
    // volume: in the bins where the layer sliding along a plate crosses (centres r/cos α
    // inside the edge) it exceeds any packing, but over the whole orifice it lies below the
    // bed's, as a dilated outflow should.
    let mean: f64 = profiles
        .iter()
        .map(|r| if r[4] > 0.0 { r[5] } else { 0.0 })
        .sum::<f64>()
        / profiles.len() as f64;
    assert!(
        mean > 0.2 && mean < summary.bulk_volume_fraction,
        "mean φ over the slot {mean}, bed {}",
        summary.bulk_volume_fraction
    );
    let forces = std::fs::read_to_string(dir.join("wall_forces.csv")).unwrap();
    for wall in [
        "left",
        "right",
        "front",
        "back",
        "plate_left",
        "plate_right",
        "gate",
    ] {
        assert!(forces.contains(&format!(",{wall},")), "no {wall} rows");
    }
}

/// A square orifice off-centre in a flat bottom: the crossings lie in the square, about its
/// centre.
#[test]
fn box_square_orifice_in_a_flat_bottom() {
    let text = format!(
        "version = 1\nseed = 2\n[geometry]\nkind = \"box\"\nwidth = 0.06\ndepth = 0.04\n\
         height = 0.1\noutlet = \"square\"\noutlet_width = 0.024\nhopper_angle_deg = 90.0\n\
         outlet_offset = 0.01\nwalls = \"meshed\"\n{}",
        // A flat bottom trickles on past its funnel: 0.4 s of it is enough here.
        settings(0.06, 0.4)
    );
    let case = parse_case(&text, "square.toml", &[]).expect("a valid box case");
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("square");
    let summary = run(&case, &dir, 1);
    assert!(summary.discharged_mass > 0.0);
    let crossings = table(&dir.join("crossings.csv"));
    // A flat bottom drains the funnel above the orifice only.
    assert!(crossings.len() > 30, "only {} crossings", crossings.len());
    for c in &crossings {
        assert!(
            (c[1] - 0.01).abs() <= 0.012 && c[8].abs() <= 0.012,
            "({}, {})",
            c[1],
            c[8]
        );
    }
    let n = crossings.len() as f64;
    let mean_x = crossings.iter().map(|c| c[1]).sum::<f64>() / n;
    assert!((mean_x - 0.01).abs() < 0.004, "mean x = {mean_x}");
    let forces = std::fs::read_to_string(dir.join("wall_forces.csv")).unwrap();
    assert!(forces.contains(",bottom,") && !forces.contains(",plate_left,"));
}

/// The conical silo of `run_silo.rs` (R = 40 mm, 45° cone, 20 mm orifice) with meshed walls.
fn cylinder_text(segments: usize) -> String {
    format!(
        "version = 1\nseed = 3\n[geometry]\nkind = \"cylinder\"\nradius = 0.04\nheight = 0.1\n\
         outlet_diameter = 0.02\nhopper_angle_deg = 45.0\nwalls = \"meshed\"\n\
         mesh_segments = {segments}\n{}",
        settings(0.06, 1.5)
    )
}

/// Writes the cylinder kind's meshed walls as ASCII STL files in `dir` (the triangles its
/// builder makes: `stl::shapes` with the same arguments) and a mesh case naming them, with the
/// same orifice and gate, whose fill box lies inside the cylinder above the cone.
fn mesh_copy_of_cylinder(dir: &Path, segments: usize) -> std::path::PathBuf {
    let (r, h, ro) = (0.04, 0.1, 0.01);
    // (R − r_o)/tan 45°, as `CylinderGeometry::cone_height` computes it.
    let hc = (r - ro) / 45f64.to_radians().tan();
    let cylinder = stl::shapes::cylinder_side(
        DVec3::new(0.0, 0.0, hc),
        DVec3::new(0.0, 0.0, h - hc),
        r,
        segments,
    )
    .unwrap();
    let cone =
        stl::shapes::frustum_side(DVec3::ZERO, DVec3::new(0.0, 0.0, hc), ro, r, segments).unwrap();
    for (name, triangles) in [("cylinder.stl", &cylinder), ("cone.stl", &cone)] {
        let mut bytes = Vec::new();
        stl::write_ascii(&mut bytes, triangles, name).unwrap();
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    let text = format!(
        "version = 1\nseed = 3\n[geometry]\nkind = \"mesh\"\n\
         fill_min = [-0.027, -0.027, 0.035]\nfill_max = [0.027, 0.027, 0.1]\n\
         outlet = {{ shape = \"disc\", centre = [0.0, 0.0], radius = 0.01, segments = {segments} }}\n\
         [[geometry.walls]]\nfile = \"cylinder.stl\"\n\
         [[geometry.walls]]\nfile = \"cone.stl\"\n{}",
        settings(0.06, 1.5)
    );
    let path = dir.join("mesh.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// STL files of the cylindrical silo's own triangles, written in ASCII (shortest exact
/// decimals) and read back, give the cylinder kind's walls bit for bit, and the same spheres in
/// both simulations move the same to the last bit through settling and discharge.
#[test]
fn stl_copy_of_the_meshed_cylinder_is_the_same_simulation() {
    let segments = 48;
    let dir = tempfile::tempdir().unwrap();
    let mesh_case = load_case(&mesh_copy_of_cylinder(dir.path(), segments), &[])
        .unwrap_or_else(|e| panic!("{e}"));
    let cylinder_case = parse_case(&cylinder_text(segments), "cylinder.toml", &[]).unwrap();
    let (mut a, walls_a, material_a) = case_simulation(&cylinder_case, 1).unwrap();
    let (mut b, walls_b, material_b) = case_simulation(&mesh_case, 1).unwrap();
    let (named_a, named_b) = (walls_a.named(), walls_b.named());
    assert_eq!(named_a.len(), named_b.len());
    for ((_, ia), (_, ib)) in named_a.iter().zip(&named_b) {
        assert_eq!(ia, ib, "the walls are added in the same order");
        let (wa, wb) = (a.wall(ia.unwrap()).unwrap(), b.wall(ib.unwrap()).unwrap());
        assert_eq!(wa, wb, "wall {ia:?} differs");
        // Bit for bit, not only equal as numbers: the stored forms serialise the same.
        assert_eq!(
            postcard::to_allocvec(wa).unwrap(),
            postcard::to_allocvec(wb).unwrap()
        );
    }
    // A column of spheres over the orifice and around it, dropped onto the closed gate.
    for sim_and_material in [(&mut a, material_a), (&mut b, material_b)] {
        let (sim, material) = sim_and_material;
        for k in 0..5 {
            for i in -2..=2 {
                for j in -2..=2 {
                    let p = DVec3::new(
                        0.0055 * i as f64 + 1e-4 * k as f64,
                        0.0055 * j as f64,
                        0.045 + 0.0055 * k as f64,
                    );
                    sim.add_particle(dem::ParticleInit::at_rest(p, 0.002, material))
                        .unwrap();
                }
            }
        }
    }
    let compare = |a: &dem::Simulation, b: &dem::Simulation, when: &str| {
        let (pa, pb) = (a.particles(), b.particles());
        assert_eq!(pa.len(), pb.len(), "{when}");
        for k in 0..pa.len() {
            assert_eq!(
                pa.positions()[k].to_array().map(f64::to_bits),
                pb.positions()[k].to_array().map(f64::to_bits),
                "{when}: particle {k}"
            );
            assert_eq!(
                pa.velocities()[k].to_array().map(f64::to_bits),
                pb.velocities()[k].to_array().map(f64::to_bits),
                "{when}: particle {k}"
            );
        }
    };
    for sim in [&mut a, &mut b] {
        sim.run(40_000).unwrap();
    }
    compare(&a, &b, "settled on the gate");
    // The spheres reach the cone and rest on the gate.
    assert!(a
        .particles()
        .positions()
        .iter()
        .all(|p| p.z > 0.0 && p.z < 0.06));
    a.remove_wall(walls_a.gate()).unwrap();
    b.remove_wall(walls_b.gate()).unwrap();
    for sim in [&mut a, &mut b] {
        sim.run(20_000).unwrap();
    }
    compare(&a, &b, "after the gate opened");
    let below = a
        .particles()
        .positions()
        .iter()
        .filter(|p| p.z < 0.0)
        .count();
    assert!(below > 20, "only {below} spheres fell through the orifice");
}

/// The same silo run through the whole protocol from STL files: it empties like the cylinder
/// kind's meshed silo (both empty, every crossing in the orifice disc, N(t) falls by the
/// crossings), at a rate within the spread that two fills of 400 spheres show.
#[test]
fn stl_silo_discharges_like_the_meshed_cylinder() {
    let segments = 48;
    let dir = tempfile::tempdir().unwrap();
    let mesh_case = load_case(&mesh_copy_of_cylinder(dir.path(), segments), &[]).unwrap();
    let cylinder_case = parse_case(&cylinder_text(segments), "cylinder.toml", &[]).unwrap();
    let mesh_summary = run_dir::finished(&mesh_case, &dir.path().join("mesh-run"), 1, true);
    // walls.vtu holds every triangle of the two files: 2 × 48 each.
    let walls = std::fs::read_to_string(dir.path().join("mesh-run/snapshots/walls.vtu")).unwrap();
    assert!(walls.contains("NumberOfCells=\"192\""));
    assert!(dir
        .path()
        .join("mesh-run/snapshots/frame_0000.png")
        .is_file());
    let cylinder_summary = run(&cylinder_case, &dir.path().join("cylinder-run"), 1);
    for (summary, run_dir) in [
        (&mesh_summary, dir.path().join("mesh-run")),
        (&cylinder_summary, dir.path().join("cylinder-run")),
    ] {
        assert_eq!(summary.stop_reason, StopReason::Empty);
        let crossings = table(&run_dir.join("crossings.csv"));
        assert_eq!(crossings.len(), 400);
        for c in &crossings {
            assert!(c[1].hypot(c[8]) <= 0.01, "crossing at ({}, {})", c[1], c[8]);
        }
        remaining_matches_crossings(&run_dir, summary, 400.0);
    }
    // STL walls have no known inside volume: no bulk fraction.
    assert!(mesh_summary.bulk_volume_fraction.is_nan());
    // The mesh case's radial profiles are those of a circular orifice.
    let profiles = std::fs::read_to_string(dir.path().join("mesh-run/profiles.csv")).unwrap();
    assert!(profiles.starts_with("r_star,"), "{profiles}");
    let forces = std::fs::read_to_string(dir.path().join("mesh-run/wall_forces.csv")).unwrap();
    assert!(forces.contains(",cylinder,") && forces.contains(",cone,"));
    // Cut in the discharge (the fill and settling take about 60 chunks of 2.5 ms) and
    // resumed from the checkpoint, the mesh case writes what the uninterrupted run wrote.
    let cut = dir.path().join("mesh-cut");
    let options = RunOptions {
        chunk_limit: Some(100),
        ..RunOptions::default()
    };
    assert!(matches!(
        run_case(&mesh_case, &cut, &options).unwrap(),
        RunOutcome::Interrupted
    ));
    let resumed = RunOptions {
        resume: true,
        ..RunOptions::default()
    };
    assert!(matches!(
        run_case(&mesh_case, &cut, &resumed).unwrap(),
        RunOutcome::Finished(_)
    ));
    for file in [
        "summary.json",
        "flow.csv",
        "crossings.csv",
        "remaining.csv",
        "wall_forces.csv",
        "profiles.csv",
    ] {
        let a = std::fs::read(dir.path().join("mesh-run").join(file)).unwrap();
        let b = std::fs::read(cut.join(file)).unwrap();
        assert!(a == b, "{file} differs after the resumption");
    }
    let (wm, wc) = (mesh_summary.discharge_rate, cylinder_summary.discharge_rate);
    assert!(
        (wm - wc).abs() < 0.2 * wc,
        "W = {wm} kg/s from STL walls, {wc} kg/s from the cylinder kind"
    );
}

/// The case's `gravity` is the engine's: a sphere released mid-air in the paper's slab falls
/// z₀ − g t²/2 under the g the case gives, for Earth's default and for Mars's 3.71 m/s².
#[test]
fn a_free_sphere_falls_under_the_cases_gravity() {
    for (sets, g) in [(vec![], 9.81), (vec!["gravity=3.71".to_string()], 3.71)] {
        let case = parse_case("version = 1\n", "g.toml", &sets).unwrap();
        let (mut sim, _walls, material) = case_simulation(&case, 1).unwrap();
        // Mid-slab and mid-height: 15 µm from the front and back walls, far from the rest.
        let z0 = 0.2;
        let start = DVec3::new(0.0, 0.5 * 0.00303, z0);
        sim.add_particle(dem::ParticleInit::at_rest(start, 0.0015, material))
            .unwrap();
        let steps = 4000;
        for _ in 0..steps {
            sim.step().unwrap();
        }
        let t = steps as f64 * case.time_step;
        let z = sim.particles().positions()[0].z;
        // Velocity Verlet is exact for a constant acceleration, so only round-off over 4000
        // steps separates z from the parabola (a drop of 0.2–0.5 mm): 1 nm is far above it
        // and far below the 0.3 mm between the two g.
        let expected = z0 - 0.5 * g * t * t;
        assert!(
            (z - expected).abs() < 1e-9,
            "g = {g}: z = {z}, expected {expected}"
        );
    }
}
