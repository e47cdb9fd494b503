//! A packing file in place of the fill: `hopperflow run CASE --packing FILE.csv|FILE.vtu`
//! (docs/user-guide.md §5).
//!
//! The particles are placed at rest where the file puts them; the run then settles with the
//! gate closed and goes on as after a fill. Two formats:
//!
//! - **CSV** with a header naming the columns `x`, `y`, `z`, `radius` and, where needed,
//!   `material`, in any order, one particle per line, SI units (m). Lines starting with `#`
//!   are comments. A case of one component needs no `material` column: its particles all
//!   get the case's one material, so the column tells nothing. If it is there, it may hold
//!   any name, the same on every line; a second name is refused. For a mixture
//!   (`particles.components`) the column is required: it names each particle's component, by
//!   the component's `name` or by its material's name when that names one component only;
//!   the particle then gets that component's material, and its radius is checked against
//!   that component's sizes. A mixture's CSV without the column is refused at its header.
//! - **VTU** as hopperflow writes its snapshots (`output::vtu`): the points and a point-data
//!   array `radius`, inline ASCII. Binary, appended or compressed data are refused with a
//!   message that says how to save the file as ASCII. For a mixture it needs the point-data
//!   array `component` (each particle's component, an index into `particles.components`),
//!   which hopperflow writes in a mixture's snapshots.
//!
//! Everything is checked before anything is written, and each problem names the file, the
//! line (CSV) or the array and index (VTU), the value and what is allowed: numbers that are
//! missing or not finite, radii ≤ 0 or outside the case's size distribution by more than
//! [`RADIUS_TOLERANCE`], particles outside the container (the fill's own tests,
//! [`inside_slab`] and [`CylinderGeometry::holds`], allowing a particle to press into a wall
//! by [`PACKING_OVERLAP_FRACTION`] of its radius), overlaps of two particles beyond the same
//! fraction of the smaller radius, and a count other than `particles.count`.

use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

use dem::DVec3;
use sha2::{Digest, Sha256};

use super::vtu::parse_vtu;
use crate::fill::inside_slab;
use case::{Case, CuboidGeometry, CylinderGeometry, Geometry, SlabGeometry};

/// The columns of a packing CSV, in the order hopperflow writes them. The first
/// [`REQUIRED_PACKING_COLUMNS`] are required; `material` only for a mixture.
pub const PACKING_COLUMNS: [&str; 5] = ["x", "y", "z", "radius", "material"];

/// How many of [`PACKING_COLUMNS`], from the first, every packing CSV must have: x, y, z and
/// radius. The fifth, `material`, names each particle's component and is required only when
/// the case has several.
pub const REQUIRED_PACKING_COLUMNS: usize = 4;

/// Largest overlap accepted between two particles, or between a particle and a wall, as a
/// fraction of the smaller radius [-]. A settled bed under its own weight overlaps far less
/// (the paper's 400 mm column: about 0.1 % of r at the bottom, docs/physics.md §1.1), so a
/// packing saved from a settled run passes; an overlap of 1 % already stores about 10⁻³ of
/// the particle's weight times r as elastic energy per contact, which the settling
/// dissipates, while the engine stops a run at 10 %.
pub const PACKING_OVERLAP_FRACTION: f64 = 0.01;

/// How far outside the case's range of radii a radius may lie, relative to the range's end
/// [-]: the rounding of a file written with five significant digits or more, far below any
/// real difference of size distributions.
pub const RADIUS_TOLERANCE: f64 = 1e-4;

/// Problems listed in one error before the rest are only counted.
const MAX_PROBLEMS: usize = 20;

/// One particle of a packing: where it is and how large.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PackedParticle {
    /// Centre [m], in the case's coordinates (z up from the orifice plane).
    pub position: DVec3,
    /// Radius [m].
    pub radius: f64,
}

/// Where in a packing file a problem lies.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PackingPlace {
    /// The file as a whole.
    File,
    /// A line of a CSV file, counted from 1.
    Line(u64),
    /// A point of a VTU file (its particle), counted from 0 as VTK does.
    Point(usize),
    /// A value of a VTU data array, counted from 0.
    Array {
        /// The array's `Name`.
        name: String,
        /// The value's index in the array.
        index: usize,
    },
}

