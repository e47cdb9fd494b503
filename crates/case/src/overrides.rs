//! `key=value` overrides (from `--set` or sweep axes) applied to a document before it is
//! validated, so that an override is checked exactly like a value written in the file.

use std::sync::Arc;

use super::document::{parse_value, split_key, Node, Table};
use super::error::{ConfigError, ConfigErrors, ErrorKind, Location};
use super::resolve::ALTERNATIVE_KEYS;

/// Source name of command-line overrides in error messages.
pub(crate) const SET_SOURCE: &str = "--set";

/// Applies every `key=value` of `sets`; errors name `--set` and are all collected.
pub(crate) fn apply_sets(document: &mut Table, sets: &[String]) -> Result<(), ConfigErrors> {
    let source: Arc<str> = Arc::from(SET_SOURCE);
    let location = Location::whole(&source);
    let mut errors = Vec::new();
    for set in sets {
        let Some((key, value)) = set.split_once('=') else {
            errors.push(ConfigError::new(
                ErrorKind::Syntax,
                location.clone(),
                "",
                Some(set.clone()),
                "expected key=value, e.g. geometry.outlet_width=0.045",
            ));
            continue;
        };
        let key = key.trim();
        let path = match split_key(key) {
            Ok(path) => path,
            Err(message) => {
                errors.push(ConfigError::new(
                    ErrorKind::Syntax,
                    location.clone(),
                    key,
                    None,
                    message,
                ));
                continue;
            }
        };
        let node = match parse_value(value.trim(), &location) {
            Ok(node) => node,
            Err(message) => {
                errors.push(ConfigError::new(
                    ErrorKind::Syntax,
                    location.clone(),
                    key,
                    Some(value.trim().to_string()),
                    message,
                ));
                continue;
            }
        };
        apply_override(document, &path, node, &location, &mut errors);
    }
    if errors.is_empty() {
        Ok(())
    } else {
        Err(ConfigErrors { errors })
    }
}

/// Sets one dotted key, first removing the keys that are its alternatives (giving the
/// outlet gap replaces an outlet offset from the file, and so on). A key that cannot be
/// set is recorded in `errors`.
pub(crate) fn apply_override(
    document: &mut Table,
    path: &[String],
    node: Node,
    location: &Location,
    errors: &mut Vec<ConfigError>,
) {
    let key = path.join(".");
    for (a, b) in ALTERNATIVE_KEYS {
        for (given, other) in [(a, b), (b, a)] {
            let given_path: Vec<String> = given.split('.').map(str::to_string).collect();
            if path.starts_with(&given_path) {
                let other_path: Vec<String> = other.split('.').map(str::to_string).collect();
                document.remove_path(&other_path);
            }
        }
    }
    if let Err(blocking) = document.set_path(path, node, location) {
        errors.push(ConfigError::new(
            ErrorKind::WrongType,
            location.clone(),
            key,
            None,
            format!("cannot set this key: `{blocking}` holds a value, not a table"),
        ));
    }
}
