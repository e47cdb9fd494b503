//! ParaView data collections (`.pvd`): the list of (time, file) pairs of a time series.
//!
//! The collection is rewritten atomically after every addition, so ParaView can open it at any
//! moment of a run and always sees a complete series of files that already exist.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::table::format_number;
use super::{write_atomic, OutputError};

/// One dataset of the series.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PvdEntry {
    /// Simulation time of the dataset [s].
    pub time: f64,
    /// Part number: datasets shown together at one time differ by part (for example 0 for
    /// particles, 1 for walls).
    pub part: u32,
    /// The dataset's path relative to the collection's directory, with `/` separators.
    pub file: String,
}

/// A `.pvd` time series that grows during a run.
///
/// ParaView shows, at each time, the entries with that exact time; a static part such as the
/// walls should therefore be pushed at every time (it may name the same file each time).
#[derive(Debug, Clone)]
pub struct PvdCollection {
    path: PathBuf,
    entries: Vec<PvdEntry>,
}

impl PvdCollection {
    /// An empty collection that will be written to `path` (nothing is written yet).
    pub fn new(path: impl Into<PathBuf>) -> Self {
        Self {
            path: path.into(),
            entries: Vec::new(),
        }
    }

    /// A collection that already holds `entries` (a resumed run's earlier datasets); nothing
    /// is written yet.
    pub fn with_entries(path: impl Into<PathBuf>, entries: Vec<PvdEntry>) -> Self {
        Self {
            path: path.into(),
            entries,
        }
    }

    /// The collection file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The datasets added so far, in order of addition.
    pub fn entries(&self) -> &[PvdEntry] {
        &self.entries
    }

    /// Adds the dataset `file` at time `time` [s] as part `part` and rewrites the collection.
    ///
    /// `file` may be given relative to the collection's directory or as a path that starts
    /// with that directory; it is stored relative, so the output folder can be moved.
    pub fn push(
        &mut self,
        time: f64,
        part: u32,
        file: impl AsRef<Path>,
    ) -> Result<(), OutputError> {
        if !time.is_finite() {
            return Err(OutputError::invalid(
                &self.path,
                format!("dataset time {time} is not finite"),
            ));
        }
        let file = file.as_ref();
        let relative = match self.path.parent() {
            Some(directory) if !directory.as_os_str().is_empty() => {
                file.strip_prefix(directory).unwrap_or(file)
            }
            _ => file,
        };
        let text = relative
            .components()
            .map(|component| component.as_os_str().to_string_lossy())
            .collect::<Vec<_>>()
            .join("/");
        if text.is_empty() {
            return Err(OutputError::invalid(&self.path, "dataset path is empty"));
        }
        self.entries.push(PvdEntry {
            time,
            part,
            file: text,
        });
        self.write()
    }

    /// Writes the collection atomically.
    pub fn write(&self) -> Result<(), OutputError> {
        let mut xml = String::with_capacity(96 * self.entries.len() + 256);
        xml.push_str("<?xml version=\"1.0\"?>\n");
        xml.push_str("<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n");
        xml.push_str("  <Collection>\n");
        for entry in &self.entries {
            let _ = writeln!(
                xml,
                "    <DataSet timestep=\"{}\" group=\"\" part=\"{}\" file=\"{}\"/>",
                format_number(entry.time),
                entry.part,
                escape_attribute(&entry.file)
            );
        }
        xml.push_str("  </Collection>\n</VTKFile>\n");
        write_atomic(&self.path, xml.as_bytes())
    }
}

/// Escapes the five XML special characters for use inside a double-quoted attribute.
fn escape_attribute(text: &str) -> String {
    let mut escaped = String::with_capacity(text.len());
    for character in text.chars() {
        match character {
            '&' => escaped.push_str("&amp;"),
            '<' => escaped.push_str("&lt;"),
            '>' => escaped.push_str("&gt;"),
            '"' => escaped.push_str("&quot;"),
            '\'' => escaped.push_str("&apos;"),
            other => escaped.push(other),
        }
    }
    escaped
}
