//! Material tables (docs/physics.md §1.2): the Dosta et al. (2024) benchmark table with the
//! E*, G* of each pair against hand-computed values, the mixing of unlisted pairs, the
//! refusal of every kind of inconsistent table with its key in the message, and a table
//! installed into a simulation, down to a sphere sliding on a wall with its own material's
//! friction.

use approx::assert_relative_eq;
use dem::material::{mixed_friction, mixed_restitution, MODULUS_TOLERANCE};
use dem::{
    DVec3, DemError, Interaction, Material, MaterialEntry, MaterialId, MaterialTable,
    MaterialTableError, PairEntry, ParticleInit, Simulation, SimulationConfig, SimulationState,
    Wall, WallId, WallMaterial, FLAG_ROTATION_LOCKED,
};

/// Relative room for round-off when a value computed in a few floating-point operations is
/// compared with its closed form.
const ROUND_OFF: f64 = 1e-14;

fn pair(a: &str, b: &str, restitution: f64, friction: f64) -> PairEntry {
    PairEntry::new(
        a,
        b,
        Interaction {
            friction,
            rolling_friction: 0.0,
            restitution,
            cohesion: dem::Cohesion::None,
        },
    )
}

#[test]
fn the_dosta_table_lists_every_pair_with_the_benchmark_moduli() {
    let table = MaterialTable::dosta2024();
    assert_eq!(table.check(), Ok(()));
    assert_eq!(table.names().collect::<Vec<_>>(), ["M1", "M2", "steel"]);
    // The benchmark's materials, exactly as given.
    for (name, e, rho) in [
        ("M1", 1.0e9, 2500.0),
        ("M2", 0.5e9, 2000.0),
        ("steel", 210.0e9, 7200.0),
    ] {
        let m = table.material(name).expect("defined");
        assert_eq!(
            m,
            Material {
                density: rho,
                youngs_modulus: e,
                poisson_ratio: 0.2
            },
            "{name}"
        );
    }
    // With ν = 0.2 for all: 1/E* = 0.96 S and 1/G* = (2 − ν)·2(1 + ν) S = 4.32 S, where
    // S = 1/E_a + 1/E_b. The closed forms below write S out for each pair; the decimals are
    // the same numbers to seven digits, computed by hand from them.
    let cases = [
        // (a, b, e, μ, E* closed form, G* closed form, E* printed, G* printed)
        (
            "M1",
            "M1",
            0.5,
            0.3,
            1e9 / 1.92,
            1e9 / 8.64,
            5.208333e8,
            1.157407e8,
        ),
        (
            "M1",
            "M2",
            0.45,
            0.2,
            1e9 / 2.88,
            1e9 / 12.96,
            3.472222e8,
            7.716049e7,
        ),
        (
            "M1",
            "steel",
            0.4,
            0.2,
            210e9 / (0.96 * 211.0),
            210e9 / (4.32 * 211.0),
            1.036730e9,
            2.303844e8,
        ),
        (
            "M2",
            "M2",
            0.4,
            0.4,
            1e9 / 3.84,
            1e9 / 17.28,
            2.604167e8,
            5.787037e7,
        ),
        (
            "M2",
            "steel",
            0.4,
            0.2,
            210e9 / (0.96 * 421.0),
            210e9 / (4.32 * 421.0),
            5.195962e8,
            1.154658e8,
        ),
        (
            "steel",
            "steel",
            0.6,
            0.5,
            105e9 / 0.96,
            105e9 / 4.32,
            1.093750e11,
            2.430556e10,
        ),
    ];
    for (a, b, e, mu, e_star, g_star, e_printed, g_printed) in cases {
        for (x, y) in [(a, b), (b, a)] {
            let c = table.coefficients(x, y).expect("listed pair");
            assert_eq!(c.restitution, e, "({x}, {y})");
            assert_eq!(c.friction, mu, "({x}, {y})");
            assert_eq!(c.rolling_friction, 0.0, "({x}, {y}): no rolling resistance");
            assert_relative_eq!(c.e_star, e_star, max_relative = ROUND_OFF);
            assert_relative_eq!(c.g_star, g_star, max_relative = ROUND_OFF);
            // Seven printed digits: half a unit in the seventh digit, relative ≤ 5e-7.
            assert_relative_eq!(c.e_star, e_printed, max_relative = 5e-7);
            assert_relative_eq!(c.g_star, g_printed, max_relative = 5e-7);
        }
    }
}

