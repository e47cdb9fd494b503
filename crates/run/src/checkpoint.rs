//! The checkpoint file: a run's state together with the inputs that produced it.
//!
//! A checkpoint is only worth resuming under the inputs that wrote it, so the file carries
//! them: the resolved case text (and its hash), the seed and the program version. A resume
//! compares them with the case at hand and refuses a mismatch, naming every key that
//! changed ([`case_changes`]).
//!
//! Layout, so that truncation and corruption are told apart from a foreign file:
//!
//! | bytes | content |
//! |---|---|
//! | 8 | [`MAGIC`] |
//! | 8 | body length n, little-endian u64 |
//! | n | body: postcard of [`CheckpointHeader`], then of [`RunState`] and [`PictureSchedule`], then of [`TimeSpent`], then, for a run that breaks its arches, of its [`UnclogRecord`] |
//! | 32 | SHA-256 of the body |
//!
//! [`TimeSpent`] came last so that checkpoints written before it existed still resume (their
//! time spent is then unknown) and builds that predate it read the ones written after. The
//! unclogging record follows it only where the run has one, so that every other run writes
//! the bytes it always wrote.

use std::collections::BTreeMap;
use std::fmt;
use std::io::Write;
use std::path::Path;

use sha2::{Digest, Sha256};

use super::outputs::PictureSchedule;
use super::protocol::{RunState, RunStateView};
use super::time_spent::TimeSpent;
use super::unclog::UnclogRecord;
use files::StartRecord;
use files::{AtomicFile, OutputError};

/// The first eight bytes of every checkpoint: a name and the layout's version (12: the
/// run's record holds the bed at the opening, for the residence times).
pub const MAGIC: [u8; 8] = *b"HFCKPT\x00\x0c";
/// Bytes before the body: the magic and the body's length.
const PREFIX: usize = 16;
/// Bytes of the trailing SHA-256.
const DIGEST: usize = 32;

/// Hex SHA-256 of a resolved case text: the identity of a run's inputs.
pub fn config_hash(text: &str) -> String {
    let digest = Sha256::digest(text.as_bytes());
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

/// What a checkpoint says about the run that wrote it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CheckpointHeader {
    /// hopperflow version that wrote it.
    pub program_version: String,
    /// Hex SHA-256 of `case_text`.
    pub config_hash: String,
    /// Seed of the run (also a key of `case_text`).
    pub seed: u64,
    /// The resolved case, as `case.toml` holds it without its header line.
    pub case_text: String,
    /// Protocol phase when it was written: "fill", "settle", "discharge" or "done".
    pub phase: String,
    /// Simulated time when it was written [s].
    pub time: f64,
    /// What the run started from instead of a fill (a saved bed, a packing file); `None`
    /// for a run that filled its container.
    pub start: Option<StartRecord>,
}

/// Why a checkpoint file cannot be resumed from.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CheckpointError {
    /// The file could not be read.
    #[error("cannot be read: {0}")]
    Io(String),
    /// The file does not start with the checkpoint magic.
    #[error("is not a hopperflow checkpoint (its first bytes are not the checkpoint signature)")]
    Foreign,
    /// The file ends before its stated length.
    #[error(
        "is truncated: {found} bytes, a complete checkpoint of this one's body has {expected}"
    )]
    Truncated {
        /// Bytes the header promises.
        expected: u64,
        /// Bytes in the file.
        found: u64,
    },
    /// The body's checksum does not match.
    #[error("is corrupt: the SHA-256 of its content does not match the one stored with it")]
    Corrupt,
    /// The body passed its checksum but does not decode (another layout).
    #[error("cannot be decoded ({0}); it was written by an incompatible build")]
    Undecodable(String),
    /// Written by another program version, whose state need not continue bit-identically.
    #[error("was written by hopperflow {found}; this is hopperflow {expected}, which does not resume another version's state")]
    OtherVersion {
        /// The version in the file.
        found: String,
        /// This program's version.
        expected: String,
    },
}

