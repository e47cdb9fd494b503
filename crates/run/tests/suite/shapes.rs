//! Shaped grains in a silo run (docs/physics.md §11.7–11.8): rods filled with random
//! orientations, settled and discharged; the outlet counts each grain once, by its centre of
//! mass, with its whole mass; N(t) counts grains; the VTU snapshot draws the members with
//! their grain's id.

use crate::run_dir::{self, table};

use case::{parse_case, Case};
use files::StopReason;
use run::{run_case, RunOptions, RunOutcome};

/// `count` rods of aspect ratio 2 (three beads) of 4 mm equal-volume diameter in the silo of
/// `silo.rs` (R = 40 mm, Δt = 5 µs, 0.15 Rayleigh times of the beads), over a flat bottom
/// with a 28 mm orifice: 7 equal-volume diameters, 5.4 rod lengths, wide enough for rods
/// to drain without arching.
fn rods(count: usize, time_limit: f64, extra: &str) -> Case {
    let text = format!(
        "version = 1\nseed = 5\n[geometry]\nkind = \"cylinder\"\nradius = 0.04\nheight = 0.1\n\
         outlet_diameter = 0.028\n[particles]\ncount = {count}\ndiameter = 0.004\n\
         shape = {{ kind = \"rod\", aspect_ratio = 2.0 }}\n\
         [time]\ntime_step = 5.0e-6\n[protocol]\nfill_top = 0.07\n\
         settle_kinetic_energy = 1.0e-8\ntime_limit = {time_limit}\n[measure]\nrate_bin_width = 0.02\n\
         [output]\ncheckpoint_interval = 0.0\n{extra}\n"
    );
    parse_case(&text, "rods.toml", &[]).expect("a valid case of rods")
}

#[test]
fn rods_fill_settle_and_drain_each_counted_once_by_its_centre_of_mass() {
    let root = tempfile::tempdir().expect("temporary directory");
    let dir = root.path().join("rods");
    let case = rods(300, 1.5, "vtu_interval = 0.25");
    let summary = run_dir::finished(&case, &dir, 1, true);
    // The grains' mass: 300 of the 4 mm sphere's volume at 2500 kg/m³ (the fill weighs
    // bodies once each, not their members; rounding of the union's closed form only).
    let grain = 2500.0 * std::f64::consts::PI / 6.0 * 0.004f64.powi(3);
    let fill = 300.0 * grain;
    let remaining = table(&dir.join("remaining.csv"));
    assert_eq!(
        remaining[0][1], 300.0,
        "N(0) counts grains, not member spheres"
    );
    assert!(
        (remaining[0][2] / fill - 1.0).abs() < 1e-9,
        "{} kg",
        remaining[0][2]
    );
    // Every crossing is one grain of one grain's mass, through the orifice disc by its
    // centre of mass; no grain crosses twice.
    let crossings = table(&dir.join("crossings.csv"));
    assert!(crossings.len() > 150, "only {} crossings", crossings.len());
    let mut ids: Vec<u64> = crossings.iter().map(|c| c[7] as u64).collect();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), crossings.len(), "a grain crossed twice");
    for c in &crossings {
        assert!(
            (c[5] / grain - 1.0).abs() < 1e-9,
            "crossing mass {} kg",
            c[5]
        );
        assert!(
            c[1].hypot(c[8]) <= 0.014,
            "crossing at ({}, {})",
            c[1],
            c[8]
        );
    }
    // N(t) falls by the crossings before t, grain for grain.
    let opened = summary.fill_time;
    for row in &remaining {
        let before = crossings.iter().filter(|c| c[0] - opened <= row[0]).count() as f64;
        assert!(
            (row[1] - (300.0 - before)).abs() <= 1.0,
            "N({}) = {} after {before} crossings",
            row[0],
            row[1]
        );
    }
    assert!(summary.discharge_rate > 0.0 && summary.discharge_rate.is_finite());
    assert_ne!(
        summary.stop_reason,
        StopReason::Clogged,
        "{:?}",
        summary.stop_reason
    );
    let orientation = summary.orientation.expect("the grains' orientation");
    let (bed, outlet) = (
        orientation.bed.expect("the bed's axes"),
        orientation.outlet.expect("the outlet's axes"),
    );
    eprintln!("bed {bed:?}\noutlet {outlet:?}");
    // Rods turn their long axes into the flow as they pass the orifice (Börzsönyi et al.
    // 2016, New J. Phys. 18, 093017); poured and settled, they lie rather than stand. For
    // axes at random ⟨P₂⟩ has a standard error of √(1/5)/√N = 0.026 at N = 300; measured
    // here: +0.15 at the outlet with a director within 6° of the vertical, −0.08 in the bed.
    // The outlet must lie 3 standard errors above random and 4 above the bed.
    assert!(outlet.vertical_alignment > 0.08, "{outlet:?}");
    assert!(outlet.director[2].abs() > 0.9, "{outlet:?}");
    assert!(
        outlet.vertical_alignment - bed.vertical_alignment > 0.1,
        "{bed:?}"
    );
    assert_eq!(bed.grains, 300);
    assert_eq!(outlet.grains, crossings.len());
    let rows = table(&dir.join("orientations.csv"));
    assert_eq!(rows.len(), 300);
    // The snapshots draw the members (three a rod), each with its grain's id.
    let snapshot = std::fs::read_dir(dir.join("snapshots"))
        .expect("the run folder")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("particles_"))
        })
        .expect("a VTU snapshot");
    let text = std::fs::read_to_string(&snapshot).expect("the snapshot");
    assert!(
        text.contains("Name=\"body\""),
        "the snapshot names each sphere's grain"
    );
}