#[test]
fn the_dosta_table_reads_from_its_documented_layout() {
    // The serde layout a case file uses: materials by name, pairs as a list; rolling friction
    // may be left out (0) and either modulus given.
    let text = r#"{
        "materials": {
            "M1": { "youngs_modulus": 1.0e9, "poisson_ratio": 0.2, "density": 2500 },
            "M2": { "youngs_modulus": 0.5e9, "poisson_ratio": 0.2, "density": 2000 },
            "steel": { "youngs_modulus": 210e9, "poisson_ratio": 0.2, "density": 7200 }
        },
        "pairs": [
            { "materials": ["M1", "M1"], "restitution": 0.5, "friction": 0.3, "rolling_friction": 0 },
            { "materials": ["M1", "M2"], "restitution": 0.45, "friction": 0.2, "rolling_friction": 0 },
            { "materials": ["M1", "steel"], "restitution": 0.4, "friction": 0.2, "rolling_friction": 0 },
            { "materials": ["M2", "M2"], "restitution": 0.4, "friction": 0.4, "rolling_friction": 0 },
            { "materials": ["M2", "steel"], "restitution": 0.4, "friction": 0.2, "rolling_friction": 0 },
            { "materials": ["steel", "steel"], "restitution": 0.6, "friction": 0.5, "rolling_friction": 0 }
        ]
    }"#;
    let read: MaterialTable = serde_json::from_str(text).expect("the documented layout");
    assert_eq!(read, MaterialTable::dosta2024());
    // Written and read back, the table is unchanged.
    let written = serde_json::to_string(&read).expect("serialisable");
    assert_eq!(
        serde_json::from_str::<MaterialTable>(&written).expect("round trip"),
        read
    );
    // A misspelt key is refused by name rather than ignored.
    let misspelt = r#"{ "materials": { "M1": { "young_modulus": 1e9 } } }"#;
    let err = serde_json::from_str::<MaterialTable>(misspelt).expect_err("unknown field");
    assert!(err.to_string().contains("young_modulus"), "{err}");
}

#[test]
fn unlisted_pairs_are_mixed_from_their_self_pairs() {
    // M1 and M2 with their self-pairs only: (M1, M2) is mixed.
    let table = MaterialTable::new()
        .with_material("M1", MaterialEntry::from_youngs_modulus(1.0e9, 0.2, 2500.0))
        .with_material("M2", MaterialEntry::from_shear_modulus(1.0e8, 0.25, 2000.0))
        .with_pair(PairEntry::new(
            "M1",
            "M1",
            Interaction {
                friction: 0.3,
                rolling_friction: 0.02,
                restitution: 0.5,
                cohesion: dem::Cohesion::None,
            },
        ))
        .with_pair(PairEntry::new(
            "M2",
            "M2",
            Interaction {
                friction: 0.4,
                rolling_friction: 0.01,
                restitution: 0.4,
                cohesion: dem::Cohesion::None,
            },
        ));
    let mixed = table.interaction("M1", "M2").expect("mixable");
    // e = √(0.5 × 0.4) = √0.2; μ_s = 2·0.3·0.4/0.7 = 0.24/0.7; μ_r = 2·0.02·0.01/0.03.
    assert_relative_eq!(
        mixed.restitution,
        0.447_213_595_499_958,
        max_relative = ROUND_OFF
    );
    assert_relative_eq!(mixed.friction, 0.24 / 0.7, max_relative = ROUND_OFF);
    assert_relative_eq!(
        mixed.rolling_friction,
        0.0004 / 0.03,
        max_relative = ROUND_OFF
    );
    assert_eq!(mixed.restitution, mixed_restitution(0.5, 0.4));
    assert_eq!(mixed.friction, mixed_friction(0.3, 0.4));
    assert_eq!(table.interaction("M2", "M1"), Ok(mixed));
    // M2 given by G: E = 2G(1 + ν) = 2.5e8 Pa.
    assert_relative_eq!(
        table.material("M2").expect("defined").youngs_modulus,
        2.5e8,
        max_relative = ROUND_OFF
    );
    // A listed pair wins over the mixing rule.
    let listed = table.clone().with_pair(pair("M2", "M1", 0.9, 0.1));
    let i = listed.interaction("M1", "M2").expect("listed");
    assert_eq!(
        (i.restitution, i.friction, i.rolling_friction),
        (0.9, 0.1, 0.0)
    );
}

