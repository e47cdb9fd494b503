//! Writing then reading: ASCII gives the same `f64` values, binary the values rounded to `f32`.
//! Writers refuse what the reader would reject.

use glam::DVec3;
use proptest::prelude::*;
use stl::shapes::{axis_aligned_box, frustum_side, rectangle};
use stl::{parse, write_ascii, write_binary, Format, Transform, Triangle, WriteError};

/// Largest relative error of rounding an `f64` to the nearest `f32` in the normal range: half
/// a unit in the last place of a 24-bit significand, 2⁻²⁴ ≈ 6e-8.
const F32_ROUNDING: f64 = 1.0 / (1u64 << 24) as f64;

/// Triangles with coordinates that are not short decimals: a tilted frustum (34 triangles), a
/// box (12) and a skewed floor (42).
fn sample() -> Vec<Triangle> {
    let mut triangles = frustum_side(
        DVec3::new(0.1, -0.2, 0.3),
        DVec3::new(0.01, 0.02, 0.7),
        0.05,
        0.31,
        17,
    )
    .unwrap();
    triangles
        .extend(axis_aligned_box(DVec3::splat(-1.0 / 3.0), DVec3::splat(2.0f64.sqrt())).unwrap());
    triangles.extend(
        rectangle(
            DVec3::ZERO,
            DVec3::new(0.7, 0.1, 0.0),
            DVec3::new(-0.1, 0.7, 0.0),
            7,
            3,
        )
        .unwrap(),
    );
    triangles
}

fn written(write: impl FnOnce(&mut Vec<u8>) -> Result<(), WriteError>) -> Vec<u8> {
    let mut bytes = Vec::new();
    write(&mut bytes).unwrap();
    bytes
}

#[test]
fn ascii_round_trip_is_exact() {
    let triangles = sample();
    let bytes = written(|out| write_ascii(out, &triangles, "hopper wall"));
    let mesh = parse(&bytes, "out.stl", &Transform::identity()).unwrap();
    assert_eq!(mesh.format, Format::Ascii);
    assert_eq!(mesh.name.as_deref(), Some("hopper wall"));
    // Exact: the writer prints the shortest decimal that parses back to the same f64.
    assert_eq!(mesh.triangles, triangles);
}

#[test]
fn ascii_with_an_empty_name_reads_back_without_one() {
    let triangles = sample();
    let bytes = written(|out| write_ascii(out, &triangles, ""));
    let mesh = parse(&bytes, "out.stl", &Transform::identity()).unwrap();
    assert_eq!(mesh.name, None);
}

#[test]
fn binary_round_trip_within_f32_rounding() {
    let triangles = sample();
    let bytes = written(|out| write_binary(out, &triangles, "solid hopper wall"));
    assert_eq!(bytes.len(), 84 + 50 * triangles.len());
    let mesh = parse(&bytes, "out.stl", &Transform::identity()).unwrap();
    assert_eq!(mesh.format, Format::Binary);
    assert_eq!(mesh.triangles.len(), triangles.len());
    for (read, original) in mesh.triangles.iter().zip(&triangles) {
        for (r, o) in read.iter().zip(original) {
            // Each coordinate is the nearest f32: within 2⁻²⁴ of its magnitude.
            let error = (*r - *o).abs();
            assert!(error.cmple(o.abs() * F32_ROUNDING).all(), "{r} vs {o}");
        }
    }
}

#[test]
fn binary_records_carry_the_unit_normal_of_the_vertex_order() {
    let triangle = [DVec3::ZERO, DVec3::Y, DVec3::X];
    let bytes = written(|out| write_binary(out, &[triangle], "n"));
    let normal: Vec<f32> = bytes[84..96]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert_eq!(normal, [0.0, 0.0, -1.0]);
}

#[test]
fn writers_refuse_an_empty_list() {
    let mut out = Vec::new();
    let error = write_ascii(&mut out, &[], "x").unwrap_err();
    assert_eq!(
        error.to_string(),
        "no triangles to write; an STL file needs at least one"
    );
    assert!(matches!(
        write_binary(&mut out, &[], "x"),
        Err(WriteError::NoTriangles)
    ));
    assert!(out.is_empty(), "nothing is written before the checks pass");
}

