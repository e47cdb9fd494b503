//! Reads a grain shape (`particles.shape`, or `shape` in a `[[particles.components]]` entry):
//! `kind = "rod"` with its `aspect_ratio` and optional `beads`; `kind = "spheres"` with a list
//! of member `spheres`, each a `centre` and a `radius`; or `kind = "stl"` with a closed STL
//! `file` to fill with spheres, its grid `cells` and allowed `shortfall`. Every refusal names
//! the key, the value and what is allowed; an STL that is not closed is refused with its
//! first open or unpaired edge.

use std::path::Path;

use dem::clump::{fill_mesh, ClumpShape, MAX_ROD_BEADS};
use dem::DVec3;

use super::error::{number, ConfigError, ErrorKind};
use super::grain_shape::{
    default_beads, GrainShape, ShapeGiven, DEFAULT_FILL_CELLS, DEFAULT_FILL_SHORTFALL,
    FILL_CELLS_RANGE, FILL_SHORTFALL_RANGE, MAX_ASPECT_RATIO, MAX_SHAPE_SPHERES,
};
use super::named_file::read_named_file;
use super::reader::Section;

/// Keys of a shape table.
const SHAPE_KEYS: &[&str] = &[
    "kind",
    "aspect_ratio",
    "beads",
    "spheres",
    "file",
    "sha256",
    "cells",
    "shortfall",
];

/// The kinds of shape.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Rod,
    Spheres,
    Stl,
}

/// Reads the `shape` key of `section`: `Ok(None)` when absent, `Err(())` when refused (the
/// errors are recorded). `dir` is the case file's folder, which a relative STL path is
/// taken from.
pub(crate) fn read_shape(
    section: &mut Section<'_>,
    dir: Option<&Path>,
    errors: &mut Vec<ConfigError>,
) -> Result<Option<GrainShape>, ()> {
    if !section.has("shape") {
        return Ok(None);
    }
    let before = errors.len();
    let mut table = section.section("shape", errors);
    if errors.len() > before {
        return Err(());
    }
    let kind = match table.string("kind", errors) {
        Some(word) => match word.value.as_str() {
            "rod" => Kind::Rod,
            "spheres" => Kind::Spheres,
            "stl" => Kind::Stl,
            _ => {
                errors.push(word.error(
                    ErrorKind::Invalid,
                    "must be one of \"rod\" (beads in a row of an aspect ratio), \"spheres\" \
                     (a list of member spheres) or \"stl\" (a closed STL body filled with \
                     spheres)",
                ));
                table.finish(SHAPE_KEYS, errors);
                return Err(());
            }
        },
        None => {
            if !table.has("kind") {
                errors.push(table.missing("kind", "required: \"rod\", \"spheres\" or \"stl\""));
            }
            return Err(());
        }
    };
    // Keys of the other kinds are refused by name, not silently ignored.
    let own: &[&str] = match kind {
        Kind::Rod => &["kind", "aspect_ratio", "beads"],
        Kind::Spheres => &["kind", "spheres"],
        Kind::Stl => &["kind", "file", "sha256", "cells", "shortfall"],
    };
    let mut ok = true;
    for key in SHAPE_KEYS.iter().filter(|k| !own.contains(k)) {
        if let Some(entry) = table.entry(key) {
            errors.push(ConfigError::new(
                ErrorKind::Conflict,
                entry.key_location.clone(),
                table.key(key),
                None,
                format!(
                    "does not belong to a shape of this kind; its keys are {}",
                    own.join(", ")
                ),
            ));
            ok = false;
        }
    }
    let shape = match kind {
        Kind::Rod => read_rod(&mut table, errors),
        Kind::Spheres => read_spheres(&mut table, errors),
        Kind::Stl => read_stl(&mut table, dir, errors),
    };
    table.finish(SHAPE_KEYS, errors);
    match shape {
        Some(shape) if ok => Ok(Some(shape)),
        _ => Err(()),
    }
}

