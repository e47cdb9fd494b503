//! Behaviour of the CSV table writers: values round-trip and bad shapes are refused.

use files::{write_csv_columns, write_csv_table, Cell, OutputError};

/// Reads a CSV file back as headers and string records.
fn read_back(path: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut reader = csv::Reader::from_path(path).expect("file opens");
    let headers = reader
        .headers()
        .expect("headers")
        .iter()
        .map(str::to_owned)
        .collect();
    let rows = reader
        .records()
        .map(|record| record.expect("record").iter().map(str::to_owned).collect())
        .collect();
    (headers, rows)
}

#[test]
fn numbers_and_text_round_trip_exactly() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("table.csv");
    // Magnitudes from 1e-12 to 1e20 exercise both the plain and the exponent formats.
    let numbers = [
        0.0,
        1.0 / 3.0,
        -2.5e-12,
        6.02214076e23,
        0.1 + 0.2,
        1e20,
        1e-4,
    ];
    let rows: Vec<Vec<Cell>> = numbers
        .iter()
        .enumerate()
        .map(|(index, &value)| vec![Cell::from(format!("case, \"{index}\"")), Cell::from(value)])
        .collect();
    write_csv_table(&path, &["case", "value [m]"], &rows).expect("write");
    let (headers, records) = read_back(&path);
    assert_eq!(headers, vec!["case", "value [m]"]);
    assert_eq!(records.len(), numbers.len());
    for (index, (record, &value)) in records.iter().zip(&numbers).enumerate() {
        // Text with commas and quotes must come back unchanged (the encoder quotes it).
        assert_eq!(record[0], format!("case, \"{index}\""));
        // Shortest round-trip formatting: the parsed number is bit-identical.
        let parsed: f64 = record[1].parse().expect("number");
        assert_eq!(parsed.to_bits(), value.to_bits(), "value {value}");
    }
}

#[test]
fn small_numbers_are_written_with_an_exponent_not_a_run_of_zeros() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("small.csv");
    write_csv_columns(&path, &["d [m]"], &[&[3e-13]]).expect("write");
    let (_, records) = read_back(&path);
    assert_eq!(records[0][0], "3e-13");
}

#[test]
fn columns_are_written_row_by_row() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("columns.csv");
    let time = [0.0, 0.02, 0.04];
    let rate = [0.1, 0.2, 0.3];
    write_csv_columns(&path, &["t [s]", "W [kg/s]"], &[&time, &rate]).expect("write");
    let (headers, records) = read_back(&path);
    assert_eq!(headers, vec!["t [s]", "W [kg/s]"]);
    let parsed: Vec<(f64, f64)> = records
        .iter()
        .map(|r| (r[0].parse().expect("t"), r[1].parse().expect("W")))
        .collect();
    assert_eq!(parsed, vec![(0.0, 0.1), (0.02, 0.2), (0.04, 0.3)]);
}

#[test]
fn a_row_of_the_wrong_length_is_refused_and_nothing_is_written() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("bad.csv");
    let rows = vec![
        vec![Cell::from(1.0), Cell::from(2.0)],
        vec![Cell::from(3.0)],
    ];
    let error = write_csv_table(&path, &["a", "b"], &rows).expect_err("ragged rows");
    assert!(
        matches!(error, OutputError::InvalidData { .. }),
        "got {error:?}"
    );
    assert_eq!(std::fs::read_dir(directory.path()).expect("dir").count(), 0);
}

#[test]
fn columns_of_different_lengths_are_refused() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("bad.csv");
    let error =
        write_csv_columns(&path, &["a", "b"], &[&[1.0, 2.0], &[1.0]]).expect_err("unequal columns");
    assert!(
        matches!(error, OutputError::InvalidData { .. }),
        "got {error:?}"
    );
    assert!(!path.exists());
}
