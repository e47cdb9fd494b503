//! Reading a sweep file into its parts: name, replicas, base case, axes and series.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::document::{parse_document, split_key, Node, NodeValue, Table};
use super::error::{ConfigError, ErrorKind, Location};
use super::reader::Section;

/// One axis of a grid: a case key and the values it takes.
pub(crate) struct Axis {
    /// Dotted key split into segments.
    pub path: Vec<String>,
    /// Dotted key as written.
    pub key: String,
    /// Values, each with its place in the sweep file.
    pub values: Vec<Node>,
    /// Identifier prefix of this axis.
    pub label: String,
    /// Factor applied to numbers in identifiers (e.g. 1000 to show metres as mm).
    pub scale: f64,
    /// Zero-padding width of integer identifiers.
    pub digits: usize,
}

/// A named sub-grid: fixed overrides plus its own axes.
pub(crate) struct Series {
    pub name: String,
    /// Fixed overrides: key segments, dotted key, value and its place in the file.
    pub set: Vec<(Vec<String>, String, Node, Location)>,
    pub axes: Vec<Axis>,
}

/// A sweep file as read, before expansion.
pub(crate) struct SweepConfig {
    pub name: String,
    pub description: String,
    pub replicas: u32,
    pub base: Table,
    pub base_source: Arc<str>,
    /// The folder relative paths of the base case are taken from: the base case file's, or
    /// the sweep file's for a `[base]` table (`None`: the current folder).
    pub base_dir: Option<PathBuf>,
    /// Name of the sweep file itself, for errors about the grid.
    pub source: Arc<str>,
    pub axes: Vec<Axis>,
    pub series: Vec<Series>,
}

/// Largest number of replicas; a guard against typos.
const MAX_REPLICAS: i64 = 10_000;

/// Largest number of grid points of one series; a guard against typos that would
/// expand into more cases than could ever run.
pub(crate) const MAX_GRID_POINTS: usize = 100_000;

pub(crate) fn read_sweep(
    document: &Table,
    source: &Arc<str>,
    base_dir: Option<&Path>,
    errors: &mut Vec<ConfigError>,
) -> Option<SweepConfig> {
    let mut root = Section::root(document, source);
    let version = root.integer_or("version", super::CASE_FORMAT_VERSION, errors);
    if version.value != super::CASE_FORMAT_VERSION {
        errors.push(version.error(
            ErrorKind::Invalid,
            "this hopperflow reads sweep format version 1 only",
        ));
    }
    let name = root.string("name", errors);
    let description = root
        .string("description", errors)
        .map_or_else(String::new, |d| d.value);
    let replicas = root.integer_or("replicas", 1, errors);
    if !(1..=MAX_REPLICAS).contains(&replicas.value) {
        errors.push(replicas.error(
            ErrorKind::Invalid,
            format!("must be an integer in [1, {MAX_REPLICAS}]"),
        ));
    }
    let name = match name {
        Some(n) if is_identifier(&n.value) => n.value,
        Some(n) => {
            errors.push(ConfigError::new(
                ErrorKind::Invalid,
                n.location,
                n.key,
                Some(format!("{:?}", n.value)),
                "must be a non-empty name of letters, digits, `_` and `-`",
            ));
            String::new()
        }
        None => {
            errors.push(ConfigError::new(
                ErrorKind::Missing,
                Location::whole(source),
                "name",
                None,
                "required: the sweep's name",
            ));
            String::new()
        }
    };
    let (base, base_source, case_dir) = read_base(&mut root, source, base_dir, errors)?;
    let axes = read_axes(&mut root, "axes", errors);
    let series = read_series(&mut root, errors);
    root.finish(
        &[
            "version",
            "name",
            "description",
            "replicas",
            "base",
            "axes",
            "series",
        ],
        errors,
    );
    let series = if series.is_empty() {
        vec![Series {
            name: name.clone(),
            set: Vec::new(),
            axes: Vec::new(),
        }]
    } else {
        series
    };
    Some(SweepConfig {
        name,
        description,
        replicas: replicas.value.clamp(1, MAX_REPLICAS) as u32,
        base,
        base_source,
        base_dir: case_dir,
        source: Arc::clone(source),
        axes,
        series,
    })
}