#[test]
fn an_unlisted_pair_without_both_self_pairs_is_refused_naming_it() {
    let table = MaterialTable::new()
        .with_material("M1", MaterialEntry::from_youngs_modulus(1.0e9, 0.2, 2500.0))
        .with_material(
            "steel",
            MaterialEntry::from_youngs_modulus(210e9, 0.2, 7200.0),
        )
        .with_pair(pair("M1", "M1", 0.5, 0.3));
    // The table itself is valid: steel's pairs only matter where steel is used.
    assert_eq!(table.check(), Ok(()));
    let err = table.interaction("M1", "steel").expect_err("not mixable");
    assert_eq!(
        err,
        MaterialTableError::UnlistedPair {
            key: "pairs".into(),
            a: "M1".into(),
            b: "steel".into(),
            missing: "steel".into()
        }
    );
    let message = err.to_string();
    assert!(
        message.contains("pairs: the pair (M1, steel) is not listed")
            && message.contains("(steel, steel) is not listed"),
        "{message}"
    );
}

/// The table's problems as messages.
fn messages(table: &MaterialTable) -> Vec<String> {
    table.problems().iter().map(ToString::to_string).collect()
}

/// Asserts that `table` has exactly one problem, `expected`, whose message contains each of
/// `fragments`, and that the checked accessors refuse with it.
fn refused(table: &MaterialTable, expected: MaterialTableError, fragments: &[&str]) {
    assert_eq!(table.problems(), vec![expected.clone()], "{table:?}");
    let message = expected.to_string();
    for fragment in fragments {
        assert!(message.contains(fragment), "`{fragment}` not in: {message}");
    }
    assert_eq!(table.check(), Err(expected.clone()));
    assert_eq!(table.interaction("M1", "M1"), Err(expected));
}

fn dosta_with_material(name: &str, entry: MaterialEntry) -> MaterialTable {
    MaterialTable::dosta2024().with_material(name, entry)
}

