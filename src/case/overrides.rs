//! Command-line overrides of case-file keys (`--set cracks.0.contact.friction=0.3`).
//!
//! An override is applied to the TOML document itself (with `toml_edit`, keeping the rest
//! of the file as written) before the case is read, so an overridden value is validated
//! exactly like one written in the file. Errors caused by an override name the override
//! (`--set cracks.0.contact.friction=abc: expected a number, found a string`); other errors
//! keep the case file's name and line.
//!
//! Entry points: [`Override::parse`], [`Case::from_file_with`](super::Case::from_file_with).
//!
//! Key syntax: the TOML key path with dots, array entries by their 0-based index
//! (`cracks.0.contact.friction`, `materials.1.E`, `steps.factors.2`). The value is read
//! as a TOML value (`0.3`, `2`, `true`, `[40, 40]`, `"segment"`); anything that is not a
//! TOML value is taken as a string (`shape=disc`, `pressure=1e6*t`).

use super::CaseError;
use std::fmt;
use std::str::FromStr;
use toml_edit::{DocumentMut, ImDocument, Item, Table, TableLike, Value};

/// One `KEY=VALUE` override.
#[derive(Debug, Clone)]
pub struct Override {
    /// The override as given (`cracks.0.contact.friction=0.3`).
    pub text: String,
    /// The key path segments (`["cracks", "0", "contact", "friction"]`).
    pub path: Vec<String>,
    /// The value to write.
    pub value: Value,
}

impl fmt::Display for Override {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "--set {}", self.text)
    }
}

impl Override {
    /// Parses `KEY=VALUE`.
    pub fn parse(arg: &str) -> Result<Override, CaseError> {
        let fail = |m: &str| CaseError {
            file: format!("--set {arg}"),
            line: None,
            key: String::new(),
            message: m.to_string(),
        };
        let (key, raw) = arg.split_once('=').ok_or_else(|| fail("expected KEY=VALUE"))?;
        let key = key.trim();
        let path: Vec<String> = key.split('.').map(|s| s.trim().to_string()).collect();
        if key.is_empty() || path.iter().any(|s| s.is_empty()) {
            return Err(fail("the key is empty or has an empty segment (write a.b.0.c)"));
        }
        let raw = raw.trim();
        if raw.is_empty() {
            return Err(fail("the value is empty"));
        }
        let value = Value::from_str(raw).unwrap_or_else(|_| Value::from(raw));
        Ok(Override { text: format!("{key}={raw}"), path, value })
    }

    /// An override of the dotted `key` with a value already typed (the Python bindings'
    /// `overrides={"cracks.0.contact.friction": 0.3}`).
    pub fn new(key: &str, value: Value) -> Result<Override, CaseError> {
        let mut value = value;
        *value.decor_mut() = Default::default();
        let text = format!("{}={}", key.trim(), value.to_string().trim());
        let path: Vec<String> = key.split('.').map(|s| s.trim().to_string()).collect();
        if key.trim().is_empty() || path.iter().any(|s| s.is_empty()) {
            return Err(CaseError {
                file: format!("--set {text}"),
                line: None,
                key: String::new(),
                message: "the key is empty or has an empty segment (write a.b.0.c)".into(),
            });
        }
        Ok(Override { text, path, value })
    }

    /// An override of the same key with another value (one value of a sweep).
    pub fn with_value(&self, value: Value) -> Override {
        let key = self.path.join(".");
        let text = format!("{key}={}", value.to_string().trim());
        Override { text, path: self.path.clone(), value }
    }

    /// The key path as the case reader writes it in errors (`cracks[0].contact.friction`).
    pub fn key(&self) -> String {
        let mut s = String::new();
        for seg in &self.path {
            if seg.parse::<usize>().is_ok() && !s.is_empty() {
                s.push_str(&format!("[{seg}]"));
            } else {
                if !s.is_empty() {
                    s.push('.');
                }
                s.push_str(seg);
            }
        }
        s
    }

    /// An error about this override.
    pub fn error(&self, message: impl Into<String>) -> CaseError {
        CaseError { file: self.to_string(), line: None, key: self.key(), message: message.into() }
    }

    /// Writes the value into `doc`; returns true when a key was added.
    fn apply(&self, doc: &mut DocumentMut) -> Result<bool, CaseError> {
        self.set_in(doc.as_table_mut(), &self.path, "")
    }

