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
use crate::contact::sjkr::{pair_intersection_area, sjkr_force, wall_intersection_area};
use crate::contact::Cohesion;
use crate::material::PairCoefficients;

/// The energy density k_c [J/m³] of a pair with the simplified JKR, else zero.
#[inline(always)]
fn density(c: &PairCoefficients) -> f64 {
    match c.cohesion {
        Cohesion::SimplifiedJkr { energy_density } => energy_density,
        _ => 0.0,
    }
}

/// Subtracts k_c A n from the force of each slot `0..len` of a resolved batch whose pair
/// has the simplified JKR: `shared` is every slot's pair where they share one (one
/// material), else `coefficients(m)` gives slot m's; `geometry(batch, m)` gives the slot's
/// area A [m²] and unit normal n (towards i).
///
/// Over every slot of the batch with no branch, so that it vectorises: a slot of another law
/// has k_c = 0 and keeps its force (a select, not a subtraction of zero, so its bits).
#[inline(always)]
fn attract<'a>(
    batch: &mut Batch,
    len: usize,
    (shared, coefficients): (
        Option<&PairCoefficients>,
        impl Fn(usize) -> &'a PairCoefficients,
    ),
    geometry: impl Fn(&Batch, usize) -> (f64, [f64; 3]),
) {
    let mut k_c = [0.0; BATCH];
    match shared {
        Some(c) => k_c.fill(density(c)),
        None => {
            for (m, k) in k_c.iter_mut().enumerate().take(len.min(BATCH)) {
                *k = density(coefficients(m));
            }
        }
    }
    for (m, &k) in k_c.iter().enumerate() {
        let (area, normal) = geometry(batch, m);
        let pull = sjkr_force(k, area);
        for (a, n) in normal.into_iter().enumerate() {
            let f = batch.force[a][m];
            batch.force[a][m] = if k > 0.0 { f - pull * n } else { f };
        }
    }
}

/// Subtracts the attraction from slots `0..len` of a resolved particle–particle batch, whose
/// `d` holds x_i − x_j and `dist2` its square; `shared` or `coefficients(m)` gives slot m's
/// pair ([`attract`]).
#[inline(never)]
pub(super) fn pairs<'a>(
    batch: &mut Batch,
    len: usize,
    coefficients: (
        Option<&PairCoefficients>,
        impl Fn(usize) -> &'a PairCoefficients,
    ),
) {
    attract(batch, len, coefficients, |b, m| {
        let (ri, rj) = (b.radius[0][m], b.radius[1][m]);
        let dist = b.dist2[m].sqrt();
        let inv = 1.0 / dist;
        let normal = [b.d[0][m] * inv, b.d[1][m] * inv, b.d[2][m] * inv];
        (pair_intersection_area(ri, rj, ri + rj - dist), normal)
    });
}

/// Subtracts the attraction from slots `0..len` of a resolved particle–wall batch, whose
/// `d` holds the unit normal (wall to particle) and `overlap` the overlap; `shared` or
/// `coefficients(m)` gives slot m's particle–wall pair ([`attract`]).
#[inline(never)]
pub(super) fn walls<'a>(
    batch: &mut Batch,
    len: usize,
    coefficients: (
        Option<&PairCoefficients>,
        impl Fn(usize) -> &'a PairCoefficients,
    ),
) {
    attract(batch, len, coefficients, |b, m| {
        let area = wall_intersection_area(b.radius[0][m], b.overlap[m]);
        (area, [b.d[0][m], b.d[1][m], b.d[2][m]])
    });
}
