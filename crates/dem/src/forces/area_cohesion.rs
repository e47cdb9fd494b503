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

/// Subtracts k_c A n from the force of each slot `0..len` of a resolved batch whose pair
/// (`coefficients(m)`) has the simplified JKR; `geometry(batch, m)` gives the slot's area A
/// [m²] and unit normal n (towards i).
#[inline(always)]
fn attract<'a>(
    batch: &mut Batch,
    len: usize,
    coefficients: impl Fn(usize) -> &'a PairCoefficients,
    geometry: impl Fn(&Batch, usize) -> (f64, [f64; 3]),
) {
    for m in 0..len.min(BATCH) {
        let Some(k) = density(coefficients(m)) else {
            continue;
        };
        let (area, normal) = geometry(batch, m);
        let pull = sjkr_force(k, area);
        for (a, n) in normal.into_iter().enumerate() {
            batch.force[a][m] -= pull * n;
        }
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
    attract(batch, len, coefficients, |b, m| {
        let (ri, rj) = (b.radius[0][m], b.radius[1][m]);
        let dist = b.dist2[m].sqrt();
        let inv = 1.0 / dist;
        let normal = [b.d[0][m] * inv, b.d[1][m] * inv, b.d[2][m] * inv];
        (intersection_area(ri, rj, ri + rj - dist), normal)
    });
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
    attract(batch, len, coefficients, |b, m| {
        let area = intersection_area(b.radius[0][m], f64::INFINITY, b.overlap[m]);
        (area, [b.d[0][m], b.d[1][m], b.d[2][m]])
    });
}
