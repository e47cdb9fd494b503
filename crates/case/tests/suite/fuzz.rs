//! No input, however malformed, may panic the case or sweep loaders.
//!
//! Random bytes exercise the UTF-8 and syntax paths; TOML-shaped text built from the
//! real keys and hostile values (NaN, infinities, huge integers, wrong types, nested
//! tables) exercises every validation branch. A panic fails the property.

use case::{default_case, load_case, parse_case, parse_sweep};
use proptest::prelude::*;

const KEYS: &[&str] = &[
    "version",
    "seed",
    "geometry.width",
    "geometry.height",
    "geometry.thickness",
    "geometry.outlet_width",
    "geometry.hopper_angle_deg",
    "geometry.outlet_gap",
    "geometry.outlet_offset",
    "particles.count",
    "particles.diameter",
    "particles.size_distribution.kind",
    "particles.size_distribution.min",
    "particles.size_distribution.max",
    "particles.size_distribution.mean",
    "particles.size_distribution.std_dev",
    "particles.size_distribution.diameters",
    "particles.size_distribution.fractions",
    "particles.material.density",
    "particles.material.poisson_ratio",
    "wall.material",
    "wall.material.density",
    "wall.friction",
    "contact.restitution",
    "contact.tangential",
    "contact.rolling",
    "contact.normal_clamp",
    "time.time_step",
    "time.rayleigh_fraction",
    "protocol.fill_top",
    "protocol.deletion_depth",
    "measure.x_bin_width",
    "measure.crossing_check_interval",
    "measure.steady_end_fraction",
    "output.plots",
    "geometry.kind",
    "geometry.depth",
    "geometry.outlet",
    "geometry.outlet.shape",
    "geometry.outlet.radius",
    "geometry.fill_min",
    "geometry.fill_max",
    "geometry.walls",
    "bogus.key",
];

const VALUES: &[&str] = &[
    "0",
    "-1",
    "1",
    "0.003",
    "0.03",
    "0.1",
    "1e308",
    "-1e-308",
    "nan",
    "inf",
    "-inf",
    "9223372036854775807",
    "-9223372036854775808",
    "90",
    "90.0000001",
    "3000",
    "\"uniform\"",
    "\"normal\"",
    "\"discrete\"",
    "\"rigid\"",
    "\"same\"",
    "\"epsd\"",
    "true",
    "[]",
    "[0.003, 0.002]",
    "[0.5, 0.5]",
    "[\"a\"]",
    "{}",
    "{ density = 1 }",
    "1979-05-27",
    "\"\"",
    "[[1], [2]]",
    "\"box\"",
    "\"mesh\"",
    "\"cylinder\"",
    "\"square\"",
    "\"disc\"",
    "[0.0, 0.0, 0.1]",
    "[{ file = \"no-such.stl\" }]",
    "{ shape = \"rectangle\", size = [0.02, 0.02] }",
];

fn toml_like() -> impl Strategy<Value = String> {
    prop::collection::vec((0..KEYS.len(), 0..VALUES.len()), 0..12).prop_map(|pairs| {
        pairs
            .into_iter()
            .map(|(k, v)| format!("{} = {}\n", KEYS[k], VALUES[v]))
            .collect()
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn random_bytes_never_panic_the_loader(bytes in prop::collection::vec(any::<u8>(), 0..256)) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("case.toml");
        std::fs::write(&path, &bytes).unwrap();
        let _ = load_case(&path, &[]);
        let text = String::from_utf8_lossy(&bytes);
        let _ = parse_case(&text, "case.toml", &[]);
        let _ = parse_sweep(&text, "sweep.toml", None, &[]);
    }

    #[test]
    fn random_toml_with_real_keys_never_panics(text in toml_like()) {
        // Dotted keys repeat across lines, so much of this is (correctly) a syntax
        // error; the rest reaches validation. Either way: a result, not a panic.
        match parse_case(&text, "case.toml", &[]) {
            Ok(case) => {
                // Whatever is accepted must also write out and read back.
                let back = parse_case(&case.to_toml_string(), "back.toml", &[]);
                prop_assert_eq!(back.as_ref().ok(), Some(&case));
            }
            Err(errors) => prop_assert!(!errors.errors.is_empty()),
        }
    }

    #[test]
    fn random_set_overrides_never_panic(
        pairs in prop::collection::vec((0..KEYS.len(), 0..VALUES.len()), 0..6),
        junk in "[ -~]{0,20}",
    ) {
        let mut sets: Vec<String> = pairs
            .into_iter()
            .map(|(k, v)| format!("{}={}", KEYS[k], VALUES[v]))
            .collect();
        sets.push(junk);
        let _ = default_case(&sets);
    }

    #[test]
    fn random_sweep_axes_never_panic(
        key in 0..KEYS.len(),
        values in prop::collection::vec(0..VALUES.len(), 0..4),
        replicas in -2i64..4,
    ) {
        let values: Vec<&str> = values.into_iter().map(|v| VALUES[v]).collect();
        let text = format!(
            "version = 1\nname = \"p\"\nreplicas = {replicas}\n[[axes]]\nkey = \"{}\"\nvalues = [{}]\n",
            KEYS[key],
            values.join(", ")
        );
        let _ = parse_sweep(&text, "sweep.toml", None, &[]);
    }
}

#[test]
fn deeply_nested_input_is_an_error_not_a_stack_overflow() {
    // The TOML parser limits nesting depth; the located tree follows the parsed depth.
    for text in [
        format!("a = {}", "[".repeat(100_000)),
        format!("a = {}1{}", "[".repeat(60), "]".repeat(60)),
        format!("a = {}", "{ b = ".repeat(10_000)),
    ] {
        assert!(parse_case(&text, "deep.toml", &[]).is_err());
    }
}