impl fmt::Display for PackingPlace {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::File => Ok(()),
            Self::Line(n) => write!(f, " line {n}"),
            Self::Point(k) => write!(f, " point {k}"),
            Self::Array { name, index } => write!(f, " array `{name}` value {index}"),
        }
    }
}

/// One thing wrong with a packing file.
#[derive(Debug, Clone, PartialEq)]
pub struct PackingProblem {
    /// Where it is.
    pub place: PackingPlace,
    /// What is wrong, with the value and what is allowed.
    pub message: String,
}

/// Why a packing file cannot start a run: every problem found (the first
/// [`MAX_PROBLEMS`], then a count).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct PackingError {
    /// The file.
    pub file: PathBuf,
    /// The problems, in file order.
    pub problems: Vec<PackingProblem>,
    /// Problems found beyond those listed.
    pub more: usize,
}

impl fmt::Display for PackingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let file = self.file.display();
        for (k, p) in self.problems.iter().enumerate() {
            if k > 0 {
                writeln!(f)?;
            }
            write!(f, "{file}{}: {}", p.place, p.message)?;
        }
        if self.more > 0 {
            write!(f, "\n{file}: and {} more problems", self.more)?;
        }
        Ok(())
    }
}

/// The problems found so far, the first [`MAX_PROBLEMS`] kept.
#[derive(Default)]
pub(super) struct Problems {
    list: Vec<PackingProblem>,
    more: usize,
}

impl Problems {
    pub(super) fn push(&mut self, place: PackingPlace, message: impl Into<String>) {
        if self.list.len() < MAX_PROBLEMS {
            self.list.push(PackingProblem {
                place,
                message: message.into(),
            });
        } else {
            self.more += 1;
        }
    }

    pub(super) fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    fn into_error(self, file: &Path) -> PackingError {
        PackingError {
            file: file.to_path_buf(),
            problems: self.list,
            more: self.more,
        }
    }
}

/// A particle as a file gives it, before the checks.
pub(super) struct RawParticle {
    /// Where the file holds it.
    pub(super) place: PackingPlace,
    /// x, y, z [m].
    pub(super) position: [f64; 3],
    /// Radius [m].
    pub(super) radius: f64,
    /// What its `material` column says (CSV); `None` from a file without one (a VTU, or a
    /// CSV of one component without the column).
    pub(super) label: Option<String>,
    /// Its component as a VTU's `component` array gives it (an index into
    /// `particles.components`, as read: checked against the case later); `None` without one.
    pub(super) component: Option<f64>,
}

/// A checked packing, ready to start a run of the case it was checked against.
#[derive(Debug, Clone, PartialEq)]
pub struct Packing {
    source: PathBuf,
    sha256: String,
    particles: Vec<PackedParticle>,
    material: Option<String>,
    /// Each particle's component (an index into `particles.components`), in file order;
    /// empty for a case of one component.
    components: Vec<u8>,
}

impl Packing {
    /// The particles, in file order (the order of their tags in the run).
    pub fn particles(&self) -> &[PackedParticle] {
        &self.particles
    }

    /// The file it was read from (or the name given to [`Packing::new`]).
    pub fn source(&self) -> &Path {
        &self.source
    }

    /// Hex SHA-256 of the file's bytes (of the numbers' bits for [`Packing::new`]).
    pub fn sha256(&self) -> &str {
        &self.sha256
    }

    /// The material name the CSV gave every particle of a case of one component (`None` for a
    /// CSV without a `material` column, a VTU file and a mixture).
    pub fn material(&self) -> Option<&str> {
        self.material.as_deref()
    }

    /// Each particle's component, an index into the case's `particles.components`, in file
    /// order; empty for a case of one component.
    pub fn components(&self) -> &[u8] {
        &self.components
    }

