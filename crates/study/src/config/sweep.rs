//! Sweep files: a base case, axes over any case key, named series and replicas, expanded
//! into a list of validated cases with stable identifiers.
//!
//! ```toml
//! version = 1
//! name = "my-study"
//! replicas = 2              # independent random fills per grid point
//! base = "base.toml"        # a case file (relative to this file) or a [base] case table
//! [[axes]]                  # axes shared by every series (grid product)
//! key = "geometry.outlet_width"
//! values = [0.018, 0.030]
//! label = "D"               # identifier prefix (default: the key's last segment)
//! scale = 1000.0            # identifier shows value × scale (here mm) ...
//! digits = 3                # ... zero-padded to 3 digits: D018
//! [[series]]                # optional named sub-grids; without any, one series named `name`
//! name = "wall"
//! set = { "wall.friction" = 0.01 }
//! ```
//!
//! Grid points whose geometry cannot be built (outlet or particles do not fit) are
//! skipped with their reasons; any other invalid value is an error.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::sync::Arc;

use sha2::{Digest, Sha256};

use super::case::Case;
use super::document::{parse_document, split_key, Node, NodeValue, Table};
use super::error::{ConfigError, ConfigErrors, ErrorKind, Location};
use super::overrides::{apply_override, apply_sets};
use super::reader::Section;
use super::resolve::resolve_case;

/// One case of an expanded sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepCase {
    /// Stable, filesystem-safe identifier, e.g. `angle-a30-D045-r0`.
    pub id: String,
    /// The validated case, with its replica's seed.
    pub case: Case,
    /// Series name, replica index and the value of every key the sweep set.
    pub labels: BTreeMap<String, String>,
}

/// A grid point left out because its geometry cannot be built.
#[derive(Clone, Debug, PartialEq)]
pub struct SkippedCase {
    /// Identifier the point would have had (without the replica suffix).
    pub id: String,
    /// Why it was skipped, one line per problem.
    pub reasons: Vec<String>,
}

/// An expanded sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPlan {
    /// Name of the sweep.
    pub name: String,
    /// Free text from the file.
    pub description: String,
    /// Replicas per grid point.
    pub replicas: u32,
    /// Cases to run, in file order (series, then axes, last axis fastest, then replica).
    pub cases: Vec<SweepCase>,
    /// Grid points that were skipped.
    pub skipped: Vec<SkippedCase>,
}

/// Reads and expands a sweep file; `sets` override keys of the base case.
pub fn load_sweep(path: &Path, sets: &[String]) -> Result<SweepPlan, ConfigErrors> {
    let name = path.display().to_string();
    let text = super::read_text(path, &name)?;
    parse_sweep(&text, &name, path.parent(), sets)
}

/// Expands sweep text. `base_dir` resolves a `base = "file.toml"` path (`None`: only a
/// `[base]` table is allowed); `sets` override keys of the base case.
pub fn parse_sweep(
    src: &str,
    source_name: &str,
    base_dir: Option<&Path>,
    sets: &[String],
) -> Result<SweepPlan, ConfigErrors> {
    let source: Arc<str> = Arc::from(source_name);
    let src = src.strip_prefix('\u{feff}').unwrap_or(src);
    let document = parse_document(src, &source)?;
    let mut errors = Vec::new();
    let config = read_sweep(&document, &source, base_dir, &mut errors);
    let Some(mut config) = config.filter(|_| errors.is_empty()) else {
        return Err(ConfigErrors { errors });
    };
    apply_sets(&mut config.base, sets)?;
    // The base must be valid on its own, so that its errors are reported once rather
    // than for every grid point.
    resolve_case(&config.base, &config.base_source)?;
    expand(&config)
}

struct Axis {
    path: Vec<String>,
    key: String,
    values: Vec<Node>,
    label: String,
    scale: f64,
    digits: usize,
}

struct Series {
    name: String,
    set: Vec<(Vec<String>, String, Node, Location)>,
    axes: Vec<Axis>,
}

struct SweepConfig {
    name: String,
    description: String,
    replicas: u32,
    base: Table,
    base_source: Arc<str>,
    axes: Vec<Axis>,
    series: Vec<Series>,
}

/// Largest number of replicas; a guard against typos.
const MAX_REPLICAS: i64 = 10_000;

/// Largest number of grid points of one series; a guard against typos that would
/// expand into more cases than could ever run.
const MAX_GRID_POINTS: usize = 100_000;

fn read_sweep(
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
    let (base, base_source) = read_base(&mut root, source, base_dir, errors)?;
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
        axes,
        series,
    })
}