/// Writes `header`, the run's `state`, the snapshot schedule `pictures` and the time `spent`
/// so far to `path` atomically, streamed: the body is never held in memory whole.
pub(crate) fn write_checkpoint(
    path: &Path,
    header: &CheckpointHeader,
    state: RunStateView<'_>,
    pictures: &PictureSchedule,
    spent: &TimeSpent,
) -> Result<(), OutputError> {
    write_framed(path, &MAGIC, |out| {
        postcard::to_io(header, &mut *out).map_err(|e| format!("checkpoint header: {e}"))?;
        postcard::to_io(&(state, pictures), &mut *out)
            .map_err(|e| format!("checkpoint state: {e}"))?;
        postcard::to_io(spent, &mut *out).map_err(|e| format!("checkpoint time spent: {e}"))?;
        if let Some(record) = &state.record.unclog {
            postcard::to_io(record, &mut *out).map_err(|e| format!("checkpoint clogs: {e}"))?;
        }
        Ok(())
    })
}

/// Bytes counted and hashed, not kept.
#[derive(Default)]
struct Tally {
    length: u64,
    hasher: Sha256,
}

impl Write for Tally {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        self.length += bytes.len() as u64;
        self.hasher.update(bytes);
        Ok(bytes.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Writes to `path` atomically the body that `body` writes, framed behind `magic` as the
/// module comment lays out (the magic, the body's length, the body, its SHA-256). The body
/// is streamed, not held in memory: `body` runs twice, once to count and hash its bytes and
/// once to write them, so it must write the same bytes each time (a serialisation does).
/// Saved beds share the frame (`run::bed`), with a magic of their own.
pub(crate) fn write_framed(
    path: &Path,
    magic: &[u8; 8],
    body: impl Fn(&mut dyn Write) -> Result<(), String>,
) -> Result<(), OutputError> {
    let mut tally = Tally::default();
    body(&mut tally).map_err(|e| OutputError::invalid(path, e))?;
    let length = tally.length;
    let digest = tally.hasher.finalize();
    let mut file = AtomicFile::create(path)?;
    file.write_all(magic)
        .and_then(|()| file.write_all(&length.to_le_bytes()))
        .map_err(|e| OutputError::io(path, e))?;
    let mut written = Counted {
        file: &mut file,
        length: 0,
    };
    body(&mut written).map_err(|e| OutputError::invalid(path, e))?;
    if written.length != length {
        return Err(OutputError::invalid(
            path,
            format!("the body wrote {length} bytes, then {}", written.length),
        ));
    }
    file.write_all(&digest)
        .map_err(|e| OutputError::io(path, e))?;
    file.commit()
}

/// A file and the bytes written to it.
struct Counted<'a> {
    file: &'a mut AtomicFile,
    length: u64,
}

impl Write for Counted<'_> {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        let n = self.file.write(bytes)?;
        self.length += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

/// The bytes that [`write_framed`] writes for `body`, in memory: the frame's definition,
/// against which the tests hold the streamed file.
#[cfg(test)]
pub(crate) fn framed(magic: &[u8; 8], body: &[u8]) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(PREFIX + body.len() + DIGEST);
    bytes.extend_from_slice(magic);
    bytes.extend_from_slice(&(body.len() as u64).to_le_bytes());
    bytes.extend_from_slice(body);
    bytes.extend_from_slice(&Sha256::digest(body));
    bytes
}

/// Why framed bytes are not a whole, intact body behind the expected magic.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum FrameFault {
    /// Another signature: not this kind of file.
    Foreign,
    /// Shorter than the length it states.
    Truncated {
        /// Bytes the frame promises.
        expected: u64,
        /// Bytes there are.
        found: u64,
    },
    /// Longer than it states, or the checksum does not match.
    Corrupt,
}

/// The verified body of bytes framed by [`framed`] behind `magic`.
pub(crate) fn unframed<'a>(magic: &[u8; 8], bytes: &'a [u8]) -> Result<&'a [u8], FrameFault> {
    if bytes.len() < magic.len() || bytes[..magic.len()] != magic[..] {
        return Err(FrameFault::Foreign);
    }
    let Some(length) = bytes.get(magic.len()..PREFIX) else {
        return Err(FrameFault::Truncated {
            expected: PREFIX as u64,
            found: bytes.len() as u64,
        });
    };
    let mut le = [0u8; 8];
    le.copy_from_slice(length);
    let body_length = u64::from_le_bytes(le);
    let expected = body_length.saturating_add((PREFIX + DIGEST) as u64);
    if (bytes.len() as u64) < expected {
        return Err(FrameFault::Truncated {
            expected,
            found: bytes.len() as u64,
        });
    }
    if (bytes.len() as u64) > expected {
        // Trailing bytes: the length field or the file was altered.
        return Err(FrameFault::Corrupt);
    }
    let end = PREFIX + body_length as usize;
    let (body, digest) = (&bytes[PREFIX..end], &bytes[end..]);
    if Sha256::digest(body).as_slice() != digest {
        return Err(FrameFault::Corrupt);
    }
    Ok(body)
}

