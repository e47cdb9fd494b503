//! Parquet tables (feature `parquet`): the same cells as a CSV table, with each column
//! stored as DOUBLE when every cell is a number and as UTF-8 text otherwise.

use std::path::Path;
use std::sync::Arc;

use parquet::data_type::{ByteArray, ByteArrayType, DoubleType};
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::parser::parse_message_type;

use super::{AtomicFile, Cell, OutputError};

fn err(path: &Path, e: impl std::fmt::Display) -> OutputError {
    OutputError::InvalidData {
        path: path.to_path_buf(),
        reason: format!("parquet: {e}"),
    }
}

/// Writes `rows` under `headers` as a Parquet file, atomically.
pub fn write_parquet_table(
    path: impl AsRef<Path>,
    headers: &[&str],
    rows: &[Vec<Cell>],
) -> Result<(), OutputError> {
    let path = path.as_ref();
    if rows.iter().any(|r| r.len() != headers.len()) {
        return Err(err(path, "every row needs one cell per header"));
    }
    let numeric: Vec<bool> = (0..headers.len())
        .map(|c| rows.iter().all(|r| matches!(r[c], Cell::Number(_))))
        .collect();
    let fields: Vec<String> = headers
        .iter()
        .zip(&numeric)
        .map(|(h, &n)| {
            // Parquet field names must be plain identifiers.
            let name: String = h
                .chars()
                .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
                .collect();
            if n {
                format!("REQUIRED DOUBLE {name};")
            } else {
                format!("REQUIRED BYTE_ARRAY {name} (UTF8);")
            }
        })
        .collect();
    let schema = Arc::new(
        parse_message_type(&format!("message table {{ {} }}", fields.join(" ")))
            .map_err(|e| err(path, e))?,
    );
    let props = Arc::new(WriterProperties::builder().build());
    let file = AtomicFile::create(path)?;
    let mut writer = SerializedFileWriter::new(file, schema, props).map_err(|e| err(path, e))?;
    let mut group = writer.next_row_group().map_err(|e| err(path, e))?;
    let mut column = 0;
    while let Some(mut out) = group.next_column().map_err(|e| err(path, e))? {
        if numeric[column] {
            let values: Vec<f64> = rows
                .iter()
                .map(|r| match r[column] {
                    Cell::Number(x) => x,
                    Cell::Text(_) => f64::NAN,
                })
                .collect();
            out.typed::<DoubleType>()
                .write_batch(&values, None, None)
                .map_err(|e| err(path, e))?;
        } else {
            let values: Vec<ByteArray> = rows
                .iter()
                .map(|r| match &r[column] {
                    Cell::Number(x) => ByteArray::from(x.to_string().as_str()),
                    Cell::Text(t) => ByteArray::from(t.as_str()),
                })
                .collect();
            out.typed::<ByteArrayType>()
                .write_batch(&values, None, None)
                .map_err(|e| err(path, e))?;
        }
        out.close().map_err(|e| err(path, e))?;
        column += 1;
    }
    group.close().map_err(|e| err(path, e))?;
    let file = writer.into_inner().map_err(|e| err(path, e))?;
    file.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parquet_table_is_written_with_magic_bytes_and_refuses_ragged_rows() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.parquet");
        let rows = vec![
            vec![Cell::Text("a".into()), Cell::Number(1.5)],
            vec![Cell::Text("b".into()), Cell::Number(2.5)],
        ];
        write_parquet_table(&path, &["id", "rate"], &rows).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        // A Parquet file starts and ends with the magic "PAR1".
        assert_eq!(&bytes[..4], b"PAR1");
        assert_eq!(&bytes[bytes.len() - 4..], b"PAR1");
        let ragged = vec![vec![Cell::Number(1.0)]];
        assert!(write_parquet_table(dir.path().join("r.parquet"), &["a", "b"], &ragged).is_err());
        assert!(!dir.path().join("r.parquet").exists());
    }
}
