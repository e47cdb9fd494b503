//! Runs of coarse-grained parcels (`particles.coarse_graining`, docs/physics.md §2.8): the
//! run of parcels is the run of spheres of the parcels' size with the scaled cohesion, bit
//! for bit, and it reports the grains the parcels stand for.

use crate::run_dir::{self, table};

use case::{parse_case, Case};

/// The small cone of `silo.rs` (40 mm radius, 20 mm orifice, 400 spheres of 4 mm), given
/// as `particles` and `cohesion`.
fn silo(particles: &str, cohesion: &str) -> Case {
    let text = format!(
        "version = 1\nseed = 3\n[geometry]\nkind = \"cylinder\"\nradius = 0.04\nheight = 0.1\n\
         outlet_diameter = 0.02\nhopper_angle_deg = 45.0\n[particles]\n{particles}\n\
         [contact]\n{cohesion}\n\
         [time]\ntime_step = 5.0e-6\n[protocol]\nfill_top = 0.06\ntime_limit = 0.6\n\
         settle_kinetic_energy = 1.0e-8\n[measure]\nrate_bin_width = 0.02\n\
         [output]\ncheckpoint_interval = 0.0\nvtu_interval = 0.0\n"
    );
    parse_case(&text, "silo.toml", &[]).expect("a valid silo case")
}

#[test]
fn parcels_run_as_spheres_of_their_size_with_the_cohesion_scaled() {
    // 3200 grains of 2 mm at κ = 2 are 400 parcels of 4 mm; their JKR work of adhesion
    // w = 0.05 J/m² becomes κ w = 0.1 J/m² (docs/physics.md §2.8). The same seed then
    // gives the run of 400 spheres of 4 mm with w = 0.1 J/m², to the bit.
    let root = tempfile::tempdir().expect("temporary directory");
    let parcels = silo(
        "count = 3200\ndiameter = 0.002\ncoarse_graining = 2.0",
        "cohesion = { law = \"jkr\", work_of_adhesion = 0.05 }",
    );
    let spheres = silo(
        "count = 400\ndiameter = 0.004",
        "cohesion = { law = \"jkr\", work_of_adhesion = 0.1 }",
    );
    let a = run_dir::finished(&parcels, &root.path().join("parcels"), 1, false);
    let b = run_dir::finished(&spheres, &root.path().join("spheres"), 1, false);
    assert_eq!(a.particles, 400);
    assert!(a.discharged_mass > 0.0, "nothing discharged");
    assert_eq!(a.discharged_mass.to_bits(), b.discharged_mass.to_bits());
    assert_eq!(a.discharge_time.to_bits(), b.discharge_time.to_bits());
    assert_eq!(
        a.discharge_rate.to_bits(),
        b.discharge_rate.to_bits(),
        "W {} against {}",
        a.discharge_rate,
        b.discharge_rate
    );
    assert!(b.coarse_graining.is_none());

    // The grains behind the parcels: κ³ = 8 a parcel, D/(κd) = 5 and D/d = 10, and the
    // discharged mass in grains of 2 mm (mass over ρ π d³/6).
    let c = a.coarse_graining.expect("the grains reported");
    assert_eq!((c.factor, c.grains_per_parcel, c.grains), (2.0, 8.0, 3200));
    assert_eq!(c.grain_diameter, 0.002);
    assert!((c.outlet_parcels - 5.0).abs() < 1e-12 && (c.outlet_grains - 10.0).abs() < 1e-12);
    let grain_mass = 2500.0 * std::f64::consts::PI * 0.002f64.powi(3) / 6.0;
    assert!((c.discharged_grains - a.discharged_mass / grain_mass).abs() < 1e-6);
    // remaining.csv counts the parcels and, in a fourth column, the grains: 8 each.
    let remaining = table(&root.path().join("parcels").join("remaining.csv"));
    assert_eq!(remaining[0][1], 400.0);
    for row in &remaining {
        assert_eq!(row[3], 8.0 * row[1], "at t = {}", row[0]);
    }
}
