//! Behaviour of the hopper frame renderer: discs at the right place in the right colour,
//! walls, colour bar, time label, clipping, PNG output.

use files::{
    render_frame, viridis, write_frame_png, FrameParticle, FrameViewport, OutputError, WallSegment,
};

const WHITE: [u8; 3] = [255, 255, 255];

/// A 0.1 m × 0.4 m hopper at 1000 px/m (100 × 400 px), small enough to render in
/// milliseconds; speeds 0–1 m/s span the colour map.
fn small_view() -> FrameViewport {
    FrameViewport {
        x_range: (0.0, 0.1),
        z_range: (0.0, 0.4),
        pixels_per_metre: 1000.0,
        speed_range: (0.0, 1.0),
    }
}

fn particle(x: f64, z: f64, speed: f64) -> FrameParticle {
    FrameParticle {
        x,
        z,
        radius: 0.004,
        speed,
    }
}

/// The PNG width and height from the IHDR chunk after checking the signature.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(
        &bytes[..8],
        &[0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n']
    );
    assert_eq!(&bytes[12..16], b"IHDR");
    let word =
        |at: usize| u32::from_be_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    (word(16), word(20))
}

#[test]
fn disc_centres_take_the_viridis_colour_of_their_speed() {
    let view = small_view();
    let layout = view.layout().expect("layout");
    let particles = [
        particle(0.03, 0.10, 1.0),
        particle(0.07, 0.10, 0.0),
        particle(0.05, 0.30, 0.5),
        // Faster than the top of the scale: saturates at the top colour.
        particle(0.05, 0.20, 7.0),
    ];
    let image = render_frame(&view, &particles, &[], 0.5).expect("render");
    for p in &particles {
        let (x, y) = layout.pixel(p.x, p.z);
        // The centre of a 4 px disc is far from its anti-aliased edge: exact colour.
        assert_eq!(
            image.pixel(x as u32, y as u32),
            Some(viridis(p.speed.min(1.0))),
            "particle at ({}, {})",
            p.x,
            p.z
        );
    }
    // Halfway between two discs there is only background.
    let (x, y) = layout.pixel(0.05, 0.10);
    assert_eq!(image.pixel(x as u32, y as u32), Some(WHITE));
}

#[test]
fn walls_are_drawn_as_black_segments() {
    let view = small_view();
    let layout = view.layout().expect("layout");
    let walls = [
        WallSegment {
            start: [0.01, 0.0],
            end: [0.01, 0.4],
        },
        // An inclined segment: its midpoint must be on it as well.
        WallSegment {
            start: [0.02, 0.05],
            end: [0.08, 0.02],
        },
    ];
    let image = render_frame(&view, &[], &walls, 0.0).expect("render");
    for (x, z) in [(0.01, 0.2), (0.05, 0.035)] {
        let (column, row) = layout.pixel(x, z);
        assert_eq!(
            image.pixel(column as u32, row as u32),
            Some([0, 0, 0]),
            "wall at ({x}, {z})"
        );
    }
    let (column, row) = layout.pixel(0.05, 0.2);
    assert_eq!(image.pixel(column as u32, row as u32), Some(WHITE));
}

#[test]
fn colour_bar_runs_from_fast_at_the_top_to_slow_at_the_bottom() {
    let view = small_view();
    let layout = view.layout().expect("layout");
    let image = render_frame(&view, &[], &[], 0.0).expect("render");
    let column = layout.colour_bar_left + layout.colour_bar_width / 2;
    let top = image.pixel(column, layout.colour_bar_top);
    let bottom = image.pixel(column, layout.colour_bar_top + layout.colour_bar_height - 1);
    assert_eq!(top, Some(viridis(1.0)));
    assert_eq!(bottom, Some(viridis(0.0)));
    let middle = image
        .pixel(column, layout.colour_bar_top + layout.colour_bar_height / 2)
        .expect("inside");
    // Linear scale: the middle row shows half speed. With an even row count the middle row
    // is half a row (0.25 % of the map here) off 0.5, which moves a channel by at most 2.
    let expected = viridis(0.5);
    for channel in 0..3 {
        let difference = i32::from(middle[channel]) - i32::from(expected[channel]);
        assert!(difference.abs() <= 2, "middle {middle:?} vs {expected:?}");
    }
    // The bar lies right of the hopper, inside the image.
    assert!(layout.colour_bar_left > layout.domain_left + layout.domain_width);
    assert!(layout.colour_bar_left + layout.colour_bar_width < layout.width);
}

#[test]
fn time_label_and_tick_labels_are_drawn_as_text() {
    let view = small_view();
    let layout = view.layout().expect("layout");
    let image = render_frame(&view, &[], &[], 1.25).expect("render");
    let dark = |columns: std::ops::Range<u32>, rows: std::ops::Range<u32>| {
        rows.flat_map(|y| columns.clone().map(move |x| (x, y)))
            .filter(|&(x, y)| {
                image
                    .pixel(x, y)
                    .is_some_and(|p| p.iter().all(|&c| c < 100))
            })
            .count()
    };
    // Glyphs of "t = 1.250 s" above the hopper; nothing else is drawn there.
    assert!(dark(0..layout.width, 0..layout.domain_top) > 50);
    // Tick labels right of the colour bar.
    let right_of_bar = layout.colour_bar_left + layout.colour_bar_width + 2;
    let bar_rows = layout.colour_bar_top..layout.colour_bar_top + layout.colour_bar_height;
    assert!(dark(right_of_bar..layout.width, bar_rows) > 50);
}

