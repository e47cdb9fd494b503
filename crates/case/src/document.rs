//! A parsed TOML document that remembers the file and line of every key and value.
//!
//! The text is parsed once with `toml_edit`, whose immutable documents keep the byte span
//! of every key and value, into a tree of located nodes. Every later check (unknown
//! keys, wrong types, ranges) can then name the line it is about, and `--set` overrides
//! and sweep axes replace nodes of the tree before anything is validated.

use std::fmt;
use std::ops::Range;
use std::sync::Arc;

use toml_edit::{ImDocument, Item, Value};

use super::error::{ConfigError, ConfigErrors, ErrorKind, Location};

/// A TOML value with the place it came from.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Node {
    pub value: NodeValue,
    pub location: Location,
}

/// The TOML value kinds the formats use (date-times are rejected at parse time).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum NodeValue {
    String(String),
    Integer(i64),
    Float(f64),
    Boolean(bool),
    Array(Vec<Node>),
    Table(Table),
}

impl NodeValue {
    /// The TOML type name, for "expected a number, found a string" messages.
    pub fn type_name(&self) -> &'static str {
        match self {
            NodeValue::String(_) => "a string",
            NodeValue::Integer(_) => "an integer",
            NodeValue::Float(_) => "a float",
            NodeValue::Boolean(_) => "a boolean",
            NodeValue::Array(_) => "an array",
            NodeValue::Table(_) => "a table",
        }
    }
}

impl fmt::Display for NodeValue {
    /// TOML-like rendering of a value, used in error messages and sweep labels.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            NodeValue::String(s) => write!(f, "{s:?}"),
            NodeValue::Integer(i) => write!(f, "{i}"),
            NodeValue::Float(x) => write!(f, "{x}"),
            NodeValue::Boolean(b) => write!(f, "{b}"),
            NodeValue::Array(items) => {
                write!(f, "[")?;
                for (i, item) in items.iter().enumerate() {
                    if i > 0 {
                        write!(f, ", ")?;
                    }
                    write!(f, "{}", item.value)?;
                }
                write!(f, "]")
            }
            NodeValue::Table(_) => write!(f, "{{…}}"),
        }
    }
}

/// One `key = value` of a table.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Entry {
    pub key: String,
    pub key_location: Location,
    pub node: Node,
}

/// A table, in document order.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Table {
    pub entries: Vec<Entry>,
}

impl Table {
    /// The entry for `key`, if present.
    pub fn get(&self, key: &str) -> Option<&Entry> {
        self.entries.iter().find(|e| e.key == key)
    }

    /// Whether the table has no entries.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Removes the entry at a dotted path, if present.
    pub fn remove_path(&mut self, path: &[String]) {
        let Some((first, rest)) = path.split_first() else {
            return;
        };
        if rest.is_empty() {
            self.entries.retain(|e| &e.key != first);
            return;
        }
        if let Some(entry) = self.entries.iter_mut().find(|e| &e.key == first) {
            if let NodeValue::Table(t) = &mut entry.node.value {
                t.remove_path(rest);
            }
        }
    }

    /// Sets the value at a dotted path, creating intermediate tables.
    ///
    /// Fails (with the dotted prefix that is in the way) when an intermediate key holds
    /// a value that is not a table.
    pub fn set_path(
        &mut self,
        path: &[String],
        node: Node,
        key_location: &Location,
    ) -> Result<(), String> {
        let Some((first, rest)) = path.split_first() else {
            return Err(String::new());
        };
        if rest.is_empty() {
            let entry = Entry {
                key: first.clone(),
                key_location: key_location.clone(),
                node,
            };
            match self.entries.iter_mut().find(|e| &e.key == first) {
                Some(existing) => *existing = entry,
                None => self.entries.push(entry),
            }
            return Ok(());
        }
        if self.get(first).is_none() {
            self.entries.push(Entry {
                key: first.clone(),
                key_location: key_location.clone(),
                node: Node {
                    value: NodeValue::Table(Table::default()),
                    location: key_location.clone(),
                },
            });
        }
        let entry = self
            .entries
            .iter_mut()
            .find(|e| &e.key == first)
            .ok_or_else(|| first.clone())?;
        match &mut entry.node.value {
            NodeValue::Table(t) => t
                .set_path(rest, node, key_location)
                .map_err(|inner| join_key(first, &inner)),
            _ => Err(first.clone()),
        }
    }
}

/// `a` + `.` + `b`, or `a` alone when `b` is empty.
pub(crate) fn join_key(a: &str, b: &str) -> String {
    match (a.is_empty(), b.is_empty()) {
        (true, _) => b.to_string(),
        (_, true) => a.to_string(),
        _ => format!("{a}.{b}"),
    }
}

/// Parses TOML text into a located tree; errors name the line of every problem.
pub(crate) fn parse_document(text: &str, source: &Arc<str>) -> Result<Table, ConfigErrors> {
    let document = ImDocument::parse(text).map_err(|e| {
        let location = match e.span() {
            Some(span) => Location::at_offset(source, text, span.start),
            None => Location::whole(source),
        };
        ConfigErrors::single(ConfigError::new(
            ErrorKind::Syntax,
            location,
            "",
            None,
            format!("invalid TOML: {}", one_line(e.message())),
        ))
    })?;
    let context = Context { source, text };
    let mut errors = Vec::new();
    let table = context.table(
        document.as_table(),
        &Location::whole(source),
        "",
        &mut errors,
    );
    if errors.is_empty() {
        Ok(table)
    } else {
        Err(ConfigErrors { errors })
    }
}

