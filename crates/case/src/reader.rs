//! Typed reading of a located document: defaults, type checks and unknown keys.
//!
//! Each section of a case file is read through a [`Section`], which records every key it
//! was asked for; whatever is left at the end is an unknown key. Type errors are
//! collected rather than returned, so one pass reports every problem of a file.

use std::sync::Arc;

use super::document::{join_key, Entry, NodeValue, Table};
use super::error::{number, ConfigError, ErrorKind, Location};

/// A value read from a document (or its default) with the key and place it came from.
#[derive(Clone, Debug)]
pub(crate) struct Located<T> {
    pub value: T,
    /// Dotted key.
    pub key: String,
    pub location: Location,
    /// Whether the value was written by the user (false: the default was used).
    pub given: bool,
    /// Unit shown after numbers in messages, e.g. `m`; empty for none.
    pub unit: &'static str,
}

impl<T> Located<T> {
    /// An error about this value, shown as `shown`.
    fn error_shown(
        &self,
        kind: ErrorKind,
        shown: String,
        message: impl Into<String>,
    ) -> ConfigError {
        ConfigError::new(
            kind,
            self.location.clone(),
            self.key.clone(),
            Some(shown),
            message,
        )
    }

    /// `text` marked `(default)` when the user did not write the value.
    fn marked(&self, mut text: String) -> String {
        if !self.given {
            text.push_str(" (default)");
        }
        text
    }
}

impl<T: Copy> Located<T> {
    /// The same key and place with a different value (e.g. a derived default).
    pub fn with_value(&self, value: T) -> Self {
        Self {
            value,
            ..self.clone()
        }
    }
}

impl Located<f64> {
    /// The value with its unit, marked `(default)` when the user did not write it.
    pub fn shown(&self) -> String {
        let mut text = number(self.value);
        match self.unit {
            "" => {}
            // Degrees sit on the number; other units follow a space (SI style).
            "°" => text.push('°'),
            unit => {
                text.push(' ');
                text.push_str(unit);
            }
        }
        self.marked(text)
    }

    /// An error about this value.
    pub fn error(&self, kind: ErrorKind, message: impl Into<String>) -> ConfigError {
        self.error_shown(kind, self.shown(), message)
    }

    /// Records an error unless the value is finite and strictly positive.
    pub fn require_positive(&self, errors: &mut Vec<ConfigError>) -> bool {
        if self.value.is_finite() && self.value > 0.0 {
            return true;
        }
        errors.push(self.error(ErrorKind::Invalid, "must be a finite number > 0"));
        false
    }

    /// Records an error unless the value is finite and ≥ 0.
    pub fn require_non_negative(&self, errors: &mut Vec<ConfigError>) -> bool {
        if self.value.is_finite() && self.value >= 0.0 {
            return true;
        }
        errors.push(self.error(ErrorKind::Invalid, "must be a finite number ≥ 0"));
        false
    }
}

/// A value with a place, for messages about integers, strings and booleans.
impl Located<i64> {
    pub fn error(&self, kind: ErrorKind, message: impl Into<String>) -> ConfigError {
        self.error_shown(kind, self.marked(self.value.to_string()), message)
    }
}

impl Located<String> {
    /// An error about this word, shown quoted.
    pub fn error(&self, kind: ErrorKind, message: impl Into<String>) -> ConfigError {
        self.error_shown(kind, format!("\"{}\"", self.value), message)
    }
}

/// A vector of numbers (a point, an axis) shows as `[x, y, z]` with its unit.
impl Located<Vec<f64>> {
    /// The vector with its unit, marked `(default)` when the user did not write it.
    pub fn shown(&self) -> String {
        let items: Vec<String> = self.value.iter().map(|x| number(*x)).collect();
        let mut text = format!("[{}]", items.join(", "));
        if !self.unit.is_empty() {
            text.push(' ');
            text.push_str(self.unit);
        }
        self.marked(text)
    }

    /// An error about this vector.
    pub fn error(&self, kind: ErrorKind, message: impl Into<String>) -> ConfigError {
        self.error_shown(kind, self.shown(), message)
    }

