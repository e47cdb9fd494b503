//! CSV tables (headers + rows of numbers or text) written atomically.

use std::io::Write;
use std::path::Path;

use super::{AtomicFile, OutputError};

/// One CSV field: a number or a piece of text.
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    /// A number, written so that parsing it back gives the same `f64`.
    Number(f64),
    /// Free text, quoted by the CSV encoder when needed.
    Text(String),
}

impl From<f64> for Cell {
    fn from(value: f64) -> Self {
        Self::Number(value)
    }
}

impl From<String> for Cell {
    fn from(value: String) -> Self {
        Self::Text(value)
    }
}

impl From<&str> for Cell {
    fn from(value: &str) -> Self {
        Self::Text(value.to_owned())
    }
}

/// Formats a number as the shortest text that parses back to the same `f64`.
///
/// Rust's `Display` is shortest-round-trip but never uses an exponent, which would print
/// 1e-12 with twelve zeros; very small and very large magnitudes use `{:e}` instead, which is
/// also shortest-round-trip.
pub(crate) fn format_number(value: f64) -> String {
    let magnitude = value.abs();
    if value == 0.0 || !value.is_finite() || (1e-4..1e15).contains(&magnitude) {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

/// Writes a table with one header line and `rows` atomically.
///
/// Every row must have as many cells as there are headers.
pub fn write_csv_table(
    path: impl AsRef<Path>,
    headers: &[&str],
    rows: &[Vec<Cell>],
) -> Result<(), OutputError> {
    let path = path.as_ref();
    if headers.is_empty() {
        return Err(OutputError::invalid(
            path,
            "a table needs at least one column",
        ));
    }
    if let Some((index, row)) = rows
        .iter()
        .enumerate()
        .find(|(_, row)| row.len() != headers.len())
    {
        return Err(OutputError::invalid(
            path,
            format!(
                "row {index} has {} cells but there are {} headers",
                row.len(),
                headers.len()
            ),
        ));
    }
    let csv_error = |source| OutputError::Csv {
        path: path.to_path_buf(),
        source,
    };
    let mut writer = csv::Writer::from_writer(AtomicFile::create(path)?);
    writer.write_record(headers).map_err(csv_error)?;
    let mut fields = Vec::with_capacity(headers.len());
    for row in rows {
        fields.clear();
        fields.extend(row.iter().map(|cell| match cell {
            Cell::Number(value) => format_number(*value),
            Cell::Text(text) => text.clone(),
        }));
        writer.write_record(&fields).map_err(csv_error)?;
    }
    let mut file = writer
        .into_inner()
        .map_err(|e| OutputError::io(path, e.into_error()))?;
    file.flush().map_err(|e| OutputError::io(path, e))?;
    file.commit()
}

/// Writes equally long numeric columns as a table atomically (column `j` under `headers[j]`).
pub fn write_csv_columns(
    path: impl AsRef<Path>,
    headers: &[&str],
    columns: &[&[f64]],
) -> Result<(), OutputError> {
    let path = path.as_ref();
    if headers.len() != columns.len() {
        return Err(OutputError::invalid(
            path,
            format!("{} headers for {} columns", headers.len(), columns.len()),
        ));
    }
    let length = columns.first().map_or(0, |column| column.len());
    if let Some(index) = columns.iter().position(|column| column.len() != length) {
        return Err(OutputError::invalid(
            path,
            format!(
                "column '{}' has {} values but column '{}' has {length}",
                headers[index],
                columns[index].len(),
                headers[0]
            ),
        ));
    }
    let rows: Vec<Vec<Cell>> = (0..length)
        .map(|row| {
            columns
                .iter()
                .map(|column| Cell::Number(column[row]))
                .collect()
        })
        .collect();
    write_csv_table(path, headers, &rows)
}
