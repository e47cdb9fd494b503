//! Behaviour of the plot writers: valid PNG/SVG files, data and bands drawn where expected,
//! text rendered with the embedded font, bad specifications refused.

use files::{
    area_fraction_profile_figure, discharge_rate_figure, plot_png, plot_svg, render_plot,
    velocity_profile_figure, Axis, Figure, FittedCurve, OutputError, Profile, RgbImage, Series,
};

/// The eight bytes every PNG file starts with (PNG specification §5.2).
const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

/// Width and height from the IHDR chunk, which must come first after the signature.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], &PNG_SIGNATURE, "PNG signature");
    assert_eq!(&bytes[12..16], b"IHDR", "IHDR is the first chunk");
    let word =
        |at: usize| u32::from_be_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    (word(16), word(20))
}

/// A rise–plateau–fall discharge history, W in kg/s sampled every 0.02 s.
fn discharge_history() -> (Vec<f64>, Vec<f64>) {
    let times: Vec<f64> = (0..100).map(|i| 0.02 * i as f64).collect();
    let rates = times
        .iter()
        .map(|&t| 0.05 * (t / 0.2).min(1.0) * ((2.0 - t) / 0.3).clamp(0.0, 1.0))
        .collect();
    (times, rates)
}

/// Columns of row `y` whose colour is exactly `colour`.
fn columns_with(image: &RgbImage, y: u32, colour: [u8; 3]) -> Vec<u32> {
    (0..image.width())
        .filter(|&x| image.pixel(x, y) == Some(colour))
        .collect()
}

/// Counts dark pixels (text and axes are black; grid lines are light grey) in rows `rows`
/// of the middle 40 % of the columns, where a centred title is and tick labels are not.
fn dark_pixels(image: &RgbImage, rows: std::ops::Range<u32>) -> usize {
    let columns = image.width() * 3 / 10..image.width() * 7 / 10;
    rows.flat_map(|y| columns.clone().map(move |x| (x, y)))
        .filter(|&(x, y)| {
            image
                .pixel(x, y)
                .is_some_and(|p| p.iter().all(|&channel| channel < 100))
        })
        .count()
}

/// A figure with fixed unit ranges and nothing else, to place things at known fractions.
fn unit_figure(title: &str) -> Figure {
    Figure::new(
        title,
        Axis::new("x", "m").with_range(0.0, 1.0),
        Axis::new("y", "m").with_range(0.0, 1.0),
    )
}

#[test]
fn png_plot_is_a_png_of_the_requested_size() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("discharge.png");
    let (times, rates) = discharge_history();
    let figure = discharge_rate_figure(&times, &rates, Some((0.3, 1.6)), Some(0.05));
    plot_png(&figure, &path, 800, 600).expect("plot");
    let bytes = std::fs::read(&path).expect("read back");
    assert_eq!(png_size(&bytes), (800, 600));
    // A blank 800×600 PNG compresses to well under 5 kB; axes, text and data take more.
    assert!(bytes.len() > 5_000, "only {} bytes", bytes.len());
    let names: Vec<_> = std::fs::read_dir(directory.path())
        .expect("dir")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("discharge.png")]);
}

#[test]
fn svg_plot_holds_title_axis_captions_and_legend_entries() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("discharge.svg");
    let (times, rates) = discharge_history();
    let figure = discharge_rate_figure(&times, &rates, Some((0.3, 1.6)), Some(0.05));
    plot_svg(&figure, &path, 800, 600).expect("plot");
    let svg = std::fs::read_to_string(&path).expect("read back");
    assert!(svg.trim_start().starts_with("<svg"), "SVG root element");
    assert!(svg.trim_end().ends_with("</svg>"), "SVG is complete");
    for text in [
        "Discharge rate",
        "t [s]",
        "W [kg/s]",
        "steady window",
        "W(t)",
    ] {
        assert!(svg.contains(text), "missing {text:?}");
    }
}

