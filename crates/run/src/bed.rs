//! A settled bed saved when the gate opens, and its reuse: `hopperflow run --save-bed DIR`
//! and `--from-bed DIR` (docs/user-guide.md §5).
//!
//! A bed is the run's whole state at the instant the settling ends, just before the gate is
//! removed: the engine's state (positions, velocities, spins, every contact history, the
//! walls, the time and step count) and the protocol's. A run from the bed with the same case
//! therefore discharges bit for bit as the run that saved it. The folder holds `bed.bin`,
//! framed as a checkpoint is (signature, length, postcard body, SHA-256: `run::checkpoint`)
//! behind its own signature, and `case.toml`, the resolved case that settled it.
//!
//! Which case may reuse a bed is decided by key ([`check_bed_case`]): the keys that made the
//! bed (the walls other than the outlet, the particles, the materials and laws, the time
//! step, the seed and the fill and settling rules) must be equal; the outlet, the rules of
//! the discharge and the measurement and output keys may differ. An outlet may change only
//! where the bottom is flat: there the plates (or the flat bottom) and the gate stay in the
//! orifice plane z = 0 and the bed rests on the same plane, while under inclined plates or a
//! cone the walls holding the bed would move with the outlet.

use std::fmt;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::checkpoint::{case_changes, config_hash, unframed, write_framed, FrameFault, KeyChange};
use files::{BED_CASE_FILE, BED_FILE};

use super::protocol::RunState;
use case::{Case, Geometry};
use files::{remove_stale_temporaries, write_atomic, OutputError};

/// The first eight bytes of every `bed.bin`: a name and the layout's version (5: the run's
/// record holds the bed at the opening, for the residence times).
pub const BED_MAGIC: [u8; 8] = *b"HFBED\x00\x00\x05";

/// Keys that may differ between a bed's case and the case that reuses it, besides every key
/// of `[measure]` and `[output]`: the outlet's size and position, and the rules that act
/// only after the gate opens.
const DISCHARGE_KEYS: [&str; 8] = [
    "geometry.outlet_width",
    "geometry.outlet_gap",
    "geometry.outlet_diameter",
    "geometry.outlet_offset",
    "protocol.deletion_depth",
    "protocol.clog_timeout",
    "protocol.time_limit",
    "protocol.stop_fraction",
];

/// The keys of [`DISCHARGE_KEYS`] that place the outlet, and so rebuild walls when changed.
const OUTLET_KEYS: [&str; 4] = [
    "geometry.outlet_width",
    "geometry.outlet_gap",
    "geometry.outlet_diameter",
    "geometry.outlet_offset",
];

/// Whether a key's value may differ between a bed's case and the case that reuses it.
fn may_differ(key: &str) -> bool {
    key.starts_with("measure.") || key.starts_with("output.") || DISCHARGE_KEYS.contains(&key)
}

/// What a bed says about the run that saved it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BedHeader {
    /// hopperflow version that wrote it.
    pub program_version: String,
    /// Hex SHA-256 of `case_text`.
    pub config_hash: String,
    /// Seed of the fill (also a key of `case_text`).
    pub seed: u64,
    /// The resolved case that filled and settled the bed, as `case.toml` holds it without
    /// its header line.
    pub case_text: String,
    /// Simulated time when the settling ended [s]: the reusing run opens its gate then.
    pub time: f64,
    /// Particles in the bed.
    pub particles: usize,
    /// Whether the settling reached its kinetic-energy threshold (false: it hit
    /// `protocol.max_settle_time`).
    pub settled: bool,
}

/// A bed read back from its folder.
#[derive(Debug, Clone)]
pub struct Bed {
    /// The file it was read from.
    pub(crate) path: PathBuf,
    /// Whose bed it is.
    pub(crate) header: BedHeader,
    /// The run's state at the end of the settling, gate closed.
    pub(crate) state: RunState,
    /// Hex SHA-256 of the body: the identity a reusing run records.
    pub(crate) sha256: String,
}

