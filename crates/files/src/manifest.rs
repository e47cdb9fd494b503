//! `study.json` (what was run: sweep, version, config hash, seeds) and `failures.json`.

use std::path::Path;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::atomic::write_json_atomic;
use crate::StudyFileError;

/// One planned case in the manifest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ManifestCase {
    /// Case identifier.
    pub id: String,
    /// Seed of its fill.
    pub seed: u64,
    /// Hex SHA-256 of its resolved case file.
    pub config_hash: String,
}

/// A grid point the sweep left out, with its reasons.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ManifestSkipped {
    /// Identifier the point would have had.
    pub id: String,
    /// Why it was left out.
    pub reasons: Vec<String>,
}

/// The content of `study.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudyManifest {
    /// Sweep name.
    pub name: String,
    /// Sweep description.
    pub description: String,
    /// hopperflow version that ran the study.
    pub version: String,
    /// Hex SHA-256 over the identifiers and resolved case files of every case, in plan
    /// order: equal hashes mean the same inputs.
    pub config_hash: String,
    /// Replicas per grid point.
    pub replicas: u32,
    /// Every planned case with its seed and case hash.
    pub cases: Vec<ManifestCase>,
    /// Grid points that were left out.
    pub skipped: Vec<ManifestSkipped>,
    /// What every case starts from instead of its fill (a saved bed); absent when each case
    /// fills its container.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<crate::StartRecord>,
}

/// Hex SHA-256 of a text.
pub fn hex_hash(text: &str) -> String {
    let digest = Sha256::digest(text.as_bytes());
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

impl StudyManifest {
    /// Reads `study.json`; `Ok(None)` when the file does not exist.
    pub fn read(path: &Path) -> Result<Option<Self>, StudyFileError> {
        let text = match std::fs::read_to_string(path) {
            Ok(text) => text,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(StudyFileError::io(path, e)),
        };
        serde_json::from_str(&text)
            .map(Some)
            .map_err(|e| StudyFileError::Parse {
                path: path.to_path_buf(),
                reason: e.to_string(),
            })
    }

    /// Writes `study.json` atomically.
    pub fn write(&self, path: &Path) -> Result<(), StudyFileError> {
        write_json_atomic(path, self)?;
        Ok(())
    }
}

/// One failed case in `failures.json`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct CaseFailure {
    /// Case identifier.
    pub id: String,
    /// The error the run returned, or the panic message.
    pub reason: String,
}