    /// Records an error unless every component is finite.
    pub fn require_finite(&self, errors: &mut Vec<ConfigError>) -> bool {
        if self.value.iter().all(|x| x.is_finite()) {
            return true;
        }
        errors.push(self.error(
            ErrorKind::Invalid,
            "every component must be a finite number",
        ));
        false
    }
}

/// One table of a document being read; see the module documentation.
pub(crate) struct Section<'a> {
    path: String,
    table: Option<&'a Table>,
    used: Vec<bool>,
    /// Where defaults of this section are said to come from (the file, without a line).
    default_location: Location,
    /// Where the section's own key is (its table header), or the file when absent.
    location: Location,
}

impl<'a> Section<'a> {
    /// The top level of a document.
    pub fn root(table: &'a Table, source: &Arc<str>) -> Self {
        Self {
            path: String::new(),
            table: Some(table),
            used: vec![false; table.entries.len()],
            default_location: Location::whole(source),
            location: Location::whole(source),
        }
    }

    /// A section over `table`, whose dotted path is `path` and header is at `location`.
    pub fn over(
        table: &'a Table,
        path: String,
        location: Location,
        default_location: Location,
    ) -> Self {
        Self {
            path,
            used: vec![false; table.entries.len()],
            table: Some(table),
            default_location,
            location,
        }
    }

    /// Dotted key of `key` in this section.
    pub fn key(&self, key: &str) -> String {
        join_key(&self.path, key)
    }

    /// Whether the user wrote `key` in this section.
    pub fn has(&self, key: &str) -> bool {
        self.table.is_some_and(|t| t.get(key).is_some())
    }

    /// The keys written in this section, in document order (none when it is absent).
    pub fn keys(&self) -> Vec<String> {
        self.table.map_or_else(Vec::new, |t| {
            t.entries.iter().map(|e| e.key.clone()).collect()
        })
    }

