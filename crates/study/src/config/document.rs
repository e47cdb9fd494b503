//! A parsed TOML document that remembers the file and line of every key and value.
//!
//! The `toml` crate reports spans through `toml::Spanned`; this module deserializes a
//! whole document into a tree of spanned nodes once, so that every later check (unknown
//! keys, wrong types, ranges) can name the line it is about, and so that `--set`
//! overrides and sweep axes can replace nodes before anything is validated.

use std::fmt;
use std::sync::Arc;

use serde::de::{self, Deserialize, Deserializer, MapAccess, SeqAccess, Visitor};
use toml::Spanned;

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

/// Parses TOML text into a located tree; the error names the line of the syntax error.
pub(crate) fn parse_document(text: &str, source: &Arc<str>) -> Result<Table, ConfigErrors> {
    let raw: RawValue = toml::from_str(text).map_err(|e| {
        let location = match e.span() {
            Some(span) => Location::at_offset(source, text, span.start),
            None => Location::whole(source),
        };
        ConfigErrors::single(ConfigError::new(
            ErrorKind::Syntax,
            location,
            "",
            None,
            syntax_message(e.message()),
        ))
    })?;
    let located = locate(raw.0, &Location::whole(source), source, text);
    match located {
        NodeValue::Table(t) => Ok(t),
        // The top level of a TOML document is always a table.
        other => Err(ConfigErrors::single(ConfigError::new(
            ErrorKind::Syntax,
            Location::whole(source),
            "",
            Some(other.to_string()),
            "a document must be a TOML table",
        ))),
    }
}

/// Rewrites parser messages that leak serde internals into plain words.
fn syntax_message(message: &str) -> String {
    let message = message.trim();
    if message.contains("$__toml_private_datetime") || message.contains("spanned value") {
        "date-time values are not accepted in hopperflow files".to_string()
    } else {
        format!("invalid TOML: {message}")
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
    let wrapped = format!("value = {text}\n");
    let parsed: Result<RawValue, _> = toml::from_str(&wrapped);
    let source = Arc::clone(&location.source);
    match parsed {
        Ok(raw) => match locate(raw.0, location, &source, "") {
            NodeValue::Table(mut t) if t.entries.len() == 1 && t.entries[0].key == "value" => {
                let mut node = t.entries.remove(0).node;
                relocate(&mut node, location);
                Ok(node)
            }
            _ => Err(format!("`{text}` is not a single TOML value")),
        },
        Err(_) if is_bare_word(text) => Ok(Node {
            value: NodeValue::String(text.to_string()),
            location: location.clone(),
        }),
        Err(e) => Err(format!(
            "`{text}` is not a TOML value: {}",
            e.message().trim()
        )),
    }
}

fn is_bare_word(text: &str) -> bool {
    let mut chars = text.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// Gives every node of a tree the same location (values from the command line).
fn relocate(node: &mut Node, location: &Location) {
    node.location = location.clone();
    match &mut node.value {
        NodeValue::Array(items) => items.iter_mut().for_each(|n| relocate(n, location)),
        NodeValue::Table(t) => {
            for entry in &mut t.entries {
                entry.key_location = location.clone();
                relocate(&mut entry.node, location);
            }
        }
        _ => {}
    }
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

fn locate(raw: RawKind, location: &Location, source: &Arc<str>, text: &str) -> NodeValue {
    let at = |start: usize| {
        if text.is_empty() {
            location.clone()
        } else {
            Location::at_offset(source, text, start)
        }
    };
    match raw {
        RawKind::String(s) => NodeValue::String(s),
        RawKind::Integer(i) => NodeValue::Integer(i),
        RawKind::Float(x) => NodeValue::Float(x),
        RawKind::Boolean(b) => NodeValue::Boolean(b),
        RawKind::Array(items) => NodeValue::Array(
            items
                .into_iter()
                .map(|item| {
                    let item_location = at(item.span().start);
                    Node {
                        value: locate(item.into_inner().0, &item_location, source, text),
                        location: item_location,
                    }
                })
                .collect(),
        ),
        RawKind::Table(entries) => NodeValue::Table(Table {
            entries: entries
                .into_iter()
                .map(|(key, value)| {
                    let key_location = at(key.span().start);
                    let value_location = at(value.span().start);
                    Entry {
                        key: key.into_inner(),
                        key_location,
                        node: Node {
                            value: locate(value.into_inner().0, &value_location, source, text),
                            location: value_location,
                        },
                    }
                })
                .collect(),
        }),
    }
}

/// Serde target mirroring a TOML value, with spans on keys and values.
struct RawValue(RawKind);

enum RawKind {
    String(String),
    Integer(i64),
    Float(f64),
    Boolean(bool),
    Array(Vec<Spanned<RawValue>>),
    Table(Vec<(Spanned<String>, Spanned<RawValue>)>),
}

impl<'de> Deserialize<'de> for RawValue {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(RawVisitor)
    }
}

struct RawVisitor;

impl<'de> Visitor<'de> for RawVisitor {
    type Value = RawValue;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "a TOML value")
    }

    fn visit_bool<E: de::Error>(self, v: bool) -> Result<RawValue, E> {
        Ok(RawValue(RawKind::Boolean(v)))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<RawValue, E> {
        Ok(RawValue(RawKind::Integer(v)))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<RawValue, E> {
        i64::try_from(v)
            .map(|i| RawValue(RawKind::Integer(i)))
            .map_err(|_| E::custom("integer out of range"))
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<RawValue, E> {
        Ok(RawValue(RawKind::Float(v)))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<RawValue, E> {
        Ok(RawValue(RawKind::String(v.to_string())))
    }

    fn visit_string<E: de::Error>(self, v: String) -> Result<RawValue, E> {
        Ok(RawValue(RawKind::String(v)))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<RawValue, A::Error> {
        let mut items = Vec::new();
        while let Some(item) = seq.next_element::<Spanned<RawValue>>()? {
            items.push(item);
        }
        Ok(RawValue(RawKind::Array(items)))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<RawValue, A::Error> {
        let mut entries = Vec::new();
        while let Some(key) = map.next_key::<Spanned<String>>()? {
            let value = map.next_value::<Spanned<RawValue>>()?;
            entries.push((key, value));
        }
        Ok(RawValue(RawKind::Table(entries)))
    }
}
