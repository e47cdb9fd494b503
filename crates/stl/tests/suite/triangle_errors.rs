//! Bad triangles in either format: non-finite coordinates, repeated vertices, degenerate
//! shapes, overflowing edges and transforms. Each message names the file, the triangle
//! counted from 1, the line or record, and the value.

use crate::common;

use common::{binary, message, with_line, FILE, ONE_TRIANGLE, TWO_TRIANGLES};
use glam::DVec3;
use stl::{parse, StlError, Transform, DEGENERACY_RATIO};

#[test]
fn nan_in_ascii() {
    assert_eq!(
        message(with_line(5, "      vertex nan 0 0").as_bytes()),
        "walls.stl, triangle 1 (counting from 1), line 5: coordinate x of vertex 2 is nan; \
         allowed: finite numbers"
    );
}

#[test]
fn infinity_in_ascii() {
    assert_eq!(
        message(with_line(6, "      vertex 0 -inf 0").as_bytes()),
        "walls.stl, triangle 1 (counting from 1), line 6: coordinate y of vertex 3 is -inf; \
         allowed: finite numbers"
    );
}

#[test]
fn a_literal_beyond_double_range_in_ascii() {
    assert_eq!(
        message(with_line(4, "      vertex 0 0 1e999").as_bytes()),
        "walls.stl, triangle 1 (counting from 1), line 4: coordinate z of vertex 1 is 1e999; \
         allowed: finite numbers"
    );
}

#[test]
fn a_non_finite_normal_is_ignored() {
    let text = with_line(2, "  facet normal nan inf 0");
    let mesh = parse(text.as_bytes(), FILE, &Transform::identity()).unwrap();
    assert_eq!(mesh.triangles.len(), 1);
}

#[test]
fn nan_in_binary_names_the_record() {
    let mut triangles = TWO_TRIANGLES;
    triangles[1][2][2] = f32::NAN;
    assert_eq!(
        message(&binary(b"walls", &triangles)),
        "walls.stl, triangle 2 (counting from 1), record at byte 134: coordinate z of vertex 3 \
         is NaN; allowed: finite numbers"
    );
}

#[test]
fn infinity_in_binary() {
    let mut triangles = TWO_TRIANGLES;
    triangles[0][0][1] = f32::INFINITY;
    assert_eq!(
        message(&binary(b"walls", &triangles)),
        "walls.stl, triangle 1 (counting from 1), record at byte 84: coordinate y of vertex 1 \
         is inf; allowed: finite numbers"
    );
}

#[test]
fn repeated_vertices_in_ascii() {
    assert_eq!(
        message(with_line(6, "      vertex 0 0 0").as_bytes()),
        "walls.stl, triangle 1 (counting from 1), line 2: vertices 1 and 3 are the same point \
         (0, 0, 0) [file units]; a triangle needs three distinct corners"
    );
}

#[test]
fn repeated_vertices_in_binary() {
    let mut triangles = TWO_TRIANGLES;
    triangles[1][1] = triangles[1][2];
    assert_eq!(
        message(&binary(b"walls", &triangles)),
        "walls.stl, triangle 2 (counting from 1), record at byte 134: vertices 2 and 3 are the \
         same point (0, 1, 0) [file units]; a triangle needs three distinct corners"
    );
}

#[test]
fn collinear_vertices() {
    let text = with_line(6, "      vertex 2 0 0");
    assert_eq!(
        message(text.as_bytes()),
        "walls.stl, triangle 1 (counting from 1), line 2: degenerate, its corners lie on one \
         line: area / L² = 0e0 with longest edge L = 2 [file units]; allowed: area / L² ≥ 1e-12"
    );
}

#[test]
fn collinear_vertices_in_binary() {
    let triangles = [[[0.0, 0.0, 5.0], [0.0, 3.0, 5.0], [0.0, 1.5, 5.0]]];
    assert_eq!(
        message(&binary(b"walls", &triangles)),
        "walls.stl, triangle 1 (counting from 1), record at byte 84: degenerate, its corners lie \
         on one line: area / L² = 0e0 with longest edge L = 3 [file units]; allowed: area / L² \
         ≥ 1e-12"
    );
}