#[test]
fn pairs_naming_unknown_materials_or_given_twice_are_refused_with_their_keys() {
    let unknown = MaterialTable::dosta2024().with_pair(pair("M3", "M1", 0.5, 0.3));
    refused(
        &unknown,
        MaterialTableError::UnknownMaterial {
            key: "pairs[6]".into(),
            name: "M3".into(),
            defined: "M1, M2, steel".into(),
        },
        &[r#"pairs[6]: material "M3" is not defined (defined: M1, M2, steel)"#],
    );
    // (M2, M1) after (M1, M2): the same pair in the other order.
    let twice = MaterialTable::dosta2024().with_pair(pair("M2", "M1", 0.5, 0.3));
    refused(
        &twice,
        MaterialTableError::DuplicatePair {
            key: "pairs[6]".into(),
            a: "M2".into(),
            b: "M1".into(),
            first: "pairs[1]".into(),
        },
        &["pairs[6]: the pair (M2, M1) is given twice (first as pairs[1])"],
    );
    // A self-pair given twice.
    let self_twice = MaterialTable::dosta2024().with_pair(pair("steel", "steel", 0.5, 0.3));
    refused(
        &self_twice,
        MaterialTableError::DuplicatePair {
            key: "pairs[6]".into(),
            a: "steel".into(),
            b: "steel".into(),
            first: "pairs[5]".into(),
        },
        &["(steel, steel) is given twice (first as pairs[5])"],
    );
}

#[test]
fn materials_without_a_modulus_or_with_two_that_disagree_are_refused() {
    let none = MaterialEntry {
        youngs_modulus: None,
        shear_modulus: None,
        poisson_ratio: Some(0.2),
        density: Some(2500.0),
    };
    refused(
        &dosta_with_material("M1", none),
        MaterialTableError::MissingModulus {
            key: "materials.M1".into(),
        },
        &["materials.M1: neither youngs_modulus nor shear_modulus is given"],
    );
    // E = 1e9 Pa with G = 3e8 Pa at ν = 0.2: 2G(1 + ν) = 7.2e8 Pa, 28 % off.
    let both = |shear: f64| MaterialEntry {
        youngs_modulus: Some(1.0e9),
        shear_modulus: Some(shear),
        poisson_ratio: Some(0.2),
        density: Some(2500.0),
    };
    let table = dosta_with_material("M1", both(3.0e8));
    match table.problems().as_slice() {
        [MaterialTableError::InconsistentModuli {
            key,
            implied_youngs_modulus,
            relative_difference,
            tolerance,
            ..
        }] => {
            assert_eq!(key, "materials.M1");
            assert_relative_eq!(*implied_youngs_modulus, 7.2e8, max_relative = ROUND_OFF);
            assert_relative_eq!(*relative_difference, 0.28, max_relative = 1e-12);
            assert_eq!(*tolerance, MODULUS_TOLERANCE);
        }
        other => panic!("expected InconsistentModuli, got {other:?}"),
    }
    let message = table.check().expect_err("inconsistent").to_string();
    for fragment in [
        "materials.M1",
        "1e9 Pa",
        "3e8 Pa",
        "7.2e8 Pa",
        "give only one",
    ] {
        assert!(message.contains(fragment), "`{fragment}` not in: {message}");
    }
    // G = E/(2(1 + ν)) = 416 666 666.67 Pa written to seven digits (4.166667e8, off by
    // 8e-8 relative) agrees within the tolerance, and E is the modulus used.
    let agreeing = dosta_with_material("M1", both(4.166667e8));
    assert_eq!(agreeing.check(), Ok(()));
    assert_eq!(agreeing.material("M1").map(|m| m.youngs_modulus), Ok(1.0e9));
    // Five digits (4.1667e8, 8e-6 relative) is beyond it.
    assert!(matches!(
        dosta_with_material("M1", both(4.1667e8)).check(),
        Err(MaterialTableError::InconsistentModuli { .. })
    ));
}

#[test]
fn material_properties_out_of_range_absent_or_not_finite_are_refused_with_key_and_value() {
    let m1 = MaterialEntry::from_youngs_modulus(1.0e9, 0.2, 2500.0);
    let with = |f: &dyn Fn(&mut MaterialEntry)| {
        let mut e = m1;
        f(&mut e);
        dosta_with_material("M1", e)
    };
    let out_of_range =
        |key: &str, value: f64, allowed: &'static str| MaterialTableError::OutOfRange {
            key: key.into(),
            value,
            allowed,
        };
    refused(
        &with(&|e| e.poisson_ratio = Some(0.5)),
        out_of_range("materials.M1.poisson_ratio", 0.5, "(-1, 0.5)"),
        &["materials.M1.poisson_ratio: 0.5 is outside the allowed range (-1, 0.5)"],
    );
    refused(
        &with(&|e| e.poisson_ratio = Some(-1.0)),
        out_of_range("materials.M1.poisson_ratio", -1.0, "(-1, 0.5)"),
        &["materials.M1.poisson_ratio: -1 is outside"],
    );
    refused(
        &with(&|e| e.density = Some(0.0)),
        out_of_range("materials.M1.density", 0.0, "> 0 kg/m³"),
        &["materials.M1.density: 0 is outside the allowed range > 0 kg/m³"],
    );
    refused(
        &with(&|e| e.density = Some(-2500.0)),
        out_of_range("materials.M1.density", -2500.0, "> 0 kg/m³"),
        &["-2500"],
    );
    refused(
        &with(&|e| e.youngs_modulus = Some(-1.0e9)),
        out_of_range("materials.M1.youngs_modulus", -1.0e9, "> 0 Pa"),
        &["materials.M1.youngs_modulus: -1000000000 is outside the allowed range > 0 Pa"],
    );
    refused(
        &with(&|e| {
            e.youngs_modulus = None;
            e.shear_modulus = Some(0.0)
        }),
        out_of_range("materials.M1.shear_modulus", 0.0, "> 0 Pa"),
        &["materials.M1.shear_modulus: 0 is outside"],
    );
    refused(
        &with(&|e| e.density = Some(f64::INFINITY)),
        MaterialTableError::NotFinite {
            key: "materials.M1.density".into(),
            value: f64::INFINITY,
            allowed: "> 0 kg/m³",
        },
        &["materials.M1.density: inf is not a finite number; allowed: > 0 kg/m³"],
    );
    // NaN ≠ NaN, so this one is matched by its message.
    let nan = with(&|e| e.poisson_ratio = Some(f64::NAN));
    assert_eq!(
        messages(&nan),
        ["materials.M1.poisson_ratio: NaN is not a finite number; allowed: (-1, 0.5)"]
    );
    refused(
        &with(&|e| e.density = None),
        MaterialTableError::Missing {
            key: "materials.M1.density".into(),
            allowed: "> 0 kg/m³",
        },
        &["materials.M1.density: missing; required, > 0 kg/m³"],
    );
    refused(
        &with(&|e| e.poisson_ratio = None),
        MaterialTableError::Missing {
            key: "materials.M1.poisson_ratio".into(),
            allowed: "(-1, 0.5)",
        },
        &["materials.M1.poisson_ratio: missing"],
    );
}

