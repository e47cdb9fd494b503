//! Case files: defaults, template, round trip, overrides and derived geometry.

use case::{
    default_case, parse_case, Case, ErrorKind, SizeDistribution, SlabGeometry, TangentialLawSpec,
    WallMaterialSpec, CASE_TEMPLATE,
};

#[test]
fn template_reads_back_to_the_paper_base_case() {
    let case = parse_case(CASE_TEMPLATE, "template.toml", &[]).expect("template must be valid");
    assert_eq!(case, Case::paper_base());
}

#[test]
fn template_mentions_every_key_of_a_resolved_case() {
    // Every key the writer emits (the complete resolved case) must be documented in the
    // template, either live or commented out.
    for line in Case::paper_base().to_toml_string().lines() {
        let line = line.trim();
        if line.starts_with('#') || line.starts_with('[') || line.is_empty() {
            continue;
        }
        let key = line.split('=').next().unwrap().trim();
        assert!(
            CASE_TEMPLATE.contains(&format!("{key} =")),
            "template lacks key `{key}`"
        );
    }
    for alternative in [
        "outlet_offset",
        "rayleigh_fraction",
        "size_distribution",
        "\"rigid\"",
    ] {
        assert!(
            CASE_TEMPLATE.contains(alternative),
            "template lacks {alternative}"
        );
    }
}

#[test]
fn paper_base_case_matches_table_one() {
    let case = Case::paper_base();
    // Exact comparisons: these are the literal numbers of Table 1 and the base case.
    assert_eq!(case.particles.count, 3000);
    assert_eq!(case.particles.components.len(), 1);
    assert_eq!(
        case.particles.components[0].size,
        SizeDistribution::Monodisperse { diameter: 3.0e-3 }
    );
    assert_eq!(case.geometry.slab().unwrap().width, 0.1);
    assert_eq!(case.geometry.slab().unwrap().outlet_width, 0.03);
    assert_eq!(case.geometry.slab().unwrap().hopper_angle_deg, 90.0);
    assert_eq!(case.geometry.slab().unwrap().outlet_offset(), 0.0);
    assert_eq!(case.wall.interaction.friction, 0.5);
    assert_eq!(case.contact.particle.restitution, 0.2);
    // Physics spec §1.1: t_R = 2.5684e-5 s, so 2.5 µs is 0.0973 t_R (4 printed digits).
    assert!((case.particles.rayleigh_time() - 2.5684e-5).abs() < 1e-9);
    assert!((case.rayleigh_fraction() - 0.0973).abs() < 1e-4);
}

#[test]
fn resolved_case_round_trips_through_its_toml_text() {
    let mut case = Case::paper_base();
    case.seed = 987_654_321;
    case.geometry = case::Geometry::Slab(SlabGeometry {
        hopper_angle_deg: 30.0,
        outlet_gap: 0.006,
        ..SlabGeometry::paper()
    });
    case.particles.components[0].size = SizeDistribution::Normal {
        mean: 2.9e-3,
        std_dev: 1.0e-4,
        min: 2.7e-3,
        max: 3.0e-3,
    };
    case.wall.material = WallMaterialSpec::Custom(case::MaterialSpec {
        density: 7800.0,
        shear_modulus: 7.9e10,
        poisson_ratio: 0.3,
    });
    case.contact.tangential = TangentialLawSpec::MindlinDeresiewicz;
    case.time_step = 1.0e-6 / 3.0;
    let text = case.to_toml_string();
    let back = parse_case(&text, "resolved.toml", &[]).expect("resolved text must be valid");
    // Exact equality: the writer prints floats in their shortest round-trip form.
    assert_eq!(back, case);

    case.particles.components[0].size = SizeDistribution::Discrete {
        diameters: vec![2.5e-3, 2.75e-3, 3.0e-3],
        fractions: vec![0.25, 0.5, 0.25],
    };
    case.wall.material = WallMaterialSpec::Rigid;
    let back = parse_case(&case.to_toml_string(), "resolved.toml", &[]).unwrap();
    assert_eq!(back, case);
}

