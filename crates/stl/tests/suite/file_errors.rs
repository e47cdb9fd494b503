//! Files that are neither format, and binary files of the wrong size or count: each message
//! names the file and states what was expected against what was found.

use crate::common;

use common::{binary, message, TWO_TRIANGLES};

#[test]
fn an_empty_file() {
    assert_eq!(
        message(b""),
        "walls.stl: the file is empty (0 bytes); an STL file holds at least one triangle"
    );
}

#[test]
fn a_short_file_that_is_neither_format() {
    assert_eq!(
        message(b"hello"),
        "walls.stl: not an STL file: it does not begin with `solid` (ASCII STL) and its 5 bytes \
         are fewer than the 84 of a binary STL's header and triangle count"
    );
}

#[test]
fn a_truncated_binary_file_states_expected_and_actual_size() {
    let bytes = binary(b"walls", &TWO_TRIANGLES);
    assert_eq!(bytes.len(), 184, "fixture: 84 + 50 × 2 bytes");
    assert_eq!(
        message(&bytes[..160]),
        "walls.stl: binary STL of the wrong size: the header declares 2 triangles, which need \
         84 + 50 × 2 = 184 bytes, but the file has 160 bytes (truncated, or not an STL file)"
    );
}

#[test]
fn a_binary_file_with_extra_bytes() {
    let mut bytes = binary(b"walls", &TWO_TRIANGLES);
    bytes.push(0);
    assert_eq!(
        message(&bytes),
        "walls.stl: binary STL of the wrong size: the header declares 2 triangles, which need \
         84 + 50 × 2 = 184 bytes, but the file has 185 bytes (truncated, or not an STL file)"
    );
}

#[test]
fn a_binary_file_declaring_no_triangles() {
    assert_eq!(
        message(&binary(b"walls", &[])),
        "walls.stl: the binary STL header declares 0 triangles; a wall mesh needs at least one"
    );
}

#[test]
fn a_truncated_binary_file_whose_header_begins_with_solid() {
    let bytes = binary(b"solid x", &TWO_TRIANGLES[..1]);
    assert_eq!(
        message(&bytes[..114]),
        "walls.stl, line 1: byte 7 (0x00) is not text, so the file is not ASCII STL although it \
         begins with `solid`; nor is it binary STL: the header declares 1 triangles, which need \
         134 bytes, but the file has 114 bytes"
    );
}

#[test]
fn a_short_file_beginning_with_solid_that_is_not_utf8() {
    assert_eq!(
        message(b"solid x\nfacet \xff\n"),
        "walls.stl, line 2: byte 14 (0xff) is not text, so the file is not ASCII STL although it \
         begins with `solid`; nor is it binary STL: its 16 bytes are fewer than the 84 of a \
         binary header"
    );
}

#[test]
fn long_garbage_is_reported_against_the_binary_size_rule() {
    assert_eq!(
        message(&[0xff; 200]),
        "walls.stl: binary STL of the wrong size: the header declares 4294967295 triangles, which \
         need 84 + 50 × 4294967295 = 214748364834 bytes, but the file has 200 bytes (truncated, \
         or not an STL file)"
    );
}

#[test]
fn reading_a_missing_file_names_it() {
    let path = std::env::temp_dir().join("hopperflow-stl-test-no-such-file.stl");
    let error = stl::read(&path, &stl::Transform::identity()).unwrap_err();
    let text = error.to_string();
    assert!(
        text.starts_with(&format!("{}: cannot read the file: ", path.display())),
        "{text}"
    );
}
