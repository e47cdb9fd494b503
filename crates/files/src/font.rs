//! The embedded DejaVu Sans font, registered once with plotters as "sans-serif".
//!
//! plotters is built with its `ab_glyph` renderer rather than a system font lookup, so
//! rendered text is identical on every machine and needs no installed fonts.

use std::sync::OnceLock;

use plotters::style::{register_font, FontStyle};

use super::OutputError;

/// DejaVu Sans (Bitstream Vera licence, redistribution allowed; see the assets folder).
static DEJAVU_SANS: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// The family name every writer in this module asks plotters for.
pub(crate) const FONT_FAMILY: &str = "sans-serif";

/// Whether registration succeeded; computed once per process.
static REGISTERED: OnceLock<bool> = OnceLock::new();

/// Registers the embedded font if that has not happened yet.
pub(crate) fn ensure_font() -> Result<(), OutputError> {
    let registered = *REGISTERED
        .get_or_init(|| register_font(FONT_FAMILY, FontStyle::Normal, DEJAVU_SANS).is_ok());
    if registered {
        Ok(())
    } else {
        Err(OutputError::Drawing {
            path: std::path::PathBuf::new(),
            reason: "the embedded font could not be parsed".to_owned(),
        })
    }
}