impl Bed {
    /// The file it was read from.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whose bed it is.
    pub fn header(&self) -> &BedHeader {
        &self.header
    }

    /// The resolved case that settled it.
    pub fn case_text(&self) -> &str {
        &self.header.case_text
    }

    /// Hex SHA-256 of its content (the checksum stored in its frame).
    pub fn sha256(&self) -> &str {
        &self.sha256
    }

    /// The run's state at the end of the settling, gate closed: what a simulation of the
    /// bed starts from.
    pub fn state(&self) -> &RunState {
        &self.state
    }
}

/// Why a bed cannot be read, or cannot be reused by a case.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BedError {
    /// Neither the path nor a `bed.bin` inside it exists.
    #[error("{}: no saved bed there (expected {BED_FILE}, written by `hopperflow run --save-bed DIR`)", .0.display())]
    Missing(PathBuf),
    /// The file could not be read.
    #[error("{}: cannot be read: {reason}", .path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        reason: String,
    },
    /// The file does not start with the bed signature.
    #[error("{}: is not a hopperflow bed (its first bytes are not the bed signature)", .0.display())]
    Foreign(PathBuf),
    /// The file ends before its stated length.
    #[error("{}: is truncated: {found} bytes, a complete bed of this one's body has {expected}", .path.display())]
    Truncated {
        /// The file.
        path: PathBuf,
        /// Bytes the frame promises.
        expected: u64,
        /// Bytes in the file.
        found: u64,
    },
    /// The body's checksum does not match.
    #[error("{}: is corrupt: the SHA-256 of its content does not match the one stored with it", .0.display())]
    Corrupt(PathBuf),
    /// The body passed its checksum but does not decode.
    #[error("{}: cannot be decoded ({reason}); it was written by an incompatible build", .path.display())]
    Undecodable {
        /// The file.
        path: PathBuf,
        /// The decoder's complaint.
        reason: String,
    },
    /// Written by another program version, whose state need not continue bit-identically.
    #[error("{}: was written by hopperflow {found}; this is hopperflow {expected}, which does not reuse another version's state", .path.display())]
    OtherVersion {
        /// The file.
        path: PathBuf,
        /// The version in the file.
        found: String,
        /// This program's version.
        expected: String,
    },
    /// The case changes keys that made the bed.
    #[error("{}: the bed was settled under other inputs; only the outlet, the discharge rules (protocol.deletion_depth, clog_timeout, time_limit, stop_fraction) and [measure] and [output] keys may differ; changed: {}", .path.display(), list(.changes))]
    OtherInputs {
        /// The bed file.
        path: PathBuf,
        /// The keys that must not differ but do, the bed's value first.
        changes: Vec<KeyChange>,
    },
    /// The case moves the outlet of a container whose bottom walls move with it.
    #[error("{}: the outlet of this container cannot change under a settled bed: its bottom is inclined ({kind} at {angle_deg}° from the vertical), so the walls that hold the bed move with the outlet; only a flat bottom (hopper_angle_deg = 90) keeps them; changed: {}", .path.display(), list(.changes))]
    WallsWouldMove {
        /// The bed file.
        path: PathBuf,
        /// "slab" or "cylinder".
        kind: &'static str,
        /// The bottom's angle from the vertical [°].
        angle_deg: f64,
        /// The outlet keys that changed.
        changes: Vec<KeyChange>,
    },
}

/// Why a run may not save its settled bed into a folder.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SaveBedError {
    /// The folder holds another bed (or the same one, for a run that starts over).
    #[error("{}: holds a saved bed already ({header}); --restart replaces it (restart=True from Python), or choose another folder", .dir.display())]
    Occupied {
        /// The folder.
        dir: PathBuf,
        /// The bed it holds, in words.
        header: String,
    },
    /// The folder holds a bed file that this version cannot read.
    #[error("{}: holds a {BED_FILE} that is not a readable bed of this version; remove it or choose another folder", .dir.display())]
    Unreadable {
        /// The folder.
        dir: PathBuf,
    },
}

