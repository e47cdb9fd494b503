//! Coarse-grained parcels in the case file (`particles.coarse_graining`, docs/physics.md
//! §2.8): the parcels the run simulates, the grains written back, and the refusals.

use case::{load_case, parse_case, SizeDistribution};

/// The reduced benchmark silo with `sets` applied.
fn silo(sets: &[&str]) -> Result<case::Case, case::ConfigErrors> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../cases/dosta2024-silo-reduced.toml"
    );
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    load_case(std::path::Path::new(path), &sets)
}

fn messages(errors: case::ConfigErrors) -> String {
    errors
        .errors
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn parcels_are_kappa_times_the_grains_and_their_count_over_kappa_cubed() {
    // 20 000 grains of 4 mm: κ = 2 gives 2500 parcels of 8 mm exactly; κ = 1.5 gives
    // 20 000 / 3.375 = 5925.9, rounded to 5926.
    let grains = silo(&[]).expect("the shipped case");
    assert!(grains.particles.coarse_graining.is_none());
    let two = silo(&["particles.coarse_graining=2.0"]).expect("κ = 2");
    assert_eq!(two.particles.count, 2500);
    assert_eq!(
        two.particles.components[0].size,
        SizeDistribution::Monodisperse { diameter: 0.008 }
    );
    let record = two
        .particles
        .coarse_graining
        .as_ref()
        .expect("the grains kept");
    assert_eq!((record.factor, record.grain_count), (2.0, 20_000));
    assert_eq!(record.grains_per_parcel(), 8.0);
    assert_eq!(two.particles.grain_mean_diameter(), 0.004);
    // The material, and so the density and the elastic constants, are the grains'.
    assert_eq!(
        two.particles.components[0].material,
        grains.particles.components[0].material
    );
    let one_and_a_half = silo(&["particles.coarse_graining=1.5"]).expect("κ = 1.5");
    assert_eq!(one_and_a_half.particles.count, 5926);
}

#[test]
fn kappa_one_is_the_grains_themselves_to_the_bit() {
    let plain = silo(&[]).expect("the shipped case");
    let one = silo(&["particles.coarse_graining=1.0"]).expect("κ = 1");
    assert_eq!(one, plain);
    assert_eq!(one.to_toml_string(), plain.to_toml_string());
}

#[test]
fn the_resolved_case_gives_the_grains_and_kappa_and_reads_back_the_same() {
    let case = silo(&["particles.coarse_graining=1.5"]).expect("κ = 1.5");
    let text = case.to_toml_string();
    assert!(text.contains("count = 20000"), "{text}");
    assert!(text.contains("coarse_graining = 1.5"), "{text}");
    assert!(text.contains("diameter = 0.004"), "{text}");
    let back = parse_case(&text, "resolved.toml", &[]).expect("the resolved text");
    assert_eq!(back, case);
    assert_eq!(back.to_toml_string(), text);
}

#[test]
fn a_mixture_scales_every_component_and_keeps_its_fractions() {
    let text = "version = 1\n[particles]\ncount = 27000\ncoarse_graining = 3.0\n\
        [[particles.components]]\nname = \"small\"\nfraction = 0.25\ndiameter = 0.002\n\
        [[particles.components]]\nname = \"large\"\nfraction = 0.75\ndiameter = 0.003\n\
        [geometry]\noutlet_width = 0.05\nwidth = 0.3\nthickness = 0.02\n";
    let case = parse_case(text, "mix.toml", &[]).expect("a coarse-grained mixture");
    assert_eq!(case.particles.count, 1000);
    let sizes: Vec<f64> = case
        .particles
        .components
        .iter()
        .map(|c| c.size.max_diameter())
        .collect();
    assert_eq!(sizes, [0.006, 0.009000000000000001]);
    assert_eq!(case.particles.number_fractions(), [0.25, 0.75]);
    let back = parse_case(&case.to_toml_string(), "back.toml", &[]).expect("written back");
    assert_eq!(back, case);
}

#[test]
fn kappa_out_of_range_or_leaving_no_parcel_is_refused_with_the_key() {
    for (value, why) in [
        ("0.5", "must lie in [1, 20]"),
        ("25.0", "must lie in [1, 20]"),
        ("nan", "must lie in [1, 20]"),
    ] {
        let text = messages(silo(&[&format!("particles.coarse_graining={value}")]).unwrap_err());
        assert!(
            text.contains("particles.coarse_graining") && text.contains(why),
            "{value}: {text}"
        );
    }
    let text = messages(silo(&["particles.count=3", "particles.coarse_graining=3.0"]).unwrap_err());
    assert!(text.contains("fewer than one parcel"), "{text}");
}

#[test]
fn the_outlet_is_checked_against_the_parcels_and_the_message_names_kappa() {
    // D = 0.02 m is 5 grains of 4 mm but 2.5 parcels of κ = 2: refused, naming both keys.
    assert!(silo(&["geometry.outlet_diameter=0.02"]).is_ok());
    let text = messages(
        silo(&[
            "geometry.outlet_diameter=0.02",
            "particles.coarse_graining=2.0",
        ])
        .unwrap_err(),
    );
    assert!(
        text.contains("geometry.outlet_diameter")
            && text.contains("particles.diameter")
            && text.contains("particles.coarse_graining = 2"),
        "{text}"
    );
}

#[test]
fn bridge_volumes_are_the_grains_and_checked_against_the_grains() {
    // V ≤ 0.1 R³ of the smallest grain (R = 2 mm: 8·10⁻¹⁰ m³): 5·10⁻¹⁰ m³ passes with κ = 2
    // (the parcels hold κ³ V, checked against κ R), 10⁻⁹ m³ is refused either way.
    let wet = |v: &str| {
        format!("contact.cohesion={{ law = \"liquid_bridge\", volume = {v}, surface_tension = 0.072, contact_angle = 0.0 }}")
    };
    assert!(silo(&[&wet("5e-10"), "particles.coarse_graining=2.0"]).is_ok());
    let text = messages(silo(&[&wet("1e-9"), "particles.coarse_graining=2.0"]).unwrap_err());
    assert!(text.contains("contact.cohesion"), "{text}");
}
