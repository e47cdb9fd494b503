//! The simplified JKR's attraction on a resolved batch (docs/physics.md §2.5): k_c times the
//! intersection area of the undeformed surfaces, along the contact normal, subtracted from
//! the batched kernel's dry force.
//!
//! It changes nothing else the kernel computes: the attraction acts through the centres
//! (no torque), and friction and rolling resistance read the elastic Hertz force, which it
//! does not change. So a batch resolved by the dry kernel and then corrected here gives the
//! one-contact pipeline's forces (`ContactLaws::resolve`, which subtracts the attraction
//! from the normal force before adding the tangential one) to a few ulps, and the dry laws'
//! batches need no cohesive code. Only contacts whose pair has the simplified JKR are
//! touched; the others keep their bits.

use super::kernel::{Batch, BATCH};
use crate::contact::sjkr::{intersection_area, sjkr_force};
use crate::contact::Cohesion;
use crate::material::PairCoefficients;

/// The energy density k_c [J/m³] of a pair with the simplified JKR, else `None`.
#[inline(always)]
fn density(c: &PairCoefficients) -> Option<f64> {
    match c.cohesion {
        Cohesion::SimplifiedJkr { energy_density } => Some(energy_density),
        _ => None,
    }
}

/// Subtracts the attraction from slots `0..len` of a resolved particle–particle batch, whose
/// `d` holds x_i − x_j and `dist2` its square; `coefficients(m)` gives slot m's pair.
#[inline(never)]
pub(super) fn pairs<'a>(
    batch: &mut Batch,
    len: usize,
    coefficients: impl Fn(usize) -> &'a PairCoefficients,
) {
    for m in 0..len.min(BATCH) {
        let Some(k) = density(coefficients(m)) else {
            continue;
        };
        let (ri, rj) = (batch.radius[0][m], batch.radius[1][m]);
        let dist = batch.dist2[m].sqrt();
        let pull = sjkr_force(k, intersection_area(ri, rj, ri + rj - dist));
        let inv = 1.0 / dist;
        for a in 0..3 {
            batch.force[a][m] -= pull * (batch.d[a][m] * inv);
        }
    }
}

/// Subtracts the attraction from slots `0..len` of a resolved particle–wall batch, whose
/// `d` holds the unit normal (wall to particle) and `overlap` the overlap;
/// `coefficients(m)` gives slot m's particle–wall pair.
#[inline(never)]
pub(super) fn walls<'a>(
    batch: &mut Batch,
    len: usize,
    coefficients: impl Fn(usize) -> &'a PairCoefficients,
) {
    for m in 0..len.min(BATCH) {
        let Some(k) = density(coefficients(m)) else {
            continue;
        };
        let area = intersection_area(batch.radius[0][m], f64::INFINITY, batch.overlap[m]);
        let pull = sjkr_force(k, area);
        for a in 0..3 {
            batch.force[a][m] -= pull * batch.d[a][m];
        }
    }
}
