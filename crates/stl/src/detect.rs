//! Telling binary from ASCII STL: the binary size rule first, then `solid` and text.

use crate::error::{binary_size, BinarySizeNote, StlError};

/// Bytes of the binary header before the triangle count.
pub(crate) const HEADER_BYTES: usize = 80;
/// Bytes of the header and the `u32` triangle count together.
pub(crate) const PREAMBLE_BYTES: usize = HEADER_BYTES + 4;

/// What a file is, once detection has accepted it.
#[derive(Debug, PartialEq)]
pub(crate) enum Detected<'a> {
    /// Binary STL of exactly `84 + 50·count` bytes.
    Binary {
        /// The triangle count in bytes 80..84.
        count: u32,
    },
    /// ASCII STL: the text, without a leading byte-order mark.
    Ascii(&'a str),
}

/// Decides the format of `bytes`, or says why it is neither (see the crate documentation).
pub(crate) fn detect<'a>(bytes: &'a [u8], file: &str) -> Result<Detected<'a>, StlError> {
    let actual = bytes.len() as u64;
    if bytes.is_empty() {
        return Err(StlError::Empty { file: file.into() });
    }
    let declared_count = declared_count(bytes);
    if let Some(count) = declared_count {
        if binary_size(count) == actual {
            return Ok(Detected::Binary { count });
        }
    }
    if begins_with_solid(bytes) {
        return match first_non_text_byte(bytes) {
            None => Ok(Detected::Ascii(as_text(bytes))),
            Some(offset) => Err(StlError::NotText {
                file: file.into(),
                line: line_of(bytes, offset),
                offset: offset as u64,
                byte: bytes[offset],
                size: BinarySizeNote {
                    actual,
                    declared_count,
                },
            }),
        };
    }
    Err(match declared_count {
        Some(count) => StlError::BinarySize {
            file: file.into(),
            count,
            expected: binary_size(count),
            actual,
        },
        None => StlError::NotStl {
            file: file.into(),
            actual,
        },
    })
}

/// The little-endian `u32` in bytes 80..84, if the file is that long.
fn declared_count(bytes: &[u8]) -> Option<u32> {
    let count: [u8; 4] = bytes.get(HEADER_BYTES..PREAMBLE_BYTES)?.try_into().ok()?;
    Some(u32::from_le_bytes(count))
}

/// Whether the file starts with `solid` (any case), after an optional UTF-8 byte-order mark
/// and white space.
fn begins_with_solid(bytes: &[u8]) -> bool {
    let start = without_byte_order_mark(bytes);
    let first = start.iter().position(|b| !b.is_ascii_whitespace());
    first
        .and_then(|i| start.get(i..i + 5))
        .is_some_and(|word| word.eq_ignore_ascii_case(b"solid"))
}

/// The offset of the first byte that is not text: a control character other than white space,
/// or the first byte of invalid UTF-8.
fn first_non_text_byte(bytes: &[u8]) -> Option<usize> {
    let invalid_utf8 = std::str::from_utf8(bytes).err().map(|e| e.valid_up_to());
    let control = bytes.iter().position(|&b| is_control(b));
    match (invalid_utf8, control) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// Control characters that do not occur in text files: all below 0x20 except tab, line feed,
/// vertical tab, form feed and carriage return; and DEL.
fn is_control(byte: u8) -> bool {
    (byte < 0x20 && !matches!(byte, b'\t' | b'\n' | 0x0b | 0x0c | b'\r')) || byte == 0x7f
}

/// The bytes as text without a leading byte-order mark; called only on bytes that passed
/// [`first_non_text_byte`], and empty otherwise rather than a panic.
fn as_text(bytes: &[u8]) -> &str {
    std::str::from_utf8(without_byte_order_mark(bytes)).unwrap_or_default()
}

/// The bytes after a leading UTF-8 byte-order mark, if there is one.
fn without_byte_order_mark(bytes: &[u8]) -> &[u8] {
    bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes)
}

/// The line, counted from 1, that holds byte `offset`.
fn line_of(bytes: &[u8], offset: usize) -> usize {
    1 + bytes[..offset].iter().filter(|&&b| b == b'\n').count()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn binary_with_header(header_start: &[u8], count: u32, records: usize) -> Vec<u8> {
        let mut bytes = vec![0u8; HEADER_BYTES];
        bytes[..header_start.len()].copy_from_slice(header_start);
        bytes.extend_from_slice(&count.to_le_bytes());
        bytes.resize(PREAMBLE_BYTES + 50 * records, 0);
        bytes
    }

    #[test]
    fn binary_beginning_with_solid_is_binary_when_the_size_fits() {
        let bytes = binary_with_header(b"solid exported by a CAD tool", 2, 2);
        assert_eq!(detect(&bytes, "f").unwrap(), Detected::Binary { count: 2 });
    }

    #[test]
    fn text_beginning_with_solid_is_ascii() {
        let bytes = b"\xEF\xBB\xBF  SOLID x\nendsolid x\n";
        assert_eq!(
            detect(bytes, "f").unwrap(),
            Detected::Ascii("  SOLID x\nendsolid x\n")
        );
    }

    #[test]
    fn a_control_byte_is_located_by_line_and_offset() {
        let bytes = b"solid x\nfacet\x01\n";
        match detect(bytes, "f") {
            Err(StlError::NotText {
                line, offset, byte, ..
            }) => assert_eq!((line, offset, byte), (2, 13, 1)),
            other => panic!("expected NotText, got {other:?}"),
        }
    }

    #[test]
    fn invalid_utf8_is_not_text() {
        assert_eq!(first_non_text_byte(b"solid \xC3\xA4 \xFF"), Some(9));
        assert_eq!(first_non_text_byte("solid ä\r\n\t".as_bytes()), None);
    }
}