#[test]
fn fields_are_off_by_default_and_round_trip_when_given() {
    // Without `[output.fields]` the resolved text is the one written before the section
    // existed (no line of it), so every config hash stays; with it, every key reads back.
    let base = Case::paper_base();
    assert!(base.fields.is_none());
    assert!(!base.to_toml_string().contains("fields"));
    let text = "version = 1\n[output.fields]\nkernel = \"gaussian\"\nwidth = 0.003\n\
                widths = [0.0015, 0.006]\nwindow = 0.25\n";
    let case = parse_case(text, "fields.toml", &[]).expect("valid fields");
    let fields = case.fields.clone().expect("fields on");
    assert_eq!(fields.kernel, case::FieldKernel::Gaussian);
    // The cells default to half the smallest width.
    assert_eq!(fields.cell_size, 0.00075);
    assert_eq!(fields.widths, vec![0.0015, 0.006]);
    let back = parse_case(&case.to_toml_string(), "resolved.toml", &[]).unwrap();
    assert_eq!(back, case);
    // A geometry without an (x, z) or (r, z) grid is refused, naming the section.
    let heap = "version = 1\n[geometry]\nkind = \"heap\"\n[output.fields]\nwidth = 0.003\n";
    let report = parse_case(heap, "heap.toml", &[]).unwrap_err().to_string();
    assert!(report.contains("output.fields"), "{report}");
}

#[test]
fn unclogging_is_off_by_default_and_round_trips_when_given() {
    // Without `[protocol.unclog]` the resolved text has no line of it, so every config hash
    // stays; with it, every key reads back, the region's height defaulting to D + 2d.
    let base = Case::paper_base();
    assert!(base.protocol.unclog.is_none());
    assert!(!base.to_toml_string().contains("unclog"));
    let text = "version = 1\n[protocol.unclog]\navalanches = 40\n";
    let case = parse_case(text, "unclog.toml", &[]).expect("valid unclogging");
    let spec = case.protocol.unclog.expect("unclogging on");
    assert_eq!(spec.method, case::UnclogMethod::AirJet);
    assert_eq!(spec.avalanches, 40);
    // The paper's D = 30 mm and d = 3 mm: 36 mm, to rounding.
    assert!((spec.height - 0.036).abs() < 1e-15, "{spec:?}");
    let back = parse_case(&case.to_toml_string(), "resolved.toml", &[]).unwrap();
    assert_eq!(back, case);
    // The heap test has no outlet to unclog: refused, naming the section.
    let heap = "version = 1\n[geometry]\nkind = \"heap\"\n[protocol.unclog]\n";
    let report = parse_case(heap, "heap.toml", &[]).unwrap_err().to_string();
    assert!(report.contains("protocol.unclog"), "{report}");
}

#[test]
fn gravity_is_written_back_only_when_it_is_not_the_default() {
    // The default g leaves the resolved text as it was before the key existed, so that the
    // configuration hashes of existing runs and beds stay valid.
    let base = Case::paper_base().to_toml_string();
    assert!(!base.contains("gravity"), "{base}");
    let text = "version = 1\ngravity = 9.81\n";
    let explicit = parse_case(text, "g.toml", &[]).unwrap();
    assert_eq!(explicit.to_toml_string(), base);
    // Another g is read, written and read back to the same bits, from the file or --set.
    let text = "version = 1\ngravity = 9.8\n";
    let benchmark = parse_case(text, "g.toml", &[]).unwrap();
    assert_eq!(benchmark.gravity, 9.8);
    let back = parse_case(&benchmark.to_toml_string(), "resolved.toml", &[]).unwrap();
    assert_eq!(back, benchmark);
    let set = parse_case("version = 1\n", "g.toml", &["gravity=3.71".to_string()]).unwrap();
    assert_eq!(set.gravity, 3.71);
    // g = 0 has no discharge and an upward g empties the container through its top; both are
    // refused with the key, the value and the range.
    for bad in ["0.0", "-9.81", "1001.0", "\"earth\""] {
        let errors = parse_case(&format!("version = 1\ngravity = {bad}\n"), "g.toml", &[])
            .unwrap_err()
            .to_string();
        assert!(
            errors.contains("g.toml:2:") && errors.contains("gravity"),
            "{errors}"
        );
        assert!(
            errors.contains("(0, 1000] m/s²") || errors.contains("expected a number"),
            "{errors}"
        );
    }
}

#[test]
fn outlet_offset_is_converted_to_the_gap_from_the_left_wall() {
    let text = "version = 1\n[geometry]\noutlet_width = 0.03\noutlet_offset = 0.02\n";
    let case = parse_case(text, "e.toml", &[]).unwrap();
    // e + s = (L − D)/2 = 0.035 m, so s = 0.015 m; x_c = −e. Tolerance: a few ulps.
    assert!((case.geometry.slab().unwrap().outlet_gap - 0.015).abs() < 1e-15);
    assert!((case.geometry.slab().unwrap().outlet_centre() + 0.02).abs() < 1e-15);
    let (left, right) = case.geometry.slab().unwrap().outlet_edges();
    assert!((left + 0.05 - 0.015).abs() < 1e-15 && (right - left - 0.03).abs() < 1e-15);
}

