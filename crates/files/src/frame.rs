//! PNG frames of the hopper: discs coloured by speed, wall segments, a colour bar and the
//! time.
//!
//! The view is the x–z plane of the quasi-2D slab (the thin y direction is flattened), at a
//! fixed scale in pixels per metre so that the hopper keeps its aspect ratio.

use std::path::Path;

use plotters::backend::BitMapBackend;
use plotters::drawing::IntoDrawingArea;
use plotters::element::{Circle, PathElement, Rectangle, Text};
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{Color, IntoFont, RGBColor, TextStyle, BLACK, WHITE};

use super::colormap::viridis;
use super::font::{ensure_font, FONT_FAMILY};
use super::image::{check_size, RgbImage};
use super::OutputError;

/// One particle as seen in the frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameParticle {
    /// Horizontal centre position x [m].
    pub x: f64,
    /// Vertical centre position z [m] (up).
    pub z: f64,
    /// Radius [m].
    pub radius: f64,
    /// Speed |v| [m/s], mapped to colour.
    pub speed: f64,
}

/// A wall drawn as a straight segment in the x–z plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallSegment {
    /// First end (x, z) [m].
    pub start: [f64; 2],
    /// Second end (x, z) [m].
    pub end: [f64; 2],
}

/// What part of the x–z plane to draw, at which scale, with which colour scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameViewport {
    /// Horizontal extent shown (left, right) [m]. Leave a few millimetres around walls on the
    /// boundary: drawing is clipped to this extent.
    pub x_range: (f64, f64),
    /// Vertical extent shown (bottom, top) [m].
    pub z_range: (f64, f64),
    /// Image scale [px/m].
    pub pixels_per_metre: f64,
    /// Speeds at the two ends of the colour map (low, high) [m/s]; speeds beyond saturate.
    pub speed_range: (f64, f64),
}

impl FrameViewport {
    /// A view whose drawn region is `domain_height` px tall, the width following from the
    /// aspect ratio of the ranges (for a 0.1 m × 0.4 m hopper and 1600 px, 400 px wide).
    pub fn fitted(
        x_range: (f64, f64),
        z_range: (f64, f64),
        domain_height: u32,
        speed_range: (f64, f64),
    ) -> Self {
        Self {
            x_range,
            z_range,
            pixels_per_metre: f64::from(domain_height) / (z_range.1 - z_range.0),
            speed_range,
        }
    }

    /// Where everything goes in the image; fails on empty ranges or a bad scale.
    pub fn layout(&self) -> Result<FrameLayout, OutputError> {
        let increasing =
            |(low, high): (f64, f64)| low.is_finite() && high.is_finite() && low < high;
        if !increasing(self.x_range) || !increasing(self.z_range) {
            return Err(invalid(
                "the x and z ranges must be increasing finite intervals",
            ));
        }
        if !increasing(self.speed_range) {
            return Err(invalid(
                "the speed range must be an increasing finite interval",
            ));
        }
        if !(self.pixels_per_metre.is_finite() && self.pixels_per_metre > 0.0) {
            return Err(invalid(
                "the scale must be a positive number of pixels per metre",
            ));
        }
        let to_pixels = |metres: f64| (metres * self.pixels_per_metre).round();
        let domain_width = to_pixels(self.x_range.1 - self.x_range.0);
        let domain_height = to_pixels(self.z_range.1 - self.z_range.0);
        let limit = f64::from(super::image::MAX_SIDE);
        if !(1.0..=limit).contains(&domain_width) || !(1.0..=limit).contains(&domain_height) {
            return Err(invalid(format!(
                "the drawn region would be {domain_width}×{domain_height} px"
            )));
        }
        let (domain_width, domain_height) = (domain_width as u32, domain_height as u32);
        // Text and decorations scale with the picture; 800 px is the reference height.
        let font = (18.0 * (f64::from(domain_height) / 800.0).clamp(0.75, 2.5)).round() as u32;
        let domain_left = font;
        let domain_top = 5 * font / 2;
        let colour_bar_left = domain_left + domain_width + 3 * font / 2;
        let colour_bar_width = 6 * font / 5;
        let colour_bar_top = domain_top + 2 * font;
        let colour_bar_height = (domain_height / 2).max(2 * font);
        // Tick labels ("0.25") take about 4.5 em after a short tick; one em of right margin.
        let width = colour_bar_left + colour_bar_width + font / 2 + 9 * font / 2 + font;
        let height =
            (domain_top + domain_height + font).max(colour_bar_top + colour_bar_height + font);
        check_size(width, height)?;
        Ok(FrameLayout {
            width,
            height,
            domain_left,
            domain_top,
            domain_width,
            domain_height,
            colour_bar_left,
            colour_bar_top,
            colour_bar_width,
            colour_bar_height,
            font_size: font,
            view: *self,
        })
    }
}

