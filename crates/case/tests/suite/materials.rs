//! Material tables and mixtures in the case file: `[materials.NAME]`, `[[pairs]]`,
//! `particles.material`, `wall.material` naming a material, `[[particles.components]]` and
//! `particles.fraction_by` (docs/physics.md §1.2, cases/README.md).

use case::{
    default_case, mass_fractions_from_number, number_fractions_from_mass, parse_case,
    FractionBasis, SizeDistribution, WallMaterialSpec,
};

/// The benchmark's table as cases/README.md writes it, between its markers.
fn readme_table() -> String {
    let readme = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../cases/README.md"
    ))
    .expect("cases/README.md");
    let start = readme
        .find("<!-- dosta2024-table -->")
        .expect("the table's marker");
    let block = &readme[start..];
    let body = &block[block.find("```toml\n").expect("a TOML block") + 8..];
    body[..body.find("```").expect("the block's end")].to_string()
}

/// `text` read as a case; the messages of its errors if refused.
fn errors_of(text: &str) -> Vec<String> {
    match parse_case(text, "case.toml", &[]) {
        Ok(case) => panic!("accepted: {case:?}"),
        Err(errors) => errors.errors.iter().map(ToString::to_string).collect(),
    }
}

#[test]
fn the_readme_table_is_the_engines_benchmark_table_and_round_trips() {
    let text = format!(
        "version = 1\n{}\n[particles]\nmaterial = \"M1\"\ndiameter = 0.003\n\
         [wall]\nmaterial = \"steel\"\n",
        readme_table()
    );
    let case = parse_case(&text, "dosta.toml", &[]).expect("the README's table is valid");
    assert_eq!(case.materials, Some(dem::MaterialTable::dosta2024()));
    let c = &case.particles.components[0];
    assert_eq!(c.material_name.as_deref(), Some("M1"));
    assert_eq!(c.material.density, 2500.0);
    // G = E / (2(1 + ν)) for the Rayleigh time.
    assert!((c.material.shear_modulus - 1.0e9 / 2.4).abs() < 1e-3);
    assert_eq!(case.wall.material, WallMaterialSpec::Named("steel".into()));
    let resolved = case.to_toml_string();
    // The table's coefficients live in [[pairs]] only.
    assert!(!resolved.contains("\n[contact]\nfriction"), "{resolved}");
    let back = parse_case(&resolved, "resolved.toml", &[]).expect("resolved text is valid");
    assert_eq!(back, case);
    assert_eq!(back.to_toml_string(), resolved);
}

#[test]
fn same_walls_with_a_table_are_the_particles_one_material() {
    let text = format!(
        "version = 1\n{}\n[particles]\nmaterial = \"M2\"\ndiameter = 0.003\n",
        readme_table()
    );
    let case = parse_case(&text, "case.toml", &[]).unwrap();
    assert_eq!(case.wall.material, WallMaterialSpec::Named("M2".into()));
}

#[test]
fn table_keys_that_do_not_belong_are_refused_at_their_lines() {
    let table = readme_table();
    let lines_before = 1 + table.lines().count() + 1;
    // Two particle materials: the walls cannot be "the same".
    let text = format!(
        "version = 1\n{table}\n[particles]\ncount = 100\n\
         [[particles.components]]\ndiameter = 0.003\nmaterial = \"M1\"\nfraction = 0.5\n\
         [[particles.components]]\ndiameter = 0.003\nmaterial = \"M2\"\nfraction = 0.5\n\
         [wall]\nfriction = 0.3\n"
    );
    let errors = errors_of(&text);
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].contains(&format!(
            "case.toml:{}:2: wall.material: the particles are of several materials",
            lines_before + 11
        )),
        "{errors:?}"
    );
    // A named wall takes its coefficients from [[pairs]].
    let text = format!(
        "version = 1\n{table}\n[particles]\nmaterial = \"M1\"\n[wall]\nmaterial = \"steel\"\n\
         restitution = 0.3\n"
    );
    let errors = errors_of(&text);
    assert_eq!(
        errors,
        vec![format!(
            "case.toml:{}:1: wall.restitution = 0.3: not used: the walls are of a named \
             material: each particle material meets them with its [[pairs]] entry (or the \
             mixing rules); give it in [[pairs]]",
            lines_before + 5
        )]
    );
    // With [materials], the particles name theirs.
    let errors = errors_of(&format!("version = 1\n{table}\n[particles]\ncount = 10\n"));
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].contains(
            "particles.material: required with [materials]: the particles' \
                            material, one of M1, M2, steel"
        ),
        "{errors:?}"
    );
    let errors = errors_of(&format!(
        "version = 1\n{table}\n[particles.material]\ndensity = 2000.0\n"
    ));
    assert!(
        errors[0].contains("particles.material: the case defines [materials]: name one of them"),
        "{errors:?}"
    );
    // Without a table, a name means nothing.
    let errors = errors_of("version = 1\n[particles]\nmaterial = \"M1\"\n");
    assert_eq!(
        errors,
        vec![
            "case.toml:3:1: particles.material = \"M1\": names a material, but the case has \
              no [materials] table; define it as [materials.NAME] (density, youngs_modulus or \
              shear_modulus, poisson_ratio), or give the properties in a [particles.material] \
              table"
                .to_string()
        ]
    );
}

