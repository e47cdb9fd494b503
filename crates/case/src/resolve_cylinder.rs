//! Reads `[geometry]` of a cylindrical silo (`kind = "cylinder"`), collecting every error
//! with its key, line, value and allowed range.

use super::cylinder::CylinderGeometry;
use super::error::{number, rounded, ConfigError, ErrorKind};
use super::limits::outlet_too_small;
use super::reader::Section;
use super::sources::source;
use super::wall_surface::{WallSurface, DEFAULT_MESH_SEGMENTS, MESH_SEGMENTS_RANGE};

/// Keys of a cylindrical silo's `[geometry]`.
const CYLINDER_KEYS: &[&str] = &[
    "kind",
    "radius",
    "height",
    "outlet_diameter",
    "hopper_angle_deg",
    "outlet_offset",
    "walls",
    "mesh_segments",
];

/// Reads a cylindrical silo; `d_max` is the largest particle diameter [m] with the key that
/// set it, when the particles are valid.
pub(crate) fn read_cylinder(
    section: &mut Section<'_>,
    d_max: Option<(f64, &str)>,
    errors: &mut Vec<ConfigError>,
) -> Option<CylinderGeometry> {
    let base = CylinderGeometry::dosta2024_large();
    let radius = section.float_or("radius", "m", base.radius, errors);
    let height = section.float_or("height", "m", base.height, errors);
    let outlet = section.float_or("outlet_diameter", "m", base.outlet_diameter, errors);
    let angle = section.float_or("hopper_angle_deg", "°", base.hopper_angle_deg, errors);
    let offset = section.float_or("outlet_offset", "m", 0.0, errors);
    let walls = section.choice(
        "walls",
        &[
            ("smooth", WallSurface::Smooth),
            ("meshed", WallSurface::Meshed),
        ],
        WallSurface::Smooth,
        errors,
    );
    let segments = section.integer_or("mesh_segments", DEFAULT_MESH_SEGMENTS as i64, errors);
    section.finish(CYLINDER_KEYS, errors);

    let mut ok = radius.require_positive(errors)
        & height.require_positive(errors)
        & outlet.require_positive(errors);
    if !offset.value.is_finite() {
        errors.push(offset.error(ErrorKind::Invalid, "must be a finite number"));
        ok = false;
    }
    let angle_ok = angle.value > 0.0 && angle.value <= 90.0;
    if !angle_ok {
        errors.push(angle.error(
            ErrorKind::Invalid,
            "must lie in (0°, 90°]: the cone's half-angle from the vertical, 90° = flat bottom",
        ));
        ok = false;
    }
    let (lo, hi) = MESH_SEGMENTS_RANGE;
    if !(lo..=hi).contains(&segments.value) {
        errors.push(segments.error(
            ErrorKind::Invalid,
            format!("must be an integer in [{lo}, {hi}]: segments around the axis"),
        ));
        ok = false;
    }
    if !ok {
        return None;
    }
    let (r, d, e) = (radius.value, outlet.value, offset.value);
    if let Some((d_max, d_source)) = d_max {
        if let Some(why) = outlet_too_small(d, Some((d_max, d_source))) {
            errors.push(outlet.error(ErrorKind::Invalid, why));
            ok = false;
        }
    }
    if e != 0.0 && angle.value < 90.0 {
        errors.push(offset.error(
            ErrorKind::Invalid,
            format!(
                "an off-centre orifice needs a flat bottom ({} = 90°); a cone narrows to \
                 the axis",
                angle.key
            ),
        ));
        ok = false;
    }
    if e.abs() + 0.5 * d >= r {
        errors.push(outlet.error(
            ErrorKind::DoesNotFit,
            format!(
                "the orifice lies outside the bottom: |e| + D/2 = {} m must be < R ({}, {})",
                rounded(e.abs() + 0.5 * d),
                source(&radius),
                source(&offset)
            ),
        ));
        ok = false;
    }
    if !ok {
        return None;
    }
    let silo = CylinderGeometry {
        radius: r,
        height: height.value,
        outlet_diameter: d,
        hopper_angle_deg: angle.value,
        outlet_offset: e,
        walls,
        mesh_segments: segments.value as usize,
    };
    if silo.cone_height() >= silo.height {
        errors.push(angle.error(
            ErrorKind::DoesNotFit,
            format!(
                "the cone would rise {} m ((R − D/2)/tan θ, from {} and {}), not below {} ({} m)",
                rounded(silo.cone_height()),
                source(&radius),
                source(&outlet),
                height.key,
                number(silo.height)
            ),
        ));
        return None;
    }
    Some(silo)
}
