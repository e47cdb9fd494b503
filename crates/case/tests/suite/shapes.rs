//! Grain shapes in the case file (`particles.shape`, docs/physics.md §11.7): rods, member
//! lists and STL bodies filled with spheres, each scaled to the equal-volume diameter,
//! written back as resolved, and the refusals with their keys and reasons.

use case::{parse_case_in, Case, ShapeGiven};
use glam::DVec3;

/// A cone-bottomed cylinder of 1500 grains of 4 mm equal-volume diameter, with `shape` as
/// the particles' shape line (empty for spheres) and `extra` appended.
fn silo(shape: &str, extra: &str) -> String {
    format!(
        r#"
version = 1
seed = 3

[geometry]
kind = "cylinder"
radius = 0.03
height = 0.12
outlet_diameter = 0.024
hopper_angle_deg = 30.0

[particles]
count = 1500
diameter = 0.004
{shape}

{extra}
"#
    )
}

fn parse(text: &str, dir: Option<&std::path::Path>) -> Result<Case, String> {
    parse_case_in(text, "shaped.toml", dir, &[]).map_err(|e| {
        e.errors
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join("\n")
    })
}

/// The union's volume of a component's unit grain over that of the unit sphere.
fn unit_volume_ratio(case: &Case) -> f64 {
    let shape = case.particles.components[0]
        .shape
        .as_ref()
        .expect("a shape");
    shape.unit_clump().body(1.0).volume / (std::f64::consts::PI / 6.0)
}

#[test]
fn a_rod_gets_its_default_beads_the_sphere_s_volume_and_reads_back_from_what_is_written() {
    let case = parse(
        &silo(r#"shape = { kind = "rod", aspect_ratio = 2.0 }"#, ""),
        None,
    )
    .expect("a rod case");
    let shape = case.particles.components[0]
        .shape
        .as_ref()
        .expect("a shape");
    // Three beads half a width apart; without triple overlaps the union is closed form, so
    // the volume is that of the unit sphere to rounding.
    assert_eq!(
        shape.given,
        ShapeGiven::Rod {
            aspect_ratio: 2.0,
            beads: 3
        }
    );
    assert!((unit_volume_ratio(&case) - 1.0).abs() < 1e-12);
    // Length over width: (2 reach) / (2 r) of the beads is the aspect ratio.
    let r = shape.unit_members[0][3];
    assert!(
        (shape.unit_reach / r - 2.0).abs() < 1e-12,
        "{}",
        shape.unit_reach / r
    );
    let text = case.to_toml_string();
    assert!(
        text.contains(r#"shape = { kind = "rod", aspect_ratio = 2.0, beads = 3 }"#),
        "{text}"
    );
    let again = parse(&text, None).expect("the written case reads back");
    assert_eq!(again.particles, case.particles);
}

#[test]
fn a_list_of_members_is_scaled_to_the_equal_volume_diameter_and_each_component_has_its_own() {
    let members = r#"shape = { kind = "spheres", spheres = [
    { centre = [0.0, 0.0, 0.0], radius = 1.0 },
    { centre = [1.5, 0.0, 0.0], radius = 1.0 },
    { centre = [0.0, 1.5, 0.0], radius = 0.8 } ] }"#;
    let case = parse(&silo(members, ""), None).expect("an L-shaped grain");
    // Three members, pairwise overlapping, none three at a time: the union is exact and
    // scaled to the unit sphere's volume.
    assert!((unit_volume_ratio(&case) - 1.0).abs() < 1e-12);
    let again = parse(&case.to_toml_string(), None).expect("written back");
    assert_eq!(again.particles, case.particles);

    let mixture = r#"
[[particles.components]]
name = "rods"
diameter = 0.004
fraction = 0.5
shape = { kind = "rod", aspect_ratio = 3.0 }

[[particles.components]]
name = "spheres"
diameter = 0.004
fraction = 0.5
"#;
    let text = silo("", mixture).replace("diameter = 0.004\n\n\n[[", "\n[[");
    let text = text.replacen("count = 1500\ndiameter = 0.004\n", "count = 1500\n", 1);
    let case = parse(&text, None).expect("rods and spheres");
    assert!(case.particles.components[0].shape.is_some());
    assert!(case.particles.components[1].shape.is_none());
    assert!(case.particles.has_shapes());
}