/// Pixel positions of the parts of a frame (columns from the left, rows from the top).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameLayout {
    /// Image width [px].
    pub width: u32,
    /// Image height [px].
    pub height: u32,
    /// Column of the drawn region's left edge [px].
    pub domain_left: u32,
    /// Row of the drawn region's top edge [px].
    pub domain_top: u32,
    /// Width of the drawn region [px].
    pub domain_width: u32,
    /// Height of the drawn region [px].
    pub domain_height: u32,
    /// Column of the colour bar's left edge [px].
    pub colour_bar_left: u32,
    /// Row of the colour bar's top edge (the high-speed end) [px].
    pub colour_bar_top: u32,
    /// Width of the colour bar [px].
    pub colour_bar_width: u32,
    /// Height of the colour bar [px].
    pub colour_bar_height: u32,
    /// Label text size [px].
    pub font_size: u32,
    view: FrameViewport,
}

impl FrameLayout {
    /// The image pixel (column, row) of the point (x, z) [m], relative to the whole image.
    pub fn pixel(&self, x: f64, z: f64) -> (i32, i32) {
        let (column, row) = self.domain_pixel(x, z);
        (
            column + self.domain_left as i32,
            row + self.domain_top as i32,
        )
    }

    /// The pixel of (x, z) [m] relative to the drawn region's top-left corner.
    fn domain_pixel(&self, x: f64, z: f64) -> (i32, i32) {
        let scale = self.view.pixels_per_metre;
        (
            ((x - self.view.x_range.0) * scale).round() as i32,
            ((self.view.z_range.1 - z) * scale).round() as i32,
        )
    }
}

/// An error for a bad view or bad particle data; the path is filled in by the file writer.
fn invalid(reason: impl Into<String>) -> OutputError {
    OutputError::invalid(Path::new(""), reason)
}

/// Converts a colour-map entry to plotters' colour type.
fn colour(rgb: [u8; 3]) -> RGBColor {
    RGBColor(rgb[0], rgb[1], rgb[2])
}

/// Renders one frame at time `time` [s] into memory.
///
/// Fails on a bad view, non-finite particle or wall data, or a negative radius; errors carry
/// an empty path, since no file is involved.
pub fn render_frame(
    view: &FrameViewport,
    particles: &[FrameParticle],
    walls: &[WallSegment],
    time: f64,
) -> Result<RgbImage, OutputError> {
    let layout = view.layout()?;
    if let Some(index) = particles.iter().position(|p| {
        let finite = p.x.is_finite() && p.z.is_finite() && p.speed.is_finite();
        !(finite && p.radius.is_finite() && p.radius >= 0.0)
    }) {
        return Err(invalid(format!(
            "particle {index} has a non-finite value or a negative radius: {:?}",
            particles[index]
        )));
    }
    if let Some(index) = walls
        .iter()
        .position(|w| w.start.iter().chain(&w.end).any(|c| !c.is_finite()))
    {
        return Err(invalid(format!("wall segment {index} is not finite")));
    }
    ensure_font()?;
    let drawing = |e: &dyn std::fmt::Display| OutputError::drawing(Path::new(""), e);

    // The region is drawn on its own canvas, which clips discs and walls at its edges, and
    // then copied into the frame.
    let mut domain = RgbImage::white(layout.domain_width, layout.domain_height)?;
    {
        let area = BitMapBackend::with_buffer(
            domain.bytes_mut(),
            (layout.domain_width, layout.domain_height),
        )
        .into_drawing_area();
        let (low, high) = view.speed_range;
        for particle in particles {
            let centre = layout.domain_pixel(particle.x, particle.z);
            // Sub-pixel discs would vanish; one pixel keeps every particle visible.
            let radius = (particle.radius * view.pixels_per_metre).round().max(1.0) as i32;
            let outside = centre.0 + radius < 0
                || centre.1 + radius < 0
                || centre.0 - radius > layout.domain_width as i32
                || centre.1 - radius > layout.domain_height as i32;
            if outside {
                continue;
            }
            let fill = colour(viridis((particle.speed - low) / (high - low)));
            area.draw(&Circle::new(centre, radius, fill.filled()))
                .map_err(|e| drawing(&e))?;
        }
        let wall_width = (layout.font_size / 6).max(2);
        for wall in walls {
            let start = layout.domain_pixel(wall.start[0], wall.start[1]);
            let end = layout.domain_pixel(wall.end[0], wall.end[1]);
            area.draw(&PathElement::new(
                vec![start, end],
                BLACK.stroke_width(wall_width),
            ))
            .map_err(|e| drawing(&e))?;
        }
        area.present().map_err(|e| drawing(&e))?;
    }

    let mut image = RgbImage::white(layout.width, layout.height)?;
    {
        let root = BitMapBackend::with_buffer(image.bytes_mut(), (layout.width, layout.height))
            .into_drawing_area();
        root.fill(&WHITE).map_err(|e| drawing(&e))?;
        let blit_target = (layout.domain_left as i32, layout.domain_top as i32);
        // plotters draws bitmaps through `draw_pixel` when there is no fast path; the bitmap
        // backend has one, so this is a plain copy.
        root.draw(
            &plotters::element::BitMapElement::with_owned_buffer(
                blit_target,
                (layout.domain_width, layout.domain_height),
                domain.as_bytes().to_vec(),
            )
            .ok_or_else(|| invalid("domain buffer has the wrong size"))?,
        )
        .map_err(|e| drawing(&e))?;

        let font_size = f64::from(layout.font_size);
        let label = TextStyle::from((FONT_FAMILY, font_size).into_font()).color(&BLACK);
        root.draw(&Text::new(
            format!("t = {time:.3} s"),
            (layout.domain_left as i32, (layout.font_size / 2) as i32),
            label.clone(),
        ))
        .map_err(|e| drawing(&e))?;

        draw_colour_bar(&root, &layout, view.speed_range, &label).map_err(|e| drawing(&e))?;
        root.present().map_err(|e| drawing(&e))?;
    }
    Ok(image)
}

