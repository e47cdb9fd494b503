//! Atomic file writing: write a temporary file in the target's directory, fsync, rename.
//!
//! A reader (ParaView following a `.pvd`, a resumed sweep reading `summary.json`) must never
//! see a half-written file. POSIX `rename` within one directory replaces the target in a single
//! step, so the target is either the old complete file or the new complete file. The temporary
//! file lives in the same directory because a rename across file systems is a copy.

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use serde::Serialize;

use super::OutputError;

/// Distinguishes temporary files made by the threads of one process (the process id
/// distinguishes processes).
static TEMPORARY_COUNTER: AtomicU64 = AtomicU64::new(0);

/// How many names to try before giving up when a temporary name is already taken.
const RESERVATION_ATTEMPTS: u32 = 64;

/// A reserved temporary path next to a target; removed on drop unless committed.
///
/// Used directly by writers whose library insists on writing to a path itself (the PNG encoder
/// picks the format from the extension), and through [`AtomicFile`] by everything else.
#[derive(Debug)]
pub(crate) struct StagedPath {
    target: PathBuf,
    temporary: PathBuf,
    committed: bool,
}

impl StagedPath {
    /// Creates an empty, uniquely named file in the directory of `target`, ending in
    /// `extension` (without the dot; empty for none).
    pub(crate) fn reserve(target: &Path, extension: &str) -> Result<(Self, File), OutputError> {
        let file_name = target
            .file_name()
            .ok_or_else(|| OutputError::invalid(target, "the path does not name a file"))?
            .to_string_lossy()
            .into_owned();
        let directory = match target.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let suffix = if extension.is_empty() {
            String::new()
        } else {
            format!(".{extension}")
        };
        let mut last_error = None;
        for _ in 0..RESERVATION_ATTEMPTS {
            let serial = TEMPORARY_COUNTER.fetch_add(1, Ordering::Relaxed);
            let temporary = directory.join(format!(
                ".{file_name}.{}-{serial}.tmp{suffix}",
                std::process::id()
            ));
            // `create_new` fails if the name exists, so two writers can never share a file.
            match OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&temporary)
            {
                Ok(file) => {
                    let staged = Self {
                        target: target.to_path_buf(),
                        temporary,
                        committed: false,
                    };
                    return Ok((staged, file));
                }
                Err(error) if error.kind() == std::io::ErrorKind::AlreadyExists => {
                    last_error = Some(error);
                }
                Err(error) => return Err(OutputError::io(target, error)),
            }
        }
        Err(OutputError::io(
            target,
            last_error.unwrap_or_else(|| std::io::Error::other("no free temporary name")),
        ))
    }

    /// Flushes the temporary file to disk and renames it onto the target.
    pub(crate) fn commit(mut self) -> Result<(), OutputError> {
        let file = File::open(&self.temporary).map_err(|e| OutputError::io(&self.target, e))?;
        file.sync_all()
            .map_err(|e| OutputError::io(&self.target, e))?;
        drop(file);
        self.rename_onto_target()
    }

    /// Renames the (already synced) temporary file onto the target.
    fn rename_onto_target(&mut self) -> Result<(), OutputError> {
        std::fs::rename(&self.temporary, &self.target)
            .map_err(|e| OutputError::io(&self.target, e))?;
        self.committed = true;
        sync_parent_directory(&self.target);
        Ok(())
    }
}

impl Drop for StagedPath {
    fn drop(&mut self) {
        if !self.committed {
            // Best effort: the error path is already reporting the original failure.
            let _ = std::fs::remove_file(&self.temporary);
        }
    }
}

/// Makes the rename itself durable. Best effort: some file systems refuse to sync a
/// directory, and the rename has already happened atomically either way.
fn sync_parent_directory(target: &Path) {
    #[cfg(unix)]
    {
        let directory = match target.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        };
        if let Ok(handle) = File::open(directory) {
            let _ = handle.sync_all();
        }
    }
    #[cfg(not(unix))]
    let _ = target;
}

/// A buffered writer whose content appears at its target path only on [`AtomicFile::commit`].
///
/// Dropping it without committing (an error part-way, a panic) deletes the temporary file and
/// leaves any previous target untouched.
#[derive(Debug)]
pub struct AtomicFile {
    staged: StagedPath,
    writer: BufWriter<File>,
}