#[test]
fn a_closed_stl_grain_is_filled_and_an_open_one_refused_with_its_edge() {
    let dir = tempfile::tempdir().expect("a folder");
    // A 3 × 1 × 1 box (any unit: the grain is scaled to its equal-volume diameter).
    let triangles =
        stl::shapes::axis_aligned_box(DVec3::ZERO, DVec3::new(3.0, 1.0, 1.0)).expect("a box");
    let mut bytes = Vec::new();
    stl::write_ascii(&mut bytes, &triangles, "grain").expect("written");
    std::fs::write(dir.path().join("grain.stl"), &bytes).expect("saved");
    let line = r#"shape = { kind = "stl", file = "grain.stl", cells = 24, shortfall = 0.1 }"#;
    // The greedy fill ends with small spheres in the box's edges, 0.075 d across: the time
    // step is the smallest member's (docs/physics.md §11.7).
    let step = "[time]\ntime_step = 5.0e-8";
    let case = parse(&silo(line, step), Some(dir.path())).expect("a filled box");
    let shape = case.particles.components[0]
        .shape
        .as_ref()
        .expect("a shape");
    // Inscribed spheres cover at most the box; at this grid they cover about four fifths.
    assert!(
        shape.filled_fraction > 0.6 && shape.filled_fraction <= 1.0,
        "{}",
        shape.filled_fraction
    );
    assert!(shape.members() > 3, "{} spheres", shape.members());
    assert!(
        (unit_volume_ratio(&case) - 1.0).abs() < 1e-4,
        "the union of overlapping spheres, to its line integral's accuracy"
    );
    let ShapeGiven::Stl { file, sha256, .. } = &shape.given else {
        panic!("an STL shape")
    };
    assert!(file.is_absolute() && sha256.len() == 64);
    let again = parse(&case.to_toml_string(), None).expect("the written case reads back");
    assert_eq!(again.particles, case.particles);

    // One face's triangles removed: a hole.
    let mut open = Vec::new();
    stl::write_ascii(&mut open, &triangles[2..], "open").expect("written");
    std::fs::write(dir.path().join("open.stl"), &open).expect("saved");
    let refused = parse(
        &silo(&line.replace("grain.stl", "open.stl"), ""),
        Some(dir.path()),
    )
    .expect_err("an open surface");
    assert!(
        refused.contains("particles.shape.file") && refused.contains("not closed"),
        "{refused}"
    );
}

#[test]
fn bad_shapes_are_refused_naming_the_key_the_value_and_the_range() {
    let cases = [
        (
            r#"shape = { kind = "spheres", spheres = [] }"#,
            "particles.shape.spheres",
            "1 to",
        ),
        (
            r#"shape = { kind = "spheres", spheres = [{ centre = [0.0, 0.0, 0.0], radius = 0.0 }] }"#,
            "particles.shape.spheres[0].radius",
            "> 0",
        ),
        (
            r#"shape = { kind = "spheres", spheres = [{ centre = [0.0, 0.0, 0.0], radius = 1.0 }, { centre = [3.0, 0.0, 0.0], radius = 1.0 }] }"#,
            "particles.shape.spheres[1].centre",
            "connected",
        ),
        (
            r#"shape = { kind = "rod", aspect_ratio = 0.5 }"#,
            "particles.shape.aspect_ratio",
            "[1, 20]",
        ),
        (
            r#"shape = { kind = "rod", aspect_ratio = 3.0, beads = 2 }"#,
            "particles.shape.beads",
            "[3, 64]",
        ),
        (
            r#"shape = { kind = "rod" }"#,
            "particles.shape.aspect_ratio",
            "required",
        ),
        (
            r#"shape = { kind = "cube" }"#,
            "particles.shape.kind",
            "\"rod\"",
        ),
        (
            r#"shape = { kind = "rod", aspect_ratio = 2.0, spheres = [] }"#,
            "particles.shape.spheres",
            "does not belong",
        ),
        (
            r#"shape = { kind = "stl", file = "nowhere.stl" }"#,
            "particles.shape.file",
            "cannot read",
        ),
        (
            r#"shape = { kind = "stl", file = "x.stl", shortfall = 0.9 }"#,
            "particles.shape.shortfall",
            "[0.001, 0.5]",
        ),
    ];
    for (line, key, why) in cases {
        let refused = parse(&silo(line, ""), None).expect_err(line);
        assert!(
            refused.contains(key) && refused.contains(why),
            "{line}: expected {key} and `{why}` in\n{refused}"
        );
        assert!(!refused.contains("panicked"));
    }
    // Shaped grains need a 3D container, spheres for coarse graining and for the fields.
    let slab =
        "version = 1\n[particles]\ncount = 300\nshape = { kind = \"rod\", aspect_ratio = 2.0 }\n";
    let refused = parse(slab, None).expect_err("a slab of rods");
    assert!(
        refused.contains("geometry.kind") && refused.contains("3D silo"),
        "{refused}"
    );
    let refused = parse(
        &silo(r#"shape = { kind = "rod", aspect_ratio = 2.0 }"#, "")
            .replace("count = 1500", "count = 1500\ncoarse_graining = 2.0"),
        None,
    )
    .expect_err("parcels of rods");
    assert!(refused.contains("particles.coarse_graining"), "{refused}");
}
