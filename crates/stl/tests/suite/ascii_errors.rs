//! ASCII syntax errors: each message names the file, the line, the token and what the grammar
//! allows there.

use crate::common;

use common::{message, with_line, without_line, ONE_TRIANGLE};

#[test]
fn the_fixture_itself_is_valid() {
    let mesh = stl::parse(ONE_TRIANGLE.as_bytes(), "f", &stl::Transform::identity()).unwrap();
    assert_eq!(mesh.triangles.len(), 1);
}

#[test]
fn a_misspelt_keyword() {
    assert_eq!(
        message(with_line(3, "    outer lop").as_bytes()),
        "walls.stl, line 3: expected `loop` after `outer`, found `lop`"
    );
    assert_eq!(
        message(with_line(2, "  facett normal 0 0 1").as_bytes()),
        "walls.stl, line 2: expected `facet` or `endsolid`, found `facett`"
    );
}

#[test]
fn a_keyword_out_of_order() {
    assert_eq!(
        message(with_line(8, "  endloop").as_bytes()),
        "walls.stl, line 8: expected `endfacet` after `endloop`, found `endloop`"
    );
}

#[test]
fn numbers_without_the_vertex_keyword() {
    assert_eq!(
        message(with_line(5, "      1 0 0").as_bytes()),
        "walls.stl, line 5: expected `vertex` or `endloop`, found `1`"
    );
}

#[test]
fn a_vertex_with_two_numbers() {
    assert_eq!(
        message(with_line(5, "      vertex 1 0").as_bytes()),
        "walls.stl, line 6: vertex 2 of triangle 1 (counting from 1) needs 3 numbers, found 2 \
         before `vertex`"
    );
}

#[test]
fn a_vertex_with_four_numbers() {
    assert_eq!(
        message(with_line(5, "      vertex 1 0 0 0").as_bytes()),
        "walls.stl, line 5: vertex 2 of triangle 1 (counting from 1) has more than 3 numbers: \
         extra `0`"
    );
}

#[test]
fn a_normal_with_two_numbers() {
    assert_eq!(
        message(with_line(2, "  facet normal 0 0").as_bytes()),
        "walls.stl, line 3: the normal of triangle 1 (counting from 1) needs 3 numbers, found 2 \
         before `outer`"
    );
}

#[test]
fn an_unreadable_number_is_quoted() {
    assert_eq!(
        message(with_line(5, "      vertex 1 0,5 0").as_bytes()),
        "walls.stl, line 5: `0,5` in vertex 2 of triangle 1 (counting from 1) is not a number"
    );
}

#[test]
fn a_facet_with_two_vertices() {
    assert_eq!(
        message(without_line(6).as_bytes()),
        "walls.stl, line 6: triangle 1 (counting from 1) has 2 vertices between `outer loop` and \
         `endloop`; a facet needs exactly 3"
    );
}

#[test]
fn a_facet_with_four_vertices() {
    let text = with_line(6, "      vertex 0 1 0\n      vertex 1 1 0");
    assert_eq!(
        message(text.as_bytes()),
        "walls.stl, line 8: triangle 1 (counting from 1) has 4 vertices between `outer loop` and \
         `endloop`; a facet needs exactly 3"
    );
}

#[test]
fn a_missing_endsolid() {
    assert_eq!(
        message(without_line(9).as_bytes()),
        "walls.stl, line 8: the file ends where `facet` or `endsolid` should follow (truncated, or \
         `endsolid` missing)"
    );
}

#[test]
fn a_file_truncated_inside_a_vertex() {
    let cut = ONE_TRIANGLE.find("vertex 1 0 0").unwrap() + "vertex 1 0".len();
    assert_eq!(
        message(&ONE_TRIANGLE.as_bytes()[..cut]),
        "walls.stl, line 5: the file ends where a number should follow (truncated, or `endsolid` \
         missing)"
    );
}

#[test]
fn a_solid_without_facets() {
    assert_eq!(
        message(b"solid empty\nendsolid empty\n"),
        "walls.stl, line 2: `endsolid` with no facet in the file; a wall mesh needs at least one \
         triangle"
    );
}

#[test]
fn words_after_endsolid() {
    let text = format!("{ONE_TRIANGLE}garbage\n");
    assert_eq!(
        message(text.as_bytes()),
        "walls.stl, line 10: expected `solid` or the end of the file, found `garbage`"
    );
}

#[test]
fn a_first_word_that_only_begins_with_solid() {
    let text = ONE_TRIANGLE.replacen("solid wall", "solidworks wall", 1);
    assert_eq!(
        message(text.as_bytes()),
        "walls.stl, line 1: expected `solid`, found `solidworks`"
    );
}

#[test]
fn a_huge_garbage_token_is_cut_in_the_message() {
    let garbage = "x".repeat(10_000);
    let text = with_line(5, &format!("      vertex 1 {garbage} 0"));
    let expected = format!(
        "walls.stl, line 5: `{}…` in vertex 2 of triangle 1 (counting from 1) is not a number",
        "x".repeat(40)
    );
    assert_eq!(message(text.as_bytes()), expected);
}