fn read_rod(table: &mut Section<'_>, errors: &mut Vec<ConfigError>) -> Option<GrainShape> {
    let Some(aspect) = table.float("aspect_ratio", "", errors) else {
        if !table.has("aspect_ratio") {
            errors.push(table.missing(
                "aspect_ratio",
                format!(
                    "required for a rod: its length over its width, in [1, {MAX_ASPECT_RATIO}]"
                ),
            ));
        }
        return None;
    };
    if !(aspect.value >= 1.0 && aspect.value <= MAX_ASPECT_RATIO) {
        errors.push(aspect.error(
            ErrorKind::Invalid,
            format!("must lie in [1, {MAX_ASPECT_RATIO}]: the rod's length over its width"),
        ));
        return None;
    }
    let beads = match table.integer("beads", errors) {
        Some(b) => {
            let least = if aspect.value == 1.0 {
                1
            } else {
                (aspect.value.ceil() as i64).max(2)
            };
            let most = if aspect.value == 1.0 {
                1
            } else {
                MAX_ROD_BEADS as i64
            };
            if !(least..=most).contains(&b.value) {
                errors.push(b.error(
                    ErrorKind::Invalid,
                    format!(
                        "must lie in [{least}, {most}] for aspect ratio {}: at least \
                         ⌈aspect ratio⌉ beads keep neighbours touching",
                        number(aspect.value)
                    ),
                ));
                return None;
            }
            b.value as usize
        }
        None if table.has("beads") => return None,
        None => default_beads(aspect.value),
    };
    let rod = ClumpShape::rod(aspect.value, beads, 1.0).ok()?;
    Some(GrainShape::from_members(
        ShapeGiven::Rod {
            aspect_ratio: aspect.value,
            beads,
        },
        &rod,
        1.0,
    ))
}

fn read_spheres(table: &mut Section<'_>, errors: &mut Vec<ConfigError>) -> Option<GrainShape> {
    let location = table.location().clone();
    let Some(entries) = table.tables("spheres", errors) else {
        if !table.has("spheres") {
            errors.push(table.missing(
                "spheres",
                "required for kind = \"spheres\": the member spheres, e.g. spheres = [{ centre \
                 = [0.0, 0.0, 0.0], radius = 1.0 }, { centre = [1.0, 0.0, 0.0], radius = 1.0 }] \
                 in any unit of length (the grain is scaled to the component's diameter)",
            ));
        }
        return None;
    };
    if entries.is_empty() || entries.len() > MAX_SHAPE_SPHERES {
        errors.push(ConfigError::new(
            ErrorKind::Invalid,
            location,
            table.key("spheres"),
            Some(format!("{} spheres", entries.len())),
            format!("a clump needs 1 to {MAX_SHAPE_SPHERES} member spheres"),
        ));
        return None;
    }
    let mut members = Vec::with_capacity(entries.len());
    let mut ok = true;
    for mut entry in entries {
        let centre = entry.float_vector("centre", "", 3, errors);
        let radius = entry.float("radius", "", errors);
        for key in ["centre", "radius"] {
            if !entry.has(key) {
                errors.push(entry.missing(
                    key,
                    "required: each member sphere has a centre [x, y, z] and a radius > 0",
                ));
                ok = false;
            }
        }
        entry.finish(&["centre", "radius"], errors);
        let (Some(centre), Some(radius)) = (centre, radius) else {
            ok = false;
            continue;
        };
        ok &= centre.require_finite(errors);
        if !(radius.value > 0.0 && radius.value.is_finite()) {
            errors.push(radius.error(ErrorKind::Invalid, "must be a finite number > 0"));
            ok = false;
        }
        members.push((centre, radius));
    }
    if !ok {
        return None;
    }
    // One body: every member reaches the others through overlaps or contacts.
    let balls: Vec<(DVec3, f64)> = members
        .iter()
        .map(|(c, r)| (DVec3::new(c.value[0], c.value[1], c.value[2]), r.value))
        .collect();
    if let Some(k) = first_detached(&balls) {
        errors.push(members[k].0.error(
            ErrorKind::Invalid,
            format!(
                "member {k} neither overlaps nor touches the members before it or any joined \
                 to them: a grain must be one connected body"
            ),
        ));
        return None;
    }
    let shape = ClumpShape::new(balls.clone()).ok()?;
    Some(GrainShape::from_members(
        ShapeGiven::Spheres {
            spheres: balls.iter().map(|(c, r)| [c.x, c.y, c.z, *r]).collect(),
        },
        &shape,
        1.0,
    ))
}