#[test]
fn fitted_view_keeps_the_aspect_ratio_and_maps_corners() {
    let view = FrameViewport::fitted((0.0, 0.1), (0.0, 0.4), 1600, (0.0, 1.0));
    let layout = view.layout().expect("layout");
    // 0.1 m × 0.4 m at 1600 px for 0.4 m: 4000 px/m, so 400 × 1600 px.
    assert_eq!((layout.domain_width, layout.domain_height), (400, 1600));
    assert_eq!(
        layout.pixel(0.0, 0.4),
        (layout.domain_left as i32, layout.domain_top as i32)
    );
    assert_eq!(
        layout.pixel(0.1, 0.0),
        (
            (layout.domain_left + 400) as i32,
            (layout.domain_top + 1600) as i32
        )
    );
    assert!(layout.height >= 1600 && layout.width > 400 && layout.width < layout.height);
}

#[test]
fn discs_outside_the_view_are_clipped_at_its_edge() {
    let view = small_view();
    let layout = view.layout().expect("layout");
    // Centre 2 mm left of the view, radius 4 mm: half of it would spill into the margin.
    let image = render_frame(&view, &[particle(-0.002, 0.2, 1.0)], &[], 0.0).expect("render");
    let (column, row) = layout.pixel(-0.002, 0.2);
    assert!(column >= 0, "the margin is wide enough to test");
    assert_eq!(image.pixel(column as u32, row as u32), Some(WHITE));
    // The part inside the view is drawn.
    let (column, row) = layout.pixel(0.001, 0.2);
    assert_eq!(image.pixel(column as u32, row as u32), Some(viridis(1.0)));
}

#[test]
fn full_size_frame_of_three_thousand_particles_is_written_as_png() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("frame_0001.png");
    let view = FrameViewport::fitted((-0.002, 0.102), (-0.02, 0.4), 1600, (0.0, 1.5));
    let layout = view.layout().expect("layout");
    // A packed block of 3 mm discs: 30 columns × 100 rows.
    let particles: Vec<FrameParticle> = (0..3000)
        .map(|i| FrameParticle {
            x: 0.0035 + 0.0031 * (i % 30) as f64,
            z: 0.0015 + 0.0031 * (i / 30) as f64,
            radius: 0.0015,
            speed: 1.5 * (i % 30) as f64 / 29.0,
        })
        .collect();
    let walls = [
        WallSegment {
            start: [0.0, 0.0],
            end: [0.0, 0.4],
        },
        WallSegment {
            start: [0.1, 0.0],
            end: [0.1, 0.4],
        },
        WallSegment {
            start: [0.0, 0.0],
            end: [0.04, 0.0],
        },
        WallSegment {
            start: [0.06, 0.0],
            end: [0.1, 0.0],
        },
    ];
    write_frame_png(&path, &view, &particles, &walls, 0.75).expect("write");
    let bytes = std::fs::read(&path).expect("read back");
    assert_eq!(png_size(&bytes), (layout.width, layout.height));
    // 3000 coloured discs cannot compress to a few kilobytes.
    assert!(bytes.len() > 50_000, "only {} bytes", bytes.len());
    assert_eq!(std::fs::read_dir(directory.path()).expect("dir").count(), 1);
}

#[test]
fn bad_views_and_particles_are_refused() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("frame.png");
    let mut reversed = small_view();
    reversed.z_range = (0.4, 0.0);
    let error = write_frame_png(&path, &reversed, &[], &[], 0.0).expect_err("reversed range");
    match error {
        OutputError::InvalidData { path: reported, .. } => assert_eq!(reported, path),
        other => panic!("unexpected error {other:?}"),
    }
    let mut flat_speeds = small_view();
    flat_speeds.speed_range = (1.0, 1.0);
    assert!(flat_speeds.layout().is_err());
    let broken = [FrameParticle {
        x: f64::NAN,
        z: 0.1,
        radius: 0.001,
        speed: 0.0,
    }];
    assert!(matches!(
        write_frame_png(&path, &small_view(), &broken, &[], 0.0),
        Err(OutputError::InvalidData { .. })
    ));
    // A scale that would need a gigapixel image is a unit mistake, not a request.
    let mut huge = small_view();
    huge.pixels_per_metre = 1e6;
    assert!(huge.layout().is_err());
    assert!(!path.exists());
}

#[test]
fn viridis_runs_from_purple_to_yellow_with_rising_lightness() {
    assert_eq!(viridis(0.0), [68, 1, 84]);
    assert_eq!(viridis(1.0), [253, 231, 37]);
    // Out-of-range values saturate.
    assert_eq!(viridis(-3.0), viridis(0.0));
    assert_eq!(viridis(4.0), viridis(1.0));
    // Perceptual ordering: Rec. 709 luma increases strictly along the map, which is what
    // makes viridis readable in grey scale.
    let luma =
        |[r, g, b]: [u8; 3]| 0.2126 * f64::from(r) + 0.7152 * f64::from(g) + 0.0722 * f64::from(b);
    let samples: Vec<f64> = (0..=100).map(|i| luma(viridis(i as f64 / 100.0))).collect();
    for pair in samples.windows(2) {
        assert!(pair[1] > pair[0], "luma must rise: {pair:?}");
    }
}
