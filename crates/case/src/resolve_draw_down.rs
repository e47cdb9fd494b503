//! Reads `[geometry]` of the draw-down test (`kind = "draw_down"`), collecting every error
//! with its key, line, value and allowed range.

use super::draw_down::DrawDownGeometry;
use super::error::{number, rounded, ConfigError, ErrorKind};
use super::reader::Section;
use super::resolve_cuboid::fits_particles;
use super::sources::source;
use super::wall_surface::WallSurface;

/// Keys of the draw-down box's `[geometry]`.
const DRAW_DOWN_KEYS: &[&str] = &["kind", "width", "depth", "height", "slot_width", "walls"];

/// Fewest largest particle diameters along each shelf: the slope left on a shelf is fitted
/// between the slot's edge and the wall, and a shorter shelf holds no slope to fit.
pub(crate) const MIN_SHELF_DIAMETERS: f64 = 3.0;

/// Reads the draw-down box; `d_max` is the largest particle diameter [m] with the key that
/// set it, when the particles are valid.
pub(crate) fn read_draw_down(
    section: &mut Section<'_>,
    d_max: Option<(f64, &str)>,
    errors: &mut Vec<ConfigError>,
) -> Option<DrawDownGeometry> {
    let base = DrawDownGeometry::example();
    let width = section.float_or("width", "m", base.width(), errors);
    let depth = section.float_or("depth", "m", base.depth(), errors);
    let height = section.float_or("height", "m", base.height(), errors);
    let slot = section.float_or("slot_width", "m", base.slot_width(), errors);
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
    let mut ok = errors.len() == before;
    section.finish(DRAW_DOWN_KEYS, errors);

    ok &= width.require_positive(errors)
        & depth.require_positive(errors)
        & height.require_positive(errors)
        & slot.require_positive(errors);
    if !ok {
        return None;
    }
    let (w, b, d) = (width.value, depth.value, slot.value);
    if d >= w {
        errors.push(slot.error(
            ErrorKind::DoesNotFit,
            format!(
                "must be < {} ({} m): the slot lies in the floor between two shelves",
                width.key,
                number(w)
            ),
        ));
        return None;
    }
    if let Some((d_max, d_source)) = d_max {
        ok &= fits_particles(&slot, &depth, (d_max, d_source), errors);
        let shortest = MIN_SHELF_DIAMETERS * d_max;
        if 0.5 * (w - d) < shortest {
            errors.push(slot.error(
                ErrorKind::DoesNotFit,
                format!(
                    "each shelf, (W − D)/2 = {} m, must be ≥ {MIN_SHELF_DIAMETERS} particle \
                     diameters ({} m) to hold a slope, so D ≤ {} m ({}; d the largest \
                     diameter, {d_source})",
                    rounded(0.5 * (w - d)),
                    rounded(shortest),
                    rounded(w - 2.0 * shortest),
                    source(&width)
                ),
            ));
            ok = false;
        }
    }
    ok.then(|| DrawDownGeometry::new(w, b, height.value, d, walls))
}