#[test]
fn pair_coefficients_out_of_range_absent_or_not_finite_are_refused_with_key_and_value() {
    let base = pair("M1", "M1", 0.5, 0.3);
    // The Dosta table without its (M1, M1) entry, plus the entry under test at pairs[5].
    let with = |f: &dyn Fn(&mut PairEntry)| {
        let mut table = MaterialTable::dosta2024();
        table.pairs.remove(0);
        let mut p = base.clone();
        f(&mut p);
        table.with_pair(p)
    };
    let out_of_range =
        |key: &str, value: f64, allowed: &'static str| MaterialTableError::OutOfRange {
            key: key.into(),
            value,
            allowed,
        };
    refused(
        &with(&|p| p.restitution = Some(0.0)),
        out_of_range("pairs[5].restitution", 0.0, "(0, 1]"),
        &["pairs[5].restitution: 0 is outside the allowed range (0, 1]"],
    );
    refused(
        &with(&|p| p.restitution = Some(1.5)),
        out_of_range("pairs[5].restitution", 1.5, "(0, 1]"),
        &["pairs[5].restitution: 1.5 is outside"],
    );
    // e = 1 (elastic) is allowed.
    assert_eq!(with(&|p| p.restitution = Some(1.0)).check(), Ok(()));
    refused(
        &with(&|p| p.friction = Some(-0.1)),
        out_of_range("pairs[5].friction", -0.1, "≥ 0"),
        &["pairs[5].friction: -0.1 is outside the allowed range ≥ 0"],
    );
    refused(
        &with(&|p| p.rolling_friction = Some(-0.01)),
        out_of_range("pairs[5].rolling_friction", -0.01, "≥ 0"),
        &["pairs[5].rolling_friction: -0.01 is outside"],
    );
    refused(
        &with(&|p| p.friction = Some(f64::INFINITY)),
        MaterialTableError::NotFinite {
            key: "pairs[5].friction".into(),
            value: f64::INFINITY,
            allowed: "≥ 0",
        },
        &["pairs[5].friction: inf is not a finite number"],
    );
    assert_eq!(
        messages(&with(&|p| p.restitution = Some(f64::NAN))),
        ["pairs[5].restitution: NaN is not a finite number; allowed: (0, 1]"]
    );
    refused(
        &with(&|p| p.restitution = None),
        MaterialTableError::Missing {
            key: "pairs[5].restitution".into(),
            allowed: "(0, 1]",
        },
        &["pairs[5].restitution: missing"],
    );
    refused(
        &with(&|p| p.friction = None),
        MaterialTableError::Missing {
            key: "pairs[5].friction".into(),
            allowed: "≥ 0",
        },
        &["pairs[5].friction: missing"],
    );
    // Rolling friction may be left out: it is then 0.
    let no_rolling = with(&|p| p.rolling_friction = None);
    assert_eq!(
        no_rolling
            .interaction("M1", "M1")
            .map(|i| i.rolling_friction),
        Ok(0.0)
    );
}

#[test]
fn every_problem_of_a_table_is_listed_at_once_in_key_order() {
    let mut table = MaterialTable::dosta2024()
        .with_material(
            "M2",
            MaterialEntry {
                youngs_modulus: None,
                shear_modulus: None,
                poisson_ratio: Some(0.7),
                density: Some(-1.0),
            },
        )
        .with_pair(pair("M1", "glass", 0.5, -0.2));
    table.pairs[0].restitution = Some(2.0);
    assert_eq!(
        messages(&table),
        [
            "materials.M2.poisson_ratio: 0.7 is outside the allowed range (-1, 0.5)",
            "materials.M2.density: -1 is outside the allowed range > 0 kg/m³",
            "materials.M2: neither youngs_modulus nor shear_modulus is given; give one of them \
             [Pa] (E = 2G(1 + ν))",
            "pairs[0].restitution: 2 is outside the allowed range (0, 1]",
            r#"pairs[6]: material "glass" is not defined (defined: M1, M2, steel)"#,
            "pairs[6].friction: -0.2 is outside the allowed range ≥ 0",
        ]
    );
}

