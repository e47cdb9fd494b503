//! Line and point plots with error bars, rendered to PNG or SVG from a plain [`Figure`].

use std::path::{Path, PathBuf};

use plotters::backend::{BitMapBackend, DrawingBackend, SVGBackend};
use plotters::chart::{ChartBuilder, SeriesLabelPosition};
use plotters::coord::Shift;
use plotters::drawing::{DrawingArea, IntoDrawingArea};
use plotters::element::{Circle, EmptyElement, PathElement, Rectangle};
use plotters::style::{Color, IntoFont, RGBColor, BLACK, WHITE};

use super::font::{ensure_font, FONT_FAMILY};
use super::image::{check_size, RgbImage};
use super::{write_atomic, OutputError};

/// Colours given to series in order when they do not name one (the "Tableau 10" palette,
/// chosen because its neighbours stay distinguishable for common colour blindness).
pub const PALETTE: [[u8; 3]; 10] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [127, 127, 127],
    [188, 189, 34],
    [23, 190, 207],
];

/// Colour of shaded x ranges; light enough that series drawn over it stay legible.
const SHADE: [u8; 3] = [255, 221, 153];

/// An axis: what is plotted, in which unit, over which range.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// Quantity name, e.g. "W" or "x*".
    pub label: String,
    /// Unit written in brackets after the label, e.g. "kg/s"; "-" for dimensionless, empty
    /// for none.
    pub unit: String,
    /// Fixed range (start < end) in the axis unit; `None` fits the data with a 5 % margin.
    pub range: Option<(f64, f64)>,
}

impl Axis {
    /// An automatically ranged axis.
    pub fn new(label: impl Into<String>, unit: impl Into<String>) -> Self {
        Self {
            label: label.into(),
            unit: unit.into(),
            range: None,
        }
    }

    /// The same axis with a fixed range.
    pub fn with_range(mut self, start: f64, end: f64) -> Self {
        self.range = Some((start, end));
        self
    }

    /// The axis caption, "label [unit]".
    pub fn caption(&self) -> String {
        if self.unit.is_empty() {
            self.label.clone()
        } else {
            format!("{} [{}]", self.label, self.unit)
        }
    }
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeriesStyle {
    /// Points joined by straight segments.
    Line,
    /// Filled circular markers.
    Points,
    /// Both.
    LineAndPoints,
}

/// One data series; `x`, `y` and `y_error` are in the units of their axes.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend entry; an empty label keeps the series out of the legend.
    pub label: String,
    /// Abscissae.
    pub x: Vec<f64>,
    /// Ordinates, as many as `x`.
    pub y: Vec<f64>,
    /// Symmetric error bar half-heights, as many as `y`.
    pub y_error: Option<Vec<f64>>,
    /// Lines, markers or both.
    pub style: SeriesStyle,
    /// sRGB colour; `None` takes the next palette colour.
    pub color: Option<[u8; 3]>,
}

impl Series {
    /// A line series.
    pub fn line(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self {
            label: label.into(),
            x,
            y,
            y_error: None,
            style: SeriesStyle::Line,
            color: None,
        }
    }

    /// A series of markers.
    pub fn points(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self {
            style: SeriesStyle::Points,
            ..Self::line(label, x, y)
        }
    }

    /// The same series with symmetric error bars.
    pub fn with_y_error(mut self, y_error: Vec<f64>) -> Self {
        self.y_error = Some(y_error);
        self
    }

    /// The same series in a fixed colour.
    pub fn with_color(mut self, color: [u8; 3]) -> Self {
        self.color = Some(color);
        self
    }
}

/// A shaded band over an x interval, e.g. the steady discharge window.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadedRange {
    /// Legend entry; empty for none.
    pub label: String,
    /// Start of the band, in x-axis units.
    pub start: f64,
    /// End of the band, in x-axis units.
    pub end: f64,
}

