//! The viridis colour map: perceptually uniform, readable in grey scale and by colour-blind
//! readers.
//!
//! Viridis was designed by van der Walt, Smith and Firing for matplotlib (2015, released to
//! the public domain). It is reproduced here from eleven evenly spaced reference colours with
//! linear interpolation in sRGB, which keeps the map's monotonic lightness (tested) and is
//! visually indistinguishable from the full 256-entry table at frame scale.

/// Reference colours at t = 0, 0.1, …, 1 (sRGB, 8 bits per channel).
const VIRIDIS: [[u8; 3]; 11] = [
    [68, 1, 84],
    [72, 37, 118],
    [65, 68, 135],
    [53, 96, 141],
    [42, 120, 142],
    [33, 144, 140],
    [34, 168, 132],
    [67, 191, 113],
    [122, 209, 81],
    [187, 223, 39],
    [253, 231, 37],
];

/// The viridis colour at `t` in [0, 1] (dark purple at 0, yellow at 1).
///
/// Values outside [0, 1] are clamped, so out-of-range speeds saturate instead of failing; NaN
/// maps to the low end.
pub fn viridis(t: f64) -> [u8; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let position = t * (VIRIDIS.len() - 1) as f64;
    // `position` is in [0, 10]; the lower index stops at 9 so that t = 1 interpolates fully
    // towards the last colour.
    let lower = (position.floor() as usize).min(VIRIDIS.len() - 2);
    let fraction = position - lower as f64;
    let (from, to) = (VIRIDIS[lower], VIRIDIS[lower + 1]);
    let mut colour = [0u8; 3];
    for channel in 0..3 {
        let value = f64::from(from[channel])
            + fraction * (f64::from(to[channel]) - f64::from(from[channel]));
        colour[channel] = value.round() as u8;
    }
    colour
}