#[test]
fn a_run_of_rods_keeps_its_bits_on_two_threads_and_across_a_resume() {
    // The same case on one thread and on two, the second interrupted and resumed: the same
    // summary, crossings and N(t) to the byte.
    let root = tempfile::tempdir().expect("temporary directory");
    // 150 rods: 75 a thread, past the 64 a thread at which the clumps' pass is shared.
    let case = rods(150, 0.3, "vtu_interval = 0.0");
    let one = root.path().join("one");
    let two = root.path().join("two");
    run_dir::finished(&case, &one, 1, false);
    let cut = RunOptions {
        threads: 2,
        chunk_limit: Some(40),
        ..RunOptions::default()
    };
    assert!(matches!(
        run_case(&case, &two, &cut).expect("the first part runs"),
        RunOutcome::Interrupted
    ));
    run_dir::finished(&case, &two, 2, false);
    for file in ["summary.json", "crossings.csv", "remaining.csv"] {
        let a = std::fs::read(one.join(file)).expect("one thread's file");
        let b = std::fs::read(two.join(file)).expect("two threads' file");
        assert!(a == b, "{file} differs between one thread and two resumed");
    }
}

#[test]
fn the_cost_block_times_whole_rods_and_counts_their_members_in_memory() {
    // Rods of aspect ratio 2 have three beads: the timed block holds whole grains, its speed
    // is per grain (three spheres' work), and memory is reckoned per sphere.
    let case = rods(300, 1.5, "");
    let speed = run::cost::measure_speed(&case, 300, 1).expect("a timed block of rods");
    assert_eq!(
        speed.grains, 300,
        "the block holds the run's grains, fewer than the cap"
    );
    assert_eq!(speed.spheres, 3 * speed.grains, "three beads a grain");
    // Unrotated rods 0.995 of their extent apart touch their neighbours end to end and side
    // by side: 4.5 contacts a bead at the start (walls counted), loosening to about 2.8 over
    // the timed steps as the overlaps push the block to its walls, as many as a flowing bed
    // holds. A block spaced by the grains' equal-volume diameter, wider than the rods, has
    // under one.
    assert!(speed.contacts_per_particle > 2.0, "{speed:?}");
    let mut spheres = case.clone();
    spheres.particles.components[0].shape = None;
    let rods_estimate =
        run::cost::CostEstimate::from_parts(&case, 300, Default::default(), Some(speed), (0, 0.0));
    let spheres_estimate = run::cost::CostEstimate::from_parts(
        &spheres,
        300,
        Default::default(),
        Some(speed),
        (0, 0.0),
    );
    // The memory of 900 spheres against 300, at BYTES_PER_SPHERE each (exact arithmetic).
    let extra = rods_estimate.peak_memory - spheres_estimate.peak_memory;
    assert!(
        (extra - 600.0 * run::cost::BYTES_PER_SPHERE).abs() < 1e-6 * extra,
        "{extra} bytes"
    );
}