    /// The entry for `key`, marking it as known.
    pub fn entry(&mut self, key: &str) -> Option<&'a Entry> {
        let table = self.table?;
        let index = table.entries.iter().position(|e| e.key == key)?;
        self.used[index] = true;
        Some(&table.entries[index])
    }

    /// A location for defaults of this section.
    pub fn default_location(&self) -> &Location {
        &self.default_location
    }

    /// Where the section itself is written (its header), for "missing key" messages.
    pub fn location(&self) -> &Location {
        &self.location
    }

    fn wrong_type(&self, entry: &Entry, expected: &str, errors: &mut Vec<ConfigError>) {
        errors.push(ConfigError::new(
            ErrorKind::WrongType,
            entry.key_location.clone(),
            self.key(&entry.key),
            Some(entry.node.value.to_string()),
            format!(
                "expected {expected}, found {}",
                entry.node.value.type_name()
            ),
        ));
    }

    fn located<T>(&self, entry: &Entry, value: T, unit: &'static str) -> Located<T> {
        Located {
            value,
            key: self.key(&entry.key),
            location: entry.key_location.clone(),
            given: true,
            unit,
        }
    }

    /// A default value, located at the file as a whole.
    pub fn default_value<T>(&self, key: &str, value: T, unit: &'static str) -> Located<T> {
        Located {
            value,
            key: self.key(key),
            location: self.default_location.clone(),
            given: false,
            unit,
        }
    }

    /// A number (integers are accepted and widened); `None` if absent or mistyped.
    pub fn float(
        &mut self,
        key: &str,
        unit: &'static str,
        errors: &mut Vec<ConfigError>,
    ) -> Option<Located<f64>> {
        let entry = self.entry(key)?;
        match entry.node.value {
            NodeValue::Float(x) => Some(self.located(entry, x, unit)),
            // TOML integers are exact up to 2^53 as f64, far beyond any physical input here.
            NodeValue::Integer(i) => Some(self.located(entry, i as f64, unit)),
            _ => {
                self.wrong_type(entry, "a number", errors);
                None
            }
        }
    }

    /// A number with a default used when the key is absent or mistyped.
    pub fn float_or(
        &mut self,
        key: &str,
        unit: &'static str,
        default: f64,
        errors: &mut Vec<ConfigError>,
    ) -> Located<f64> {
        self.float(key, unit, errors)
            .unwrap_or_else(|| self.default_value(key, default, unit))
    }

    /// An integer; `None` if absent or mistyped.
    pub fn integer(&mut self, key: &str, errors: &mut Vec<ConfigError>) -> Option<Located<i64>> {
        let entry = self.entry(key)?;
        match entry.node.value {
            NodeValue::Integer(i) => Some(self.located(entry, i, "")),
            _ => {
                self.wrong_type(entry, "an integer", errors);
                None
            }
        }
    }

    /// An integer with a default used when the key is absent or mistyped.
    pub fn integer_or(
        &mut self,
        key: &str,
        default: i64,
        errors: &mut Vec<ConfigError>,
    ) -> Located<i64> {
        self.integer(key, errors)
            .unwrap_or_else(|| self.default_value(key, default, ""))
    }

    /// A boolean with a default used when the key is absent or mistyped.
    pub fn boolean_or(&mut self, key: &str, default: bool, errors: &mut Vec<ConfigError>) -> bool {
        let Some(entry) = self.entry(key) else {
            return default;
        };
        match entry.node.value {
            NodeValue::Boolean(b) => b,
            _ => {
                self.wrong_type(entry, "true or false", errors);
                default
            }
        }
    }

    /// A string; `None` if absent or mistyped.
    pub fn string(&mut self, key: &str, errors: &mut Vec<ConfigError>) -> Option<Located<String>> {
        let entry = self.entry(key)?;
        match &entry.node.value {
            NodeValue::String(s) => Some(self.located(entry, s.clone(), "")),
            _ => {
                self.wrong_type(entry, "a string", errors);
                None
            }
        }
    }

    /// One of a fixed set of words, mapped to a value; errors list the allowed words.
    pub fn choice<T: Copy>(
        &mut self,
        key: &str,
        options: &[(&str, T)],
        default: T,
        errors: &mut Vec<ConfigError>,
    ) -> T {
        let Some(word) = self.string(key, errors) else {
            return default;
        };
        match options.iter().find(|(name, _)| *name == word.value) {
            Some((_, value)) => *value,
            None => {
                let allowed: Vec<String> =
                    options.iter().map(|(n, _)| format!("\"{n}\"")).collect();
                errors.push(ConfigError::new(
                    ErrorKind::Invalid,
                    word.location,
                    word.key,
                    Some(format!("\"{}\"", word.value)),
                    format!("must be one of {}", allowed.join(", ")),
                ));
                default
            }
        }
    }

    /// An array of numbers; `None` if absent or mistyped.
    pub fn float_array(
        &mut self,
        key: &str,
        unit: &'static str,
        errors: &mut Vec<ConfigError>,
    ) -> Option<Vec<Located<f64>>> {
        let entry = self.entry(key)?;
        let NodeValue::Array(items) = &entry.node.value else {
            self.wrong_type(entry, "an array of numbers", errors);
            return None;
        };
        let mut values = Vec::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            let value = match item.value {
                NodeValue::Float(x) => x,
                NodeValue::Integer(i) => i as f64,
                _ => {
                    errors.push(ConfigError::new(
                        ErrorKind::WrongType,
                        item.location.clone(),
                        format!("{}[{i}]", self.key(key)),
                        Some(item.value.to_string()),
                        format!("expected a number, found {}", item.value.type_name()),
                    ));
                    return None;
                }
            };
            values.push(Located {
                value,
                key: format!("{}[{i}]", self.key(key)),
                location: item.location.clone(),
                given: true,
                unit,
            });
        }
        Some(values)
    }

    /// An array of exactly `len` numbers (a point, an axis); `None` if absent or mistyped,
    /// with an error for a wrong type or length.
    pub fn float_vector(
        &mut self,
        key: &str,
        unit: &'static str,
        len: usize,
        errors: &mut Vec<ConfigError>,
    ) -> Option<Located<Vec<f64>>> {
        let location = self.table?.get(key)?.key_location.clone();
        let shown = self.table?.get(key)?.node.value.to_string();
        let items = self.float_array(key, unit, errors)?;
        if items.len() != len {
            errors.push(ConfigError::new(
                ErrorKind::WrongType,
                location,
                self.key(key),
                Some(shown),
                format!("expected an array of {len} numbers, found {}", items.len()),
            ));
            return None;
        }
        Some(Located {
            value: items.iter().map(|x| x.value).collect(),
            key: self.key(key),
            location,
            given: true,
            unit,
        })
    }

    /// [`Section::float_vector`] with a default used when the key is absent or mistyped.
    pub fn float_vector_or(
        &mut self,
        key: &str,
        unit: &'static str,
        default: &[f64],
        errors: &mut Vec<ConfigError>,
    ) -> Located<Vec<f64>> {
        self.float_vector(key, unit, default.len(), errors)
            .unwrap_or_else(|| self.default_value(key, default.to_vec(), unit))
    }

    /// An array of strings (words), each with its own place; `None` if absent or mistyped.
    pub fn string_array(
        &mut self,
        key: &str,
        errors: &mut Vec<ConfigError>,
    ) -> Option<Vec<Located<String>>> {
        let entry = self.entry(key)?;
        let NodeValue::Array(items) = &entry.node.value else {
            self.wrong_type(entry, "an array of strings", errors);
            return None;
        };
        let mut words = Vec::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            let NodeValue::String(word) = &item.value else {
                errors.push(ConfigError::new(
                    ErrorKind::WrongType,
                    item.location.clone(),
                    format!("{}[{i}]", self.key(key)),
                    Some(item.value.to_string()),
                    format!("expected a string, found {}", item.value.type_name()),
                ));
                return None;
            };
            words.push(Located {
                value: word.clone(),
                key: format!("{}[{i}]", self.key(key)),
                location: item.location.clone(),
                given: true,
                unit: "",
            });
        }
        Some(words)
    }

    /// An array of tables (`[[key]]` headers, or an array of inline tables), one section
    /// each, keyed `key[i]`; `None` if absent, mistyped, or holding something not a table.
    pub fn tables(&mut self, key: &str, errors: &mut Vec<ConfigError>) -> Option<Vec<Section<'a>>> {
        let entry = self.entry(key)?;
        let NodeValue::Array(items) = &entry.node.value else {
            self.wrong_type(entry, "an array of tables", errors);
            return None;
        };
        let mut sections = Vec::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            let path = format!("{}[{i}]", self.key(key));
            let NodeValue::Table(table) = &item.value else {
                errors.push(ConfigError::new(
                    ErrorKind::WrongType,
                    item.location.clone(),
                    path,
                    Some(item.value.to_string()),
                    format!("expected a table, found {}", item.value.type_name()),
                ));
                return None;
            };
            sections.push(Section::over(
                table,
                path,
                item.location.clone(),
                self.default_location.clone(),
            ));
        }
        Some(sections)
    }

    /// A sub-table; an absent key gives an empty section, a mistyped one an error.
    pub fn section(&mut self, key: &str, errors: &mut Vec<ConfigError>) -> Section<'a> {
        let path = self.key(key);
        let default_location = self.default_location.clone();
        let entry = self.entry(key);
        let location = entry.map_or_else(|| default_location.clone(), |e| e.key_location.clone());
        let table = match entry {
            Some(entry) => match &entry.node.value {
                NodeValue::Table(t) => Some(t),
                _ => {
                    self.wrong_type(entry, "a table", errors);
                    None
                }
            },
            None => None,
        };
        Section {
            path,
            used: vec![false; table.map_or(0, |t| t.entries.len())],
            table,
            default_location,
            location,
        }
    }

    /// The error of a required `key` missing from this section, with `message` saying
    /// what it must hold.
    pub fn missing(&self, key: &str, message: impl Into<String>) -> ConfigError {
        ConfigError::new(
            ErrorKind::Missing,
            self.location().clone(),
            self.key(key),
            None,
            message,
        )
    }

    /// Reports every key of this section that nobody asked for.
    pub fn finish(&self, allowed: &[&str], errors: &mut Vec<ConfigError>) {
        let Some(table) = self.table else {
            return;
        };
        for (entry, used) in table.entries.iter().zip(&self.used) {
            if !used {
                let message = if allowed.is_empty() {
                    "unknown key".to_string()
                } else {
                    format!("unknown key; allowed here: {}", allowed.join(", "))
                };
                errors.push(ConfigError::new(
                    ErrorKind::UnknownKey,
                    entry.key_location.clone(),
                    self.key(&entry.key),
                    None,
                    message,
                ));
            }
        }
    }
}
