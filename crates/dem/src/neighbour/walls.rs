//! The particle–wall candidates of one wall: every body closer than R_i + skin to it.

use super::*;
use crate::wall::WallShape;

/// Appends to `out`, in index order, the bodies (positions `pos`, radii `rad`) closer than
/// R_i + `skin` [m] to `wall` and not wholly behind it.
///
/// An unbounded shape (a plane) has nearly every body as a candidate when it is a face of
/// the slab and few otherwise, and a branch would be mispredicted at the edge of every run:
/// every body is tested and stored, and the count advances only for a candidate. A bounded
/// shape has few candidates, and its cheap far test ([`Wall::certainly_beyond`]) rejects
/// most bodies before the closest-point test.
pub(super) fn wall_candidates(
    wall: &Wall,
    (pos, rad): (&[DVec3], &[f64]),
    skin: f64,
    out: &mut Vec<u32>,
) {
    let n = pos.len();
    let before = out.len();
    if wall.shape().is_unbounded() {
        out.resize(before + n, 0);
        let slots = &mut out[before..];
        let mut count = 0;
        for i in 0..n {
            let (_, dist) = wall.closest_point(pos[i]);
            slots[count] = i as u32;
            count += usize::from((dist < rad[i] + skin) & (dist > -rad[i]));
        }
        out.truncate(before + count);
    } else if let WallShape::Polygon(p) = wall.shape() {
        // The polygon's own tests, the common bounded wall, without a dispatch per body.
        for i in 0..n {
            let reach = rad[i] + skin;
            if !p.certainly_beyond(pos[i], reach) && p.closest_point(pos[i]).1 < reach {
                out.push(i as u32);
            }
        }
    } else {
        for i in 0..n {
            let reach = rad[i] + skin;
            if !wall.certainly_beyond(pos[i], reach) && wall.comes_within(pos[i], reach) {
                out.push(i as u32);
            }
        }
    }
}
