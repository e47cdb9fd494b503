//! Reads `[geometry]` of a container of STL walls (`kind = "mesh"`): the `[[geometry.walls]]`
//! files, read and checked here so that a malformed, missing or degenerate mesh is a case error
//! naming the key and the STL's own message; the orifice; the fill box, refused where it meets
//! a triangle.
//!
//! A relative `file` is taken from the case file's folder (`dir`; the current folder for case
//! text that has no file) and kept absolute, so that the resolved case names the same file
//! wherever it is read from.

use std::path::Path;
use std::sync::Arc;

use super::error::{number, rounded, ConfigError, ErrorKind, Location};
use super::limits::outlet_too_small;
use super::mesh::{box_meets_triangle, MeshGeometry, MeshOutlet, MeshWall, MAX_MESH_WALLS};
use super::named_file::read_named_file;
use super::reader::{Located, Section};

/// Keys of a mesh container's `[geometry]`.
pub(crate) const MESH_KEYS: &[&str] = &["kind", "walls", "outlet", "fill_min", "fill_max"];

/// Keys of one `[[geometry.walls]]` entry.
const WALL_KEYS: &[&str] = &[
    "name",
    "file",
    "sha256",
    "scale",
    "rotate_axis",
    "rotate_deg",
    "translate",
];

/// Wall names that other rows of `wall_forces.csv` use.
const RESERVED_NAMES: &[&str] = &["gate"];

/// Reads a container of STL walls; `d_max` is the largest particle diameter [m] with the key
/// that set it, when the particles are valid; `dir` is the case file's folder.
pub(crate) fn read_mesh(
    section: &mut Section<'_>,
    d_max: Option<(f64, &str)>,
    dir: Option<&Path>,
    errors: &mut Vec<ConfigError>,
) -> Option<MeshGeometry> {
    let before = errors.len();
    let entries = section.tables("walls", errors).unwrap_or_default();
    let walls_mistyped = errors.len() > before;
    let has_walls = section.has("walls");
    let mut outlet_section = section
        .has("outlet")
        .then(|| section.section("outlet", errors));
    let fill_min = section.float_vector("fill_min", "m", 3, errors);
    let fill_max = section.float_vector("fill_max", "m", 3, errors);
    let missing = |key: &str, what: &str| {
        ConfigError::new(
            ErrorKind::Missing,
            section.location().clone(),
            section.key(key),
            None,
            format!("required for geometry.kind = \"mesh\": {what}"),
        )
    };
    let mut ok = true;
    if !has_walls {
        errors.push(missing(
            "walls",
            "at least one [[geometry.walls]] table with the `file` of an STL wall",
        ));
        ok = false;
    }
    if outlet_section.is_none() {
        errors.push(missing(
            "outlet",
            "the orifice in the plane z = 0, e.g. outlet = { shape = \"disc\", centre = [0.0, \
             0.0], radius = 0.01 }",
        ));
        ok = false;
    }
    for (key, value) in [("fill_min", &fill_min), ("fill_max", &fill_max)] {
        if value.is_none() && !section.has(key) {
            errors.push(missing(
                key,
                "a corner [x, y, z] [m] of the box the particles are poured into",
            ));
            ok = false;
        }
    }
    section.finish(MESH_KEYS, errors);

    let mut walls = Vec::new();
    if entries.len() > MAX_MESH_WALLS {
        errors.push(ConfigError::new(
            ErrorKind::Invalid,
            entries[MAX_MESH_WALLS].location().clone(),
            section.key("walls"),
            Some(format!("{} tables", entries.len())),
            format!("at most {MAX_MESH_WALLS} STL walls"),
        ));
        ok = false;
    } else if walls_mistyped {
        ok = false;
    } else if has_walls && entries.is_empty() {
        errors.push(missing("walls", "at least one STL wall"));
        ok = false;
    }
    let mut names: Vec<(String, String)> = Vec::new();
    for (index, mut entry) in entries.into_iter().enumerate() {
        let location = entry.location().clone();
        match read_wall(&mut entry, &location, index, dir, &mut names, errors) {
            Some(wall) => walls.push(wall),
            None => ok = false,
        }
    }
    let outlet = outlet_section
        .as_mut()
        .and_then(|o| read_outlet(o, d_max, errors));
    ok &= outlet.is_some() || outlet_section.is_none();
    let fill = read_fill(fill_min, fill_max, d_max, errors);
    let (Some(outlet), Some((fill_min, fill_max)), true) = (outlet, fill, ok) else {
        return None;
    };
    let container = MeshGeometry {
        walls,
        outlet,
        fill_min: fill_min.0,
        fill_max: fill_max.0,
    };
    // The fill box must lie inside the walls: with an open mesh that cannot be decided, but a
    // box that cuts a triangle certainly does not. The first such triangle of each wall.
    let mut clear = true;
    for (index, wall) in container.walls.iter().enumerate() {
        let hit = wall
            .triangles
            .iter()
            .position(|t| box_meets_triangle(container.fill_min, container.fill_max, t));
        if let Some(t) = hit {
            errors.push(fill_min.1.error(
                ErrorKind::DoesNotFit,
                format!(
                    "the fill box from {} to {} m meets triangle {} (counting from 1) of \
                     geometry.walls[{index}] ({}); the box must lie inside the walls, clear of \
                     every triangle",
                    shown(&container.fill_min),
                    shown(&container.fill_max),
                    t + 1,
                    wall.file.display()
                ),
            ));
            clear = false;
        }
    }
    clear.then_some(container)
}