/// A sliver of base 1 and height `h`: area / L² = h / 2 with L = 1 for small `h`.
fn sliver(height: f64) -> String {
    with_line(6, &format!("      vertex 0.5 {height:e} 0"))
}

#[test]
fn a_sliver_below_the_ratio_is_rejected_and_one_above_is_kept() {
    match parse(sliver(1e-13).as_bytes(), FILE, &Transform::identity()) {
        Err(StlError::Degenerate {
            triangle,
            area_ratio,
            longest_edge,
            ..
        }) => {
            assert_eq!((triangle, longest_edge), (1, 1.0));
            // area / L² = 1e-13 / 2 up to the rounding of the cross product's length.
            approx::assert_relative_eq!(area_ratio, 5e-14, max_relative = 1e-12);
        }
        other => panic!("expected a degenerate triangle, got {other:?}"),
    }
    // Height 1e-11 gives area / L² = 5e-12, five times the limit.
    const { assert!(5e-12 > DEGENERACY_RATIO) };
    let mesh = parse(sliver(1e-11).as_bytes(), FILE, &Transform::identity()).unwrap();
    assert_eq!(mesh.triangles.len(), 1);
}

#[test]
fn the_degeneracy_criterion_does_not_depend_on_size() {
    // The same sliver shape at 1e-9 and 1e9 file units: rejected at both sizes.
    for size in [1e-9, 1e9] {
        let text = ONE_TRIANGLE
            .replace("vertex 1 0 0", &format!("vertex {size:e} 0 0"))
            .replace(
                "vertex 0 1 0",
                &format!("vertex {:e} {:e} 0", 0.5 * size, 1e-13 * size),
            );
        let error = parse(text.as_bytes(), FILE, &Transform::identity()).unwrap_err();
        assert!(
            matches!(error, StlError::Degenerate { .. }),
            "size {size}: {error}"
        );
    }
}

#[test]
fn an_edge_beyond_double_range() {
    let text = ONE_TRIANGLE
        .replace("vertex 0 0 0", "vertex -1e308 0 0")
        .replace("vertex 1 0 0", "vertex 1e308 0 0")
        .replace("vertex 0 1 0", "vertex 0 1e308 0");
    assert_eq!(
        message(text.as_bytes()),
        "walls.stl, triangle 1 (counting from 1), line 2: an edge is beyond the double range, so \
         its shape cannot be measured; allowed: coordinate differences below 1.8e308 file units"
    );
}

#[test]
fn huge_triangles_are_measured_without_overflow() {
    // Edges of 1e200: their squares overflow, but the check works on scaled edges.
    let text = ONE_TRIANGLE
        .replace("vertex 1 0 0", "vertex 1e200 0 0")
        .replace("vertex 0 1 0", "vertex 0 1e200 0");
    let mesh = parse(text.as_bytes(), FILE, &Transform::identity()).unwrap();
    assert_eq!(mesh.triangles[0][2], DVec3::new(0.0, 1e200, 0.0));
}

#[test]
fn a_transform_that_overflows() {
    let text = ONE_TRIANGLE
        .replace("vertex 0 0 0", "vertex 1e300 0 0")
        .replace("vertex 1 0 0", "vertex 1e300 1e150 0")
        .replace("vertex 0 1 0", "vertex 1e300 0 1e150");
    let transform = Transform::scaled(1e10).unwrap();
    let error = parse(text.as_bytes(), FILE, &transform).unwrap_err();
    assert_eq!(
        error.to_string(),
        "walls.stl, triangle 1 (counting from 1), line 2: vertex 1 is not finite after the \
         transform (scale 10000000000 m per file unit); allowed: coordinates that stay finite in \
         metres"
    );
    // The same file in metres is fine.
    let mesh = parse(text.as_bytes(), FILE, &Transform::identity()).unwrap();
    assert_eq!(mesh.triangles[0][0], DVec3::new(1e300, 0.0, 0.0));
}