fn sim() -> Simulation {
    let mut config = SimulationConfig::new(1.0e-6);
    config.gravity = DVec3::ZERO;
    Simulation::new(config).expect("valid configuration")
}

#[test]
fn installing_a_table_registers_its_particle_materials_with_every_pair() {
    let table = MaterialTable::dosta2024();
    let mut sim = sim();
    let ids = sim
        .add_material_table(&table, &["M2", "M1"])
        .expect("valid table");
    // In the order asked for.
    assert_eq!(ids.get("M2"), Some(MaterialId(0)));
    assert_eq!(ids.get("M1"), Some(MaterialId(1)));
    assert_eq!(ids.get("steel"), None, "steel is not a particle material");
    assert_eq!(
        ids.iter().collect::<Vec<_>>(),
        [("M2", MaterialId(0)), ("M1", MaterialId(1))]
    );
    // An M1 and an M2 sphere far apart: the step needs the (M1, M2) interaction, which the
    // table set; without it the step would be refused with MissingInteraction.
    for (x, name) in [(0.0, "M1"), (0.1, "M2")] {
        let id = ids.get(name).expect("registered");
        sim.add_particle(ParticleInit::at_rest(DVec3::new(x, 0.0, 0.0), 2e-3, id))
            .expect("valid particle");
    }
    sim.step().expect("every pair of the two materials is set");
    // The particle mass comes from the table's density: ρ (4/3)π R³.
    let volume = 4.0 / 3.0 * std::f64::consts::PI * 8e-9;
    let mut masses = sim.particles().masses().to_vec();
    masses.sort_by(f64::total_cmp);
    assert_relative_eq!(masses[0], 2000.0 * volume, max_relative = ROUND_OFF);
    assert_relative_eq!(masses[1], 2500.0 * volume, max_relative = ROUND_OFF);
}

#[test]
fn a_material_added_outside_the_table_still_needs_its_interactions() {
    // The low-level API keeps its check: a table material and one added by hand meet only
    // through an interaction nobody set.
    let mut sim = sim();
    let ids = sim
        .add_material_table(&MaterialTable::dosta2024(), &["M1"])
        .expect("valid table");
    let other = sim
        .add_material(Material::fan2023(), Interaction::fan2023())
        .expect("valid material");
    let m1 = ids.get("M1").expect("registered");
    for (x, id) in [(0.0, m1), (0.1, other)] {
        sim.add_particle(ParticleInit::at_rest(DVec3::new(x, 0.0, 0.0), 2e-3, id))
            .expect("valid particle");
    }
    assert_eq!(sim.step(), Err(DemError::MissingInteraction(0, 1)));
    sim.set_interaction(m1, other, Interaction::fan2023())
        .expect("valid interaction");
    sim.step().expect("the interaction is set");
}

#[test]
fn tables_that_cannot_be_installed_are_refused_and_leave_nothing_behind() {
    let table = MaterialTable::dosta2024();
    let mut sim = sim();
    let cases: [(&[&str], &str); 2] = [
        (
            &["M1", "M3"],
            r#"material table: particle_materials[1]: material "M3" is not defined (defined: M1, M2, steel)"#,
        ),
        (
            &["M1", "M2", "M1"],
            r#"material table: particle_materials[2]: material "M1" is named twice (first as particle_materials[0])"#,
        ),
    ];
    for (names, message) in cases {
        let err = sim.add_material_table(&table, names).expect_err("refused");
        assert!(matches!(err, DemError::MaterialTable(_)), "{err:?}");
        assert_eq!(err.to_string(), message);
    }
    // An invalid table and an unmixable pair are refused the same way.
    let mut invalid = table.clone();
    invalid.pairs[0].friction = Some(-1.0);
    assert_eq!(
        sim.add_material_table(&invalid, &["M1"]),
        Err(DemError::MaterialTable(MaterialTableError::OutOfRange {
            key: "pairs[0].friction".into(),
            value: -1.0,
            allowed: "≥ 0"
        }))
    );
    let mut unmixable = table.clone();
    unmixable.pairs.retain(|p| p.materials != ["M1", "M2"]);
    unmixable.pairs.retain(|p| p.materials != ["M2", "M2"]);
    assert!(matches!(
        sim.add_material_table(&unmixable, &["M1", "M2"]),
        Err(DemError::MaterialTable(
            MaterialTableError::UnlistedPair { .. }
        ))
    ));
    // Nothing was registered: the next material takes id 0.
    assert_eq!(
        sim.add_material(Material::fan2023(), Interaction::fan2023()),
        Ok(MaterialId(0))
    );
}