/// `[x, y, z]` for messages.
fn shown(p: &[f64]) -> String {
    let items: Vec<String> = p.iter().map(|x| number(*x)).collect();
    format!("[{}]", items.join(", "))
}

/// A name fit for a CSV cell and a message: letters, digits, `_`, `-` and `.`.
fn is_wall_name(name: &str) -> bool {
    !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
}

/// Reads one `[[geometry.walls]]` table and its STL file; `names` holds the names taken so
/// far with their keys.
fn read_wall(
    entry: &mut Section<'_>,
    location: &Location,
    index: usize,
    dir: Option<&Path>,
    names: &mut Vec<(String, String)>,
    errors: &mut Vec<ConfigError>,
) -> Option<MeshWall> {
    let name = entry.string("name", errors);
    let file = entry.string("file", errors);
    let sha = entry.string("sha256", errors);
    let scale = entry.float_or("scale", "m per file unit", 1.0, errors);
    let axis = entry.float_vector_or("rotate_axis", "", &[0.0, 0.0, 1.0], errors);
    let angle = entry.float_or("rotate_deg", "°", 0.0, errors);
    let translate = entry.float_vector_or("translate", "m", &[0.0, 0.0, 0.0], errors);
    entry.finish(WALL_KEYS, errors);

    let mut ok = true;
    if !(scale.value.is_finite() && scale.value > 0.0) {
        errors.push(scale.error(
            ErrorKind::Invalid,
            "must be a finite number > 0 (metres per file unit, e.g. 0.001 for millimetres)",
        ));
        ok = false;
    }
    if axis.require_finite(errors) && axis.value.iter().all(|x| *x == 0.0) {
        errors.push(axis.error(
            ErrorKind::Invalid,
            "must not be zero: the rotation's axis (any length)",
        ));
        ok = false;
    } else if !axis.value.iter().all(|x| x.is_finite()) {
        ok = false;
    }
    if !angle.value.is_finite() {
        errors.push(angle.error(ErrorKind::Invalid, "must be a finite number"));
        ok = false;
    }
    ok &= translate.require_finite(errors);
    let Some(file) = file else {
        if !entry.has("file") {
            errors.push(ConfigError::new(
                ErrorKind::Missing,
                location.clone(),
                entry.key("file"),
                None,
                "required: the STL file of this wall (ASCII or binary; a relative path is \
                 taken from the case file's folder)",
            ));
        }
        return None;
    };
    let default_name = Path::new(&file.value)
        .file_stem()
        .and_then(|s| s.to_str())
        .filter(|s| is_wall_name(s))
        .map_or_else(|| format!("wall_{index}"), str::to_string);
    let name_value = match &name {
        Some(n) if !is_wall_name(&n.value) => {
            errors.push(n.error(
                ErrorKind::Invalid,
                "must be a non-empty name of letters, digits, `_`, `-` and `.`",
            ));
            ok = false;
            n.value.clone()
        }
        Some(n) => n.value.clone(),
        None => default_name,
    };
    let name_key = name
        .as_ref()
        .map_or_else(|| file.key.clone(), |n| n.key.clone());
    if RESERVED_NAMES.contains(&name_value.as_str()) {
        let message = format!(
            "the name \"{name_value}\" belongs to another wall of wall_forces.csv; give \
             {} another",
            entry.key("name")
        );
        errors.push(match &name {
            Some(n) => n.error(ErrorKind::Invalid, message),
            None => file.error(ErrorKind::Invalid, message),
        });
        ok = false;
    } else if let Some((_, other)) = names.iter().find(|(n, _)| *n == name_value) {
        let message = format!(
            "the wall name \"{name_value}\" is taken by {other}; names must differ (give \
             {} another)",
            entry.key("name")
        );
        errors.push(match &name {
            Some(n) => n.error(ErrorKind::Conflict, message),
            None => file.error(ErrorKind::Conflict, message),
        });
        ok = false;
    }
    names.push((name_value.clone(), name_key));

    let (named, pinned) = read_named_file(&file, sha.as_ref(), dir, "STL file", errors)?;
    ok &= pinned;
    let path_text = &named.path_text;
    if !ok {
        return None;
    }
    let rotate = [axis.value[0], axis.value[1], axis.value[2]];
    let shift = [translate.value[0], translate.value[1], translate.value[2]];
    let transform = match stl::Transform::new(
        scale.value,
        glam::DVec3::from(rotate),
        angle.value.to_radians(),
        glam::DVec3::from(shift),
    ) {
        Ok(t) => t,
        Err(e) => {
            errors.push(file.error(ErrorKind::Invalid, e.to_string()));
            return None;
        }
    };
    let mesh = match stl::parse(&named.bytes, path_text, &transform) {
        Ok(mesh) => mesh,
        Err(e) => {
            errors.push(file.error(ErrorKind::Invalid, format!("not a usable STL wall: {e}")));
            return None;
        }
    };
    // The engine's own test of each triangle (a stricter area ratio than the reader's), so
    // that every wall the case names can be built.
    let probe = dem::Interaction {
        friction: 0.0,
        rolling_friction: 0.0,
        restitution: 1.0,
        cohesion: dem::Cohesion::None,
    };
    if let Err(e) = dem::Wall::mesh(&mesh.triangles, dem::WallMaterial::Rigid, probe) {
        let reason = match e {
            dem::wall::WallError::BadTriangle { triangle, reason } => format!(
                "{path_text}, triangle {} (counting from 1): {reason}",
                triangle + 1
            ),
            other => format!("{path_text}: {other}"),
        };
        errors.push(file.error(
            ErrorKind::Invalid,
            format!("not a usable wall mesh: {reason}"),
        ));
        return None;
    }
    Some(MeshWall {
        name: name_value,
        file: named.path,
        sha256: named.digest,
        scale: scale.value,
        rotate_axis: rotate,
        rotate_deg: angle.value,
        translate: shift,
        triangles: Arc::new(mesh.triangles),
    })
}