/// The verified body of a checkpoint file's bytes.
fn body_of(bytes: &[u8]) -> Result<&[u8], CheckpointError> {
    unframed(&MAGIC, bytes).map_err(|fault| match fault {
        FrameFault::Foreign => CheckpointError::Foreign,
        FrameFault::Truncated { expected, found } => CheckpointError::Truncated { expected, found },
        FrameFault::Corrupt => CheckpointError::Corrupt,
    })
}

/// A checkpoint's content.
pub(crate) struct Checkpoint {
    /// Whose run it is.
    pub(crate) header: CheckpointHeader,
    /// The protocol's state, the engine's included.
    pub(crate) state: RunState,
    /// Where the snapshot series stands.
    pub(crate) pictures: PictureSchedule,
    /// The run's time spent up to the checkpoint; `None` in a checkpoint written before
    /// checkpoints recorded it.
    pub(crate) spent: Option<TimeSpent>,
}

/// Reads a checkpoint, checking its signature, length, checksum and program version.
pub(crate) fn read_checkpoint(path: &Path) -> Result<Checkpoint, CheckpointError> {
    let bytes = std::fs::read(path).map_err(|e| CheckpointError::Io(e.to_string()))?;
    let body = body_of(&bytes)?;
    let (header, rest) = postcard::take_from_bytes::<CheckpointHeader>(body)
        .map_err(|e| CheckpointError::Undecodable(e.to_string()))?;
    if header.program_version != env!("CARGO_PKG_VERSION") {
        return Err(CheckpointError::OtherVersion {
            found: header.program_version,
            expected: env!("CARGO_PKG_VERSION").to_string(),
        });
    }
    let ((mut state, pictures), rest): ((RunState, PictureSchedule), _) =
        postcard::take_from_bytes(rest).map_err(|e| CheckpointError::Undecodable(e.to_string()))?;
    let spent = if rest.is_empty() {
        None
    } else {
        let (spent, rest) = postcard::take_from_bytes::<TimeSpent>(rest)
            .map_err(|e| CheckpointError::Undecodable(format!("time spent: {e}")))?;
        if !rest.is_empty() {
            state.record.unclog = Some(
                postcard::from_bytes::<UnclogRecord>(rest)
                    .map_err(|e| CheckpointError::Undecodable(format!("clogs: {e}")))?,
            );
        }
        Some(spent)
    };
    Ok(Checkpoint {
        header,
        state,
        pictures,
        spent,
    })
}

/// Reads only a checkpoint's header (after the same checks as [`read_checkpoint`], less the
/// program version): what a study or a tool needs to tell whose checkpoint it is.
pub fn read_checkpoint_header(path: &Path) -> Result<CheckpointHeader, CheckpointError> {
    let bytes = std::fs::read(path).map_err(|e| CheckpointError::Io(e.to_string()))?;
    let body = body_of(&bytes)?;
    postcard::take_from_bytes::<CheckpointHeader>(body)
        .map(|(header, _)| header)
        .map_err(|e| CheckpointError::Undecodable(e.to_string()))
}

/// One key whose value differs between two resolved cases.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KeyChange {
    /// Dotted key, e.g. `geometry.outlet_width`.
    pub key: String,
    /// Its value in the earlier inputs (`None`: absent there).
    pub old: Option<String>,
    /// Its value in the case at hand (`None`: absent here).
    pub new: Option<String>,
}

impl fmt::Display for KeyChange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let show = |v: &Option<String>| v.clone().unwrap_or_else(|| "(absent)".to_string());
        write!(
            f,
            "{}: {} -> {}",
            self.key,
            show(&self.old),
            show(&self.new)
        )
    }
}

