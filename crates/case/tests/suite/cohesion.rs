//! Cohesion in the case file: the `cohesion` table of `[contact]`, `[wall]` and `[[pairs]]`
//! (docs/physics.md §2.4–2.7), read into the engine's laws and written back to the same bits.

use case::parse_case;
use dem::Cohesion;

/// `text` read as a case; the messages of its errors if refused.
fn errors_of(text: &str) -> Vec<String> {
    match parse_case(text, "case.toml", &[]) {
        Ok(case) => panic!("accepted: {case:?}"),
        Err(errors) => errors.errors.iter().map(ToString::to_string).collect(),
    }
}

#[test]
fn each_law_is_read_into_the_engine_and_round_trips() {
    let text = "version = 1\n\
        [contact]\ncohesion = { law = \"jkr\", work_of_adhesion = 0.05 }\n\
        [wall]\ncohesion = { law = \"liquid_bridge\", volume = 1e-12, surface_tension = 0.072, \
        contact_angle_deg = 20.0 }\n";
    let case = parse_case(text, "wet.toml", &[]).expect("a valid cohesive case");
    assert_eq!(
        case.contact.particle.cohesion,
        Cohesion::Jkr {
            work_of_adhesion: 0.05
        }
    );
    assert_eq!(
        case.wall.interaction.cohesion,
        Cohesion::LiquidBridge {
            volume: 1e-12,
            surface_tension: 0.072,
            contact_angle: 20f64.to_radians(),
        }
    );
    // The resolved text gives the angle in radians, which reads back to the same bits.
    let resolved = case.to_toml_string();
    assert!(resolved.contains("law = \"liquid_bridge\""), "{resolved}");
    let back = parse_case(&resolved, "resolved.toml", &[]).expect("resolved text is valid");
    assert_eq!(back, case);
    assert_eq!(back.to_toml_string(), resolved);
}

#[test]
fn a_dry_case_writes_no_cohesion_and_none_means_dry() {
    let dry = parse_case("version = 1\n", "dry.toml", &[]).expect("the default case");
    assert!(!dry.to_toml_string().contains("cohesion"));
    let none = parse_case(
        "version = 1\n[contact]\ncohesion = { law = \"none\" }\n",
        "none.toml",
        &[],
    )
    .expect("law none");
    assert_eq!(none, dry);
}

#[test]
fn pairs_carry_their_cohesion_and_unlisted_pairs_mix() {
    // Two JKR self-pairs mix to the geometric mean of their works of adhesion.
    let text = "version = 1\n\
        [materials.a]\ndensity = 2500.0\nyoungs_modulus = 1e8\npoisson_ratio = 0.3\n\
        [materials.b]\ndensity = 2500.0\nyoungs_modulus = 1e8\npoisson_ratio = 0.3\n\
        [[pairs]]\nmaterials = [\"a\", \"a\"]\nrestitution = 0.5\nfriction = 0.3\n\
        cohesion = { law = \"jkr\", work_of_adhesion = 0.04 }\n\
        [[pairs]]\nmaterials = [\"b\", \"b\"]\nrestitution = 0.5\nfriction = 0.3\n\
        cohesion = { law = \"jkr\", work_of_adhesion = 0.09 }\n\
        [particles]\ncount = 100\n\
        [[particles.components]]\ndiameter = 0.003\nmaterial = \"a\"\nfraction = 0.5\n\
        [[particles.components]]\ndiameter = 0.003\nmaterial = \"b\"\nfraction = 0.5\n\
        [wall]\nmaterial = \"rigid\"\n";
    let case = parse_case(text, "mix.toml", &[]).expect("a valid table");
    let table = case.materials.as_ref().expect("a material table");
    let ab = table.interaction("a", "b").expect("mixable");
    // √(0.04 × 0.09) = 0.06 up to the square root's rounding.
    match ab.cohesion {
        Cohesion::Jkr { work_of_adhesion } => assert!((work_of_adhesion - 0.06).abs() < 1e-15),
        other => panic!("mixed to {other:?}"),
    }
    let back = parse_case(&case.to_toml_string(), "resolved.toml", &[]).expect("round trip");
    assert_eq!(back, case);
}

#[test]
fn bad_cohesion_values_are_refused_naming_key_and_range() {
    let cases = [
        (
            "[contact]\ncohesion = { law = \"jkr\" }\n",
            "contact.cohesion.work_of_adhesion: required by this law; allowed: > 0 J/m²",
        ),
        (
            "[contact]\ncohesion = { law = \"jkr\", work_of_adhesion = 0.0 }\n",
            "contact.cohesion.work_of_adhesion = 0 J/m²: must be a finite number > 0",
        ),
        (
            "[contact]\ncohesion = { law = \"liquid_bridge\", volume = 1e-12, \
             surface_tension = 0.07, contact_angle = 2.0 }\n",
            "contact.cohesion.contact_angle = 2 rad: must lie in [0, π/2] rad",
        ),
        (
            "[contact]\ncohesion = { law = \"liquid_bridge\", volume = 1e-12, \
             surface_tension = 0.07, contact_angle = 0.1, contact_angle_deg = 5.0 }\n",
            "give one of contact.cohesion.contact_angle and contact.cohesion.contact_angle_deg",
        ),
        (
            "[contact]\ncohesion = { law = \"sjkr\", energy_density = 1e5, volume = 1.0 }\n",
            "contact.cohesion.volume: unknown key; allowed here: law, energy_density",
        ),
        ("[contact]\ncohesion = 5\n", "contact.cohesion"),
    ];
    for (body, expected) in cases {
        let errors = errors_of(&format!("version = 1\n{body}"));
        assert!(
            errors.iter().any(|e| e.contains(expected)),
            "{body}: {errors:?} lacks {expected:?}"
        );
    }
}
