//! Valid files in both formats: what the mesh holds, and the tolerances of the formats.

use crate::common;

use common::{binary, FILE, ONE_TRIANGLE, TWO_TRIANGLES};
use glam::DVec3;
use stl::{parse, read, Format, Transform};

#[test]
fn ascii_gives_the_triangle_the_name_and_the_format() {
    let mesh = parse(ONE_TRIANGLE.as_bytes(), FILE, &Transform::identity()).unwrap();
    assert_eq!(mesh.triangles, vec![[DVec3::ZERO, DVec3::X, DVec3::Y]]);
    assert_eq!(mesh.name.as_deref(), Some("wall"));
    assert_eq!(mesh.format, Format::Ascii);
}

#[test]
fn ascii_keeps_the_vertex_order_whatever_the_written_normal() {
    // The normal says −z, the vertex order +z: the order wins and the normal is not checked.
    let text = ONE_TRIANGLE.replace("normal 0 0 1", "normal 0 0 -1");
    let mesh = parse(text.as_bytes(), FILE, &Transform::identity()).unwrap();
    let [a, b, c] = mesh.triangles[0];
    assert_eq!((b - a).cross(c - a), DVec3::Z);
}

#[test]
fn ascii_accepts_upper_case_crlf_tabs_and_a_byte_order_mark() {
    let text = format!(
        "\u{feff}SOLID Wall Part\r\n{}",
        ONE_TRIANGLE
            .lines()
            .skip(1)
            .map(|l| l.to_uppercase().replace("  ", "\t"))
            .collect::<Vec<_>>()
            .join("\r\n")
    );
    let mesh = parse(text.as_bytes(), FILE, &Transform::identity()).unwrap();
    assert_eq!(mesh.triangles, vec![[DVec3::ZERO, DVec3::X, DVec3::Y]]);
    assert_eq!(mesh.name.as_deref(), Some("Wall Part"));
}

#[test]
fn ascii_on_one_line_and_without_names() {
    let text = "solid facet normal 0 0 0 outer loop vertex 0 0 0 vertex 2 0 0 vertex 0 2 0 \
                endloop endfacet endsolid";
    let mesh = parse(text.as_bytes(), FILE, &Transform::identity()).unwrap();
    assert_eq!(mesh.name, None);
    assert_eq!(mesh.triangles[0][1], DVec3::new(2.0, 0.0, 0.0));
}

#[test]
fn ascii_with_several_solids_reads_them_all_and_keeps_the_first_name() {
    let second = ONE_TRIANGLE
        .replace("wall", "lid")
        .replace("vertex 0 0 0", "vertex 0 0 1");
    let text = format!("{ONE_TRIANGLE}{second}");
    let mesh = parse(text.as_bytes(), FILE, &Transform::identity()).unwrap();
    assert_eq!(mesh.triangles.len(), 2);
    assert_eq!(mesh.triangles[1][0], DVec3::Z);
    assert_eq!(mesh.name.as_deref(), Some("wall"));
}

#[test]
fn ascii_numbers_keep_double_precision() {
    let text = ONE_TRIANGLE.replace("vertex 1 0 0", "vertex 0.1000000000000001 0 0");
    let mesh = parse(text.as_bytes(), FILE, &Transform::identity()).unwrap();
    assert_eq!(mesh.triangles[0][1].x, 0.1000000000000001);
}

#[test]
fn binary_gives_the_triangles_exactly_widened_from_f32() {
    let mut triangles = TWO_TRIANGLES;
    triangles[0][1][0] = 0.1;
    let mesh = parse(&binary(b"walls", &triangles), FILE, &Transform::identity()).unwrap();
    assert_eq!(mesh.format, Format::Binary);
    assert_eq!(mesh.name, None);
    assert_eq!(mesh.triangles.len(), 2);
    // 0.1 stored as f32 and widened: the f32 value exactly, not the f64 nearest to 0.1.
    assert_eq!(mesh.triangles[0][1].x, f64::from(0.1f32));
    assert_eq!(mesh.triangles[1][1], DVec3::new(1.0, 1.0, 0.0));
}

#[test]
fn binary_whose_header_begins_with_solid_is_read_as_binary() {
    let bytes = binary(b"solid part exported as binary", &TWO_TRIANGLES);
    let mesh = parse(&bytes, FILE, &Transform::identity()).unwrap();
    assert_eq!(mesh.format, Format::Binary);
    assert_eq!(mesh.triangles.len(), 2);
}

#[test]
fn the_transform_is_applied_to_every_vertex() {
    let transform = Transform::new(
        0.001,
        DVec3::Z,
        std::f64::consts::FRAC_PI_2,
        DVec3::new(1.0, 2.0, 3.0),
    )
    .unwrap();
    let text = ONE_TRIANGLE.replace("vertex 1 0 0", "vertex 1000 0 0");
    let mesh = parse(text.as_bytes(), FILE, &transform).unwrap();
    let [a, b, _] = mesh.triangles[0];
    // (1000, 0, 0) mm → (1, 0, 0) m → rotated a quarter turn about z → (0, 1, 0) → shifted.
    // Tolerance: cos(π/2) evaluates to 6e-17, not 0, and the sum rounds at 1 ulp of 3.
    assert!(a.abs_diff_eq(DVec3::new(1.0, 2.0, 3.0), 1e-15), "{}", a);
    assert!(b.abs_diff_eq(DVec3::new(1.0, 3.0, 3.0), 1e-15), "{}", b);
}

#[test]
fn read_takes_a_path() {
    let path = std::env::temp_dir().join(format!("hopperflow-stl-read-{}.stl", std::process::id()));
    std::fs::write(&path, ONE_TRIANGLE).unwrap();
    let mesh = read(&path, &Transform::scaled(2.0).unwrap());
    std::fs::remove_file(&path).unwrap();
    assert_eq!(mesh.unwrap().triangles[0][1], DVec3::new(2.0, 0.0, 0.0));
}
