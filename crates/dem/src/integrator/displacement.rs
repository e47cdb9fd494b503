//! How far the bodies have moved since the last neighbour-list build: the largest
//! displacement and the diagonal of the box of all displacements (docs/physics.md §6.3).

use super::*;

/// Largest |x − x_ref|² [m²] and a probe that is zero unless some displacement is not
/// finite, in [`LANES`] independent accumulators, as [`kick_drift_per_body`] takes them;
/// also the measure a [`kick_drift_flat_tracked`] pass without `measure` left out.
pub(crate) fn largest_displacement(position: &[DVec3], reference: &[DVec3]) -> (f64, f64) {
    let mut acc = [Reduction::default(); LANES];
    let chunks = position
        .chunks_exact(LANES)
        .zip(reference.chunks_exact(LANES));
    let rest = position.len() - position.len() % LANES;
    for (x, r) in chunks {
        for (lane, a) in acc.iter_mut().enumerate() {
            a.see_displacement((x[lane] - r[lane]).length_squared());
        }
    }
    for (x, r) in position[rest..].iter().zip(&reference[rest..]) {
        acc[0].see_displacement((*x - *r).length_squared());
    }
    let all = Reduction::merge_lanes(&acc);
    (all.max_disp2, all.position_probe)
}

/// The length [m] of the diagonal of the smallest axis-aligned box that holds every
/// displacement x − x_ref: twice the largest distance of a displacement from the box's
/// centre, at most. Minima and maxima do not depend on the order they are taken in, so the
/// result is the same however the bodies are grouped. Non-finite positions are reported by
/// the kick and drift before this is asked for.
pub(crate) fn displacement_box_diagonal(position: &[DVec3], reference: &[DVec3]) -> f64 {
    if position.is_empty() {
        return 0.0;
    }
    let x: &[f64] = bytemuck::cast_slice(position);
    let r: &[f64] = bytemuck::cast_slice(&reference[..position.len()]);
    // Over the flat arrays, WIDTH × 3 numbers at a time, each lane with its own extremes, so
    // that no lane waits on another's comparison; lane l always holds component l mod 3.
    const LANES3: usize = 3 * WIDTH;
    let (mut lo, mut hi) = ([f64::INFINITY; LANES3], [f64::NEG_INFINITY; LANES3]);
    for (xc, rc) in x.chunks_exact(LANES3).zip(r.chunks_exact(LANES3)) {
        for l in 0..LANES3 {
            let d = xc[l] - rc[l];
            lo[l] = if d < lo[l] { d } else { lo[l] };
            hi[l] = if d > hi[l] { d } else { hi[l] };
        }
    }
    let whole = x.len() - x.len() % LANES3;
    for (q, (a, b)) in x[whole..].iter().zip(&r[whole..]).enumerate() {
        let d = a - b;
        // `whole` is a multiple of 3, so number q of the rest is component q mod 3.
        let l = q % 3;
        lo[l] = if d < lo[l] { d } else { lo[l] };
        hi[l] = if d > hi[l] { d } else { hi[l] };
    }
    let mut extent = [0.0; 3];
    for (c, e) in extent.iter_mut().enumerate() {
        let low = lo
            .iter()
            .skip(c)
            .step_by(3)
            .fold(f64::INFINITY, |a, &b| a.min(b));
        let high = hi
            .iter()
            .skip(c)
            .step_by(3)
            .fold(f64::NEG_INFINITY, |a, &b| a.max(b));
        *e = high - low;
    }
    DVec3::from(extent).length()
}
