//! Reads `[geometry]` of a rectangular silo (`kind = "box"`), collecting every error with its
//! key, line, value and allowed range.

use super::cuboid::{CuboidGeometry, CuboidOutlet};
use super::error::{number, rounded, ConfigError, ErrorKind};
use super::limits::outlet_too_small;
use super::reader::{Located, Section};
use super::sources::source;
use super::wall_surface::WallSurface;

/// Keys of a rectangular silo's `[geometry]`.
pub(crate) const BOX_KEYS: &[&str] = &[
    "kind",
    "width",
    "depth",
    "height",
    "outlet",
    "outlet_width",
    "hopper_angle_deg",
    "outlet_offset",
    "walls",
];

/// Reads a rectangular silo; `d_max` is the largest particle diameter [m] with the key that
/// set it, when the particles are valid.
pub(crate) fn read_cuboid(
    section: &mut Section<'_>,
    d_max: Option<(f64, &str)>,
    errors: &mut Vec<ConfigError>,
) -> Option<CuboidGeometry> {
    let base = CuboidGeometry::example();
    let width = section.float_or("width", "m", base.width, errors);
    let depth = section.float_or("depth", "m", base.depth, errors);
    let height = section.float_or("height", "m", base.height, errors);
    let before = errors.len();
    let outlet = section.choice(
        "outlet",
        &[
            ("slot", CuboidOutlet::Slot),
            ("square", CuboidOutlet::Square),
        ],
        base.outlet,
        errors,
    );
    let mut ok = errors.len() == before;
    let outlet_width = section.float_or("outlet_width", "m", base.outlet_width, errors);
    let angle = section.float_or("hopper_angle_deg", "°", base.hopper_angle_deg, errors);
    let offset = section.float_or("outlet_offset", "m", 0.0, errors);
    let before = errors.len();
    let walls = section.choice(
        "walls",
        &[
            ("smooth", WallSurface::Smooth),
            ("meshed", WallSurface::Meshed),
        ],
        WallSurface::Smooth,
        errors,
    );
    ok &= errors.len() == before;
    section.finish(BOX_KEYS, errors);

    ok &= width.require_positive(errors)
        & depth.require_positive(errors)
        & height.require_positive(errors)
        & outlet_width.require_positive(errors);
    if !offset.value.is_finite() {
        errors.push(offset.error(ErrorKind::Invalid, "must be a finite number"));
        ok = false;
    }
    if !(angle.value > 0.0 && angle.value <= 90.0) {
        errors.push(angle.error(
            ErrorKind::Invalid,
            "must lie in (0°, 90°]: the plates' angle from the vertical, 90° = flat bottom",
        ));
        ok = false;
    }
    if !ok {
        return None;
    }
    let (w, b, d, e) = (width.value, depth.value, outlet_width.value, offset.value);
    if let Some(d_max) = d_max {
        ok &= fits_particles(&outlet_width, &depth, d_max, errors);
    }
    if e != 0.0 && angle.value < 90.0 {
        errors.push(offset.error(
            ErrorKind::Invalid,
            format!(
                "an off-centre orifice needs a flat bottom ({} = 90°); the plates meet at the \
                 axis",
                angle.key
            ),
        ));
        ok = false;
    }
    if e.abs() + 0.5 * d >= 0.5 * w {
        errors.push(outlet_width.error(
            ErrorKind::DoesNotFit,
            format!(
                "the orifice lies outside the bottom: |e| + D/2 = {} m must be < W/2 = {} m \
                 ({}, {})",
                rounded(e.abs() + 0.5 * d),
                rounded(0.5 * w),
                source(&width),
                source(&offset)
            ),
        ));
        ok = false;
    }
    if outlet == CuboidOutlet::Square && d >= b {
        errors.push(outlet_width.error(
            ErrorKind::DoesNotFit,
            format!(
                "a square orifice must be narrower than the depth: D must be < {} ({} m); a \
                 slot (geometry.outlet = \"slot\") spans the whole depth",
                depth.key,
                number(b)
            ),
        ));
        ok = false;
    }
    if !ok {
        return None;
    }
    let silo = CuboidGeometry {
        width: w,
        depth: b,
        height: height.value,
        outlet,
        outlet_width: d,
        hopper_angle_deg: angle.value,
        outlet_offset: e,
        walls,
    };
    if silo.hopper_height() >= silo.height {
        let what = match outlet {
            CuboidOutlet::Slot => format!("(W − D)/2 · cot α, from {}", source(&width)),
            CuboidOutlet::Square => format!(
                "the larger of (W − D)/2 and (B − D)/2 times cot α, from {} and {}",
                source(&width),
                source(&depth)
            ),
        };
        errors.push(angle.error(
            ErrorKind::DoesNotFit,
            format!(
                "the plates would rise {} m ({what} and {}), not below {} ({} m)",
                rounded(silo.hopper_height()),
                source(&outlet_width),
                height.key,
                number(silo.height)
            ),
        ));
        return None;
    }
    Some(silo)
}

/// Whether a box's orifice `outlet` (its width D [m]) and depth `depth` [m] are wide enough
/// for the largest particle diameter `d_max` [m] (with the key that set it): the orifice as
/// every outlet must be, the depth at least one diameter. Errors name the key that fails.
pub(crate) fn fits_particles(
    outlet: &Located<f64>,
    depth: &Located<f64>,
    (d_max, d_source): (f64, &str),
    errors: &mut Vec<ConfigError>,
) -> bool {
    let mut ok = true;
    if let Some(why) = outlet_too_small(outlet.value, Some((d_max, d_source))) {
        errors.push(outlet.error(ErrorKind::Invalid, why));
        ok = false;
    }
    if depth.value < d_max {
        errors.push(depth.error(
            ErrorKind::Invalid,
            format!(
                "must be ≥ the largest particle diameter ({} m), {d_source}",
                rounded(d_max)
            ),
        ));
        ok = false;
    }
    ok
}