/// Parses a single TOML value written on a command line (`--set key=value`).
///
/// A bare word such as `mindlin_deresiewicz` is not valid TOML; it is taken as a string,
/// since nothing else could be meant.
pub(crate) fn parse_value(text: &str, location: &Location) -> Result<Node, String> {
    if text.contains('\n') || text.contains('\r') {
        return Err("a value must be on one line".to_string());
    }
    if text.parse::<Value>().is_err() && is_bare_word(text) {
        return Ok(Node {
            value: NodeValue::String(text.to_string()),
            location: location.clone(),
        });
    }
    let value: Value = text.parse().map_err(|e: toml_edit::TomlError| {
        format!("`{text}` is not a TOML value: {}", one_line(e.message()))
    })?;
    // Everything from the command line is located at `--set` itself.
    let context = Context {
        source: &location.source,
        text: "",
    };
    let mut errors = Vec::new();
    let node = context.value(&value, location, "", &mut errors);
    match errors.first() {
        None => Ok(node),
        Some(error) => Err(error.message.clone()),
    }
}

/// Source text and name, to turn byte spans into locations.
struct Context<'a> {
    source: &'a Arc<str>,
    text: &'a str,
}

impl Context<'_> {
    /// The location of a span, or `fallback` when the parser kept none (implicit tables,
    /// values from the command line).
    fn at(&self, span: Option<Range<usize>>, fallback: &Location) -> Location {
        match span {
            Some(span) if !self.text.is_empty() => {
                Location::at_offset(self.source, self.text, span.start)
            }
            _ => fallback.clone(),
        }
    }

    fn table(
        &self,
        table: &toml_edit::Table,
        location: &Location,
        path: &str,
        errors: &mut Vec<ConfigError>,
    ) -> Table {
        let mut entries = Vec::new();
        for (key, _) in table.iter() {
            let Some((key, item)) = table.get_key_value(key) else {
                continue;
            };
            let key_location = self.at(key.span(), location);
            let key_path = join_key(path, key.get());
            if let Some(node) = self.item(item, &key_location, &key_path, errors) {
                entries.push(Entry {
                    key: key.get().to_string(),
                    key_location,
                    node,
                });
            }
        }
        Table { entries }
    }

    fn item(
        &self,
        item: &Item,
        key_location: &Location,
        path: &str,
        errors: &mut Vec<ConfigError>,
    ) -> Option<Node> {
        match item {
            Item::None => None,
            Item::Value(value) => Some(self.value(value, key_location, path, errors)),
            Item::Table(table) => {
                let location = self.at(table.span(), key_location);
                Some(Node {
                    value: NodeValue::Table(self.table(table, key_location, path, errors)),
                    location,
                })
            }
            Item::ArrayOfTables(tables) => {
                let items = tables
                    .iter()
                    .enumerate()
                    .map(|(i, table)| {
                        let location = self.at(table.span(), key_location);
                        let item_path = format!("{path}[{i}]");
                        Node {
                            value: NodeValue::Table(
                                self.table(table, &location, &item_path, errors),
                            ),
                            location,
                        }
                    })
                    .collect();
                Some(Node {
                    value: NodeValue::Array(items),
                    location: self.at(tables.span(), key_location),
                })
            }
        }
    }

    fn value(
        &self,
        value: &Value,
        fallback: &Location,
        path: &str,
        errors: &mut Vec<ConfigError>,
    ) -> Node {
        let location = self.at(value.span(), fallback);
        let node_value = match value {
            Value::String(s) => NodeValue::String(s.value().clone()),
            Value::Integer(i) => NodeValue::Integer(*i.value()),
            Value::Float(x) => NodeValue::Float(*x.value()),
            Value::Boolean(b) => NodeValue::Boolean(*b.value()),
            Value::Datetime(d) => {
                errors.push(ConfigError::new(
                    ErrorKind::WrongType,
                    location.clone(),
                    path,
                    Some(d.value().to_string()),
                    "date-time values are not accepted in hopperflow files",
                ));
                NodeValue::String(d.value().to_string())
            }
            Value::Array(array) => NodeValue::Array(
                array
                    .iter()
                    .enumerate()
                    .map(|(i, item)| self.value(item, &location, &format!("{path}[{i}]"), errors))
                    .collect(),
            ),
            Value::InlineTable(table) => {
                let mut entries = Vec::new();
                for (key, _) in table.iter() {
                    let Some((key, item)) = table.get_key_value(key) else {
                        continue;
                    };
                    let key_location = self.at(key.span(), &location);
                    let key_path = join_key(path, key.get());
                    if let Some(node) = self.item(item, &key_location, &key_path, errors) {
                        entries.push(Entry {
                            key: key.get().to_string(),
                            key_location,
                            node,
                        });
                    }
                }
                NodeValue::Table(Table { entries })
            }
        };
        Node {
            value: node_value,
            location,
        }
    }
}

/// A parser message on one line, so that every error stays one line of output.
fn one_line(message: &str) -> String {
    message
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

fn is_bare_word(text: &str) -> bool {
    let mut chars = text.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// Splits and checks a dotted key such as `geometry.outlet_width`.
pub(crate) fn split_key(key: &str) -> Result<Vec<String>, String> {
    let key = key.trim();
    if key.is_empty() {
        return Err("the key is empty".to_string());
    }
    key.split('.')
        .map(|segment| {
            let ok = !segment.is_empty()
                && segment
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
            if ok {
                Ok(segment.to_string())
            } else {
                Err(format!(
                    "`{key}` is not a dotted key (letters, digits, `_` and `-` separated by `.`)"
                ))
            }
        })
        .collect()
}