    /// A packing of `particles` checked against `case` as a file's would be; `name` stands
    /// for the file in the errors (its places are the particles' indices).
    pub fn new(
        name: &Path,
        particles: &[PackedParticle],
        case: &Case,
    ) -> Result<Self, PackingError> {
        let raw = raw_particles(particles, |_| None);
        let mut hasher = Sha256::new();
        for p in particles {
            for v in p.position.to_array().iter().chain([&p.radius]) {
                hasher.update(v.to_le_bytes());
            }
        }
        let sha256 = hex(&hasher.finalize());
        checked(name, raw, None, case, sha256)
    }

    /// Checks the packing against `case` again (what [`read_packing`] checked): a run
    /// refuses a packing of another case.
    pub fn check(&self, case: &Case) -> Result<(), PackingError> {
        if case.particles.has_shapes() {
            let mut problems = Problems::default();
            problems.push(
                PackingPlace::File,
                "a packing file gives spheres, and the case's grains are shaped \
                 (particles.shape): start it from its own fill or from a bed it saved",
            );
            return Err(problems.into_error(&self.source));
        }
        // Each particle labelled as it was read: by its component's name (a mixture) or the
        // one material name (a CSV of one component).
        let names = &case.particles.components;
        let raw = raw_particles(&self.particles, |k| match self.components.get(k) {
            Some(&c) => Some(
                names
                    .get(usize::from(c))
                    .map_or_else(|| format!("component {c}"), |c| c.name.clone()),
            ),
            None => self.material.clone(),
        });
        checked(&self.source, raw, None, case, self.sha256.clone()).map(|_| ())
    }
}

