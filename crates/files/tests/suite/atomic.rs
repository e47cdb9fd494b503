//! Behaviour of the atomic writers: complete files appear, failed writes leave nothing behind.

use std::io::Write;
use std::path::Path;

use files::{write_atomic, write_json_atomic, AtomicFile, OutputError};
use serde::ser::{Error as _, SerializeSeq};
use serde::{Serialize, Serializer};

/// Names of every entry in `directory`, sorted, so a test can assert that no temporary file
/// survived.
fn entries(directory: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(directory)
        .expect("test directory is readable")
        .map(|entry| {
            entry
                .expect("entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    names
}

/// A value that serialises a few elements and then fails, so the temporary file holds a
/// partial document when the error surfaces.
struct FailsPartWay;

impl Serialize for FailsPartWay {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut sequence = serializer.serialize_seq(Some(1000))?;
        for value in 0..100 {
            sequence.serialize_element(&value)?;
        }
        Err(S::Error::custom("deliberate failure after 100 elements"))
    }
}

#[test]
fn write_atomic_creates_the_file_with_exactly_the_given_bytes() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let target = directory.path().join("data.bin");
    let bytes: Vec<u8> = (0..=255u8).cycle().take(10_000).collect();
    write_atomic(&target, &bytes).expect("write succeeds");
    assert_eq!(std::fs::read(&target).expect("read back"), bytes);
    // Only the target may remain: the temporary file was renamed, not copied.
    assert_eq!(entries(directory.path()), vec!["data.bin".to_string()]);
}

#[test]
fn write_atomic_replaces_an_existing_file_completely() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let target = directory.path().join("summary.txt");
    write_atomic(&target, b"a much longer first version of the file").expect("first write");
    write_atomic(&target, b"short").expect("second write");
    assert_eq!(std::fs::read(&target).expect("read back"), b"short");
}

#[test]
fn failed_json_serialisation_leaves_no_target_and_no_temporary_file() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let target = directory.path().join("summary.json");
    let error = write_json_atomic(&target, &FailsPartWay).expect_err("serialisation fails");
    assert!(matches!(error, OutputError::Json { .. }), "got {error:?}");
    assert!(!target.exists(), "no partial target may appear");
    assert!(
        entries(directory.path()).is_empty(),
        "temporary file must be removed"
    );
}

#[test]
fn failed_json_serialisation_keeps_the_previous_target_intact() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let target = directory.path().join("summary.json");
    write_json_atomic(&target, &vec![1.5_f64, 2.5]).expect("first write");
    let before = std::fs::read(&target).expect("read");
    write_json_atomic(&target, &FailsPartWay).expect_err("second write fails");
    assert_eq!(std::fs::read(&target).expect("read"), before);
    assert_eq!(entries(directory.path()), vec!["summary.json".to_string()]);
}

#[test]
fn json_round_trips_through_the_atomic_writer() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let target = directory.path().join("values.json");
    // Values chosen to need all 17 significant digits; serde_json writes shortest round-trip.
    let values = vec![0.1_f64 + 0.2, 1.0 / 3.0, -2.2250738585072014e-308];
    write_json_atomic(&target, &values).expect("write succeeds");
    let text = std::fs::read_to_string(&target).expect("read back");
    let parsed: Vec<f64> = serde_json::from_str(&text).expect("valid JSON");
    assert_eq!(parsed, values);
}

#[test]
fn writing_into_a_missing_directory_is_an_io_error_and_creates_nothing() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let target = directory.path().join("missing").join("out.json");
    let error = write_json_atomic(&target, &1.0_f64).expect_err("directory does not exist");
    assert!(matches!(error, OutputError::Io { .. }), "got {error:?}");
    assert!(entries(directory.path()).is_empty());
}

#[test]
fn dropping_an_uncommitted_atomic_file_discards_its_content() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let target = directory.path().join("log.txt");
    {
        let mut file = AtomicFile::create(&target).expect("create");
        assert_eq!(file.target(), target.as_path());
        // Larger than the buffer, so some bytes reach the temporary file before the drop.
        file.write_all(&vec![b'x'; 100_000]).expect("write");
    }
    assert!(!target.exists());
    assert!(entries(directory.path()).is_empty());
}

#[test]
fn committed_atomic_file_holds_everything_written() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let target = directory.path().join("log.txt");
    let mut file = AtomicFile::create(&target).expect("create");
    for line in 0..1000 {
        writeln!(file, "line {line}").expect("write");
    }
    // Nothing is visible under the target name before the commit.
    assert!(!target.exists());
    file.commit().expect("commit");
    let text = std::fs::read_to_string(&target).expect("read back");
    assert_eq!(text.lines().count(), 1000);
    assert_eq!(text.lines().last(), Some("line 999"));
}

#[test]
fn concurrent_writers_to_one_target_never_produce_a_mixed_file() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let target = directory.path().join("shared.txt");
    // Each writer writes one repeated letter; a torn file would contain two letters.
    std::thread::scope(|scope| {
        for letter in [b'a', b'b', b'c', b'd'] {
            let target = &target;
            scope.spawn(move || {
                for _ in 0..20 {
                    write_atomic(target, &vec![letter; 50_000]).expect("write");
                }
            });
        }
    });
    let content = std::fs::read(&target).expect("read back");
    assert_eq!(content.len(), 50_000);
    assert!(content.iter().all(|&byte| byte == content[0]));
    assert_eq!(entries(directory.path()), vec!["shared.txt".to_string()]);
}