/// Reads `geometry.outlet`: a disc or a rectangle in the plane z = 0.
fn read_outlet(
    section: &mut Section<'_>,
    d_max: Option<(f64, &str)>,
    errors: &mut Vec<ConfigError>,
) -> Option<MeshOutlet> {
    let shape = section.string("shape", errors);
    let centre = section.float_vector_or("centre", "m", &[0.0, 0.0], errors);
    let mut ok = centre.require_finite(errors);
    let centre_value = [centre.value[0], centre.value[1]];
    let Some(shape) = shape else {
        if !section.has("shape") {
            errors.push(ConfigError::new(
                ErrorKind::Missing,
                section.location().clone(),
                section.key("shape"),
                None,
                "required: \"disc\" (centre, radius, segments) or \"rectangle\" (centre, size)",
            ));
        }
        section.finish(&[], &mut Vec::new());
        return None;
    };
    let too_small = |value: f64| outlet_too_small(value, d_max);
    match shape.value.as_str() {
        "disc" => {
            let radius = section.float("radius", "m", errors);
            let segments =
                section.integer_or("segments", MeshOutlet::DEFAULT_SEGMENTS as i64, errors);
            section.finish(&["shape", "centre", "radius", "segments"], errors);
            let (lo, hi) = MeshOutlet::SEGMENTS_RANGE;
            if !(lo..=hi).contains(&segments.value) {
                errors.push(segments.error(
                    ErrorKind::Invalid,
                    format!(
                        "must be an integer in [{lo}, {hi}]: sides of the gate's polygon around \
                         the disc"
                    ),
                ));
                ok = false;
            }
            let Some(radius) = radius else {
                if !section.has("radius") {
                    errors.push(ConfigError::new(
                        ErrorKind::Missing,
                        section.location().clone(),
                        section.key("radius"),
                        None,
                        "required: the disc's radius [m]",
                    ));
                }
                return None;
            };
            ok &= radius.require_positive(errors);
            if ok {
                if let Some(message) = too_small(2.0 * radius.value) {
                    errors.push(radius.error(
                        ErrorKind::Invalid,
                        format!("the diameter 2 × {} {message}", radius.key),
                    ));
                    ok = false;
                }
            }
            ok.then_some(MeshOutlet::Disc {
                centre: centre_value,
                radius: radius.value,
                segments: segments.value as usize,
            })
        }
        "rectangle" => {
            let size = section.float_vector("size", "m", 2, errors);
            section.finish(&["shape", "centre", "size"], errors);
            let Some(size) = size else {
                if !section.has("size") {
                    errors.push(ConfigError::new(
                        ErrorKind::Missing,
                        section.location().clone(),
                        section.key("size"),
                        None,
                        "required: the rectangle's sides [along x, along y] [m]",
                    ));
                }
                return None;
            };
            if !size.value.iter().all(|x| x.is_finite() && *x > 0.0) {
                errors
                    .push(size.error(ErrorKind::Invalid, "both sides must be finite numbers > 0"));
                return None;
            }
            if let Some(message) = too_small(size.value[0].min(size.value[1])) {
                errors.push(size.error(ErrorKind::Invalid, format!("each side {message}")));
                ok = false;
            }
            ok.then_some(MeshOutlet::Rectangle {
                centre: centre_value,
                size: [size.value[0], size.value[1]],
            })
        }
        other => {
            errors.push(shape.error(
                ErrorKind::Invalid,
                format!("unknown outlet shape \"{other}\"; must be one of \"disc\", \"rectangle\""),
            ));
            section.finish(&[], &mut Vec::new());
            None
        }
    }
}