impl AtomicFile {
    /// Opens a new temporary file next to `target`.
    pub fn create(target: impl AsRef<Path>) -> Result<Self, OutputError> {
        let (staged, file) = StagedPath::reserve(target.as_ref(), "")?;
        Ok(Self {
            staged,
            writer: BufWriter::new(file),
        })
    }

    /// The path the content will appear at.
    pub fn target(&self) -> &Path {
        &self.staged.target
    }

    /// Flushes, fsyncs and renames the temporary file onto the target.
    pub fn commit(self) -> Result<(), OutputError> {
        let Self { mut staged, writer } = self;
        let target = staged.target.clone();
        let file = writer
            .into_inner()
            .map_err(|e| OutputError::io(&target, e.into_error()))?;
        file.sync_all().map_err(|e| OutputError::io(&target, e))?;
        drop(file);
        staged.rename_onto_target()
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buffer: &[u8]) -> std::io::Result<usize> {
        self.writer.write(buffer)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.writer.flush()
    }
}

/// Whether `name` is a temporary name that [`StagedPath::reserve`] makes:
/// `.{target}.{pid}-{serial}.tmp`, optionally followed by `.{extension}`. Returns the pid.
pub fn is_temporary_name(name: &str) -> Option<u32> {
    let rest = name.strip_prefix('.')?;
    let at = rest.rfind(".tmp")?;
    let (before, after) = rest.split_at(at);
    let after = &after[".tmp".len()..];
    if !(after.is_empty() || (after.starts_with('.') && !after[1..].contains('.'))) {
        return None;
    }
    let (target, ids) = before.rsplit_once('.')?;
    let (pid, serial) = ids.split_once('-')?;
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    if target.is_empty() || !digits(pid) || !digits(serial) {
        return None;
    }
    pid.parse().ok()
}

/// Whether the process `pid` still runs (on Linux, by its `/proc` entry; elsewhere every
/// other process counts as gone).
fn process_alive(pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    if cfg!(target_os = "linux") {
        Path::new("/proc").join(pid.to_string()).exists()
    } else {
        false
    }
}

/// Removes the temporary files in `dir` that a killed write left behind: those named as
/// [`is_temporary_name`] says, whose writing process no longer runs. Readers never look at
/// them, so they are only clutter; a missing `dir` has none. Returns how many were removed.
pub fn remove_stale_temporaries(dir: &Path) -> Result<usize, OutputError> {
    let entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(0),
        Err(e) => return Err(OutputError::io(dir, e)),
    };
    let mut removed = 0;
    for entry in entries {
        let entry = entry.map_err(|e| OutputError::io(dir, e))?;
        let name = entry.file_name();
        let Some(pid) = name.to_str().and_then(is_temporary_name) else {
            continue;
        };
        if process_alive(pid) || !entry.file_type().is_ok_and(|t| t.is_file()) {
            continue;
        }
        match std::fs::remove_file(entry.path()) {
            Ok(()) => removed += 1,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(OutputError::io(&entry.path(), e)),
        }
    }
    Ok(removed)
}

/// Writes `bytes` to `path` atomically.
pub fn write_atomic(path: impl AsRef<Path>, bytes: &[u8]) -> Result<(), OutputError> {
    let path = path.as_ref();
    let mut file = AtomicFile::create(path)?;
    file.write_all(bytes)
        .map_err(|e| OutputError::io(path, e))?;
    file.commit()
}

/// Serialises `value` as pretty-printed JSON (with a trailing newline) to `path` atomically.
pub fn write_json_atomic<T: Serialize + ?Sized>(
    path: impl AsRef<Path>,
    value: &T,
) -> Result<(), OutputError> {
    let path = path.as_ref();
    let mut file = AtomicFile::create(path)?;
    serde_json::to_writer_pretty(&mut file, value).map_err(|source| OutputError::Json {
        path: path.to_path_buf(),
        source,
    })?;
    file.write_all(b"\n")
        .map_err(|e| OutputError::io(path, e))?;
    file.commit()
}