fn read_base(
    root: &mut Section<'_>,
    source: &Arc<str>,
    base_dir: Option<&Path>,
    errors: &mut Vec<ConfigError>,
) -> Option<(Table, Arc<str>, Option<PathBuf>)> {
    let own_dir = base_dir.map(Path::to_path_buf);
    let Some(entry) = root.entry("base") else {
        return Some((Table::default(), Arc::clone(source), own_dir));
    };
    match &entry.node.value {
        NodeValue::Table(t) => Some((t.clone(), Arc::clone(source), own_dir)),
        NodeValue::String(file) => {
            let Some(dir) = base_dir else {
                errors.push(ConfigError::new(
                    ErrorKind::Invalid,
                    entry.key_location.clone(),
                    "base",
                    Some(format!("{file:?}")),
                    "a built-in sweep must give its base as a [base] table",
                ));
                return None;
            };
            let path = dir.join(file);
            let name = path.display().to_string();
            let loaded = super::read_text(&path, &name).and_then(|text| {
                let base_source: Arc<str> = Arc::from(name.as_str());
                let case_dir = path.parent().map(Path::to_path_buf);
                parse_document(&text, &base_source).map(|t| (t, base_source, case_dir))
            });
            match loaded {
                Ok(base) => Some(base),
                Err(e) => {
                    errors.extend(e.errors);
                    None
                }
            }
        }
        other => {
            errors.push(ConfigError::new(
                ErrorKind::WrongType,
                entry.key_location.clone(),
                "base",
                Some(other.to_string()),
                format!(
                    "expected a case file name or a table, found {}",
                    other.type_name()
                ),
            ));
            None
        }
    }
}

/// The tables of an array-of-tables key, each with its dotted path and location.
fn tables<'a>(
    section: &mut Section<'a>,
    key: &str,
    errors: &mut Vec<ConfigError>,
) -> Vec<(Section<'a>, Location)> {
    let path = section.key(key);
    let default_location = section.default_location().clone();
    let Some(entry) = section.entry(key) else {
        return Vec::new();
    };
    let NodeValue::Array(items) = &entry.node.value else {
        errors.push(ConfigError::new(
            ErrorKind::WrongType,
            entry.key_location.clone(),
            path,
            Some(entry.node.value.to_string()),
            "expected an array of tables ([[…]])",
        ));
        return Vec::new();
    };
    let mut out = Vec::new();
    for (i, item) in items.iter().enumerate() {
        let item_path = format!("{path}[{i}]");
        match &item.value {
            NodeValue::Table(t) => out.push((
                Section::over(
                    t,
                    item_path,
                    item.location.clone(),
                    default_location.clone(),
                ),
                item.location.clone(),
            )),
            other => errors.push(ConfigError::new(
                ErrorKind::WrongType,
                item.location.clone(),
                item_path,
                Some(other.to_string()),
                "expected a table",
            )),
        }
    }
    out
}

