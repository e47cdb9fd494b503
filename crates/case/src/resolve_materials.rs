//! Validation of a case's material table: `[materials.NAME]` entries and `[[pairs]]`
//! (docs/physics.md §1.2).
//!
//! The tables are read into the engine's [`MaterialTable`] and judged by its own checks
//! ([`MaterialTable::problems`]), so a case file and the engine accept the same tables. The
//! engine names each problem by a key relative to the table (`materials.M1.poisson_ratio`,
//! `pairs[3]`); the case file uses the same keys at its top level, and each problem is
//! reported at the line of that key, with its value and allowed range.

use std::collections::{BTreeMap, HashMap, HashSet};

use dem::{MaterialEntry, MaterialTable, MaterialTableError, PairEntry};

use super::error::{number, ConfigError, ErrorKind, Location};
use super::particles::MaterialSpec;
use super::reader::{Located, Section};
use super::sources::{source, MaterialSources};

/// Words `wall.material` gives a meaning of its own, so no material may be named so.
pub(crate) const RESERVED_NAMES: &[&str] = &["same", "rigid"];

/// The keys of one `[materials.NAME]` table.
const MATERIAL_KEYS: &[&str] = &[
    "density",
    "youngs_modulus",
    "shear_modulus",
    "poisson_ratio",
];

/// The keys of one `[[pairs]]` entry.
const PAIR_KEYS: &[&str] = &[
    "materials",
    "restitution",
    "friction",
    "rolling_friction",
    "cohesion",
];

/// A case's material table, read and checked, with where each value was written.
#[derive(Debug, Clone)]
pub(crate) struct NamedMaterials {
    /// The table as the engine takes it.
    pub table: MaterialTable,
    /// Every usable material's properties for the checks of the case (G from E where only
    /// E is given) and where they were set, by name.
    pub materials: BTreeMap<String, (MaterialSpec, MaterialSources)>,
    /// Whether the engine's checks accepted the table.
    pub valid: bool,
    /// Where the `[[pairs]]` list is written, else the `[materials]` table.
    pub pairs_location: Location,
}

impl NamedMaterials {
    /// The defined names, comma-separated, for messages.
    pub fn defined(&self) -> String {
        self.table.names().collect::<Vec<_>>().join(", ")
    }

    /// Checks that `name`, written at `word`, is a defined material; records an error if not.
    pub fn require_known(&self, word: &Located<String>, errors: &mut Vec<ConfigError>) -> bool {
        if self.table.materials.contains_key(&word.value) {
            return true;
        }
        errors.push(word.error(
            ErrorKind::Invalid,
            format!(
                "material \"{}\" is not defined in [materials] (defined: {})",
                word.value,
                self.defined()
            ),
        ));
        false
    }

    /// Records an error for each pair of `names` (particle materials, or a particle and the
    /// wall material) that is neither listed nor mixable from listed self-pairs. Only for a
    /// valid table.
    pub fn require_pairs(&self, pairs: &[(&str, &str)], errors: &mut Vec<ConfigError>) {
        if !self.valid {
            return;
        }
        let mut seen = HashSet::new();
        for &(a, b) in pairs {
            let key = if a <= b { (a, b) } else { (b, a) };
            if !seen.insert(key) {
                continue;
            }
            if let Err(problem) = self.table.interaction(a, b) {
                errors.push(ConfigError::new(
                    ErrorKind::Missing,
                    self.pairs_location.clone(),
                    "pairs",
                    None,
                    without_key(&problem),
                ));
            }
        }
    }
}

/// Whether `name` can be a material's name: a TOML bare key (letters, digits, `_`, `-`), so
/// that a resolved case writes it back as `[materials.NAME]`, and not a reserved word.
fn valid_name(name: &str) -> bool {
    !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        && !RESERVED_NAMES.contains(&name)
}

/// What the error mapping needs: every number and name written, by its key.
#[derive(Default)]
struct Written {
    numbers: HashMap<String, Located<f64>>,
    /// The names of each pair, by pair index.
    pair_names: Vec<Vec<Located<String>>>,
    /// Where each table (`materials.NAME`, `pairs[i]`) starts.
    tables: HashMap<String, Location>,
    /// Keys written with a value of the wrong type (already reported, so not also missing).
    mistyped: HashSet<String>,
    /// Pairs whose `materials` is absent or malformed (already reported).
    broken_pairs: HashSet<usize>,
}