#[test]
fn writers_refuse_a_non_finite_coordinate() {
    let triangles = [[DVec3::ZERO, DVec3::new(1.0, 0.0, f64::NAN), DVec3::Y]];
    let error = write_ascii(Vec::new(), &triangles, "x").unwrap_err();
    assert_eq!(
        error.to_string(),
        "triangle 1 (counting from 1): coordinate z of vertex 2 is NaN m; allowed: finite numbers"
    );
}

#[test]
fn binary_refuses_a_coordinate_beyond_f32() {
    let triangles = [[
        DVec3::ZERO,
        DVec3::new(1e39, 0.0, 0.0),
        DVec3::new(0.0, 1e39, 0.0),
    ]];
    let error = write_binary(Vec::new(), &triangles, "x").unwrap_err();
    assert_eq!(
        error.to_string(),
        "triangle 1 (counting from 1): coordinate x of vertex 2 = 1000000000000000000000000000000000000000 m \
         is beyond binary STL's 32-bit floats; allowed: |value| ≤ 340282350000000000000000000000000000000 m"
    );
    // ASCII has double precision and writes it.
    assert!(write_ascii(Vec::new(), &triangles, "x").is_ok());
}

#[test]
fn binary_refuses_a_triangle_that_f32_rounding_collapses() {
    // A micrometre triangle a kilometre from the origin along x: distinct in f64, but x =
    // 1000 + 1e-6 rounds to 1000 in f32 (whose spacing there is 6e-5), merging two vertices.
    let far = DVec3::new(1000.0, 0.0, 0.0);
    let triangles = [[far, far + 1e-6 * DVec3::X, far + 1e-6 * DVec3::Y]];
    let error = write_binary(Vec::new(), &triangles, "x").unwrap_err();
    assert_eq!(
        error.to_string(),
        "triangle 1 (counting from 1) would be unreadable as Binary STL: vertices 1 and 2 are \
         the same point (1000, 0, 0) (coordinates in m)"
    );
    let bytes = written(|out| write_ascii(out, &triangles, "x"));
    let mesh = parse(&bytes, "out.stl", &Transform::identity()).unwrap();
    assert_eq!(mesh.triangles[0], triangles[0]);
}

#[test]
fn ascii_refuses_names_it_could_not_read_back() {
    let triangles = sample();
    let cases = [
        (
            "two\nlines",
            "it holds a line break or another control character",
        ),
        (
            "my solid wall",
            "the words `solid`, `facet` and `endsolid` would be read as keywords",
        ),
        (
            "double  space",
            "words must be separated by single spaces, without leading or trailing spaces",
        ),
        (
            " leading",
            "words must be separated by single spaces, without leading or trailing spaces",
        ),
    ];
    for (name, reason) in cases {
        let error = write_ascii(Vec::new(), &triangles, name).unwrap_err();
        assert_eq!(
            error.to_string(),
            format!("solid name `{name}` cannot be written to ASCII STL: {reason}")
        );
    }
}

/// A triangle with corners in a 20 m cube, kept when the writers accept it.
fn any_triangle() -> impl Strategy<Value = Triangle> {
    let point = prop::array::uniform3(-10.0..10.0f64).prop_map(DVec3::from_array);
    prop::array::uniform3(point)
}

proptest! {
    #[test]
    fn random_triangles_round_trip(triangles in prop::collection::vec(any_triangle(), 1..20)) {
        let mut binary = Vec::new();
        prop_assume!(write_binary(&mut binary, &triangles, "p").is_ok());
        let mesh = parse(&binary, "p.stl", &Transform::identity()).unwrap();
        for (read, original) in mesh.triangles.iter().zip(&triangles) {
            for (r, o) in read.iter().zip(original) {
                // Nearest f32: within 2⁻²⁴ of the magnitude.
                prop_assert!((*r - *o).abs().cmple(o.abs() * F32_ROUNDING).all());
            }
        }
        let mut ascii = Vec::new();
        write_ascii(&mut ascii, &triangles, "p").unwrap();
        let mesh = parse(&ascii, "p.stl", &Transform::identity()).unwrap();
        prop_assert_eq!(mesh.triangles, triangles);
    }
}
