//! `parse` never panics: random bytes, random word soups of the ASCII grammar, and random
//! damage to valid files all end in `Ok` or `Err`. Every accepted mesh has at least one
//! finite triangle; every error message begins with the source name.

use crate::common;

use common::{binary, ONE_TRIANGLE, TWO_TRIANGLES};
use proptest::prelude::*;
use stl::{parse, Transform};

const NAME: &str = "fuzz.stl";

/// Parses without a transform and checks what every outcome promises.
fn check_outcome(bytes: &[u8]) -> Result<(), TestCaseError> {
    match parse(bytes, NAME, &Transform::identity()) {
        Ok(mesh) => {
            prop_assert!(!mesh.triangles.is_empty());
            prop_assert!(mesh.triangles.iter().flatten().all(|p| p.is_finite()));
        }
        Err(error) => prop_assert!(error.to_string().starts_with(NAME), "{}", error),
    }
    Ok(())
}

/// One change to a file: overwrite a byte, insert a byte, delete a byte or cut the rest.
#[derive(Debug, Clone)]
enum Damage {
    Overwrite(usize, u8),
    Insert(usize, u8),
    Delete(usize),
    Truncate(usize),
}

fn damage() -> impl Strategy<Value = Damage> {
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Damage::Overwrite(i, b)),
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Damage::Insert(i, b)),
        any::<usize>().prop_map(Damage::Delete),
        any::<usize>().prop_map(Damage::Truncate),
    ]
}

fn damaged(mut bytes: Vec<u8>, damages: &[Damage]) -> Vec<u8> {
    for damage in damages {
        let len = bytes.len().max(1);
        match *damage {
            Damage::Overwrite(i, b) if !bytes.is_empty() => bytes[i % len] = b,
            Damage::Insert(i, b) => bytes.insert(i % (bytes.len() + 1), b),
            Damage::Delete(i) if !bytes.is_empty() => {
                bytes.remove(i % len);
            }
            Damage::Truncate(i) => bytes.truncate(i % (bytes.len() + 1)),
            _ => {}
        }
    }
    bytes
}

/// Words of the ASCII grammar, numbers of every kind and some junk.
fn word() -> impl Strategy<Value = String> {
    prop_oneof![
        prop::sample::select(vec![
            "solid", "facet", "normal", "outer", "loop", "vertex", "endloop", "endfacet",
            "endsolid", "nan", "-inf", "1e999", "0", "1", "-2.5", "1e-300", "x", "0,5",
        ])
        .prop_map(String::from),
        any::<f64>().prop_map(|v| v.to_string()),
        "[a-z0-9.+-]{1,6}",
    ]
}

fn separator() -> impl Strategy<Value = &'static str> {
    prop::sample::select(vec![" ", "\n", "\t", "\r\n", "  "])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn random_bytes(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        check_outcome(&bytes)?;
    }

    #[test]
    fn random_bytes_after_solid(tail in prop::collection::vec(any::<u8>(), 0..400)) {
        let bytes = [b"solid ".as_slice(), &tail].concat();
        check_outcome(&bytes)?;
    }

    #[test]
    fn random_words_after_solid(
        words in prop::collection::vec((word(), separator()), 0..80)
    ) {
        let text: String = std::iter::once("solid x\n".to_string())
            .chain(words.into_iter().map(|(w, s)| w + s))
            .collect();
        check_outcome(text.as_bytes())?;
    }

    #[test]
    fn damaged_ascii(damages in prop::collection::vec(damage(), 1..6)) {
        check_outcome(&damaged(ONE_TRIANGLE.as_bytes().to_vec(), &damages))?;
    }

    #[test]
    fn damaged_binary(damages in prop::collection::vec(damage(), 1..6)) {
        check_outcome(&damaged(binary(b"solid wall", &TWO_TRIANGLES), &damages))?;
    }

    #[test]
    fn overwritten_binary_keeps_its_size_and_stays_binary(
        overwrites in prop::collection::vec((84usize..184, any::<u8>()), 1..10)
    ) {
        // Damage inside the records only: the size rule still holds, so the file is read
        // record by record and any outcome must come from the record checks.
        let mut bytes = binary(b"walls", &TWO_TRIANGLES);
        for (i, b) in overwrites {
            bytes[i] = b;
        }
        match parse(&bytes, NAME, &Transform::identity()) {
            Ok(mesh) => prop_assert_eq!(mesh.triangles.len(), 2),
            Err(error) => prop_assert!(
                error.to_string().starts_with("fuzz.stl, triangle "),
                "{}", error
            ),
        }
    }
}