#[test]
fn shaded_band_covers_its_x_interval_and_moves_with_it() {
    let band_colour_and_columns = |start: f64, end: f64| {
        let figure = unit_figure("").with_shaded_x_range("", start, end);
        let image = render_plot(&figure, 600, 400).expect("render");
        // The band spans the whole plot height, so the middle row crosses it.
        let row = image.height() / 2;
        let centre = ((start + end) / 2.0 * 0.8 + 0.15) * f64::from(image.width());
        let colour = image.pixel(centre as u32, row).expect("inside");
        (colour, columns_with(&image, row, colour), image.width())
    };
    let (colour, middle, width) = band_colour_and_columns(0.4, 0.6);
    // The band is a tint, not white and not a grey grid line.
    assert!(colour != [255, 255, 255] && !(colour[0] == colour[1] && colour[1] == colour[2]));
    // 20 % of a plot area that takes 75–95 % of the image width (labels take the rest).
    let fraction = middle.len() as f64 / f64::from(width);
    assert!((0.15..=0.19).contains(&fraction), "band covers {fraction}");
    let (_, left, _) = band_colour_and_columns(0.1, 0.3);
    let mean =
        |columns: &[u32]| columns.iter().map(|&c| f64::from(c)).sum::<f64>() / columns.len() as f64;
    // Moving the interval by 0.3 of the axis moves the band by 0.3 of the plot width.
    let shift = (mean(&middle) - mean(&left)) / f64::from(width);
    assert!((0.22..=0.29).contains(&shift), "band moved by {shift}");
}

#[test]
fn a_higher_line_is_drawn_higher_in_its_colour() {
    let red = [200, 0, 0];
    let line_row = |level: f64| {
        let figure = unit_figure("")
            .with_series(Series::line("", vec![0.0, 1.0], vec![level, level]).with_color(red));
        let image = render_plot(&figure, 600, 400).expect("render");
        let column = image.width() / 2;
        let rows: Vec<u32> = (0..image.height())
            .filter(|&y| image.pixel(column, y) == Some(red))
            .collect();
        assert!(
            !rows.is_empty(),
            "line at {level} not found in the middle column"
        );
        rows.iter().sum::<u32>() as f64 / rows.len() as f64
    };
    let low = line_row(0.2);
    let high = line_row(0.8);
    // Rows count downwards: the higher value sits at a smaller row, by roughly 0.6 of the
    // plot height (at least half the 400 px image minus label areas).
    assert!(low - high > 150.0, "rows {low} and {high}");
}

#[test]
fn title_text_is_rendered_with_the_embedded_font() {
    let titled = render_plot(&unit_figure("Outlet velocity profile"), 600, 400).expect("render");
    let untitled = render_plot(&unit_figure(""), 600, 400).expect("render");
    // The caption sits in the top band; without it that band holds only the light grid.
    let band = 0..40;
    assert!(dark_pixels(&titled, band.clone()) > 100, "no title glyphs");
    assert_eq!(dark_pixels(&untitled, band), 0);
}

#[test]
fn profile_figures_combine_points_error_bars_and_fit() {
    let x_star: Vec<f64> = (0..19).map(|i| -0.9 + 0.1 * i as f64).collect();
    let velocity: Vec<f64> = x_star
        .iter()
        .map(|x| 0.4 * (1.0 - x * x).powf(0.5))
        .collect();
    let error = vec![0.01; x_star.len()];
    let profile = Profile {
        x_star: &x_star,
        value: &velocity,
        error: Some(&error),
    };
    let fit = FittedCurve::sampled("fit a = 0.5", (-1.0, 1.0), 101, |x| {
        0.4 * (1.0 - x * x).max(0.0).powf(0.5)
    });
    let figure = velocity_profile_figure(&profile, Some(&fit));
    assert_eq!(figure.series.len(), 2);
    assert_eq!(figure.series[0].y_error.as_deref(), Some(error.as_slice()));
    assert_eq!(figure.y_axis.caption(), "v [m/s]");
    let directory = tempfile::tempdir().expect("temporary directory");
    let png = directory.path().join("v.png");
    plot_png(&figure, &png, 640, 480).expect("plot");
    assert_eq!(png_size(&std::fs::read(&png).expect("read")), (640, 480));

    let phi = area_fraction_profile_figure(&profile, None);
    assert_eq!(phi.series.len(), 1);
    assert_eq!(phi.y_axis.caption(), "φ [-]");
    let svg = directory.path().join("phi.svg");
    plot_svg(&phi, &svg, 640, 480).expect("plot");
    assert!(std::fs::read_to_string(&svg)
        .expect("read")
        .contains("φ [-]"));
}

#[test]
fn sampled_fit_evaluates_the_curve_on_an_even_grid() {
    let fit = FittedCurve::sampled("parabola", (-1.0, 1.0), 5, |x| 1.0 - x * x);
    assert_eq!(fit.x, vec![-1.0, -0.5, 0.0, 0.5, 1.0]);
    // Each value is one subtraction and one product of exact binary fractions: exact.
    assert_eq!(fit.y, vec![0.0, 0.75, 1.0, 0.75, 0.0]);
}

