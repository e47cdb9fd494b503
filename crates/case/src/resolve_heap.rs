//! Reads `[geometry]` of the lifted-cylinder test (`kind = "heap"`), collecting every error
//! with its key, line, value and allowed range.

use super::error::{number, rounded, ConfigError, ErrorKind};
use super::heap::HeapGeometry;
use super::reader::Section;
use super::sources::source;

/// Keys of the heap's `[geometry]`.
const HEAP_KEYS: &[&str] = &[
    "kind",
    "cylinder_radius",
    "height",
    "plate_radius",
    "lift_speed",
];

/// Fewest largest particle diameters across the cylinder: narrower, the wall holds the
/// column up as a plug and the grains leave it as a collapse, not as a flow at its foot.
pub(crate) const MIN_CYLINDER_DIAMETERS: f64 = 5.0;

/// Fastest lift allowed [m/s]: well above √(g d) for any grain of millimetres, where the
/// column no longer flows out under the edge but is left standing and collapses.
pub(crate) const MAX_LIFT_SPEED: f64 = 1.0;

/// Reads the heap test; `d_max` is the largest particle diameter [m] with the key that set
/// it, when the particles are valid.
pub(crate) fn read_heap(
    section: &mut Section<'_>,
    d_max: Option<(f64, &str)>,
    errors: &mut Vec<ConfigError>,
) -> Option<HeapGeometry> {
    let base = HeapGeometry::example();
    let radius = section.float_or("cylinder_radius", "m", base.cylinder_radius, errors);
    let height = section.float_or("height", "m", base.height, errors);
    let plate = section.float_or("plate_radius", "m", base.plate_radius, errors);
    let speed = section.float_or("lift_speed", "m/s", base.lift_speed, errors);
    section.finish(HEAP_KEYS, errors);

    // A bad speed does not stop the checks of the sizes below.
    let speed_ok = speed.value.is_finite() && speed.value > 0.0 && speed.value <= MAX_LIFT_SPEED;
    if !speed_ok {
        errors.push(speed.error(
            ErrorKind::Invalid,
            format!(
                "must lie in (0, {}] m/s: the speed the cylinder is lifted at",
                number(MAX_LIFT_SPEED)
            ),
        ));
    }
    let mut ok = radius.require_positive(errors)
        & height.require_positive(errors)
        & plate.require_positive(errors);
    if !ok {
        return None;
    }
    let (r, rp) = (radius.value, plate.value);
    let d = d_max.map_or(0.0, |(d, _)| d);
    if let Some((d_max, d_source)) = d_max {
        let smallest = MIN_CYLINDER_DIAMETERS * d_max;
        if 2.0 * r < smallest * (1.0 - 4.0 * f64::EPSILON) {
            errors.push(radius.error(
                ErrorKind::Invalid,
                format!(
                    "the cylinder must be ≥ {MIN_CYLINDER_DIAMETERS} particle diameters across: \
                     2 R_c must be ≥ {} m, so R_c ≥ {} m, d being the largest diameter, \
                     {d_source}",
                    rounded(smallest),
                    rounded(0.5 * smallest)
                ),
            ));
            ok = false;
        }
    }
    if rp < r + d {
        let why = if d > 0.0 {
            format!(
                "must be ≥ R_c + d = {} m ({} and the largest particle diameter): the cylinder \
                 stands on the plate with room for a grain beyond its wall",
                rounded(r + d),
                source(&radius)
            )
        } else {
            format!(
                "must be ≥ {} ({} m): the cylinder stands on the plate",
                radius.key,
                number(r)
            )
        };
        errors.push(plate.error(ErrorKind::DoesNotFit, why));
        ok = false;
    }
    (ok && speed_ok).then_some(HeapGeometry {
        cylinder_radius: r,
        height: height.value,
        plate_radius: rp,
        lift_speed: speed.value,
    })
}