    fn set_in(&self, t: &mut dyn TableLike, path: &[String], here: &str) -> Result<bool, CaseError> {
        let seg = &path[0];
        let rest = &path[1..];
        let name = if here.is_empty() { seg.clone() } else { format!("{here}.{seg}") };
        if rest.is_empty() {
            return match t.get_mut(seg) {
                None => {
                    t.insert(seg, Item::Value(self.value.clone()));
                    Ok(true)
                }
                Some(Item::Value(old)) => {
                    let mut value = self.value.clone();
                    *value.decor_mut() = old.decor().clone();
                    *old = value;
                    Ok(false)
                }
                Some(Item::ArrayOfTables(a)) => {
                    Err(self.error(format!("{name} is an array of {} tables: give an index and a key", a.len())))
                }
                Some(_) => Err(self.error(format!("{name} is a table: give one of its keys"))),
            };
        }
        if t.get(seg).is_none() {
            let mut sub = Table::new();
            sub.set_dotted(true);
            t.insert(seg, Item::Table(sub));
        }
        match t.get_mut(seg).expect("present") {
            Item::Table(sub) => self.set_in(sub, rest, &name).map(|_| true),
            Item::Value(Value::InlineTable(sub)) => self.set_in(sub, rest, &name),
            Item::ArrayOfTables(a) => {
                let n = a.len();
                let i = self.index(&rest[0], &name, n)?;
                if rest.len() == 1 {
                    return Err(self.error(format!("{name}.{i} is a table: give one of its keys")));
                }
                let sub = a.get_mut(i).expect("index checked");
                self.set_in(sub, &rest[1..], &format!("{name}.{i}"))
            }
            Item::Value(Value::Array(a)) => {
                let n = a.len();
                let i = self.index(&rest[0], &name, n)?;
                let entry = a.get_mut(i).expect("index checked");
                if rest.len() == 1 {
                    let mut value = self.value.clone();
                    *value.decor_mut() = entry.decor().clone();
                    *entry = value;
                    return Ok(false);
                }
                match entry {
                    Value::InlineTable(sub) => self.set_in(sub, &rest[1..], &format!("{name}.{i}")),
                    v => Err(self.error(format!("{name}.{i} is {}, not a table", value_kind(v)))),
                }
            }
            Item::Value(v) => Err(self.error(format!("{name} is {}, not a table", value_kind(v)))),
            Item::None => unreachable!("inserted above"),
        }
    }

    fn index(&self, seg: &str, name: &str, n: usize) -> Result<usize, CaseError> {
        match seg.parse::<usize>() {
            Ok(i) if i < n => Ok(i),
            Ok(i) => {
                Err(self.error(format!("there is no {name}.{i}: {name} has {n} entries (0..{})", n.saturating_sub(1))))
            }
            Err(_) => Err(self.error(format!(
                "{name} is an array: give an entry index (0..{}) instead of '{seg}'",
                n.saturating_sub(1)
            ))),
        }
    }
}

fn value_kind(v: &Value) -> &'static str {
    match v {
        Value::String(_) => "a string",
        Value::Integer(_) => "an integer",
        Value::Float(_) => "a number",
        Value::Boolean(_) => "a boolean",
        Value::Datetime(_) => "a date",
        Value::Array(_) => "an array",
        Value::InlineTable(_) => "a table",
    }
}

/// What a case was read from, to attribute errors found after reading (unknown groups,
/// missing mesh files) to the file's line or to the override that caused them.
#[derive(Debug, Clone, Default)]
pub struct Origin {
    /// The case file's own text.
    text: String,
    /// The overrides changed no line numbers.
    same_lines: bool,
    pub overrides: Vec<Override>,
}

impl Origin {
    pub(super) fn new(text: &str, same_lines: bool, overrides: &[Override]) -> Origin {
        Origin { text: text.to_string(), same_lines, overrides: overrides.to_vec() }
    }

    /// The error as the user must see it: naming the override it comes from, or on the
    /// case file's own line.
    pub fn attribute(&self, e: CaseError) -> CaseError {
        if self.overrides.is_empty() {
            e
        } else {
            attribute(e, &self.text, self.same_lines, &self.overrides)
        }
    }
}

