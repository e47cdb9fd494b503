//! Built-in sweep files that users can print, edit and run.

/// The programme of Fan et al. (2023), 44 cases: the angle series (α ∈ {15, 30, 55, 75,
/// 90}° × D ∈ {18, 30, 45, 60} mm, centred) and the eccentric series (flat bottom, s ∈
/// {0, 6, …, 30} mm × the same D).
pub const FAN2023_SWEEP: &str = include_str!("sweeps/fan2023.toml");

/// Sensitivity series around the paper's base case, 12 cases: wall friction 0.01, and slab
/// thicknesses 1.1 d and 1.5 d, each across the four outlet widths.
pub const FAN2023_SENSITIVITY_SWEEP: &str = include_str!("sweeps/fan2023-sensitivity.toml");

/// The reduced preset behind `--quick`: 600 spheres in a 60 mm × 150 mm hopper, 6 cases.
pub const FAN2023_QUICK_SWEEP: &str = include_str!("sweeps/fan2023-quick.toml");

/// Names accepted by [`builtin_sweep`].
pub const BUILTIN_SWEEP_NAMES: &[&str] = &["fan2023", "fan2023-sensitivity", "fan2023-quick"];

/// The text of a built-in sweep, by name (`fan2023`, `fan2023-sensitivity`, `fan2023-quick`).
pub fn builtin_sweep(name: &str) -> Option<&'static str> {
    match name {
        "fan2023" => Some(FAN2023_SWEEP),
        "fan2023-sensitivity" => Some(FAN2023_SENSITIVITY_SWEEP),
        "fan2023-quick" | "quick" => Some(FAN2023_QUICK_SWEEP),
        _ => None,
    }
}