/// Checks, reading only, that a run of `case` may save its bed into `dir`: the folder holds
/// no bed, or the run starts over (`restart`: its bed replaces the one there), or the run is
/// resumed (`resume`) and the bed there is this case's own. Anything else would overwrite a
/// bed that other runs may start from.
pub fn check_save_bed(
    dir: &Path,
    case: &Case,
    resume: bool,
    restart: bool,
) -> Result<(), SaveBedError> {
    if restart || !dir.join(BED_FILE).exists() {
        return Ok(());
    }
    match bed_header(dir) {
        Some(h) if resume && h.case_text == case.to_toml_string() => Ok(()),
        Some(h) => Err(SaveBedError::Occupied {
            dir: dir.to_path_buf(),
            header: h.to_string(),
        }),
        None => Err(SaveBedError::Unreadable {
            dir: dir.to_path_buf(),
        }),
    }
}

/// "a: x -> y, b: …".
fn list(changes: &[KeyChange]) -> String {
    let items: Vec<String> = changes.iter().map(ToString::to_string).collect();
    items.join(", ")
}

/// The bed file a `--from-bed` argument names: `bed.bin` inside a folder, or the file.
fn bed_file(path: &Path) -> Result<PathBuf, BedError> {
    if path.is_dir() {
        let file = path.join(BED_FILE);
        if file.is_file() {
            return Ok(file);
        }
        return Err(BedError::Missing(path.to_path_buf()));
    }
    if path.is_file() {
        return Ok(path.to_path_buf());
    }
    Err(BedError::Missing(path.to_path_buf()))
}

/// Reads the bed saved in folder `path` (or the `bed.bin` file `path`), checking its
/// signature, length, checksum and program version.
pub fn read_bed(path: &Path) -> Result<Bed, BedError> {
    let file = bed_file(path)?;
    let bytes = std::fs::read(&file).map_err(|e| BedError::Io {
        path: file.clone(),
        reason: e.to_string(),
    })?;
    let body = unframed(&BED_MAGIC, &bytes).map_err(|fault| match fault {
        FrameFault::Foreign => BedError::Foreign(file.clone()),
        FrameFault::Truncated { expected, found } => BedError::Truncated {
            path: file.clone(),
            expected,
            found,
        },
        FrameFault::Corrupt => BedError::Corrupt(file.clone()),
    })?;
    let undecodable = |e: postcard::Error| BedError::Undecodable {
        path: file.clone(),
        reason: e.to_string(),
    };
    let (header, rest) = postcard::take_from_bytes::<BedHeader>(body).map_err(undecodable)?;
    if header.program_version != env!("CARGO_PKG_VERSION") {
        return Err(BedError::OtherVersion {
            path: file,
            found: header.program_version,
            expected: env!("CARGO_PKG_VERSION").to_string(),
        });
    }
    let state: RunState = postcard::from_bytes(rest).map_err(undecodable)?;
    let digest = &bytes[bytes.len() - 32..];
    Ok(Bed {
        path: file,
        header,
        state,
        sha256: digest.iter().map(|b| format!("{b:02x}")).collect(),
    })
}

/// Writes a bed into folder `dir` (created if missing): `case.toml` first, then `bed.bin`,
/// each atomically, so that a `bed.bin` present is always whole and its case beside it.
pub(crate) fn write_bed(
    dir: &Path,
    header: &BedHeader,
    state: &RunState,
    case_file_text: &str,
) -> Result<(), OutputError> {
    std::fs::create_dir_all(dir).map_err(|e| OutputError::io(dir, e))?;
    remove_stale_temporaries(dir)?;
    write_atomic(dir.join(BED_CASE_FILE), case_file_text.as_bytes())?;
    let path = dir.join(BED_FILE);
    write_framed(&path, &BED_MAGIC, |out| {
        postcard::to_io(header, &mut *out).map_err(|e| format!("bed header: {e}"))?;
        postcard::to_io(state, &mut *out).map_err(|e| format!("bed state: {e}"))?;
        Ok(())
    })
}