/// The case text with `overrides` applied, and whether the line numbers still match the
/// file's (no key added, no multi-line value replaced).
pub(super) fn apply_all(text: &str, file: &str, overrides: &[Override]) -> Result<(String, bool), CaseError> {
    let mut doc = DocumentMut::from_str(text).map_err(|e| CaseError {
        file: file.to_string(),
        line: ImDocument::parse(text).err().and_then(|e| e.span()).map(|r| text[..r.start].matches('\n').count() + 1),
        key: String::new(),
        message: format!("not valid TOML: {}", e.message()),
    })?;
    let mut added = false;
    for ov in overrides {
        added |= ov.apply(&mut doc)?;
    }
    let out = doc.to_string();
    let same_lines = !added && out.matches('\n').count() == text.matches('\n').count();
    Ok((out, same_lines))
}

/// Names the override an error comes from, or puts the error back on the file's lines.
pub(super) fn attribute(mut e: CaseError, original: &str, same_lines: bool, overrides: &[Override]) -> CaseError {
    let below = |k: &str, of: &str| k == of || k.starts_with(&format!("{of}.")) || k.starts_with(&format!("{of}["));
    // The last override of a key wins, as in the document.
    if let Some(ov) = overrides.iter().rev().find(|o| !e.key.is_empty() && below(&e.key, &o.key())) {
        return ov.error(e.message);
    }
    let Ok(doc) = ImDocument::parse(original) else { return e };
    let (found, line) = line_of_key(&doc, original, &e.key);
    if !found {
        // A table the override created (an unknown key above the override's key).
        if let Some(ov) = overrides.iter().rev().find(|o| !e.key.is_empty() && below(&o.key(), &e.key)) {
            return ov.error(e.message);
        }
    }
    if !same_lines {
        e.line = line;
    }
    e
}

/// Whether the key of `ov` holds an array in the case text (a list value is then a plain
/// override, not a sweep).
pub fn holds_array(text: &str, ov: &Override) -> bool {
    let Ok(doc) = ImDocument::parse(text) else { return false };
    let mut t: &dyn TableLike = doc.as_table();
    let mut item: Option<&Item> = None;
    let mut segs = ov.path.iter().peekable();
    while let Some(seg) = segs.next() {
        let Some(it) = t.get(seg) else { return false };
        let it = match (it, segs.peek()) {
            (Item::ArrayOfTables(a), Some(i)) => {
                let Some(sub) = i.parse::<usize>().ok().and_then(|i| a.get(i)) else { return false };
                segs.next();
                t = sub;
                item = None;
                continue;
            }
            (it, _) => it,
        };
        item = Some(it);
        if segs.peek().is_some() {
            match it.as_table_like() {
                Some(sub) => t = sub,
                None => return false,
            }
        }
    }
    matches!(item, Some(Item::Value(Value::Array(_))))
}

/// Walks `key` (`cracks[0].contact.friction`) in the file: whether it is there, and the
/// line of its deepest part that is.
fn line_of_key(doc: &ImDocument<&str>, text: &str, key: &str) -> (bool, Option<usize>) {
    let mut segs: Vec<&str> = vec![];
    for part in key.split('.') {
        segs.extend(part.split(['[', ']']).filter(|s| !s.is_empty()));
    }
    let line_of =
        |r: Option<std::ops::Range<usize>>| r.map(|r| text[..r.start.min(text.len())].matches('\n').count() + 1);
    walk(doc.as_table(), &segs, Some(1), &line_of)
}

fn walk(
    t: &dyn TableLike,
    segs: &[&str],
    line: Option<usize>,
    line_of: &dyn Fn(Option<std::ops::Range<usize>>) -> Option<usize>,
) -> (bool, Option<usize>) {
    let Some((seg, rest)) = segs.split_first() else { return (true, line) };
    let Some((k, item)) = t.get_key_value(seg) else { return (false, line) };
    let line = line_of(k.span()).or(line);
    if rest.is_empty() {
        return (true, line);
    }
    match item {
        Item::ArrayOfTables(a) => match rest[0].parse::<usize>().ok().and_then(|i| a.get(i)) {
            Some(sub) => walk(sub, &rest[1..], line_of(sub.span()).or(line), line_of),
            None => (false, line),
        },
        Item::Value(Value::Array(a)) => match rest[0].parse::<usize>().ok().and_then(|i| a.get(i)) {
            Some(Value::InlineTable(sub)) => walk(sub, &rest[1..], line_of(sub.span()).or(line), line_of),
            Some(v) => (rest.len() == 1, line_of(v.span()).or(line)),
            None => (false, line),
        },
        _ => match item.as_table_like() {
            Some(sub) => walk(sub, rest, line, line_of),
            None => (false, line),
        },
    }
}