/// Everything needed to draw one plot.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Title above the plot; empty for none.
    pub title: String,
    /// Horizontal axis.
    pub x_axis: Axis,
    /// Vertical axis.
    pub y_axis: Axis,
    /// Series, drawn in order over the shaded bands.
    pub series: Vec<Series>,
    /// Bands shaded behind the series.
    pub shaded_x_ranges: Vec<ShadedRange>,
}

impl Figure {
    /// A figure without data.
    pub fn new(title: impl Into<String>, x_axis: Axis, y_axis: Axis) -> Self {
        Self {
            title: title.into(),
            x_axis,
            y_axis,
            series: Vec::new(),
            shaded_x_ranges: Vec::new(),
        }
    }

    /// The same figure with one more series.
    pub fn with_series(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// The same figure with a shaded band from `start` to `end` (x-axis units).
    pub fn with_shaded_x_range(mut self, label: impl Into<String>, start: f64, end: f64) -> Self {
        self.shaded_x_ranges.push(ShadedRange {
            label: label.into(),
            start,
            end,
        });
        self
    }

    /// Checks lengths and fixed ranges, so that drawing cannot fail on the data.
    fn validate(&self) -> Result<(), String> {
        for series in &self.series {
            if series.x.len() != series.y.len() {
                return Err(format!(
                    "series '{}' has {} x values and {} y values",
                    series.label,
                    series.x.len(),
                    series.y.len()
                ));
            }
            if let Some(error) = &series.y_error {
                if error.len() != series.y.len() {
                    return Err(format!(
                        "series '{}' has {} y values and {} error bars",
                        series.label,
                        series.y.len(),
                        error.len()
                    ));
                }
            }
        }
        for axis in [&self.x_axis, &self.y_axis] {
            if let Some((start, end)) = axis.range {
                if !(start.is_finite() && end.is_finite() && start < end) {
                    return Err(format!(
                        "axis '{}' range {start}..{end} is not an increasing finite interval",
                        axis.label
                    ));
                }
            }
        }
        Ok(())
    }

    /// The x range to draw: fixed, or fitted to the data and bands.
    fn x_range(&self) -> (f64, f64) {
        self.x_axis.range.unwrap_or_else(|| {
            let data = self.series.iter().flat_map(|s| s.x.iter().copied());
            let bands = self
                .shaded_x_ranges
                .iter()
                .flat_map(|band| [band.start, band.end]);
            padded_range(data.chain(bands))
        })
    }

    /// The y range to draw: fixed, or fitted to the data including error bars.
    fn y_range(&self) -> (f64, f64) {
        self.y_axis.range.unwrap_or_else(|| {
            padded_range(self.series.iter().flat_map(|series| {
                series.y.iter().enumerate().flat_map(move |(i, &y)| {
                    let error = series.y_error.as_ref().map_or(0.0, |e| e[i].abs());
                    [y - error, y + error]
                })
            }))
        })
    }
}

/// The finite extent of `values` widened by 5 % each side; a single value gets a band around
/// it and no value at all gives 0..1, so an empty plot still has axes.
fn padded_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (low, high) = values
        .filter(|value| value.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(low, high), v| {
            (low.min(v), high.max(v))
        });
    if low > high {
        return (0.0, 1.0);
    }
    let span = high - low;
    let span = if span > 0.0 {
        span
    } else if low != 0.0 {
        0.2 * low.abs()
    } else {
        1.0
    };
    (low - 0.05 * span, high + 0.05 * span)
}

/// Renders `figure` into memory at `width`×`height` px.
///
/// Errors carry an empty path, since no file is involved.
pub fn render_plot(figure: &Figure, width: u32, height: u32) -> Result<RgbImage, OutputError> {
    let mut image = RgbImage::white(width, height)?;
    ensure_font()?;
    figure
        .validate()
        .map_err(|reason| OutputError::invalid(Path::new(""), reason))?;
    {
        let root =
            BitMapBackend::with_buffer(image.bytes_mut(), (width, height)).into_drawing_area();
        draw_figure(&root, figure, height)
            .map_err(|reason| OutputError::drawing(Path::new(""), reason))?;
    }
    Ok(image)
}