/// A plane z = 0 of `material` with `interaction`.
fn floor(material: WallMaterial, interaction: Interaction) -> Wall {
    Wall::plane(DVec3::ZERO, DVec3::Z, material, interaction).expect("valid plane")
}

#[test]
fn wall_interactions_are_set_per_material_and_refused_for_unknown_handles() {
    let mut sim = sim();
    let a = sim
        .add_material(Material::fan2023(), Interaction::fan2023())
        .expect("valid material");
    let b = sim
        .add_material(Material::fan2023(), Interaction::fan2023())
        .expect("valid material");
    let own = Interaction::fan2023();
    let wall = sim
        .add_wall(floor(WallMaterial::Rigid, own))
        .expect("valid wall");
    let slippery = Interaction {
        friction: 0.1,
        rolling_friction: 0.0,
        restitution: 0.9,
        cohesion: dem::Cohesion::None,
    };
    sim.set_wall_interaction(wall, b, slippery)
        .expect("valid interaction");
    assert_eq!(sim.wall_interaction(wall, a), Some(own));
    assert_eq!(sim.wall_interaction(wall, b), Some(slippery));
    assert_eq!(sim.wall_interaction(wall, MaterialId(2)), None);
    assert_eq!(sim.wall_interaction(WallId(3), a), None);
    // Unknown wall, unknown material, bad interaction: refused, naming what is wrong.
    assert_eq!(
        sim.set_wall_interaction(WallId(3), a, slippery),
        Err(DemError::UnknownWall(3))
    );
    match sim.set_wall_interaction(wall, MaterialId(5), slippery) {
        Err(DemError::InvalidInput(m)) => assert!(
            m.contains("unknown material 5") && m.contains("2 material(s)"),
            "{m}"
        ),
        other => panic!("expected InvalidInput, got {other:?}"),
    }
    let mut bad = slippery;
    bad.restitution = 0.0;
    match sim.set_wall_interaction(wall, a, bad) {
        Err(DemError::InvalidInput(m)) => assert!(m.contains("restitution in (0, 1]"), "{m}"),
        other => panic!("expected InvalidInput, got {other:?}"),
    }
    assert_eq!(
        sim.wall_interaction(wall, a),
        Some(own),
        "refusals change nothing"
    );
    // A checkpoint keeps the per-material interaction.
    let bytes = postcard::to_allocvec(sim.state()).expect("state serialises");
    let state: SimulationState = postcard::from_bytes(&bytes).expect("state deserialises");
    let restored = Simulation::from_state(state, 1).expect("state restores");
    assert_eq!(restored.wall_interaction(wall, b), Some(slippery));
    assert_eq!(restored.wall_interaction(wall, a), Some(own));
    // A removed wall's handle is refused too.
    sim.remove_wall(wall).expect("the wall exists");
    assert_eq!(
        sim.set_wall_interaction(wall, a, slippery),
        Err(DemError::UnknownWall(wall.0))
    );
    assert_eq!(sim.wall_interaction(wall, b), None);
}

#[test]
fn add_wall_refuses_a_bad_interaction_or_wall_material() {
    let mut sim = sim();
    let mut bad = Interaction::fan2023();
    bad.friction = -0.5;
    let mut soft = Material::fan2023();
    soft.poisson_ratio = 0.5;
    for (wall, fragment) in [
        (floor(WallMaterial::Rigid, bad), "friction ≥ 0"),
        (
            floor(WallMaterial::Elastic(soft), Interaction::fan2023()),
            "Poisson ratio 0.5",
        ),
    ] {
        match sim.add_wall(wall) {
            Err(DemError::InvalidInput(m)) => assert!(m.contains(fragment), "{m}"),
            other => panic!("expected InvalidInput naming `{fragment}`, got {other:?}"),
        }
    }
    // Nothing was added: the first valid wall takes handle 0.
    assert_eq!(
        sim.add_wall(floor(WallMaterial::Rigid, Interaction::fan2023())),
        Ok(WallId(0))
    );
}