#[test]
fn every_problem_of_a_table_is_reported_at_its_key_and_line() {
    let text = "version = 1
[materials.same]
density = 2500.0
youngs_modulus = 1.0e9
poisson_ratio = 0.2
[materials.M1]
density = -1.0
poisson_ratio = 0.2
[[pairs]]
materials = [\"M1\", \"M1\"]
restitution = 0.5
[[pairs]]
materials = [\"M1\", \"X\"]
restitution = 0.5
friction = 0.1
[[pairs]]
materials = [\"M1\", \"M1\"]
restitution = 0.5
friction = 0.2
rolling_friction = -0.1
[[pairs]]
materials = [\"M1\"]
restitution = 0.5
friction = 0.1
[particles]
material = \"M1\"
";
    let errors = errors_of(text);
    let expected = [
        "case.toml:2:12: materials.same = \"same\": a material's name must be letters, digits, \
         `_` or `-`, and not \"same\" or \"rigid\"",
        "case.toml:6:12: materials.M1: give youngs_modulus (E) or shear_modulus (G) [Pa], > 0 \
         (E = 2G(1 + ν))",
        "case.toml:7:1: materials.M1.density = -1 kg/m³: must be > 0 kg/m³",
        "case.toml:9:1: pairs[0].friction: required: ≥ 0",
        "case.toml:13:20: pairs[1].materials[1] = \"X\": material \"X\" is not defined in \
         [materials] (defined: M1, same)",
        "case.toml:17:14: pairs[2].materials = [\"M1\", \"M1\"]: the pair (M1, M1) is given \
         twice, first as pairs[0], line 9; list each pair once, in either order",
        "case.toml:20:1: pairs[2].rolling_friction = -0.1: must be ≥ 0",
        "case.toml:21:1: pairs[3].materials = [\"M1\"]: must name exactly two materials",
    ];
    for e in expected {
        assert!(
            errors.iter().any(|m| m == e),
            "missing `{e}` in:\n{}",
            errors.join("\n")
        );
    }
    assert_eq!(errors.len(), expected.len(), "{}", errors.join("\n"));
}

#[test]
fn a_pair_the_run_needs_must_be_listed_or_mixable() {
    // M1–M2 is not listed, and M2 has no self-pair to mix from.
    let text = "version = 1
[materials.M1]
density = 2500.0
youngs_modulus = 1.0e9
poisson_ratio = 0.2
[materials.M2]
density = 2000.0
shear_modulus = 2.0e8
poisson_ratio = 0.2
[[pairs]]
materials = [\"M1\", \"M1\"]
restitution = 0.5
friction = 0.3
[particles]
count = 100
[[particles.components]]
diameter = 0.003
material = \"M1\"
fraction = 0.5
[[particles.components]]
diameter = 0.003
material = \"M2\"
fraction = 0.5
[wall]
material = \"rigid\"
";
    let errors = errors_of(text);
    assert!(
        errors.iter().any(|e| e
            == "case.toml:10:3: pairs: the pair (M1, M2) is not listed, and it cannot be mixed \
                from the self-pairs because (M2, M2) is not listed either; list one of them"),
        "{}",
        errors.join("\n")
    );
    // Listing M2's self-pair lets M1–M2 be mixed: e = √(0.5 · 0.4), μ = 2·0.3·0.4/0.7.
    let listed = text.replace(
        "[particles]",
        "[[pairs]]\nmaterials = [\"M2\", \"M2\"]\nrestitution = 0.4\nfriction = 0.4\n[particles]",
    );
    let case = parse_case(&listed, "case.toml", &[]).expect("mixable");
    let mixed = case
        .materials
        .as_ref()
        .unwrap()
        .interaction("M1", "M2")
        .unwrap();
    assert!((mixed.restitution - 0.2f64.sqrt()).abs() < 1e-15);
    assert!((mixed.friction - 0.24 / 0.7).abs() < 1e-15);
    // Rigid walls keep the [wall] coefficients.
    assert_eq!(case.wall.material, WallMaterialSpec::Rigid);
}

#[test]
fn mass_fractions_become_number_fractions_by_mean_particle_mass() {
    // Sizes 1:2 of one material: a large sphere has 8 times the mass, so 50/50 by mass is
    // 8/9 and 1/9 by number.
    let n = number_fractions_from_mass(&[0.5, 0.5], &[1.0, 8.0]);
    assert!((n[0] - 8.0 / 9.0).abs() < 1e-15 && (n[1] - 1.0 / 9.0).abs() < 1e-15);
    // Three components of different masses; a zero mass fraction stays zero.
    let masses = [2.0e-6, 5.0e-6, 1.0e-5];
    let n = number_fractions_from_mass(&[0.2, 0.0, 0.8], &masses);
    // w/m = 1e5, 0, 8e4: n = 5/9, 0, 4/9.
    assert!((n[0] - 5.0 / 9.0).abs() < 1e-15 && n[1] == 0.0 && (n[2] - 4.0 / 9.0).abs() < 1e-15);
    // The inverse gives the mass fractions back.
    let w = mass_fractions_from_number(&n, &masses);
    for (a, b) in w.iter().zip([0.2, 0.0, 0.8]) {
        assert!((a - b).abs() < 1e-15, "{w:?}");
    }
}

#[test]
fn a_mixture_by_mass_resolves_to_its_number_fractions_and_round_trips() {
    let text = "version = 1
[geometry]
kind = \"cylinder\"
radius = 0.04
height = 0.2
outlet_diameter = 0.024
[particles]
count = 2000
fraction_by = \"mass\"
[[particles.components]]
name = \"small\"
diameter = 0.002
fraction = 0.5
[[particles.components]]
name = \"large\"
fraction = 0.5
[particles.components.size_distribution]
kind = \"uniform\"
min = 0.0038
max = 0.0042
";
    let case = parse_case(text, "mix.toml", &[]).expect("a valid mixture");
    let p = &case.particles;
    assert!(p.is_mixture());
    assert_eq!(p.fraction_by, FractionBasis::Mass);
    assert_eq!(p.max_diameter(), 0.0042);
    assert_eq!(p.min_diameter(), 0.002);
    // ⟨d³⟩ of the uniform 3.8–4.2 mm: (4.2⁴ − 3.8⁴)/(4 · 0.4) mm³ = 64.16 mm³.
    let large = 64.16e-9;
    let small = 8.0e-9;
    let n = p.number_fractions();
    let expected_small = (0.5 / small) / (0.5 / small + 0.5 / large);
    assert!((n[0] - expected_small).abs() < 1e-12, "{n:?}");
    // The mean diameter is number-weighted over the mixture.
    assert!((p.mean_diameter() - (n[0] * 0.002 + n[1] * 0.004)).abs() < 1e-15);
    // The time step is judged on the smallest particle (2 mm): 2.5e-6 s would be 0.146 t_R.
    assert!((case.particles.rayleigh_time() - 1.7123e-5).abs() < 1e-8);
    let resolved = case.to_toml_string();
    let back = parse_case(&resolved, "resolved.toml", &[]).expect("resolved text is valid");
    assert_eq!(back, case);
}

#[test]
fn components_are_refused_beside_a_diameter_and_need_sizes_and_fractions() {
    let errors = errors_of(
        "version = 1\n[particles]\ndiameter = 0.003\nfraction_by = \"volume\"\n\
         [[particles.components]]\nfraction = 1.0\nname = \"a b\"\n",
    );
    let expected = [
        "case.toml:3:1: particles.diameter: give either particles.diameter (one size) or \
         particles.components (a mixture, each with its own size), not both",
        "case.toml:4:1: particles.fraction_by = \"volume\": must be one of \"number\", \"mass\"",
        "case.toml:5:1: particles.components[0].diameter: required: a diameter [m] or a \
         size_distribution table",
        "case.toml:7:1: particles.components[0].name = \"a b\": a component's name must be \
         letters, digits, `_` or `-` (it heads columns of composition.csv)",
    ];
    for e in expected {
        assert!(
            errors.iter().any(|m| m == e),
            "missing `{e}` in:\n{}",
            errors.join("\n")
        );
    }
    let errors = errors_of("version = 1\n[particles]\nfraction_by = \"mass\"\n");
    assert_eq!(
        errors,
        vec![
            "case.toml:3:1: particles.fraction_by = \"mass\": counts the fractions of \
              particles.components; a case of one size distribution has none"
                .to_string()
        ]
    );
}

#[test]
fn set_overrides_give_a_mixture_in_place_of_the_diameter() {
    let sets = [
        "particles.components=[{name=\"small\", diameter=0.0015, fraction=0.5}, \
         {name=\"large\", diameter=0.003, fraction=0.5}]"
            .to_string(),
        "particles.fraction_by=\"mass\"".to_string(),
        "particles.count=500".to_string(),
    ];
    let case = default_case(&sets).expect("a valid mixture");
    assert_eq!(case.particles.components.len(), 2);
    assert_eq!(
        case.particles.components[1].size,
        SizeDistribution::Monodisperse { diameter: 0.003 }
    );
    // A diameter given afterwards replaces the components again.
    let one_size = [sets[0].clone(), "particles.diameter=0.003".to_string()];
    let case = default_case(&one_size).expect("one size");
    assert!(!case.particles.is_mixture());
}

#[test]
fn cases_without_the_new_keys_resolve_to_the_text_they_always_did() {
    // SHA-256 of the resolved text (what the summary's config hash covers) as the code
    // before material tables and mixtures wrote it: the base case, a polydisperse one, one
    // with a wall material table, and the benchmark silo preset.
    let hash = |case: &case::Case| -> String {
        use sha2::Digest;
        sha2::Sha256::digest(case.to_toml_string().as_bytes())
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect()
    };
    let sets = |s: &[&str]| s.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let preset = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../cases/dosta2024-silo-m1-small.toml");
    let cases = [
        (
            default_case(&[]).unwrap(),
            "a01a60f1a4a99ba13235c7d6d000161563c4f90615552fd1eb4095b6c0d1cc2d",
        ),
        (
            default_case(&sets(&[
                "particles.size_distribution.kind=\"discrete\"",
                "particles.size_distribution.diameters=[0.003,0.0025]",
                "particles.size_distribution.fractions=[0.5,0.5]",
            ]))
            .unwrap(),
            "76fe25c0969ed8c2ee6dfca841b031324f8da13cfa2b992b45173c184f2a4c5e",
        ),
        (
            default_case(&sets(&["wall.material.density=3000.0"])).unwrap(),
            "c3973f424442e1368bee6aee9253f40bab4bdf19e221e838c202c380c4c587cc",
        ),
        (
            // The preset gives the benchmark's g since `gravity` exists; at the default g it
            // is the text it was before.
            case::load_case(&preset, &sets(&["gravity=9.81"])).unwrap(),
            "706062968275990c5838ab99edd360733079030a0994fcd137dcf94cdeb5b01d",
        ),
    ];
    for (case, expected) in cases {
        assert_eq!(hash(&case), expected, "{}", case.to_toml_string());
    }
}
