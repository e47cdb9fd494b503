//! An in-memory RGB image and its atomic PNG encoding.
//!
//! Plots and frames are first drawn into memory, where tests and callers can read pixels,
//! then encoded as PNG by the `png` crate (plotters draws into the buffer only: its file
//! backend would bring a whole image library, JPEG and BMP included, for one encoder).

use std::path::Path;

use super::atomic::StagedPath;
use super::OutputError;

/// The largest width or height accepted [px]; larger requests are almost surely a unit
/// mistake and would allocate gigabytes.
pub(crate) const MAX_SIDE: u32 = 16_384;

/// An 8-bit RGB image, rows from top to bottom.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbImage {
    width: u32,
    height: u32,
    pixels: Vec<u8>,
}

impl RgbImage {
    /// A white image of the given size [px].
    pub(crate) fn white(width: u32, height: u32) -> Result<Self, OutputError> {
        check_size(width, height)?;
        Ok(Self {
            width,
            height,
            pixels: vec![255; 3 * width as usize * height as usize],
        })
    }

    /// Width [px].
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height [px].
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The colour at column `x`, row `y` (from the top), or `None` outside the image.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 3]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let start = 3 * (y as usize * self.width as usize + x as usize);
        Some([
            self.pixels[start],
            self.pixels[start + 1],
            self.pixels[start + 2],
        ])
    }

    /// The raw pixels, three bytes per pixel, row by row.
    pub fn as_bytes(&self) -> &[u8] {
        &self.pixels
    }

    /// Mutable raw pixels, for the plotters buffer backend.
    pub(crate) fn bytes_mut(&mut self) -> &mut [u8] {
        &mut self.pixels
    }

    /// Encodes the image as PNG at `path` atomically: 8-bit RGB, the encoder's default
    /// compression and filter.
    pub fn write_png(&self, path: impl AsRef<Path>) -> Result<(), OutputError> {
        let path = path.as_ref();
        let (staged, file) = StagedPath::reserve(path, "png")?;
        let encoded = (|| {
            let mut encoder = png::Encoder::new(file, self.width, self.height);
            encoder.set_color(png::ColorType::Rgb);
            encoder.set_depth(png::BitDepth::Eight);
            let mut writer = encoder.write_header()?;
            writer.write_image_data(&self.pixels)?;
            writer.finish()
        })();
        encoded.map_err(|e| OutputError::drawing(path, e))?;
        staged.commit()
    }
}

/// Refuses empty or absurdly large images.
pub(crate) fn check_size(width: u32, height: u32) -> Result<(), OutputError> {
    if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
        return Err(OutputError::InvalidData {
            path: std::path::PathBuf::new(),
            reason: format!("image size {width}×{height} px is outside 1..={MAX_SIDE} px"),
        });
    }
    Ok(())
}
