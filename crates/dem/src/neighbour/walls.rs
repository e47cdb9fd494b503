//! The particle–wall candidates of one wall: every body closer than R_i + skin to it.

use glam::DVec3;

use crate::wall::geometry::{ShapeVisitor, WallGeometry};
use crate::wall::Wall;

/// Appends to `out`, in index order, the bodies (positions `pos`, radii `rad`) closer than
/// R_i + `skin` [m] to `wall` and not wholly behind it.
///
/// The loop is compiled once per shape ([`crate::wall::WallShape::visit`]), so that it
/// calls the shape's own tests with no dispatch per body.
pub(super) fn wall_candidates(
    wall: &Wall,
    (pos, rad): (&[DVec3], &[f64]),
    skin: f64,
    out: &mut Vec<u32>,
) {
    struct Candidates<'b> {
        bodies: (&'b [DVec3], &'b [f64]),
        skin: f64,
        out: &'b mut Vec<u32>,
    }
    impl ShapeVisitor<'_> for Candidates<'_> {
        type Output = ();
        #[inline(always)]
        fn visit<S: WallGeometry>(self, shape: &S) {
            candidates_of(shape, self.bodies, self.skin, self.out);
        }
    }
    wall.shape().visit(Candidates {
        bodies: (pos, rad),
        skin,
        out,
    });
}

/// [`wall_candidates`] of one shape.
///
/// An unbounded shape (a plane) has nearly every body as a candidate when it is a face of
/// the slab and few otherwise, and a branch would be mispredicted at the edge of every run:
/// every body is tested and stored, and the count advances only for a candidate. A bounded
/// shape has few candidates, and its cheap far test ([`WallGeometry::certainly_beyond`])
/// rejects most bodies before the closer test.
#[inline(always)]
fn candidates_of<S: WallGeometry>(
    shape: &S,
    (pos, rad): (&[DVec3], &[f64]),
    skin: f64,
    out: &mut Vec<u32>,
) {
    let n = pos.len();
    let before = out.len();
    if shape.is_unbounded() {
        out.resize(before + n, 0);
        let slots = &mut out[before..];
        let mut count = 0;
        for i in 0..n {
            let (_, dist) = shape.closest_point(pos[i]);
            slots[count] = i as u32;
            count += usize::from((dist < rad[i] + skin) & (dist > -rad[i]));
        }
        out.truncate(before + count);
    } else {
        for i in 0..n {
            let reach = rad[i] + skin;
            if !shape.certainly_beyond(pos[i], reach) && shape.comes_within(pos[i], reach) {
                out.push(i as u32);
            }
        }
    }
}