#[test]
fn set_overrides_replace_file_values_and_their_alternatives() {
    let text = "version = 1\n[geometry]\noutlet_offset = 0.01\n";
    let sets = [
        "geometry.outlet_gap=0".to_string(),
        "contact.tangential=mindlin_deresiewicz".to_string(),
        "particles.count = 1500".to_string(),
    ];
    let case = parse_case(text, "case.toml", &sets).unwrap();
    // Setting the gap must drop the file's offset instead of reporting a conflict.
    assert_eq!(case.geometry.slab().unwrap().outlet_gap, 0.0);
    assert_eq!(
        case.contact.tangential,
        TangentialLawSpec::MindlinDeresiewicz
    );
    assert_eq!(case.particles.count, 1500);
}

#[test]
fn bad_set_overrides_are_reported_with_set_as_the_source() {
    let sets = [
        "geometry.width".to_string(),
        "geometry.outlet_width=\"wide\"".to_string(),
        "geometry..width=1".to_string(),
        "geometry.nonsense=1".to_string(),
    ];
    let errors = default_case(&sets).unwrap_err();
    let text = errors.to_string();
    assert!(
        text.contains("--set: geometry.width: expected key=value"),
        "{text}"
    );
    assert!(text.contains("not a dotted key"), "{text}");
    // The first two problems stop before validation; fix them and see the rest.
    let errors = default_case(
        &sets[1..2]
            .iter()
            .chain(&sets[3..])
            .cloned()
            .collect::<Vec<_>>(),
    )
    .unwrap_err();
    let text = errors.to_string();
    assert!(
        text.contains("--set: geometry.outlet_width = \"wide\": expected a number, found a string"),
        "{text}"
    );
    assert!(
        text.contains("--set: geometry.nonsense: unknown key"),
        "{text}"
    );
}

#[test]
fn every_error_of_a_file_is_reported_at_once() {
    let text = "version = 1\n[geometry]\nwidth = -1.0\nheight = \"tall\"\nbogus = 3\n[contact]\nrestitution = 0.0\n";
    let errors = parse_case(text, "many.toml", &[]).unwrap_err();
    let kinds: Vec<ErrorKind> = errors.errors.iter().map(|e| e.kind).collect();
    assert_eq!(errors.errors.len(), 4, "{errors}");
    assert!(kinds.contains(&ErrorKind::Invalid));
    assert!(kinds.contains(&ErrorKind::WrongType));
    assert!(kinds.contains(&ErrorKind::UnknownKey));
    // Document order: lines 3, 4, 5, 7.
    let lines: Vec<usize> = errors
        .errors
        .iter()
        .map(|e| e.location.line.unwrap())
        .collect();
    assert_eq!(lines, vec![3, 4, 5, 7]);
}

#[test]
fn flat_bottom_hopper_area_is_the_rectangle() {
    let g = SlabGeometry::paper();
    // L·H = 0.1 × 0.4 m²; relative tolerance 1e-12 for rounding only.
    assert!((g.cross_section_area() - 0.04).abs() < 0.04e-12);
    assert_eq!(g.funnel_height(), 0.0);
}

#[test]
fn inclined_plates_remove_the_triangles_below_them() {
    // α = 45°: a plate of run r rises r, so each dead triangle is r²/2.
    let g = SlabGeometry::centred(0.1, 0.4, 3.03e-3, 0.03, 45.0);
    let run: f64 = 0.035;
    let expected = 0.04 - run * run;
    assert!((g.cross_section_area() - expected).abs() < 1e-12);
    assert!((g.funnel_height() - run).abs() < 1e-12);
    // Below the funnel top the container is a trapezoid: width D + 2z at height z.
    let z = 0.01;
    assert!((g.area_below(z) - (0.03 * z + z * z)).abs() < 1e-12);
}

#[test]
fn fill_height_of_the_base_case_is_about_a_quarter_metre() {
    let case = Case::paper_base();
    // 3000 discs of 3 mm cover 0.0212 m²; at area fraction 0.885 in a 0.1 m wide hopper
    // they stand 0.2396 m high. Tolerance 1e-6 m: bisection resolves 1e-9 of H.
    let h = case.fill_height().unwrap();
    let expected = 3000.0 * std::f64::consts::FRAC_PI_4 * 9.0e-6 / 0.885 / 0.1;
    assert!((h - expected).abs() < 1e-6, "{h} vs {expected}");
}