#[test]
fn discharge_figure_shades_the_window_and_draws_the_steady_level_across_it() {
    let (times, rates) = discharge_history();
    let figure = discharge_rate_figure(&times, &rates, Some((0.3, 1.6)), Some(0.05));
    assert_eq!(figure.shaded_x_ranges.len(), 1);
    assert_eq!(
        (
            figure.shaded_x_ranges[0].start,
            figure.shaded_x_ranges[0].end
        ),
        (0.3, 1.6)
    );
    assert_eq!(figure.series[0].y, rates);
    assert_eq!(figure.series[1].x, vec![0.3, 1.6]);
    assert_eq!(figure.series[1].y, vec![0.05, 0.05]);
    let bare = discharge_rate_figure(&times, &rates, None, Some(0.05));
    assert!(bare.shaded_x_ranges.is_empty() && bare.series.len() == 1);
}

#[test]
fn series_of_mismatched_lengths_are_refused_without_writing() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("bad.png");
    let figure = unit_figure("bad").with_series(Series::line("", vec![0.0, 1.0], vec![0.5]));
    let error = plot_png(&figure, &path, 400, 300).expect_err("length mismatch");
    match error {
        OutputError::InvalidData { path: reported, .. } => assert_eq!(reported, path),
        other => panic!("unexpected error {other:?}"),
    }
    assert_eq!(std::fs::read_dir(directory.path()).expect("dir").count(), 0);
}

#[test]
fn empty_image_sizes_and_reversed_ranges_are_refused() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("bad.svg");
    let figure = unit_figure("");
    assert!(matches!(
        plot_svg(&figure, &path, 0, 300),
        Err(OutputError::InvalidData { .. })
    ));
    let reversed = Figure::new(
        "",
        Axis::new("x", "m").with_range(1.0, 0.0),
        Axis::new("y", "m"),
    );
    assert!(matches!(
        plot_svg(&reversed, &path, 400, 300),
        Err(OutputError::InvalidData { .. })
    ));
    assert!(!path.exists());
}

#[test]
fn non_finite_points_are_skipped_rather_than_breaking_the_plot() {
    let figure =
        Figure::new("", Axis::new("x", "m"), Axis::new("y", "m")).with_series(Series::points(
            "",
            vec![0.0, 1.0, f64::NAN, 2.0],
            vec![1.0, f64::INFINITY, 3.0, 2.0],
        ));
    // The automatic range ignores the non-finite values instead of becoming NaN.
    let image = render_plot(&figure, 400, 300).expect("render");
    assert_eq!((image.width(), image.height()), (400, 300));
}

#[test]
fn the_legend_shows_a_marker_for_points_and_a_line_for_lines() {
    // Three labelled points and a labelled line: the SVG holds the three data circles and one
    // legend circle of non-zero radius (the points' entry), and no visible circle for the
    // line's entry, whose glyph is a line as before.
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("legend.svg");
    let figure = unit_figure("legend")
        .with_series(Series::points(
            "dots",
            vec![0.2, 0.5, 0.8],
            vec![0.3, 0.6, 0.4],
        ))
        .with_series(Series::line("curve", vec![0.0, 1.0], vec![0.1, 0.9]));
    plot_svg(&figure, &path, 800, 600).expect("plot");
    let svg = std::fs::read_to_string(&path).expect("read back");
    let visible = svg
        .split("<circle")
        .skip(1)
        .filter(|c| !c.contains("r=\"0\""))
        .count();
    assert_eq!(visible, 4, "{svg}");
}

#[test]
fn the_legend_moves_to_the_emptiest_corner() {
    // Points rising to the upper right: the legend's entry is drawn in the left half, where
    // the data leave room; points falling to the lower right keep it at the upper right.
    let directory = tempfile::tempdir().expect("temporary directory");
    let legend_x = |y: Vec<f64>| {
        let path = directory.path().join("corner.svg");
        let figure =
            unit_figure("corner").with_series(Series::points("dots", vec![0.1, 0.5, 0.9, 1.0], y));
        plot_svg(&figure, &path, 800, 600).expect("plot");
        let svg = std::fs::read_to_string(&path).expect("read back");
        let at = svg.find(">\ndots\n<").expect("the legend entry");
        let tag = &svg[svg[..at].rfind("<text").expect("its text element")..at];
        let x = tag
            .split("x=\"")
            .nth(1)
            .expect("an x")
            .split('"')
            .next()
            .expect("a value");
        x.parse::<f64>().expect("a number")
    };
    assert!(legend_x(vec![0.1, 0.5, 0.9, 1.0]) < 400.0);
    assert!(legend_x(vec![1.0, 0.5, 0.1, 0.0]) > 400.0);
}
