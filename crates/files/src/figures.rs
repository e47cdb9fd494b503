//! The study's standard figures as [`Figure`] specifications: discharge rate W(t) with its
//! steady window, and the outlet profiles v(x*) and φ(x*) with their fitted curves.
//!
//! These only assemble plain data; draw them with [`super::plot_png`] or [`super::plot_svg`].
//! All fields of the returned figure are public, so a caller can retitle an axis (for
//! example to plot v/v_c instead of v) before drawing.

use super::plot::{Axis, Figure, Series};

/// Colour of measured data: dark blue, the first palette colour.
const DATA_COLOR: [u8; 3] = [31, 119, 180];
/// Colour of fits and reference levels: red, to stand apart from the data.
const FIT_COLOR: [u8; 3] = [214, 39, 40];

/// Discharge rate W(t) [kg/s] against time t [s] (paper Fig. 2a).
///
/// `steady_window` = (start, end) [s] is shaded; `steady_rate` [kg/s], the mean over that
/// window, is drawn as a level across it.
pub fn discharge_rate_figure(
    times: &[f64],
    rates: &[f64],
    steady_window: Option<(f64, f64)>,
    steady_rate: Option<f64>,
) -> Figure {
    let mut figure = Figure::new(
        "Discharge rate",
        Axis::new("t", "s"),
        Axis::new("W", "kg/s"),
    );
    if let Some((start, end)) = steady_window {
        figure = figure.with_shaded_x_range("steady window", start, end);
        if let Some(rate) = steady_rate {
            figure = figure.with_series(
                Series::line(
                    format!("steady W = {rate:.4} kg/s"),
                    vec![start, end],
                    vec![rate, rate],
                )
                .with_color(FIT_COLOR),
            );
        }
    }
    let measured = Series::line("W(t)", times.to_vec(), rates.to_vec()).with_color(DATA_COLOR);
    // The measured curve goes first so the steady level is drawn over it.
    figure.series.insert(0, measured);
    figure
}

/// A measured profile across the orifice, binned in x* = (x − x_c)/R.
#[derive(Debug, Clone, Copy)]
pub struct Profile<'a> {
    /// Bin centres x* [-].
    pub x_star: &'a [f64],
    /// Mean value per bin, in the unit of the quantity plotted.
    pub value: &'a [f64],
    /// Standard error per bin, same unit; `None` for no error bars.
    pub error: Option<&'a [f64]>,
}

/// A fitted curve sampled for drawing, e.g. v_c (1 − x*²)^a (paper Eq. 9).
#[derive(Debug, Clone, PartialEq)]
pub struct FittedCurve {
    /// Legend entry, e.g. "fit a = 0.52".
    pub label: String,
    /// Abscissae x* [-].
    pub x: Vec<f64>,
    /// Fitted values, in the unit of the profile.
    pub y: Vec<f64>,
}

impl FittedCurve {
    /// Samples `curve` at `samples` evenly spaced points from `start` to `end` (at least 2).
    pub fn sampled(
        label: impl Into<String>,
        (start, end): (f64, f64),
        samples: usize,
        curve: impl Fn(f64) -> f64,
    ) -> Self {
        let samples = samples.max(2);
        let step = (end - start) / (samples - 1) as f64;
        let x: Vec<f64> = (0..samples).map(|i| start + step * i as f64).collect();
        let y = x.iter().map(|&x| curve(x)).collect();
        Self {
            label: label.into(),
            x,
            y,
        }
    }
}

/// Vertical velocity profile v(x*) [m/s] at the orifice with an optional fit (paper Fig. 5).
pub fn velocity_profile_figure(profile: &Profile<'_>, fit: Option<&FittedCurve>) -> Figure {
    profile_figure(
        "Outlet velocity profile",
        Axis::new("v", "m/s"),
        profile,
        fit,
    )
}

/// Area fraction profile φ(x*) [-] at the orifice with an optional fit (paper Fig. 7).
pub fn area_fraction_profile_figure(profile: &Profile<'_>, fit: Option<&FittedCurve>) -> Figure {
    profile_figure(
        "Outlet area fraction profile",
        Axis::new("φ", "-"),
        profile,
        fit,
    )
}

/// Markers with error bars for the measurement, a line for the fit, x* on [−1, 1].
fn profile_figure(
    title: &str,
    y_axis: Axis,
    profile: &Profile<'_>,
    fit: Option<&FittedCurve>,
) -> Figure {
    // x* spans the orifice, −1 at one edge and 1 at the other; a small margin keeps edge bins
    // off the frame.
    let x_axis = Axis::new("x*", "-").with_range(-1.05, 1.05);
    let mut measured = Series::points("measured", profile.x_star.to_vec(), profile.value.to_vec())
        .with_color(DATA_COLOR);
    if let Some(error) = profile.error {
        measured = measured.with_y_error(error.to_vec());
    }
    let mut figure = Figure::new(title, x_axis, y_axis).with_series(measured);
    if let Some(fit) = fit {
        let curve =
            Series::line(fit.label.clone(), fit.x.clone(), fit.y.clone()).with_color(FIT_COLOR);
        figure = figure.with_series(curve);
    }
    figure
}

/// The colour of a reference that is neither measured nor fitted: grey.
const REFERENCE_COLOR: [u8; 3] = [127, 127, 127];

/// A settled silo's wall stresses against depth below its surface (docs/physics.md §7.7):
/// the normal pressure p_w [Pa] and the shear stress τ_w [Pa] of each zone of the cylinder,
/// Janssen's fitted p_w(h) where there is one, and the hydrostatic ρ_b g h that a bed without
/// wall friction would press with.
pub fn wall_pressure_figure(
    depths: &[f64],
    pressures: &[f64],
    shears: &[f64],
    janssen: Option<&FittedCurve>,
    hydrostatic: &FittedCurve,
) -> Figure {
    let mut figure = Figure::new(
        "Wall stresses of the settled bed",
        Axis::new("depth h", "m"),
        Axis::new("stress", "Pa"),
    )
    .with_series(
        Series::points("wall pressure p_w", depths.to_vec(), pressures.to_vec())
            .with_color(DATA_COLOR),
    )
    .with_series(
        Series::points("wall shear τ_w", depths.to_vec(), shears.to_vec())
            .with_color([44, 160, 44]),
    )
    .with_series(
        Series::line(
            hydrostatic.label.clone(),
            hydrostatic.x.clone(),
            hydrostatic.y.clone(),
        )
        .with_color(REFERENCE_COLOR),
    );
    if let Some(fit) = janssen {
        figure = figure.with_series(
            Series::line(fit.label.clone(), fit.x.clone(), fit.y.clone()).with_color(FIT_COLOR),
        );
    }
    figure
}