#[test]
fn a_sphere_sliding_on_a_table_wall_decelerates_at_its_own_materials_friction() {
    // Two Table-1 spheres, of materials "glass" and "sand" (same elastic properties), slide
    // with rotation locked on a steel floor whose table gives glass–steel μ = 0.2 and
    // sand–steel μ = 0.5; the floor's own interaction (μ = 0.5) must not apply to glass.
    // While sliding, the tangential force is the Coulomb cap μ F_ne and nothing else (no
    // dashpot while sliding, docs/physics.md §3.1), and F_ne = m g because each sphere starts
    // at its Hertz equilibrium overlap with no vertical velocity, so v_x falls at μ g.
    const R: f64 = 1.5e-3;
    const G: f64 = 9.81;
    const V0: f64 = 0.5;
    let fan = |name: &str| {
        let m = Material::fan2023();
        (
            name.to_owned(),
            MaterialEntry::from_shear_modulus(m.shear_modulus(), m.poisson_ratio, m.density),
        )
    };
    let mut table = MaterialTable::new()
        .with_material(
            "steel",
            MaterialEntry::from_youngs_modulus(210e9, 0.3, 7800.0),
        )
        .with_pair(pair("glass", "glass", 0.6, 0.3))
        .with_pair(pair("sand", "sand", 0.2, 0.6))
        .with_pair(pair("steel", "steel", 0.6, 0.5))
        .with_pair(pair("glass", "steel", 0.5, 0.2))
        .with_pair(pair("sand", "steel", 0.3, 0.5));
    for (name, entry) in [fan("glass"), fan("sand")] {
        table.materials.insert(name, entry);
    }
    let mut sim = Simulation::new(SimulationConfig::new(2.5e-6)).expect("valid configuration");
    let ids = sim
        .add_material_table(&table, &["glass", "sand"])
        .expect("valid table");
    let wall = sim
        .add_wall(floor(WallMaterial::Rigid, Interaction::fan2023()))
        .expect("valid wall");
    sim.set_wall_from_table(wall, &table, &ids, "steel")
        .expect("steel is in the table");
    assert_eq!(
        sim.wall(wall).map(|w| w.material),
        Some(WallMaterial::Elastic(
            table.material("steel").expect("defined")
        ))
    );
    let mut tags = Vec::new();
    for (k, name) in ["glass", "sand"].into_iter().enumerate() {
        // Equilibrium overlap: (4/3) E* √R δ^{3/2} = m g, E* of the pair with steel.
        let e_star = table.coefficients(name, "steel").expect("listed").e_star;
        let mass = Material::fan2023().density * 4.0 / 3.0 * std::f64::consts::PI * R.powi(3);
        let overlap = (3.0 * mass * G / (4.0 * e_star * R.sqrt())).powf(2.0 / 3.0);
        let tag = sim
            .add_particle(ParticleInit {
                position: DVec3::new(0.0, 0.02 * k as f64, R - overlap),
                velocity: DVec3::new(V0, 0.0, 0.0),
                angular_velocity: DVec3::ZERO,
                radius: R,
                material: ids.get(name).expect("registered"),
                flags: FLAG_ROTATION_LOCKED,
            })
            .expect("valid particle");
        tags.push(tag);
    }
    let speed = |sim: &Simulation, tag: u64| {
        let p = sim.particles();
        let k = p.tags().iter().position(|&t| t == tag).expect("present");
        p.velocities()[k].x
    };
    // From 5 ms (the tangential spring saturated within microseconds) to 25 ms: both still
    // slide (glass stops at V0/(0.2 g) = 0.25 s, sand at 0.10 s).
    sim.run(2_000).expect("runs");
    let start = [speed(&sim, tags[0]), speed(&sim, tags[1])];
    sim.run(8_000).expect("runs");
    let elapsed = 8_000.0 * 2.5e-6;
    for (k, mu) in [0.2, 0.5].into_iter().enumerate() {
        let deceleration = (start[k] - speed(&sim, tags[k])) / elapsed;
        // F_ne = m g to round-off at the equilibrium overlap (the closed form above is the
        // engine's Hertz law), so the only error is round-off accumulated over 8000 steps
        // (a few 1e-11); 1e-9 leaves margin and is far below the 0.2 vs 0.5 difference.
        assert_relative_eq!(deceleration, mu * G, max_relative = 1e-9);
    }
}