/// The first member (by index) not joined to member 0 through a chain of overlapping or
/// touching members; `None` when all are joined.
fn first_detached(balls: &[(DVec3, f64)]) -> Option<usize> {
    let mut joined = vec![false; balls.len()];
    let mut stack = vec![0];
    joined[0] = true;
    while let Some(i) = stack.pop() {
        for j in 0..balls.len() {
            let touch =
                balls[i].0.distance(balls[j].0) <= (balls[i].1 + balls[j].1) * (1.0 + 1e-12);
            if !joined[j] && touch {
                joined[j] = true;
                stack.push(j);
            }
        }
    }
    joined.iter().position(|j| !j)
}

fn read_stl(
    table: &mut Section<'_>,
    dir: Option<&Path>,
    errors: &mut Vec<ConfigError>,
) -> Option<GrainShape> {
    let file = table.string("file", errors);
    let sha = table.string("sha256", errors);
    let cells = table.integer_or("cells", DEFAULT_FILL_CELLS as i64, errors);
    let shortfall = table.float_or("shortfall", "", DEFAULT_FILL_SHORTFALL, errors);
    let mut ok = true;
    let (lo, hi) = FILL_CELLS_RANGE;
    if !(lo as i64..=hi as i64).contains(&cells.value) {
        errors.push(cells.error(
            ErrorKind::Invalid,
            format!("must be an integer in [{lo}, {hi}]: grid cells along the body's longest side"),
        ));
        ok = false;
    }
    let (lo, hi) = FILL_SHORTFALL_RANGE;
    if !(shortfall.value >= lo && shortfall.value <= hi) {
        errors.push(shortfall.error(
            ErrorKind::Invalid,
            format!(
                "must lie in [{lo}, {hi}]: the share of the body's inside the spheres may leave \
                 uncovered"
            ),
        ));
        ok = false;
    }
    let Some(file) = file else {
        if !table.has("file") {
            errors.push(table.missing(
                "file",
                "required for kind = \"stl\": a closed STL surface of the grain (any unit of \
                 length; a relative path is taken from the case file's folder)",
            ));
        }
        return None;
    };
    let (named, pinned) = read_named_file(&file, sha.as_ref(), dir, "STL file", errors)?;
    ok &= pinned;
    let path_text = &named.path_text;
    if !ok {
        return None;
    }
    let mesh = match stl::parse(&named.bytes, path_text, &stl::Transform::identity()) {
        Ok(mesh) => mesh,
        Err(e) => {
            errors.push(file.error(ErrorKind::Invalid, format!("not a usable STL grain: {e}")));
            return None;
        }
    };
    if let Err(e) = stl::check_closed(&mesh.triangles) {
        errors.push(file.error(
            ErrorKind::Invalid,
            format!("{path_text} cannot be a grain: {e}; a grain's surface must enclose a solid"),
        ));
        return None;
    }
    // Wound inside out (clockwise seen from outside), the same surface turned the right way.
    let triangles: Vec<[DVec3; 3]> = if stl::enclosed_volume(&mesh.triangles) < 0.0 {
        mesh.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect()
    } else {
        mesh.triangles.clone()
    };
    let filled = match fill_mesh(&triangles, cells.value as usize, shortfall.value) {
        Ok(filled) => filled,
        Err(e) => {
            errors.push(file.error(
                ErrorKind::Invalid,
                format!("{path_text} could not be filled with spheres: {e}"),
            ));
            return None;
        }
    };
    Some(GrainShape::from_members(
        ShapeGiven::Stl {
            file: named.path,
            sha256: named.digest,
            cells: cells.value as usize,
            shortfall: shortfall.value,
        },
        &filled.shape,
        filled.union_volume / filled.mesh_volume,
    ))
}