fn read_axes(section: &mut Section<'_>, key: &str, errors: &mut Vec<ConfigError>) -> Vec<Axis> {
    let mut axes = Vec::new();
    for (mut axis, location) in tables(section, key, errors) {
        let key = axis.string("key", errors);
        let values = axis
            .entry("values")
            .map(|e| (e.node.clone(), e.key_location.clone()));
        let label = axis.string("label", errors);
        let scale = axis.float_or("scale", "", 1.0, errors);
        let digits = axis.integer_or("digits", 0, errors);
        axis.finish(&["key", "values", "label", "scale", "digits"], errors);
        let Some(key) = key else {
            errors.push(ConfigError::new(
                ErrorKind::Missing,
                location,
                axis.key("key"),
                None,
                "required: the dotted case key this axis varies",
            ));
            continue;
        };
        let path = match split_key(&key.value) {
            Ok(path) => path,
            Err(message) => {
                errors.push(ConfigError::new(
                    ErrorKind::Invalid,
                    key.location,
                    key.key,
                    Some(key.value),
                    message,
                ));
                continue;
            }
        };
        let values = match values {
            Some((
                Node {
                    value: NodeValue::Array(items),
                    ..
                },
                _,
            )) if !items.is_empty() => items,
            Some((_, at)) => {
                errors.push(ConfigError::new(
                    ErrorKind::WrongType,
                    at,
                    axis.key("values"),
                    None,
                    "expected a non-empty array of values",
                ));
                continue;
            }
            None => {
                errors.push(ConfigError::new(
                    ErrorKind::Missing,
                    location,
                    axis.key("values"),
                    None,
                    "required: the values this axis takes",
                ));
                continue;
            }
        };
        if !(scale.value.is_finite() && scale.value > 0.0) {
            errors.push(scale.error(ErrorKind::Invalid, "must be a finite number > 0"));
        }
        if !(0..=12).contains(&digits.value) {
            errors.push(digits.error(ErrorKind::Invalid, "must be an integer in [0, 12]"));
        }
        let label = match label {
            Some(l) if is_identifier(&l.value) || l.value.is_empty() => l.value,
            Some(l) => {
                errors.push(ConfigError::new(
                    ErrorKind::Invalid,
                    l.location,
                    l.key,
                    Some(format!("{:?}", l.value)),
                    "must hold only letters, digits, `_` and `-`",
                ));
                continue;
            }
            None => path.last().cloned().unwrap_or_default(),
        };
        axes.push(Axis {
            key: path.join("."),
            path,
            values,
            label,
            scale: scale.value,
            digits: digits.value.clamp(0, 12) as usize,
        });
    }
    axes
}

fn read_series(root: &mut Section<'_>, errors: &mut Vec<ConfigError>) -> Vec<Series> {
    let mut series = Vec::new();
    for (mut section, location) in tables(root, "series", errors) {
        let name = section.string("name", errors);
        section.string("description", errors);
        let mut set = Vec::new();
        if let Some(entry) = section.entry("set") {
            match &entry.node.value {
                NodeValue::Table(t) => {
                    for item in &t.entries {
                        match split_key(&item.key) {
                            Ok(path) => set.push((
                                path,
                                item.key.clone(),
                                item.node.clone(),
                                item.key_location.clone(),
                            )),
                            Err(message) => errors.push(ConfigError::new(
                                ErrorKind::Invalid,
                                item.key_location.clone(),
                                section.key("set"),
                                Some(item.key.clone()),
                                message,
                            )),
                        }
                    }
                }
                other => errors.push(ConfigError::new(
                    ErrorKind::WrongType,
                    entry.key_location.clone(),
                    section.key("set"),
                    Some(other.to_string()),
                    "expected a table of \"dotted.key\" = value",
                )),
            }
        }
        let axes = read_axes(&mut section, "axes", errors);
        section.finish(&["name", "description", "set", "axes"], errors);
        match name {
            Some(n) if is_identifier(&n.value) => series.push(Series {
                name: n.value,
                set,
                axes,
            }),
            Some(n) => errors.push(ConfigError::new(
                ErrorKind::Invalid,
                n.location,
                n.key,
                Some(format!("{:?}", n.value)),
                "must be a non-empty name of letters, digits, `_` and `-`",
            )),
            None => errors.push(ConfigError::new(
                ErrorKind::Missing,
                location,
                section.key("name"),
                None,
                "required: the series name, used in case identifiers",
            )),
        }
    }
    series
}

pub(crate) fn is_identifier(text: &str) -> bool {
    !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}