/// `particles` as a file would give them, each at its index, labelled by `label(index)`.
fn raw_particles(
    particles: &[PackedParticle],
    label: impl Fn(usize) -> Option<String>,
) -> Vec<RawParticle> {
    particles
        .iter()
        .enumerate()
        .map(|(k, p)| RawParticle {
            place: PackingPlace::Point(k),
            position: p.position.to_array(),
            radius: p.radius,
            label: label(k),
            component: None,
        })
        .collect()
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Reads and checks the packing file `path` for `case`: CSV or VTU by its extension.
pub fn read_packing(path: &Path, case: &Case) -> Result<Packing, PackingError> {
    let parsed = parse_file(path)?;
    checked(
        path,
        parsed.raw,
        parsed.unlabelled_header,
        case,
        parsed.sha256,
    )
}

/// The number of particles in the packing file `path`, read as [`read_packing`] reads it but
/// not checked against a case: for a case that takes its `particles.count` from the packing
/// (`hopperflow bench --packing`). Every problem of the file's format is an error, as there.
pub fn packing_count(path: &Path) -> Result<usize, PackingError> {
    parse_file(path).map(|parsed| parsed.raw.len())
}

/// A packing file's particles as written, before the checks against a case.
struct ParsedFile {
    raw: Vec<RawParticle>,
    /// The header's line of a CSV without a `material` column, where a mixture's refusal
    /// points; `None` for a CSV with the column and for a VTU.
    unlabelled_header: Option<u64>,
    /// Hex SHA-256 of the file's bytes.
    sha256: String,
}

/// Reads the packing file `path` (CSV or VTU by its extension) into its particles, or every
/// problem of its format.
fn parse_file(path: &Path) -> Result<ParsedFile, PackingError> {
    let mut problems = Problems::default();
    let bytes = match std::fs::read(path) {
        Ok(bytes) => bytes,
        Err(e) => {
            problems.push(PackingPlace::File, format!("cannot be read: {e}"));
            return Err(problems.into_error(path));
        }
    };
    let sha256 = hex(&Sha256::digest(&bytes));
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let parsed = match extension.as_deref() {
        Some("csv") => parse_csv(&bytes, &mut problems),
        Some("vtu") => match std::str::from_utf8(&bytes) {
            Ok(text) => parse_vtu(text, &mut problems).map(|raw| (raw, None)),
            Err(e) => {
                problems.push(
                    PackingPlace::File,
                    format!(
                        "is not text (invalid UTF-8 at byte {}): hopperflow reads VTU files \
                         with inline ASCII data, as it writes them",
                        e.valid_up_to()
                    ),
                );
                None
            }
        },
        other => {
            problems.push(
                PackingPlace::File,
                format!(
                    "has an unknown packing format (extension {}): hopperflow reads .csv \
                     (columns x, y, z, radius and, for a mixture, material) and .vtu (points \
                     and a `radius` point-data array)",
                    other.map_or("none".to_string(), |e| format!("`.{e}`"))
                ),
            );
            None
        }
    };
    match parsed {
        Some((raw, unlabelled_header)) if problems.is_empty() => Ok(ParsedFile {
            raw,
            unlabelled_header,
            sha256,
        }),
        _ => Err(problems.into_error(path)),
    }
}

/// The particles of CSV `bytes`, each with its `material` label if the file has the column,
/// and the header's line if it has not; or `None` with the problems pushed.
fn parse_csv(bytes: &[u8], problems: &mut Problems) -> Option<(Vec<RawParticle>, Option<u64>)> {
    // A byte-order mark (spreadsheets write one) is not part of the first column's name.
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(bytes);
    let line_of = |e: &csv::Error| {
        e.position()
            .map_or(PackingPlace::File, |p| PackingPlace::Line(p.line()))
    };
    let mut records = reader.records();
    let header = match records.next() {
        None => {
            problems.push(
                PackingPlace::File,
                "is empty: a packing CSV starts with the header `x,y,z,radius,material` (the \
                 material column may be left out for a case of one component) and holds one \
                 particle per line",
            );
            return None;
        }
        Some(Err(e)) => {
            problems.push(line_of(&e), format!("cannot be read as CSV: {e}"));
            return None;
        }
        Some(Ok(header)) => header,
    };
    let header_line = header.position().map_or(1, csv::Position::line);
    // Column index of each of PACKING_COLUMNS.
    let mut column: [Option<usize>; 5] = [None; 5];
    for (k, name) in header.iter().enumerate() {
        let lower = name.to_ascii_lowercase();
        match PACKING_COLUMNS.iter().position(|c| *c == lower) {
            Some(c) if column[c].is_some() => problems.push(
                PackingPlace::Line(header_line),
                format!("column `{name}` appears twice in the header"),
            ),
            Some(c) => column[c] = Some(k),
            None => problems.push(
                PackingPlace::Line(header_line),
                format!(
                    "unknown column `{name}` in the header: a packing names the columns x, y, \
                     z, radius and, for a mixture, material (SI units; particles start at \
                     rest, so no velocities are read)"
                ),
            ),
        }
    }
    let missing: Vec<&str> = PACKING_COLUMNS[..REQUIRED_PACKING_COLUMNS]
        .iter()
        .zip(&column)
        .filter(|(_, c)| c.is_none())
        .map(|(name, _)| *name)
        .collect();
    if !missing.is_empty() {
        problems.push(
            PackingPlace::Line(header_line),
            format!(
                "the header lacks the column(s) {}: it must name x, y, z and radius, and \
                 material for a mixture (found: {})",
                missing.join(", "),
                header.iter().collect::<Vec<_>>().join(", ")
            ),
        );
    }
    if !problems.is_empty() {
        return None;
    }
    // The material column, if the file has one; the others are all there.
    let material_column = column[4];
    let column = column.map(|c| c.unwrap_or_default());
    let width = header.len();
    let header_names = header.iter().collect::<Vec<_>>().join(", ");
    let mut raw = Vec::new();
    for record in records {
        let record = match record {
            Ok(r) => r,
            Err(e) => {
                problems.push(line_of(&e), format!("cannot be read as CSV: {e}"));
                continue;
            }
        };
        let line = record.position().map_or(0, csv::Position::line);
        let place = PackingPlace::Line(line);
        if record.len() != width {
            problems.push(
                place,
                format!(
                    "has {} fields, the header has {width} ({header_names})",
                    record.len()
                ),
            );
            continue;
        }
        let mut values = [0.0; 4];
        let mut good = true;
        for (k, value) in values.iter_mut().enumerate() {
            let name = PACKING_COLUMNS[k];
            let text = &record[column[k]];
            if text.is_empty() {
                problems.push(
                    place.clone(),
                    format!("{name} is empty; a number [m] is needed"),
                );
                good = false;
                continue;
            }
            match text.parse::<f64>() {
                Ok(v) => *value = v,
                Err(_) => {
                    problems.push(
                        place.clone(),
                        format!("{name} `{text}` is not a number; a number [m] is needed"),
                    );
                    good = false;
                }
            }
        }
        let label = material_column.map(|k| record[k].to_string());
        if label.as_deref() == Some("") {
            problems.push(
                place.clone(),
                "material is empty; give each particle its material (for a mixture, the name of \
                 its component), or leave the column out for a case of one component",
            );
            good = false;
        }
        if good {
            raw.push(RawParticle {
                place,
                position: [values[0], values[1], values[2]],
                radius: values[3],
                label,
                component: None,
            });
        }
    }
    if problems.is_empty() && raw.is_empty() {
        problems.push(
            PackingPlace::File,
            "has a header but no particles: one line per particle is needed",
        );
    }
    let unlabelled_header = material_column.is_none().then_some(header_line);
    Some((raw, unlabelled_header))
}

/// The packing of `raw` after every check against `case`, or every problem found.
/// `unlabelled_header` is the header's line of a CSV without a `material` column.
fn checked(
    file: &Path,
    raw: Vec<RawParticle>,
    unlabelled_header: Option<u64>,
    case: &Case,
    sha256: String,
) -> Result<Packing, PackingError> {
    let mut problems = Problems::default();
    let (material, components) = labels(&raw, unlabelled_header, case, &mut problems);
    // A mixture's radii are checked against each particle's component, once all are known.
    if problems.is_empty() || components.is_empty() {
        check_values(&raw, &components, case, &mut problems);
    }
    if problems.is_empty() {
        check_container(&raw, case, &mut problems);
        check_overlaps(&raw, &mut problems);
    }
    if raw.len() != case.particles.count {
        problems.push(
            PackingPlace::File,
            format!(
                "holds {} particles; the case has particles.count = {} (a packing replaces the \
                 fill, so the two must agree: set --set particles.count={})",
                raw.len(),
                case.particles.count,
                raw.len()
            ),
        );
    }
    if !problems.is_empty() {
        return Err(problems.into_error(file));
    }
    Ok(Packing {
        source: file.to_path_buf(),
        sha256,
        particles: raw
            .iter()
            .map(|p| PackedParticle {
                position: DVec3::from_array(p.position),
                radius: p.radius,
            })
            .collect(),
        material,
        components,
    })
}

/// What the particles' `material` labels say: for a case of one component, the one name
/// they all give (a second name is a problem; no labels at all are none); for a mixture,
/// each particle's component ([`component_named`]; a label that names none, or a file
/// without labels, is a problem, at the header of a CSV without a `material` column, whose
/// line `unlabelled_header` gives).
fn labels(
    raw: &[RawParticle],
    unlabelled_header: Option<u64>,
    case: &Case,
    problems: &mut Problems,
) -> (Option<String>, Vec<u8>) {
    let components = &case.particles.components;
    if components.len() <= 1 {
        let mut first: Option<(&str, &PackingPlace)> = None;
        for p in raw {
            let Some(name) = p.label.as_deref() else {
                continue;
            };
            match first {
                None => first = Some((name, &p.place)),
                Some((first_name, first_place)) if first_name != name => problems.push(
                    p.place.clone(),
                    format!(
                        "material `{name}` differs from `{first_name}` ({}): the case has one \
                         particle material, so every particle names the same one",
                        first_place.to_string().trim_start()
                    ),
                ),
                Some(_) => {}
            }
        }
        return (first.map(|(name, _)| name.to_string()), Vec::new());
    }
    let names = components
        .iter()
        .map(|c| format!("`{}`", c.name))
        .collect::<Vec<_>>()
        .join(", ");
    if let Some(line) = unlabelled_header {
        problems.push(
            PackingPlace::Line(line),
            format!(
                "the header has no column `material`, and the case is a mixture of {} \
                 components (particles.components: {names}): a mixture's packing CSV names \
                 each particle's component in a `material` column, by the component's name or \
                 by its material's when no other component is made of it",
                components.len()
            ),
        );
        return (None, Vec::new());
    }
    if raw
        .iter()
        .any(|p| p.label.is_none() && p.component.is_none())
    {
        problems.push(
            PackingPlace::File,
            format!(
                "gives no particle its component, and the case is a mixture of {} components \
                 (particles.components: {names}): start it from a CSV packing whose material \
                 column names each particle's component, or from a VTU with a `component` \
                 point-data array (as hopperflow writes a mixture's snapshots)",
                components.len()
            ),
        );
        return (None, Vec::new());
    }
    let mut found = Vec::with_capacity(raw.len());
    for p in raw {
        let component = match (&p.label, p.component) {
            (Some(name), _) => component_named(case, name).ok_or_else(|| {
                format!(
                    "material `{name}` names no component of the case; a mixture's packing \
                     names each particle's component: one of {names} \
                     (particles.components[].name), or a material that one component alone \
                     is made of"
                )
            }),
            (None, Some(index)) => component_index(index, components.len()).ok_or_else(|| {
                format!(
                    "component = {index} is not a component of the case: an index from 0 to {} \
                     into particles.components ({names})",
                    components.len() - 1
                )
            }),
            (None, None) => Err(String::new()),
        };
        match component {
            Ok(k) => found.push(k),
            Err(message) => {
                problems.push(p.place.clone(), message);
                found.push(0);
            }
        }
    }
    (None, found)
}

/// `value`, read as an index among `count` components: a whole number in 0..count.
fn component_index(value: f64, count: usize) -> Option<u8> {
    let whole = value.is_finite() && value >= 0.0 && value.fract() == 0.0;
    (whole && value < count as f64)
        .then(|| u8::try_from(value as usize).ok())
        .flatten()
}

/// The component of a mixture that `name` names: the one of that `name`, or else the only one
/// made of the material of that name.
fn component_named(case: &Case, name: &str) -> Option<u8> {
    let components = &case.particles.components;
    let index = components.iter().position(|c| c.name == name).or_else(|| {
        let mut made_of = components
            .iter()
            .enumerate()
            .filter(|(_, c)| c.material_name.as_deref() == Some(name));
        match (made_of.next(), made_of.next()) {
            (Some((k, _)), None) => Some(k),
            _ => None,
        }
    })?;
    u8::try_from(index).ok()
}

/// Finite numbers, positive radii within the case's size distribution, or for a mixture
/// within the sizes of each particle's component (`components`, in file order).
fn check_values(raw: &[RawParticle], components: &[u8], case: &Case, problems: &mut Problems) {
    let size = &case.particles;
    let range = |k: Option<u8>| match k.and_then(|k| size.components.get(usize::from(k))) {
        Some(c) => (
            0.5 * c.size.min_diameter(),
            0.5 * c.size.max_diameter(),
            format!("component `{}`'s", c.name),
        ),
        None => (
            0.5 * size.min_diameter(),
            0.5 * size.max_diameter(),
            "the case's".to_string(),
        ),
    };
    for (index, p) in raw.iter().enumerate() {
        let (low, high, whose) = range(components.get(index).copied());
        let (low_ok, high_ok) = (
            low * (1.0 - RADIUS_TOLERANCE),
            high * (1.0 + RADIUS_TOLERANCE),
        );
        for (name, v) in ["x", "y", "z"].iter().zip(p.position) {
            if !v.is_finite() {
                problems.push(
                    p.place.clone(),
                    format!("{name} = {v} is not finite; a finite number [m] is needed"),
                );
            }
        }
        let r = p.radius;
        if !r.is_finite() || r <= 0.0 {
            problems.push(
                p.place.clone(),
                format!("radius = {r} must be finite and > 0 [m]"),
            );
        } else if r < low_ok || r > high_ok {
            problems.push(
                p.place.clone(),
                format!(
                    "radius = {r} m is outside {whose} radii [{low}, {high}] m (half the \
                     diameters of particles.diameter or particles.size_distribution, or of the \
                     component's; {} % tolerance)",
                    RADIUS_TOLERANCE * 100.0
                ),
            );
        }
    }
}

/// Every particle inside the container, pressing into a wall by at most
/// [`PACKING_OVERLAP_FRACTION`] of its radius.
fn check_container(raw: &[RawParticle], case: &Case, problems: &mut Problems) {
    for p in raw {
        let [x, y, z] = p.position;
        let r = p.radius;
        let slack = PACKING_OVERLAP_FRACTION * r;
        let why = match &case.geometry {
            Geometry::Slab(g) => {
                let across = y - r >= -slack && y + r <= g.thickness + slack;
                if inside_slab(g, x, z, r, -slack) && across {
                    continue;
                }
                slab_violation(g, [x, y, z], r, slack)
            }
            Geometry::Cylinder(g) => {
                if g.holds(x, y, z, r, -slack) {
                    continue;
                }
                silo_violation(g, [x, y, z], r, slack)
            }
            Geometry::Heap(g) => {
                if g.holds(x, y, z, r, -slack) {
                    continue;
                }
                let c = r - slack;
                format!(
                    "it must lie inside the heap test's cylinder: at most {:.6e} m from the \
                     axis, z in {}",
                    g.cylinder_radius - c,
                    range(c, g.height - c)
                )
            }
            Geometry::Cuboid(g) | Geometry::DrawDown(case::DrawDownGeometry { container: g }) => {
                if g.holds(x, y, z, r, -slack) {
                    continue;
                }
                box_violation(g, [x, y, z], r, slack)
            }
            // An open mesh has no inside to test: only the walls' bounds and the orifice
            // plane bound a packing of STL walls.
            Geometry::Mesh(g) => {
                let (lo, hi) = g.bounds();
                let c = r - slack;
                let inside = (0..2).all(|k| [x, y][k] >= lo[k] + c && [x, y][k] <= hi[k] - c)
                    && z >= c
                    && z <= hi[2].max(g.fill_max[2]) - c;
                if inside {
                    continue;
                }
                format!(
                    "it must lie within the walls' bounds x in {}, y in {} and above the orifice \
                     plane z = 0",
                    range(lo[0] + c, hi[0] - c),
                    range(lo[1] + c, hi[1] - c)
                )
            }
        };
        problems.push(
            p.place.clone(),
            format!(
                "the particle at (x, y, z) = ({x}, {y}, {z}) m of radius {r} m lies outside the \
                 {}: {why} (a particle may press into a wall by at most {} % of its radius)",
                case.geometry.kind(),
                PACKING_OVERLAP_FRACTION * 100.0
            ),
        );
    }
}

/// "[a, b] m" for the range of a coordinate.
fn range(low: f64, high: f64) -> String {
    format!("[{low:.6e}, {high:.6e}] m")
}

/// Which wall of the slab a particle of radius `r` at `x` crosses, in words.
fn slab_violation(g: &SlabGeometry, x: [f64; 3], r: f64, slack: f64) -> String {
    let c = r - slack;
    let half = 0.5 * g.width;
    if x[0] < -half + c || x[0] > half - c {
        return format!(
            "x must lie in {} between the side walls at x = ±{half} m",
            range(-half + c, half - c)
        );
    }
    if x[1] < c || x[1] > g.thickness - c {
        return format!(
            "y must lie in {} between the front and back walls at y = 0 and {} m",
            range(c, g.thickness - c),
            g.thickness
        );
    }
    if x[2] < c || x[2] > g.height - c {
        return format!(
            "z must lie in {} above the orifice plane z = 0 and below the top z = {} m",
            range(c, g.height - c),
            g.height
        );
    }
    let (xl, xr) = g.outlet_edges();
    let a = g.hopper_angle();
    let (sa, ca) = (a.sin(), a.cos());
    let left = (x[0] - xl) * ca + x[2] * sa;
    let right = (xr - x[0]) * ca + x[2] * sa;
    let (side, distance) = if left < right {
        ("left", left)
    } else {
        ("right", right)
    };
    format!(
        "its centre lies {distance:.6e} m from the {side} bottom plate's plane, which must be at \
         least {c:.6e} m"
    )
}

/// Which wall of the silo a particle of radius `r` at `x` crosses, in words.
fn silo_violation(g: &CylinderGeometry, x: [f64; 3], r: f64, slack: f64) -> String {
    let c = r - slack;
    if x[2] < c || x[2] > g.height - c {
        return format!(
            "z must lie in {} above the orifice plane z = 0 and below the top z = {} m",
            range(c, g.height - c),
            g.height
        );
    }
    let rho = x[0].hypot(x[1]);
    if rho > g.radius - c {
        return format!(
            "its distance from the axis √(x² + y²) = {rho:.6e} m must be at most {:.6e} m \
             inside the cylinder of radius {} m",
            g.radius - c,
            g.radius
        );
    }
    let theta = g.hopper_angle();
    let cone = g.outlet_radius() + x[2] * theta.tan();
    format!(
        "its centre lies {:.6e} m inside the cone (half-angle {}°) at its height, which must be \
         at least {c:.6e} m",
        (cone - rho) * theta.cos(),
        g.hopper_angle_deg
    )
}

/// Which bounding plane of a rectangular silo a particle of radius `r` at `x` crosses, in
/// words.
fn box_violation(g: &CuboidGeometry, x: [f64; 3], r: f64, slack: f64) -> String {
    let c = r - slack;
    let p = DVec3::from(x);
    let spaces = g.half_spaces(g.height);
    let worst = spaces
        .iter()
        .max_by(|a, b| a.outside(p).total_cmp(&b.outside(p)))
        .expect("a box has half-spaces");
    format!(
        "its centre lies {:.6e} m inside the plane of its {:?} face, which must be at least \
         {c:.6e} m",
        -worst.outside(p),
        worst.face
    )
}

/// No two particles overlapping by more than [`PACKING_OVERLAP_FRACTION`] of the smaller
/// radius; each overlap is named once, at the later particle.
fn check_overlaps(raw: &[RawParticle], problems: &mut Problems) {
    let largest = raw.iter().map(|p| p.radius).fold(0.0, f64::max);
    if raw.is_empty() || largest <= 0.0 {
        return;
    }
    // Cells one largest diameter wide: any two touching centres lie in neighbouring cells.
    let cell = 2.0 * largest;
    let key = |x: [f64; 3]| {
        let k = |v: f64| (v / cell).floor() as i64;
        (k(x[0]), k(x[1]), k(x[2]))
    };
    let mut cells: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
    for (i, p) in raw.iter().enumerate() {
        let (a, b, c) = key(p.position);
        let xi = DVec3::from_array(p.position);
        let mut worst: Option<(usize, f64)> = None;
        for da in -1..=1 {
            for db in -1..=1 {
                for dc in -1..=1 {
                    let Some(list) = cells.get(&(a + da, b + db, c + dc)) else {
                        continue;
                    };
                    for &j in list {
                        let q = &raw[j];
                        let overlap =
                            p.radius + q.radius - xi.distance(DVec3::from_array(q.position));
                        let allowed = PACKING_OVERLAP_FRACTION * p.radius.min(q.radius);
                        let first = worst.is_none_or(|(k, _)| j < k);
                        if overlap > allowed && first {
                            worst = Some((j, overlap));
                        }
                    }
                }
            }
        }
        if let Some((j, overlap)) = worst {
            let smaller = p.radius.min(raw[j].radius);
            let other = match &raw[j].place {
                PackingPlace::Line(n) => format!("the particle of line {n}"),
                PackingPlace::Point(k) => format!("point {k}"),
                place => format!("the particle at{place}"),
            };
            problems.push(
                p.place.clone(),
                format!(
                    "overlaps {other} by {overlap:.6e} m, {:.3} % of the smaller radius; at most \
                     {} % is allowed",
                    100.0 * overlap / smaller,
                    PACKING_OVERLAP_FRACTION * 100.0
                ),
            );
        }
        cells.entry((a, b, c)).or_default().push(i);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn places_read_as_the_messages_name_them() {
        assert_eq!(PackingPlace::Line(7).to_string(), " line 7");
        assert_eq!(PackingPlace::Point(3).to_string(), " point 3");
        assert_eq!(
            PackingPlace::Array {
                name: "radius".into(),
                index: 4
            }
            .to_string(),
            " array `radius` value 4"
        );
    }
}
