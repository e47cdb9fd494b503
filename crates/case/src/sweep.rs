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
use super::document::{parse_document, NodeValue};
use super::error::{ConfigError, ConfigErrors, ErrorKind, Location};
use super::overrides::{apply_override, apply_sets};
use super::resolve::resolve_case;
use super::sweep_file::{read_sweep, Axis, SweepConfig, MAX_GRID_POINTS};

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
    /// What every case starts from instead of its own fill: a saved bed
    /// (`hopperflow study --from-bed`, `study::plan_from_bed`); `None`: each case
    /// fills its container.
    pub start: Option<files::StartRecord>,
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
    let set_errors = apply_sets(&mut config.base, sets).err();
    // The base must be valid on its own, so that its errors are reported once rather
    // than for every grid point.
    super::merge_errors(
        resolve_case(
            &config.base,
            &config.base_source,
            config.base_dir.as_deref(),
        ),
        set_errors,
    )?;
    expand(&config)
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
pub fn replica_seed(base_seed: u64, point_id: &str, replica: u32) -> u64 {
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
            apply_override(&mut document, path, node.clone(), location, &mut errors);
        }
        let total = axes
            .iter()
            .try_fold(1usize, |n, a| n.checked_mul(a.values.len()))
            .filter(|n| *n <= MAX_GRID_POINTS);
        let Some(total) = total else {
            errors.push(ConfigError::new(
                ErrorKind::Invalid,
                Location::whole(&config.source),
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
                apply_override(
                    &mut point,
                    &axis.path,
                    node.clone(),
                    &node.location,
                    &mut errors,
                );
            }
            let point_id = parts.join("-");
            if !seen.insert(point_id.clone()) {
                errors.push(ConfigError::new(
                    ErrorKind::Conflict,
                    Location::whole(&config.source),
                    "",
                    Some(point_id.clone()),
                    "two grid points share this identifier; give the series distinct names or the axes distinct labels",
                ));
                continue;
            }
            match resolve_case(&point, &config.base_source, config.base_dir.as_deref()) {
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
            start: None,
        })
    } else {
        Err(ConfigErrors { errors })
    }
}

/// The sweep text with its top-level `replicas = …` line replaced (or added): replicas are
/// expanded by the sweep reader, each with its own seed, so a new count means a new text.
pub fn sweep_with_replicas(text: &str, replicas: u32) -> String {
    let mut out = String::new();
    let mut replaced = false;
    let mut in_table = false;
    for line in text.lines() {
        let trimmed = line.trim_start();
        if trimmed.starts_with('[') {
            in_table = true;
        }
        if !in_table && !replaced && trimmed.starts_with("replicas") && trimmed.contains('=') {
            out.push_str(&format!("replicas = {replicas}\n"));
            replaced = true;
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
    if !replaced {
        out = format!("replicas = {replicas}\n{out}");
    }
    out
}