/// The header of `dir`'s bed, if it holds a readable one of this program version.
pub fn bed_header(dir: &Path) -> Option<BedHeader> {
    read_bed(dir).ok().map(|bed| bed.header)
}

/// How a case reuses a bed: the keys it changes (all of them allowed), and whether the
/// outlet is among them (then the walls are rebuilt around the bed).
#[derive(Debug, Clone, PartialEq)]
pub struct BedReuse {
    /// The keys that differ from the bed's case, the bed's value first.
    pub changes: Vec<KeyChange>,
    /// Whether the outlet's size or position changed.
    pub outlet_changed: bool,
}

/// Checks that `case` may start from a bed settled under the resolved case `bed_case_text`
/// (see the module comment), naming every key that may not differ but does, with both
/// values. `path` names the bed in the errors.
pub fn check_bed_case(path: &Path, bed_case_text: &str, case: &Case) -> Result<BedReuse, BedError> {
    let changes = case_changes(bed_case_text, &case.to_toml_string());
    let (allowed, refused): (Vec<KeyChange>, Vec<KeyChange>) =
        changes.into_iter().partition(|c| may_differ(&c.key));
    if !refused.is_empty() {
        return Err(BedError::OtherInputs {
            path: path.to_path_buf(),
            changes: refused,
        });
    }
    let outlet: Vec<KeyChange> = allowed
        .iter()
        .filter(|c| OUTLET_KEYS.contains(&c.key.as_str()))
        .cloned()
        .collect();
    let flat = match &case.geometry {
        Geometry::Slab(g) => g.hopper_angle_deg >= 90.0,
        Geometry::Cylinder(g) => g.is_flat(),
        Geometry::Cuboid(g) => g.is_flat(),
        Geometry::DrawDown(_) => true,
        // The heap has no outlet keys.
        Geometry::Heap(_) => false,
        // A mesh's outlet keys (`geometry.outlet.*`) may not differ at all.
        Geometry::Mesh(_) => false,
    };
    if !outlet.is_empty() && !flat {
        return Err(BedError::WallsWouldMove {
            path: path.to_path_buf(),
            kind: case.geometry.kind(),
            angle_deg: case.geometry.hopper_angle_deg(),
            changes: outlet,
        });
    }
    Ok(BedReuse {
        outlet_changed: !outlet.is_empty(),
        changes: allowed,
    })
}

/// [`check_bed_case`] for a bed read from disk.
pub fn check_bed(bed: &Bed, case: &Case) -> Result<BedReuse, BedError> {
    check_bed_case(&bed.path, &bed.header.case_text, case)
}

impl fmt::Display for BedHeader {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} particles settled at t = {:.4} s{} (config hash {})",
            self.particles,
            self.time,
            if self.settled {
                ""
            } else {
                ", the settle time limit reached"
            },
            &self.config_hash[..self.config_hash.len().min(12)]
        )
    }
}

/// Whether `header` is the bed of the resolved case `case_text`.
pub(crate) fn is_bed_of(header: &BedHeader, case_text: &str) -> bool {
    header.config_hash == config_hash(case_text) && header.case_text == case_text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_outlet_discharge_measure_and_output_keys_may_differ() {
        for key in [
            "geometry.outlet_width",
            "geometry.outlet_offset",
            "protocol.time_limit",
            "measure.x_bin_width",
            "output.plots",
        ] {
            assert!(may_differ(key), "{key}");
        }
        for key in [
            "seed",
            "gravity",
            "geometry.width",
            "geometry.hopper_angle_deg",
            "geometry.mesh_segments",
            "particles.count",
            "particles.material.density",
            "wall.friction",
            "contact.friction",
            "time.time_step",
            "protocol.settle_kinetic_energy",
            "protocol.fill_top",
        ] {
            assert!(!may_differ(key), "{key}");
        }
    }
}