/// Every key whose value differs between two resolved case texts, in key order. Comments
/// and layout do not count; a text that is not TOML counts as having no keys.
pub fn case_changes(old_text: &str, new_text: &str) -> Vec<KeyChange> {
    let (old, new) = (flatten(old_text), flatten(new_text));
    let keys: std::collections::BTreeSet<&String> = old.keys().chain(new.keys()).collect();
    keys.into_iter()
        .filter(|k| old.get(*k) != new.get(*k))
        .map(|k| KeyChange {
            key: k.clone(),
            old: old.get(k).cloned(),
            new: new.get(k).cloned(),
        })
        .collect()
}

/// The values of a TOML text by dotted key.
fn flatten(text: &str) -> BTreeMap<String, String> {
    fn walk(prefix: &str, table: &toml::Table, out: &mut BTreeMap<String, String>) {
        for (key, value) in table {
            let dotted = if prefix.is_empty() {
                key.clone()
            } else {
                format!("{prefix}.{key}")
            };
            match value {
                toml::Value::Table(inner) => walk(&dotted, inner, out),
                other => {
                    out.insert(dotted, other.to_string());
                }
            }
        }
    }
    let mut out = BTreeMap::new();
    if let Ok(table) = text.parse::<toml::Table>() {
        walk("", &table, &mut out);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn changes_name_each_differing_key_with_both_values() {
        let old = "seed = 1\n[geometry]\nwidth = 0.1\noutlet_width = 0.018\n";
        let new =
            "seed = 1\n# a comment\n[geometry]\nwidth = 0.1\noutlet_width = 0.03\nextra = true\n";
        let changes = case_changes(old, new);
        assert_eq!(
            changes,
            vec![
                KeyChange {
                    key: "geometry.extra".into(),
                    old: None,
                    new: Some("true".into())
                },
                KeyChange {
                    key: "geometry.outlet_width".into(),
                    old: Some("0.018".into()),
                    new: Some("0.03".into())
                },
            ]
        );
        assert_eq!(
            changes[1].to_string(),
            "geometry.outlet_width: 0.018 -> 0.03"
        );
        assert!(case_changes(old, old).is_empty());
    }

    #[test]
    fn a_streamed_frame_holds_the_bytes_of_the_frame_in_memory() {
        let dir = std::env::temp_dir().join(format!("hopperflow-frame-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("frame.bin");
        let parts: [&[u8]; 3] = [b"some ", b"", b"body"];
        write_framed(&path, &MAGIC, |out| {
            parts
                .iter()
                .try_for_each(|p| out.write_all(p))
                .map_err(|e| e.to_string())
        })
        .unwrap();
        let written = std::fs::read(&path).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(written, framed(&MAGIC, b"some body"));
    }

    #[test]
    fn a_body_that_writes_other_bytes_the_second_time_is_refused() {
        let dir = std::env::temp_dir().join(format!("hopperflow-frame2-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("frame.bin");
        let calls = std::cell::Cell::new(0);
        let result = write_framed(&path, &MAGIC, |out| {
            calls.set(calls.get() + 1);
            out.write_all(&vec![0; calls.get()])
                .map_err(|e| e.to_string())
        });
        let left = std::fs::read_dir(&dir).unwrap().count();
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(result.is_err(), "{result:?}");
        assert_eq!(left, 0, "nothing is left behind");
    }

    #[test]
    fn damaged_bodies_are_told_apart() {
        let body = b"some body".to_vec();
        let bytes = framed(&MAGIC, &body);
        assert_eq!(body_of(&bytes), Ok(&body[..]));
        // Every proper prefix is truncated (or, shorter than the magic, foreign).
        for cut in 0..bytes.len() {
            let err = body_of(&bytes[..cut]).unwrap_err();
            if cut < MAGIC.len() {
                assert_eq!(err, CheckpointError::Foreign, "cut at {cut}");
            } else {
                assert!(
                    matches!(err, CheckpointError::Truncated { found, .. } if found == cut as u64),
                    "cut at {cut}: {err:?}"
                );
            }
        }
        let mut flipped = bytes.clone();
        flipped[PREFIX + 2] ^= 1;
        assert_eq!(body_of(&flipped), Err(CheckpointError::Corrupt));
        let mut longer = bytes.clone();
        longer.push(0);
        assert_eq!(body_of(&longer), Err(CheckpointError::Corrupt));
        assert_eq!(body_of(b"{\"json\": true}"), Err(CheckpointError::Foreign));
    }
}