/// Writes `figure` as a `width`×`height` px PNG at `path` atomically.
pub fn plot_png(
    figure: &Figure,
    path: impl AsRef<Path>,
    width: u32,
    height: u32,
) -> Result<(), OutputError> {
    let path = path.as_ref();
    let image = render_plot(figure, width, height).map_err(|e| e.for_path(path))?;
    image.write_png(path)
}

/// Writes `figure` as a `width`×`height` px SVG at `path` atomically.
///
/// Text is stored as SVG text in the "sans-serif" family, so it stays selectable.
pub fn plot_svg(
    figure: &Figure,
    path: impl AsRef<Path>,
    width: u32,
    height: u32,
) -> Result<(), OutputError> {
    let path = path.as_ref();
    check_size(width, height).map_err(|e| e.for_path(path))?;
    ensure_font().map_err(|e| e.for_path(path))?;
    figure
        .validate()
        .map_err(|reason| OutputError::invalid(path, reason))?;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        draw_figure(&root, figure, height).map_err(|reason| OutputError::Drawing {
            path: PathBuf::from(path),
            reason,
        })?;
    }
    write_atomic(path, svg.as_bytes())
}

/// The corner of the plot whose quarter-sized box (35 % of each axis) holds the fewest data
/// points, in the order upper right, upper left, lower right, lower left among equals: where
/// the legend hides the least.
fn legend_corner(
    figure: &Figure,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> SeriesLabelPosition {
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let box_share = 0.35;
    let crowd = |right: bool, upper: bool| {
        figure
            .series
            .iter()
            .flat_map(|s| s.x.iter().zip(&s.y))
            .filter(|(x, y)| {
                let (u, v) = ((**x - x0) / (x1 - x0), (**y - y0) / (y1 - y0));
                let across = if right {
                    u >= 1.0 - box_share
                } else {
                    u <= box_share
                };
                let along = if upper {
                    v >= 1.0 - box_share
                } else {
                    v <= box_share
                };
                across && along
            })
            .count()
    };
    let mut best = (SeriesLabelPosition::UpperRight, usize::MAX);
    for (corner, right, upper) in corners {
        let n = crowd(right, upper);
        if n < best.1 {
            best = (corner, n);
        }
    }
    best.0
}

/// Draws the whole figure on `root`; text sizes follow the image height.
fn draw_figure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    figure: &Figure,
    height: u32,
) -> Result<(), String> {
    let text = |e: &dyn std::fmt::Display| e.to_string();
    root.fill(&WHITE).map_err(|e| text(&e))?;
    // 600 px is the reference height at which the base sizes look right.
    let scale = (f64::from(height) / 600.0).clamp(0.8, 4.0);
    // Text below 8 px is unreadable; lines and markers only need to stay visible.
    let size = |base: f64| (base * scale).round().max(8.0) as u32;
    let pixels = |base: f64| (base * scale).round().max(1.0) as u32;

    let (x_start, x_end) = figure.x_range();
    let (y_start, y_end) = figure.y_range();
    let mut builder = ChartBuilder::on(root);
    builder
        .margin(pixels(12.0))
        .x_label_area_size(pixels(50.0))
        .y_label_area_size(pixels(75.0));
    if !figure.title.is_empty() {
        builder.caption(&figure.title, (FONT_FAMILY, size(22.0)).into_font());
    }
    let mut chart = builder
        .build_cartesian_2d(x_start..x_end, y_start..y_end)
        .map_err(|e| text(&e))?;
    chart
        .configure_mesh()
        .x_desc(figure.x_axis.caption())
        .y_desc(figure.y_axis.caption())
        .label_style((FONT_FAMILY, size(14.0)).into_font())
        .axis_desc_style((FONT_FAMILY, size(16.0)).into_font())
        .light_line_style(RGBColor(235, 235, 235))
        .max_light_lines(4)
        .draw()
        .map_err(|e| text(&e))?;

    let shade = RGBColor(SHADE[0], SHADE[1], SHADE[2]);
    let mut has_legend = false;
    for band in &figure.shaded_x_ranges {
        if !(band.start.is_finite() && band.end.is_finite()) {
            continue;
        }
        let rectangle = Rectangle::new([(band.start, y_start), (band.end, y_end)], shade.filled());
        let drawn = chart
            .draw_series(std::iter::once(rectangle))
            .map_err(|e| text(&e))?;
        if !band.label.is_empty() {
            has_legend = true;
            let legend_size = pixels(10.0) as i32;
            drawn.label(band.label.clone()).legend(move |(x, y)| {
                Rectangle::new(
                    [
                        (x, y - legend_size / 2),
                        (x + 2 * legend_size, y + legend_size / 2),
                    ],
                    shade.filled(),
                )
            });
        }
    }

    let line_width = pixels(2.0);
    let marker = pixels(4.0);
    for (index, series) in figure.series.iter().enumerate() {
        let [r, g, b] = series.color.unwrap_or(PALETTE[index % PALETTE.len()]);
        let color = RGBColor(r, g, b);
        let finite: Vec<(usize, (f64, f64))> = series
            .x
            .iter()
            .zip(&series.y)
            .map(|(&x, &y)| (x, y))
            .enumerate()
            .filter(|(_, (x, y))| x.is_finite() && y.is_finite())
            .collect();
        let draws_line = series.style != SeriesStyle::Points;
        let draws_points = series.style != SeriesStyle::Line;
        if let Some(errors) = &series.y_error {
            let style = color.stroke_width(pixels(1.5));
            let cap = marker as i32;
            for &(i, (x, y)) in &finite {
                let error = errors[i].abs();
                if !error.is_finite() || error == 0.0 {
                    continue;
                }
                // The bar is in data coordinates; the caps are fixed-width pixel segments
                // anchored at the bar's ends.
                let bar = PathElement::new(vec![(x, y - error), (x, y + error)], style);
                let low_cap = EmptyElement::at((x, y - error))
                    + PathElement::new(vec![(-cap, 0), (cap, 0)], style);
                let high_cap = EmptyElement::at((x, y + error))
                    + PathElement::new(vec![(-cap, 0), (cap, 0)], style);
                chart
                    .draw_series(std::iter::once(bar))
                    .map_err(|e| text(&e))?;
                chart
                    .draw_series([low_cap, high_cap])
                    .map_err(|e| text(&e))?;
            }
        }
        let points: Vec<(f64, f64)> = finite.iter().map(|&(_, point)| point).collect();
        // The legend is attached to whichever element is drawn last, once per series.
        let mut drawn = None;
        if draws_line {
            drawn = Some(
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        points.clone(),
                        color.stroke_width(line_width),
                    )))
                    .map_err(|e| text(&e))?,
            );
        }
        if draws_points {
            drawn = Some(
                chart
                    .draw_series(
                        points
                            .iter()
                            .map(|&point| Circle::new(point, marker, color.filled())),
                    )
                    .map_err(|e| text(&e))?,
            );
        }
        if let (Some(drawn), false) = (drawn, series.label.is_empty()) {
            has_legend = true;
            let legend_length = pixels(20.0) as i32;
            let radius = marker as i32;
            // The legend shows what the series draws: a line, a marker, or a line through one.
            drawn.label(series.label.clone()).legend(move |(x, y)| {
                let ends = if draws_line {
                    vec![(x, y), (x + legend_length, y)]
                } else {
                    Vec::new()
                };
                let (size, fill) = if draws_points {
                    (radius, color.filled())
                } else {
                    (0, color.mix(0.0).filled())
                };
                EmptyElement::at((0, 0))
                    + PathElement::new(ends, color.stroke_width(line_width))
                    + Circle::new((x + legend_length / 2, y), size, fill)
            });
        }
    }

    if has_legend {
        chart
            .configure_series_labels()
            .position(legend_corner(figure, (x_start, x_end), (y_start, y_end)))
            .label_font((FONT_FAMILY, size(14.0)).into_font())
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| text(&e))?;
    }
    root.present().map_err(|e| text(&e))?;
    Ok(())
}
