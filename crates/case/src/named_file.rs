//! A file a case names by a key (an STL wall, an STL grain): its path taken from the case
//! file's folder and kept absolute, its bytes, and the SHA-256 the case may pin it to. Every
//! refusal names the key and the file.

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use super::error::{ConfigError, ErrorKind};
use super::reader::Located;

/// A file read for a case: its absolute path (and the path as text, which the resolved case
/// writes), its bytes and their hex SHA-256.
pub(crate) struct NamedFile {
    pub(crate) path: PathBuf,
    pub(crate) path_text: String,
    pub(crate) bytes: Vec<u8>,
    pub(crate) digest: String,
}

/// The file's path from the case file's folder, made absolute without touching the disk.
pub(crate) fn resolve_path(dir: Option<&Path>, file: &str) -> std::io::Result<PathBuf> {
    match dir {
        Some(dir) => std::path::absolute(dir.join(file)),
        None => std::path::absolute(file),
    }
}

/// Reads the `what` (e.g. "STL file") that `file` names, from `dir` where relative; `None`
/// (with the error) when the name is empty, the path cannot be made absolute or named as
/// text, or the file cannot be read. A `sha` given and not the file's digest is an error
/// too; the file is still returned, so that the caller can go on checking.
pub(crate) fn read_named_file(
    file: &Located<String>,
    sha: Option<&Located<String>>,
    dir: Option<&Path>,
    what: &str,
    errors: &mut Vec<ConfigError>,
) -> Option<(NamedFile, bool)> {
    if file.value.is_empty() {
        errors.push(file.error(ErrorKind::Invalid, format!("must name an {what}")));
        return None;
    }
    let path = match resolve_path(dir, &file.value) {
        Ok(path) => path,
        Err(e) => {
            errors.push(file.error(ErrorKind::Io, format!("cannot make the path absolute: {e}")));
            return None;
        }
    };
    let Some(path_text) = path.to_str().map(str::to_string) else {
        errors.push(file.error(
            ErrorKind::Invalid,
            format!(
                "the absolute path {} is not valid UTF-8, so the resolved case could not name it",
                path.display()
            ),
        ));
        return None;
    };
    let bytes = match std::fs::read(&path) {
        Ok(bytes) => bytes,
        Err(e) => {
            errors.push(file.error(
                ErrorKind::Io,
                format!("cannot read the {what}: {path_text}: {e}"),
            ));
            return None;
        }
    };
    let digest: String = Sha256::digest(&bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    let mut pinned = true;
    if let Some(sha) = sha {
        if !sha.value.eq_ignore_ascii_case(&digest) {
            errors.push(sha.error(
                ErrorKind::Invalid,
                format!(
                    "{path_text} has the SHA-256 {digest}: the file changed since this case \
                     named it; remove {} to accept the file as it is",
                    sha.key
                ),
            ));
            pinned = false;
        }
    }
    Some((
        NamedFile {
            path,
            path_text,
            bytes,
            digest,
        },
        pinned,
    ))
}
