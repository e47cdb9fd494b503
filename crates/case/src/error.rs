//! Configuration errors: where a bad value came from, what it was and what is allowed.
//!
//! A case file is checked completely before anything runs, and every problem found is
//! reported at once, so a user fixes a file in one pass instead of one error per run.

use std::fmt;
use std::sync::Arc;

/// Where a value of a case or sweep document came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// Name of the source: a file name as given by the user, `--set`, or `default`.
    pub source: Arc<str>,
    /// 1-based line in the source, when the source is a file.
    pub line: Option<usize>,
    /// 1-based column (in characters) in the source, when the source is a file.
    pub column: Option<usize>,
}

impl Location {
    /// A location with no line, e.g. a whole file or a command-line override.
    pub fn whole(source: &Arc<str>) -> Self {
        Self {
            source: Arc::clone(source),
            line: None,
            column: None,
        }
    }

    /// The location of byte `offset` in `text`, with 1-based line and character column.
    pub fn at_offset(source: &Arc<str>, text: &str, offset: usize) -> Self {
        let offset = offset.min(text.len());
        // Step back to a character boundary: spans from the parser are byte offsets.
        let mut offset = offset;
        while !text.is_char_boundary(offset) {
            offset -= 1;
        }
        let before = &text[..offset];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = text[line_start..offset].chars().count() + 1;
        Self {
            source: Arc::clone(source),
            line: Some(line),
            column: Some(column),
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.source)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(column) = self.column {
                write!(f, ":{column}")?;
            }
        }
        Ok(())
    }
}

/// What kind of problem a [`ConfigError`] reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The file could not be read, or is not UTF-8.
    Io,
    /// The text is not valid TOML, or a `--set` override is malformed.
    Syntax,
    /// A key that the format does not know.
    UnknownKey,
    /// A value of the wrong TOML type (e.g. a string where a number is expected).
    WrongType,
    /// A required key is absent, or alternatives are both absent.
    Missing,
    /// Two keys that exclude each other are both given.
    Conflict,
    /// A value outside its allowed range or set.
    Invalid,
    /// A geometry that cannot be built: the outlet or the particles do not fit the hopper.
    /// Sweeps skip such grid points instead of failing.
    DoesNotFit,
}

/// One problem in a case or sweep document.
#[derive(Clone, Debug, PartialEq)]
pub struct ConfigError {
    /// Where the offending key or value is.
    pub location: Location,
    /// Dotted key, e.g. `geometry.outlet_width`; empty for whole-document problems.
    pub key: String,
    /// The offending value as the user wrote it (with its unit), when there is one.
    pub value: Option<String>,
    /// What is wrong and what is allowed.
    pub message: String,
    /// Category, used by sweeps to tell a geometry that does not fit from a real error.
    pub kind: ErrorKind,
}

impl ConfigError {
    /// A new error; `value` is shown after the key when present.
    pub fn new(
        kind: ErrorKind,
        location: Location,
        key: impl Into<String>,
        value: Option<String>,
        message: impl Into<String>,
    ) -> Self {
        Self {
            location,
            key: key.into(),
            value,
            message: message.into(),
            kind,
        }
    }
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: ", self.location)?;
        match (self.key.is_empty(), &self.value) {
            (false, Some(value)) => write!(f, "{} = {}: ", self.key, value)?,
            (false, None) => write!(f, "{}: ", self.key)?,
            (true, Some(value)) => write!(f, "{value}: ")?,
            (true, None) => {}
        }
        write!(f, "{}", self.message)
    }
}

/// Every problem found in a document; never empty when returned as an error.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct ConfigErrors {
    /// The problems, in document order as far as it is known.
    pub errors: Vec<ConfigError>,
}

impl ConfigErrors {
    /// Process exit code for an invalid input file, as the command line promises.
    pub const EXIT_CODE: i32 = 2;

    /// A list holding one error.
    pub fn single(error: ConfigError) -> Self {
        Self {
            errors: vec![error],
        }
    }

    /// Whether every error is a geometry that does not fit (sweeps skip those points).
    pub fn only_does_not_fit(&self) -> bool {
        !self.errors.is_empty() && self.errors.iter().all(|e| e.kind == ErrorKind::DoesNotFit)
    }
}

impl fmt::Display for ConfigErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, error) in self.errors.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "error: {error}")?;
        }
        Ok(())
    }
}

/// Formats a number for messages: plain decimals in the usual range, exponents outside it.
pub(crate) fn number(value: f64) -> String {
    let magnitude = value.abs();
    if value == 0.0 || (1e-3..1e6).contains(&magnitude) || !value.is_finite() {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

/// Formats a derived number (a product or a sum) to 4 significant digits, so messages do
/// not show floating-point noise such as 0.009000000000000001.
pub(crate) fn rounded(value: f64) -> String {
    let four_digits: f64 = format!("{value:.3e}").parse().unwrap_or(value);
    number(four_digits)
}