fn read_base(
    root: &mut Section<'_>,
    source: &Arc<str>,
    base_dir: Option<&Path>,
    errors: &mut Vec<ConfigError>,
) -> Option<(Table, Arc<str>)> {
    let Some(entry) = root.entry("base") else {
        return Some((Table::default(), Arc::clone(source)));
    };
    match &entry.node.value {
        NodeValue::Table(t) => Some((t.clone(), Arc::clone(source))),
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
                parse_document(&text, &base_source).map(|t| (t, base_source))
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

fn is_identifier(text: &str) -> bool {
    !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// The identifier text of one axis value: value × scale, integers zero-padded.
fn value_tag(axis: &Axis, value: &NodeValue, index: usize) -> String {
    let number = match value {
        NodeValue::Integer(i) => Some(*i as f64),
        NodeValue::Float(x) => Some(*x),
        _ => None,
    };
    let text = match (number, value) {
        (Some(x), _) => {
            let scaled = x * axis.scale;
            let rounded = scaled.round();
            // Values like 0.045 × 1000 land within a few ulps of an integer.
            if (scaled - rounded).abs() <= 1e-9 * rounded.abs().max(1.0) && rounded.abs() < 1e15 {
                let magnitude = format!("{:0width$}", rounded.abs() as i64, width = axis.digits);
                if rounded < 0.0 {
                    format!("m{magnitude}")
                } else {
                    magnitude
                }
            } else {
                format!("{scaled}").replace('-', "m").replace('.', "p")
            }
        }
        (None, NodeValue::String(s)) => s.clone(),
        (None, NodeValue::Boolean(b)) => b.to_string(),
        _ => format!("v{index}"),
    };
    let clean: String = text
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("{}{clean}", axis.label)
}

/// A label value: strings without their quotes, everything else as TOML.
fn label_text(value: &NodeValue) -> String {
    match value {
        NodeValue::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// Seed of one replica: the first 63 bits of SHA-256 over the base seed, the grid point's
/// identifier and the replica index. Stable across runs and platforms, different for
/// every point and replica, and independent of the order of the sweep.
pub(crate) fn replica_seed(base_seed: u64, point_id: &str, replica: u32) -> u64 {
    let mut hash = Sha256::new();
    hash.update(format!("hopperflow-seed|{base_seed}|{point_id}|{replica}").as_bytes());
    let digest = hash.finalize();
    let mut bytes = [0u8; 8];
    bytes.copy_from_slice(&digest[..8]);
    u64::from_le_bytes(bytes) >> 1
}

fn expand(config: &SweepConfig) -> Result<SweepPlan, ConfigErrors> {
    let mut cases = Vec::new();
    let mut skipped = Vec::new();
    let mut errors = Vec::new();
    let mut seen = BTreeSet::new();
    for series in &config.series {
        let axes: Vec<&Axis> = config.axes.iter().chain(&series.axes).collect();
        let mut document = config.base.clone();
        let mut fixed = BTreeMap::new();
        for (path, key, node, location) in &series.set {
            fixed.insert(key.clone(), label_text(&node.value));
            if let Err(e) = apply_override(&mut document, path, node.clone(), location) {
                errors.push(e);
            }
        }
        let total = axes
            .iter()
            .try_fold(1usize, |n, a| n.checked_mul(a.values.len()))
            .filter(|n| *n <= MAX_GRID_POINTS);
        let Some(total) = total else {
            errors.push(ConfigError::new(
                ErrorKind::Invalid,
                Location::whole(&config.base_source),
                "series",
                Some(series.name.clone()),
                format!("the axes of this series make more than {MAX_GRID_POINTS} grid points"),
            ));
            continue;
        };
        for flat in 0..total {
            // Mixed-radix digits of `flat`, last axis fastest.
            let mut indices = vec![0; axes.len()];
            let mut rest = flat;
            for (k, axis) in axes.iter().enumerate().rev() {
                indices[k] = rest % axis.values.len();
                rest /= axis.values.len();
            }
            let mut point = document.clone();
            let mut labels = fixed.clone();
            let mut parts = vec![series.name.clone()];
            for (axis, &i) in axes.iter().zip(&indices) {
                let node = &axis.values[i];
                parts.push(value_tag(axis, &node.value, i));
                labels.insert(axis.key.clone(), label_text(&node.value));
                if let Err(e) = apply_override(&mut point, &axis.path, node.clone(), &node.location)
                {
                    errors.push(e);
                }
            }
            let point_id = parts.join("-");
            if !seen.insert(point_id.clone()) {
                errors.push(ConfigError::new(
                    ErrorKind::Conflict,
                    Location::whole(&Arc::from(config.name.as_str())),
                    "",
                    Some(point_id.clone()),
                    "two grid points share this identifier; give the series distinct names or the axes distinct labels",
                ));
                continue;
            }
            match resolve_case(&point, &config.base_source) {
                Ok(case) => {
                    labels.insert("series".to_string(), series.name.clone());
                    for replica in 0..config.replicas {
                        let mut case = case.clone();
                        case.seed = replica_seed(case.seed, &point_id, replica);
                        let mut labels = labels.clone();
                        labels.insert("replica".to_string(), replica.to_string());
                        cases.push(SweepCase {
                            id: format!("{point_id}-r{replica}"),
                            case,
                            labels,
                        });
                    }
                }
                Err(e) if e.only_does_not_fit() => skipped.push(SkippedCase {
                    id: point_id,
                    reasons: e.errors.iter().map(ToString::to_string).collect(),
                }),
                Err(e) => errors.extend(e.errors.into_iter().map(|mut error| {
                    error.message = format!("{} (in sweep case {point_id})", error.message);
                    error
                })),
            }
        }
    }
    if errors.is_empty() {
        Ok(SweepPlan {
            name: config.name.clone(),
            description: config.description.clone(),
            replicas: config.replicas,
            cases,
            skipped,
        })
    } else {
        Err(ConfigErrors { errors })
    }
}
