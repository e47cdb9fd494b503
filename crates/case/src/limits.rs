//! The limits that the readers of several sections check against: the largest particle count
//! and the smallest outlet. Each reader imports them from here, so that no reader depends on
//! another.

use super::error::rounded;

/// Largest particle count accepted; a guard against typos that would exhaust memory.
pub(crate) const MAX_PARTICLE_COUNT: i64 = 10_000_000;
/// The largest coarse-graining factor κ [-] (`particles.coarse_graining`): parcels of 20
/// grains' diameters stand for 8000 grains each, far past where the validation found them
/// faithful (docs/physics.md §2.8), a bound against typing mistakes.
pub(crate) const MAX_COARSE_GRAINING: f64 = 20.0;

/// Smallest outlet width in largest particle diameters (the rule: D ≥ 3 d).
pub(crate) const MIN_OUTLET_DIAMETERS: f64 = 3.0;

/// Why an outlet of size `value` [m] is refused: narrower than [`MIN_OUTLET_DIAMETERS`]
/// largest particle diameters, `d_max` with the key that set it; `None` when it is wide
/// enough or the particles are unknown.
pub(crate) fn outlet_too_small(value: f64, d_max: Option<(f64, &str)>) -> Option<String> {
    let (d_max, source) = d_max?;
    let smallest = MIN_OUTLET_DIAMETERS * d_max;
    // The product rounds: 3 × 0.003 is 0.009000000000000001, above the 0.009 a user writes
    // for exactly three diameters. A few units in the last place decide nothing.
    (value < smallest * (1.0 - 4.0 * f64::EPSILON)).then(|| {
        format!(
            "must be ≥ {MIN_OUTLET_DIAMETERS} particle diameters ({} m), d being the largest \
             diameter, {source}",
            rounded(smallest)
        )
    })
}
