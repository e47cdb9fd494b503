//! Coarse-grained fields of a run (`[output.fields]`, docs/physics.md §7.13): the bed at rest
//! against its weight, the mass the fields hold, the files and the check of the width.

use crate::tiny_hopper::tiny_case;
use run::{run_case, RunOptions, RunOutcome};

/// Reads one point-data array of a `.vti` written by the run.
fn array(xml: &str, name: &str) -> Vec<f64> {
    let start = xml
        .find(&format!("Name=\"{name}\""))
        .unwrap_or_else(|| panic!("{name} in the file"));
    let body = &xml[start..];
    let open = body.find('>').expect("opening tag") + 1;
    let close = body.find("</DataArray>").expect("closing tag");
    body[open..close]
        .split_whitespace()
        .map(|x| x.parse().expect("a number"))
        .collect()
}

#[test]
#[ignore = "a whole tiny run with fields: about 10 s; cargo test -p hopperflow-run --test suite fields -- --ignored --nocapture"]
fn the_tiny_bed_at_rest_carries_its_weight_and_its_fields_hold_its_mass() {
    // The tiny slab (250 spheres of 3 mm, 50 mm wide, 3.3 mm thick) settles, and its field at
    // rest (Lucy, w = d/2) is written with the discharge's at three widths.
    //
    // Mass: Σ ρ ΔV over the grid against the particles' mass. The grid stops at the side
    // walls, so the part of the kernel of the spheres touching a wall that reaches beyond it
    // is lost: about (w/4)/(W/2) of their share, a few per cent at most. Tolerance 5 %.
    //
    // Weight: averaged across the width, σ_zz at height z must be the weight of the material
    // above per unit area, ∫ρ g dz from the field's own density, less what the walls carry
    // by friction (Janssen's screening). The walls carry a few per cent here (about 3 %
    // seen: the bed is only 45 mm high, 1.5 widths); tolerance: from 85 % (screening far
    // beyond what this bed shows) to 103 % (the field's graininess over one cell row; a
    // field that ignored the wall contacts or doubled a branch misses by tens of per cent).
    // Checked in the lower half of the bed above 2 d, where the fill's last grains have
    // long landed; near the top the bed was still loaded by them when the gate opened.
    let root = tempfile::tempdir().expect("temporary directory");
    let case = tiny_case(&[
        "output.checkpoint_interval=0.0",
        "protocol.time_limit=0.1",
        "output.fields.width=0.0015",
        "output.fields.widths=[0.0015, 0.003, 0.006]", // the first is the width itself,
        "output.fields.window=0.05",
        "output.fields.interval=0.005",
    ]);
    let options = RunOptions {
        pictures: false,
        ..RunOptions::default()
    };
    let summary = match run_case(&case, root.path(), &options).expect("the tiny case runs") {
        RunOutcome::Finished(summary) => *summary,
        RunOutcome::Interrupted => panic!("interrupted"),
    };
    let fields = summary.fields.expect("the fields' summary");
    eprintln!("{fields:?}");
    let (field_mass, mass) = (
        fields.settled_field_mass.expect("settled frame"),
        fields.settled_particle_mass.expect("settled frame"),
    );
    assert!(
        (field_mass - mass).abs() < 0.05 * mass,
        "{field_mass} against {mass}"
    );
    assert_eq!(fields.widths.len(), 2, "three distinct widths, two steps");
    for name in [
        "fields.vti",
        "fields_settled.vti",
        "fields_w2.vti",
        "field_widths.csv",
    ] {
        assert!(root.path().join(name).exists(), "{name}");
    }

    let xml = std::fs::read_to_string(root.path().join("fields_settled.vti")).unwrap();
    let density = array(&xml, "density_kg_m3");
    let stress = array(&xml, "stress_Pa");
    let h = fields.cell_size;
    let columns = (0.05 / h).ceil() as usize;
    let rows = density.len() / columns;
    let g = case.gravity;
    let z_of = |row: usize| -3.0 * h + (row as f64 + 0.5) * h;
    let row_mean = |r: usize, f: &dyn Fn(usize) -> f64| {
        (0..columns).map(|c| f(r * columns + c)).sum::<f64>() / columns as f64
    };
    // The weight above each row per unit cross-section, ∫ρ g dz from the field's own density.
    let above = |r: usize| (r..rows).map(|q| row_mean(q, &|k| density[k])).sum::<f64>() * h * g;
    let bed_top = (0..rows)
        .rev()
        .find(|&r| row_mean(r, &|k| density[k]) > 500.0)
        .map_or(0.0, z_of);
    let mut checked = 0;
    for r in 0..rows {
        let z = z_of(r);
        if !(z > 0.006 && z < 0.5 * bed_top) {
            continue;
        }
        let (sigma, weight) = (row_mean(r, &|k| stress[k * 9 + 8]), above(r));
        eprintln!("z {z:.4} m: <σ_zz> {sigma:.1} Pa, weight above {weight:.1} Pa");
        assert!(
            sigma > 0.85 * weight && sigma < 1.03 * weight,
            "at z = {z}: σ_zz {sigma} Pa against the weight above, {weight} Pa"
        );
        checked += 1;
    }
    assert!(
        checked >= 5,
        "the bed's lower half has rows ({bed_top} m high)"
    );
}