/// The vertical colour bar (high speeds at the top), its ticks and its caption.
fn draw_colour_bar<DB: plotters::backend::DrawingBackend>(
    root: &plotters::drawing::DrawingArea<DB, plotters::coord::Shift>,
    layout: &FrameLayout,
    (low, high): (f64, f64),
    label: &TextStyle<'_>,
) -> Result<(), plotters::drawing::DrawingAreaErrorKind<DB::ErrorType>> {
    let left = layout.colour_bar_left as i32;
    let right = left + layout.colour_bar_width as i32;
    let top = layout.colour_bar_top as i32;
    let rows = layout.colour_bar_height as i32;
    for row in 0..rows {
        // Row 0 is the top, so the fraction runs from 1 at the top to 0 at the bottom.
        let fraction = 1.0 - f64::from(row) / f64::from((rows - 1).max(1));
        // The bitmap backend fills rectangles with exclusive lower-right corners.
        root.draw(&Rectangle::new(
            [(left, top + row), (right, top + row + 1)],
            colour(viridis(fraction)).filled(),
        ))?;
    }
    root.draw(&Rectangle::new(
        [(left - 1, top - 1), (right, top + rows)],
        BLACK.stroke_width(1),
    ))?;
    root.draw(&Text::new(
        "speed [m/s]".to_owned(),
        (left, top - (3 * layout.font_size / 2) as i32),
        label.clone(),
    ))?;

    let ticks = 5;
    let span = high - low;
    let step = span / f64::from(ticks - 1);
    // Four significant digits of the step show quarter steps such as 0.375 exactly; trailing
    // zeros are then trimmed ("0.750" → "0.75").
    let decimals = (3.0 - step.log10().floor()).clamp(0.0, 9.0) as usize;
    let tick_length = (layout.font_size / 3) as i32;
    let tick_label = label.pos(Pos::new(HPos::Left, VPos::Center));
    for tick in 0..ticks {
        let fraction = f64::from(tick) / f64::from(ticks - 1);
        let row = top + ((1.0 - fraction) * f64::from(rows - 1)).round() as i32;
        root.draw(&PathElement::new(
            vec![(right, row), (right + tick_length, row)],
            BLACK.stroke_width(1),
        ))?;
        root.draw(&Text::new(
            tick_text(low + fraction * span, decimals),
            (right + tick_length + 4, row),
            tick_label.clone(),
        ))?;
    }
    Ok(())
}

/// `value` with `decimals` decimals, trailing zeros and a bare decimal point removed.
fn tick_text(value: f64, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.')
    } else {
        &text
    };
    // "-0" reads as a different tick from "0".
    if text == "-0" {
        "0".to_owned()
    } else {
        text.to_owned()
    }
}

/// Renders one frame and writes it as PNG at `path` atomically.
pub fn write_frame_png(
    path: impl AsRef<Path>,
    view: &FrameViewport,
    particles: &[FrameParticle],
    walls: &[WallSegment],
    time: f64,
) -> Result<(), OutputError> {
    let path = path.as_ref();
    let image = render_frame(view, particles, walls, time).map_err(|e| e.for_path(path))?;
    image.write_png(path)
}