#[test]
fn thick_slab_judges_packing_by_sphere_volume() {
    let text = "version = 1\n[geometry]\nthickness = 0.03\n[particles]\ncount = 30000\n";
    let case = parse_case(text, "thick.toml", &[]).unwrap();
    assert!(case.is_thick_slab());
    // 30000 spheres of 3 mm: 4.24e-4 m³ at φ = 0.64 in a 30 mm slab need 0.0221 m²
    // (rounded to 3 digits here, hence the 1e-4 m² tolerance).
    assert!((case.packed_area() - 0.0221).abs() < 1e-4);
}

#[test]
fn empty_file_is_refused_with_advice() {
    for text in ["", "   \n# only a comment\n", "\u{feff}"] {
        let errors = parse_case(text, "empty.toml", &[]).unwrap_err();
        assert_eq!(errors.errors[0].kind, ErrorKind::Missing);
        assert!(errors
            .to_string()
            .contains("empty.toml: the case file has no keys"));
    }
    // A file holding only the version asks for the base case explicitly.
    assert_eq!(
        parse_case("version = 1", "v.toml", &[]).unwrap(),
        Case::paper_base()
    );
}

#[test]
fn rayleigh_fraction_sets_the_time_step() {
    let text = "version = 1\n[time]\nrayleigh_fraction = 0.05\n";
    let case = parse_case(text, "t.toml", &[]).unwrap();
    // Δt = 0.05 t_R with t_R = 2.5684e-5 s (physics spec §1.1, 5 digits).
    assert!((case.time_step - 0.05 * 2.5684e-5).abs() < 1e-10);
}

#[test]
fn errors_point_at_the_key_in_dotted_inline_and_implicit_tables() {
    // Dotted key at the top level, an inline table, and a table whose parent is implicit:
    // each error must still carry the line and column of its key.
    let text = "version = 1\ngeometry.width = -0.1\ncontact = { friction = -1.0 }\n[particles.material]\ndensity = 0\n";
    let errors = parse_case(text, "forms.toml", &[]).unwrap_err();
    let report = errors.to_string();
    for fragment in [
        "forms.toml:2:10: geometry.width = -0.1 m: must be a finite number > 0",
        "forms.toml:3:13: contact.friction = -1: must be a finite number ≥ 0",
        "forms.toml:5:1: particles.material.density = 0 kg/m³: must be a finite number > 0",
    ] {
        assert!(report.contains(fragment), "lacks `{fragment}`:\n{report}");
    }
}

#[test]
fn an_outlet_of_exactly_three_diameters_is_accepted_and_less_is_not() {
    // 3 × 0.003 m rounds to 0.009000000000000001 in binary; the decimal 0.009 the user
    // writes is the limit itself and must pass, while one part in 10^6 less must not.
    let at_limit = default_case(&["geometry.outlet_width=0.009".into()]);
    assert!(
        at_limit.is_ok(),
        "{:?}",
        at_limit.err().map(|e| e.to_string())
    );
    let below = default_case(&["geometry.outlet_width=0.008999991".into()]);
    let message = below.expect_err("below 3 d").to_string();
    assert!(message.contains("geometry.outlet_width"), "{message}");
    assert!(message.contains("3 particle diameters"), "{message}");
}

/// The cylinder template is a valid silo case, it documents every key its resolved text
/// holds, and that text reads back to the same case (so a run folder's case.toml is exact).
#[test]
fn cylinder_template_is_complete_and_round_trips() {
    let case =
        parse_case(case::CYLINDER_TEMPLATE, "cylinder.toml", &[]).expect("template must be valid");
    let silo = case.geometry.cylinder().expect("a cylinder case");
    assert_eq!(
        (silo.radius, silo.outlet_diameter, silo.hopper_angle_deg),
        (0.1, 0.06, 45.0)
    );
    // E = 1e9 Pa, ν = 0.2: G = E / (2 (1 + ν)).
    assert_eq!(
        case.particles.components[0].material.shear_modulus,
        1.0e9 / 2.4
    );
    let text = case.to_toml_string();
    for line in text.lines() {
        let line = line.trim();
        if line.starts_with('#') || line.starts_with('[') || line.is_empty() {
            continue;
        }
        let key = line.split('=').next().unwrap().trim();
        // The resolved text writes G; the template gives E, its documented alternative.
        let key = if key == "shear_modulus" {
            "youngs_modulus"
        } else {
            key
        };
        assert!(
            case::CYLINDER_TEMPLATE.contains(&format!("{key} =")),
            "template lacks key `{key}`"
        );
    }
    let back = parse_case(&text, "resolved.toml", &[]).expect("resolved text is valid");
    assert_eq!(back, case);
}