/// Reads the number at `key` of `section` into `written`, noting a mistyped one.
fn number_at(
    section: &mut Section<'_>,
    key: &str,
    unit: &'static str,
    written: &mut Written,
    errors: &mut Vec<ConfigError>,
) -> Option<f64> {
    let located = section.float(key, unit, errors);
    match &located {
        Some(located) => {
            written.numbers.insert(located.key.clone(), located.clone());
        }
        None if section.has(key) => {
            written.mistyped.insert(section.key(key));
        }
        None => {}
    }
    located.map(|l| l.value)
}

/// Reads `[materials]` and `[[pairs]]` from the top level of a case; `None` when the case
/// has no `[materials]` table (and then `[[pairs]]` is refused).
pub(crate) fn read_materials(
    root: &mut Section<'_>,
    volumes: &mut Vec<Located<f64>>,
    errors: &mut Vec<ConfigError>,
) -> Option<NamedMaterials> {
    if !root.has("materials") {
        if root.has("pairs") {
            let entry = root.entry("pairs").expect("present");
            errors.push(ConfigError::new(
                ErrorKind::Missing,
                entry.key_location.clone(),
                "pairs",
                None,
                "[[pairs]] gives the coefficients of named materials: define them in \
                 [materials.NAME] tables (density, youngs_modulus or shear_modulus, \
                 poisson_ratio)",
            ));
        }
        return None;
    }
    let mut written = Written::default();
    let mut table = MaterialTable::new();
    let mut section = root.section("materials", errors);
    let materials_location = section.location().clone();
    let names = section.keys();
    if names.is_empty() {
        errors.push(ConfigError::new(
            ErrorKind::Missing,
            materials_location.clone(),
            "materials",
            None,
            "define at least one material, e.g. [materials.M1] with density, youngs_modulus \
             and poisson_ratio",
        ));
    }
    let start = errors.len();
    for name in &names {
        let before = errors.len();
        let mut material = section.section(name, errors);
        if errors.len() > before {
            // A value where the material's table belongs, reported by `section`: its
            // properties are not missing as well.
            for key in ["", "density", "poisson_ratio"] {
                written.mistyped.insert(material.key(key));
            }
        }
        written
            .tables
            .insert(material.key(""), material.location().clone());
        if !valid_name(name) {
            errors.push(ConfigError::new(
                ErrorKind::Invalid,
                material.location().clone(),
                material.key(""),
                Some(format!("\"{name}\"")),
                format!(
                    "a material's name must be letters, digits, `_` or `-`, and not {}",
                    RESERVED_NAMES
                        .iter()
                        .map(|w| format!("\"{w}\""))
                        .collect::<Vec<_>>()
                        .join(" or ")
                ),
            ));
        }
        let w = &mut written;
        let entry = MaterialEntry {
            density: number_at(&mut material, "density", "kg/m³", w, errors),
            youngs_modulus: number_at(&mut material, "youngs_modulus", "Pa", w, errors),
            shear_modulus: number_at(&mut material, "shear_modulus", "Pa", w, errors),
            poisson_ratio: number_at(&mut material, "poisson_ratio", "", w, errors),
        };
        material.finish(MATERIAL_KEYS, errors);
        table.materials.insert(name.clone(), entry);
    }
    section.finish(&[], errors);

    let pairs_location = root
        .entry("pairs")
        .map_or_else(|| materials_location.clone(), |e| e.key_location.clone());
    for (i, mut pair) in root
        .tables("pairs", errors)
        .into_iter()
        .flatten()
        .enumerate()
    {
        written
            .tables
            .insert(pair.key("").to_string(), pair.location().clone());
        let names = pair.string_array("materials", errors);
        if !pair.has("materials") {
            errors.push(ConfigError::new(
                ErrorKind::Missing,
                pair.location().clone(),
                pair.key("materials"),
                None,
                "required: the two materials of the pair, e.g. materials = [\"M1\", \"steel\"] \
                 (the same name twice for a material with itself)",
            ));
        }
        let names = match names {
            Some(names) if names.len() == 2 => names,
            Some(names) => {
                errors.push(ConfigError::new(
                    ErrorKind::Invalid,
                    pair.location().clone(),
                    pair.key("materials"),
                    Some(format!(
                        "[{}]",
                        names
                            .iter()
                            .map(|n| format!("\"{}\"", n.value))
                            .collect::<Vec<_>>()
                            .join(", ")
                    )),
                    "must name exactly two materials",
                ));
                Vec::new()
            }
            None => Vec::new(),
        };
        if names.is_empty() {
            written.broken_pairs.insert(i);
        }
        let w = &mut written;
        let restitution = number_at(&mut pair, "restitution", "", w, errors);
        let friction = number_at(&mut pair, "friction", "", w, errors);
        let rolling_friction = number_at(&mut pair, "rolling_friction", "", w, errors);
        // An invalid cohesion is reported here; the pair stays dry for the table's checks.
        let cohesion =
            super::resolve_cohesion::read_cohesion(&mut pair, volumes, errors).unwrap_or_default();
        pair.finish(PAIR_KEYS, errors);
        let materials = match names.as_slice() {
            [a, b] => [a.value.clone(), b.value.clone()],
            _ => [String::new(), String::new()],
        };
        debug_assert_eq!(written.pair_names.len(), i);
        written.pair_names.push(names);
        table.pairs.push(PairEntry {
            materials,
            restitution,
            friction,
            rolling_friction,
            cohesion,
        });
    }

    map_problems(&table, &written, &materials_location, errors);
    let valid = errors.len() == start;
    let materials = table
        .materials
        .iter()
        .filter_map(|(name, entry)| {
            let usable = table.material(name).ok()?;
            let key = |k: &str| written.numbers.get(&format!("materials.{name}.{k}"));
            // G for the Rayleigh time: as written, or from E and ν (E = 2G(1 + ν)).
            let shear = entry
                .shear_modulus
                .unwrap_or_else(|| usable.youngs_modulus / (2.0 * (1.0 + usable.poisson_ratio)));
            let modulus = key("shear_modulus").or(key("youngs_modulus"))?;
            Some((
                name.clone(),
                (
                    MaterialSpec {
                        density: usable.density,
                        shear_modulus: shear,
                        poisson_ratio: usable.poisson_ratio,
                    },
                    MaterialSources {
                        density: source(key("density")?),
                        shear_modulus: source(modulus),
                        poisson_ratio: source(key("poisson_ratio")?),
                    },
                ),
            ))
        })
        .collect();
    Some(NamedMaterials {
        table,
        materials,
        valid,
        pairs_location,
    })
}

