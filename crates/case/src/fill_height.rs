//! The height to which a container holds a volume, shared by the container kinds that can
//! say how much they hold below a height.

/// Height [m] below which a container of height `height` [m] whose volume below z is
/// `volume_below(z)` [m³] holds `volume` [m³], or `None` if it cannot. `volume_below` is
/// continuous and increasing: bisection to 2^-60 of the height.
pub(crate) fn height_holding(
    height: f64,
    volume: f64,
    volume_below: impl Fn(f64) -> f64,
) -> Option<f64> {
    if volume > volume_below(height) {
        return None;
    }
    let (mut low, mut high) = (0.0, height);
    for _ in 0..60 {
        let mid = 0.5 * (low + high);
        if volume_below(mid) < volume {
            low = mid;
        } else {
            high = mid;
        }
    }
    Some(high)
}