/// A corner of the fill box with the place it was written.
type Corner = ([f64; 3], Located<Vec<f64>>);

/// Checks the fill box: finite corners, min < max on every axis with room for the largest
/// particle, above the orifice plane.
fn read_fill(
    fill_min: Option<Located<Vec<f64>>>,
    fill_max: Option<Located<Vec<f64>>>,
    d_max: Option<(f64, &str)>,
    errors: &mut Vec<ConfigError>,
) -> Option<(Corner, Corner)> {
    let (lo, hi) = (fill_min?, fill_max?);
    if !(lo.require_finite(errors) & hi.require_finite(errors)) {
        return None;
    }
    let mut ok = true;
    if lo.value[2] < 0.0 {
        errors.push(lo.error(
            ErrorKind::Invalid,
            "z must be ≥ 0: the fill box lies above the orifice plane z = 0",
        ));
        ok = false;
    }
    let least = d_max.map_or(0.0, |(d, _)| d);
    for (axis, name) in ["x", "y", "z"].iter().enumerate() {
        if hi.value[axis] - lo.value[axis] <= least {
            let room = match d_max {
                Some((d, source)) => format!(
                    "by more than the largest particle diameter ({} m), {source}",
                    rounded(d)
                ),
                None => "by more than a particle diameter".to_string(),
            };
            errors.push(hi.error(
                ErrorKind::Invalid,
                format!(
                    "{name} must exceed {}[{axis}] = {} m {room}",
                    lo.key,
                    number(lo.value[axis])
                ),
            ));
            ok = false;
        }
    }
    let corner = |l: &Located<Vec<f64>>| [l.value[0], l.value[1], l.value[2]];
    ok.then(|| ((corner(&lo), lo.clone()), (corner(&hi), hi.clone())))
}