/// The engine's message without its leading `key: `.
fn without_key(problem: &MaterialTableError) -> String {
    let text = problem.to_string();
    match text.split_once(": ") {
        Some((_, rest)) => rest.to_string(),
        None => text,
    }
}

/// The line of a table (`pairs[1]`) for messages, when it has one.
fn line_of(written: &Written, key: &str) -> String {
    match written.tables.get(key).and_then(|l| l.line) {
        Some(line) => format!("{key}, line {line}"),
        None => key.to_string(),
    }
}

/// Each problem the engine finds in `table`, as an error at the case file's key and line.
fn map_problems(
    table: &MaterialTable,
    written: &Written,
    fallback: &Location,
    errors: &mut Vec<ConfigError>,
) {
    let whole = |key: &str| {
        written
            .tables
            .get(key)
            .cloned()
            .unwrap_or_else(|| fallback.clone())
    };
    // The table a key belongs to: `materials.M1` of `materials.M1.density`, `pairs[2]` of
    // `pairs[2].friction`.
    let table_of = |key: &str| match key.rsplit_once('.') {
        Some((head, _)) if !head.contains('.') || head.starts_with("materials.") => {
            head.to_string()
        }
        _ => key.to_string(),
    };
    let mut reported_names: HashSet<(usize, usize)> = HashSet::new();
    for problem in table.problems() {
        let broken = |key: &str| pair_index(key).is_some_and(|i| written.broken_pairs.contains(&i));
        let error = match &problem {
            // Reported already: a mistyped value, or a pair without its two names.
            MaterialTableError::Missing { key, .. }
            | MaterialTableError::MissingModulus { key }
                if written.mistyped.contains(key) =>
            {
                continue
            }
            MaterialTableError::UnknownMaterial { key, .. }
            | MaterialTableError::DuplicatePair { key, .. }
                if broken(key) =>
            {
                continue
            }
            MaterialTableError::Missing { key, allowed } => ConfigError::new(
                ErrorKind::Missing,
                whole(&table_of(key)),
                key.clone(),
                None,
                format!("required: {allowed}"),
            ),
            MaterialTableError::NotFinite {
                key,
                value,
                allowed,
            }
            | MaterialTableError::OutOfRange {
                key,
                value,
                allowed,
            } => {
                let message = if allowed.starts_with(['(', '[']) {
                    format!("must lie in {allowed}")
                } else {
                    format!("must be {allowed}")
                };
                match written.numbers.get(key) {
                    Some(located) => located.error(ErrorKind::Invalid, message),
                    None => ConfigError::new(
                        ErrorKind::Invalid,
                        whole(&table_of(key)),
                        key.clone(),
                        Some(number(*value)),
                        message,
                    ),
                }
            }
            MaterialTableError::MissingModulus { key } => ConfigError::new(
                ErrorKind::Missing,
                whole(key),
                key.clone(),
                None,
                "give youngs_modulus (E) or shear_modulus (G) [Pa], > 0 (E = 2G(1 + ν))",
            ),
            MaterialTableError::InconsistentModuli { key, .. } => {
                let modulus = format!("{key}.shear_modulus");
                match written.numbers.get(&modulus) {
                    Some(located) => located.error(ErrorKind::Conflict, without_key(&problem)),
                    None => ConfigError::new(
                        ErrorKind::Conflict,
                        whole(key),
                        key.clone(),
                        None,
                        without_key(&problem),
                    ),
                }
            }
            MaterialTableError::UnknownMaterial { key, name, defined } => {
                let index = pair_index(key);
                let word = index.and_then(|i| {
                    let words = written.pair_names.get(i)?;
                    let k = (0..words.len())
                        .find(|&k| words[k].value == *name && !reported_names.contains(&(i, k)))?;
                    reported_names.insert((i, k));
                    Some(&words[k])
                });
                let message = format!(
                    "material \"{name}\" is not defined in [materials] (defined: {defined})"
                );
                match word {
                    Some(word) => word.error(ErrorKind::Invalid, message),
                    None => ConfigError::new(
                        ErrorKind::Invalid,
                        whole(key),
                        format!("{key}.materials"),
                        Some(format!("\"{name}\"")),
                        message,
                    ),
                }
            }
            MaterialTableError::DuplicatePair { key, a, b, first } => {
                let location = pair_index(key)
                    .and_then(|i| written.pair_names.get(i)?.first())
                    .map_or_else(|| whole(key), |w| w.location.clone());
                ConfigError::new(
                    ErrorKind::Conflict,
                    location,
                    format!("{key}.materials"),
                    Some(format!("[\"{a}\", \"{b}\"]")),
                    format!(
                        "the pair ({a}, {b}) is given twice, first as {}; list each pair once, \
                         in either order",
                        line_of(written, first)
                    ),
                )
            }
            // Not among a table's own problems (they arise from its use); kept general.
            MaterialTableError::UnlistedPair { key, .. }
            | MaterialTableError::UnmixableCohesion { key, .. }
            | MaterialTableError::RepeatedName { key, .. } => ConfigError::new(
                ErrorKind::Invalid,
                whole(key),
                key.clone(),
                None,
                without_key(&problem),
            ),
        };
        errors.push(error);
    }
}

/// The index i of a key `pairs[i]`.
fn pair_index(key: &str) -> Option<usize> {
    key.strip_prefix("pairs[")?.strip_suffix(']')?.parse().ok()
}
