//! A thin typed reader over `toml_edit` that knows where every key is: every error it
//! returns names the key path and the line, and every table rejects keys it does not know.
//!
//! Entry points: [`Source`], [`Table`].

use super::CaseError;
use crate::formula::{Formula, Scalar};
use std::cell::RefCell;
use std::collections::BTreeMap;
use toml_edit::{Item, TableLike, Value};

/// The text of a case file, for turning byte offsets into line numbers.
pub struct Source<'s> {
    pub file: String,
    pub text: &'s str,
}

impl Source<'_> {
    pub fn line_of(&self, span: Option<std::ops::Range<usize>>) -> Option<usize> {
        span.map(|r| self.text[..r.start.min(self.text.len())].matches('\n').count() + 1)
    }
}

/// A table being read: its key path, its line, and the keys consumed so far.
pub struct Table<'a, 's> {
    pub src: &'a Source<'s>,
    pub table: &'a dyn TableLike,
    pub path: String,
    pub line: Option<usize>,
    used: RefCell<Vec<String>>,
}

/// Human name of a TOML value type.
fn type_of(item: &Item) -> &'static str {
    match item {
        Item::Value(Value::String(_)) => "a string",
        Item::Value(Value::Integer(_)) => "an integer",
        Item::Value(Value::Float(_)) => "a number",
        Item::Value(Value::Boolean(_)) => "a boolean",
        Item::Value(Value::Datetime(_)) => "a date",
        Item::Value(Value::Array(_)) => "an array",
        Item::Value(Value::InlineTable(_)) | Item::Table(_) => "a table",
        Item::ArrayOfTables(_) => "an array of tables",
        Item::None => "nothing",
    }
}

/// The candidate closest to `key` by edit distance, when close enough to be a typo
/// (at most one edit for names of up to five characters, two beyond).
pub fn closest<'c>(key: &str, candidates: &[&'c str]) -> Option<&'c str> {
    let limit = if key.chars().count() <= 5 { 1 } else { 2 };
    candidates
        .iter()
        .map(|c| (strsim::damerau_levenshtein(key, c), *c))
        .filter(|&(d, c)| d <= limit && c != key)
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c)
}

fn value_span(v: &Value) -> Option<std::ops::Range<usize>> {
    v.span()
}

impl<'a, 's> Table<'a, 's> {
    pub fn new(src: &'a Source<'s>, table: &'a dyn TableLike, path: String, line: Option<usize>) -> Self {
        Table { src, table, path, line, used: RefCell::new(vec![]) }
    }

    fn key_path(&self, key: &str) -> String {
        if self.path.is_empty() {
            key.to_string()
        } else {
            format!("{}.{}", self.path, key)
        }
    }

    /// An error about `key` at the line of that key (or of the table).
    pub fn error(&self, key: &str, message: impl Into<String>) -> CaseError {
        let line = self
            .table
            .get_key_value(key)
            .and_then(|(k, item)| self.src.line_of(k.span()).or_else(|| self.src.line_of(item.span())))
            .or(self.line);
        CaseError { file: self.src.file.clone(), line, key: self.key_path(key), message: message.into() }
    }

    fn item(&self, key: &str) -> Option<&'a Item> {
        self.used.borrow_mut().push(key.to_string());
        self.table.get(key).filter(|i| !i.is_none())
    }

    pub fn has(&self, key: &str) -> bool {
        self.table.get(key).is_some_and(|i| !i.is_none())
    }

    /// A missing required key. When the table holds a key nobody has read that is a
    /// likely misspelling of it (`nuu` for `nu`), the error names that key and its line.
    fn missing(&self, key: &str, what: &str) -> CaseError {
        let used = self.used.borrow().clone();
        let typo = self
            .table
            .iter()
            .map(|(k, _)| k)
            .filter(|k| *k != key && !used.iter().any(|u| u == k))
            .find(|k| closest(k, &[key]).is_some());
        if let Some(k) = typo {
            return self.error(k, format!("unknown key '{k}': did you mean '{key}'? (missing key '{key}', {what})"));
        }
        // No likely misspelling: name the keys the table holds that nobody has read yet, so
        // that a key under another name (`young` for `E`) is seen next to the error.
        let unread: Vec<String> = self
            .table
            .iter()
            .map(|(k, _)| k)
            .filter(|k| *k != key && !used.iter().any(|u| u == k))
            .map(|k| format!("'{k}'"))
            .collect();
        let holds = if unread.is_empty() { String::new() } else { format!("; the table holds {}", unread.join(", ")) };
        let mut e = self.error(key, format!("missing key '{key}' ({what}){holds}"));
        e.line = self.line;
        e
    }

    fn wrong(&self, key: &str, expected: &str, item: &Item) -> CaseError {
        self.error(key, format!("expected {expected}, found {}", type_of(item)))
    }

    pub fn opt_f64(&self, key: &str) -> Result<Option<f64>, CaseError> {
        match self.item(key) {
            None => Ok(None),
            Some(Item::Value(Value::Float(f))) => Ok(Some(*f.value())),
            Some(Item::Value(Value::Integer(i))) => Ok(Some(*i.value() as f64)),
            Some(other) => Err(self.wrong(key, "a number", other)),
        }
    }

    pub fn req_f64(&self, key: &str, what: &str) -> Result<f64, CaseError> {
        self.opt_f64(key)?.ok_or_else(|| self.missing(key, what))
    }

    pub fn opt_usize(&self, key: &str) -> Result<Option<usize>, CaseError> {
        match self.item(key) {
            None => Ok(None),
            Some(Item::Value(Value::Integer(i))) if *i.value() >= 0 => Ok(Some(*i.value() as usize)),
            Some(other) => Err(self.wrong(key, "a non-negative integer", other)),
        }
    }

    pub fn opt_bool(&self, key: &str) -> Result<Option<bool>, CaseError> {
        match self.item(key) {
            None => Ok(None),
            Some(Item::Value(Value::Boolean(b))) => Ok(Some(*b.value())),
            Some(other) => Err(self.wrong(key, "true or false", other)),
        }
    }

    pub fn opt_str(&self, key: &str) -> Result<Option<String>, CaseError> {
        match self.item(key) {
            None => Ok(None),
            Some(Item::Value(Value::String(s))) => Ok(Some(s.value().clone())),
            Some(other) => Err(self.wrong(key, "a string", other)),
        }
    }

    pub fn req_str(&self, key: &str, what: &str) -> Result<String, CaseError> {
        self.opt_str(key)?.ok_or_else(|| self.missing(key, what))
    }

    /// A string that must be one of `choices`.
    pub fn opt_choice(&self, key: &str, choices: &[&str]) -> Result<Option<String>, CaseError> {
        let v = self.opt_str(key)?;
        if let Some(s) = &v {
            if !choices.contains(&s.as_str()) {
                return Err(self.error(key, format!("'{s}' is not one of: {}", choices.join(", "))));
            }
        }
        Ok(v)
    }

    /// An array of numbers.
    pub fn opt_f64_array(&self, key: &str) -> Result<Option<Vec<f64>>, CaseError> {
        match self.item(key) {
            None => Ok(None),
            Some(Item::Value(Value::Array(a))) => a
                .iter()
                .map(|v| match v {
                    Value::Float(f) => Ok(*f.value()),
                    Value::Integer(i) => Ok(*i.value() as f64),
                    _ => Err(self.error(key, "expected an array of numbers")),
                })
                .collect::<Result<Vec<_>, _>>()
                .map(Some),
            Some(other) => Err(self.wrong(key, "an array of numbers", other)),
        }
    }

    /// An array of non-negative integers.
    pub fn opt_usize_array(&self, key: &str) -> Result<Option<Vec<usize>>, CaseError> {
        match self.item(key) {
            None => Ok(None),
            Some(Item::Value(Value::Array(a))) => a
                .iter()
                .map(|v| match v {
                    Value::Integer(i) if *i.value() >= 0 => Ok(*i.value() as usize),
                    _ => Err(self.error(key, "expected an array of non-negative integers")),
                })
                .collect::<Result<Vec<_>, _>>()
                .map(Some),
            Some(other) => Err(self.wrong(key, "an array of integers", other)),
        }
    }

    /// An array of strings.
    pub fn opt_str_array(&self, key: &str) -> Result<Option<Vec<String>>, CaseError> {
        match self.item(key) {
            None => Ok(None),
            Some(Item::Value(Value::String(s))) => Ok(Some(vec![s.value().clone()])),
            Some(Item::Value(Value::Array(a))) => a
                .iter()
                .map(|v| match v {
                    Value::String(s) => Ok(s.value().clone()),
                    _ => Err(self.error(key, "expected an array of strings")),
                })
                .collect::<Result<Vec<_>, _>>()
                .map(Some),
            Some(other) => Err(self.wrong(key, "a string or an array of strings", other)),
        }
    }

    fn scalar_of(&self, key: &str, v: &Value, params: &BTreeMap<String, f64>) -> Result<Scalar, CaseError> {
        match v {
            Value::Float(f) => Ok(Scalar::Const(*f.value())),
            Value::Integer(i) => Ok(Scalar::Const(*i.value() as f64)),
            Value::String(s) => Formula::parse(s.value(), params).map(Scalar::Formula).map_err(|e| {
                let mut err = self.error(key, e.to_string());
                err.line = self.src.line_of(value_span(v)).or(err.line);
                err
            }),
            _ => Err(self.error(key, "expected a number or a formula string")),
        }
    }

    /// A number or a formula (string).
    pub fn opt_scalar(&self, key: &str, params: &BTreeMap<String, f64>) -> Result<Option<Scalar>, CaseError> {
        match self.item(key) {
            None => Ok(None),
            Some(Item::Value(v)) if !matches!(v, Value::Array(_) | Value::InlineTable(_)) => {
                self.scalar_of(key, v, params).map(Some)
            }
            Some(other) => Err(self.wrong(key, "a number or a formula string", other)),
        }
    }

    /// An array whose entries are numbers or formulas.
    pub fn opt_scalar_array(
        &self,
        key: &str,
        params: &BTreeMap<String, f64>,
    ) -> Result<Option<Vec<Scalar>>, CaseError> {
        match self.item(key) {
            None => Ok(None),
            Some(Item::Value(Value::Array(a))) => {
                a.iter().map(|v| self.scalar_of(key, v, params)).collect::<Result<Vec<_>, _>>().map(Some)
            }
            Some(other) => Err(self.wrong(key, "an array of numbers or formula strings", other)),
        }
    }

    /// A sub-table (`[a.b]` or inline).
    pub fn opt_table(&self, key: &str) -> Result<Option<Table<'a, 's>>, CaseError> {
        match self.item(key) {
            None => Ok(None),
            Some(item) => match item.as_table_like() {
                Some(t) => {
                    let line = self
                        .src
                        .line_of(item.span())
                        .or_else(|| self.table.get_key_value(key).and_then(|(k, _)| self.src.line_of(k.span())));
                    Ok(Some(Table::new(self.src, t, self.key_path(key), line)))
                }
                None => Err(self.wrong(key, "a table", item)),
            },
        }
    }

    /// An array of tables (`[[key]]`, or an array of inline tables).
    pub fn opt_tables(&self, key: &str) -> Result<Vec<Table<'a, 's>>, CaseError> {
        match self.item(key) {
            None => Ok(vec![]),
            Some(Item::ArrayOfTables(aot)) => Ok(aot
                .iter()
                .enumerate()
                .map(|(i, t)| {
                    Table::new(self.src, t, format!("{}[{}]", self.key_path(key), i), self.src.line_of(t.span()))
                })
                .collect()),
            Some(Item::Value(Value::Array(a))) => a
                .iter()
                .enumerate()
                .map(|(i, v)| match v {
                    Value::InlineTable(t) => Ok(Table::new(
                        self.src,
                        t,
                        format!("{}[{}]", self.key_path(key), i),
                        self.src.line_of(v.span()),
                    )),
                    _ => Err(self.error(key, "expected an array of tables")),
                })
                .collect(),
            Some(other) => Err(self.wrong(key, "an array of tables ([[...]])", other)),
        }
    }

    /// Every key of the table as (name, line), for free-form tables like `[parameters]`.
    pub fn entries(&self) -> Vec<(String, &'a Item)> {
        self.table.iter().map(|(k, v)| (k.to_string(), v)).collect()
    }

    /// Marks every key as used (for free-form tables).
    pub fn use_all(&self) {
        let keys: Vec<String> = self.table.iter().map(|(k, _)| k.to_string()).collect();
        self.used.borrow_mut().extend(keys);
    }

    /// Errors on the first key that was never read: unknown keys are mistakes.
    pub fn finish(&self, known_hint: &[&str]) -> Result<(), CaseError> {
        let used = self.used.borrow();
        for (k, _) in self.table.iter() {
            if !used.iter().any(|u| u == k) {
                let hint = if known_hint.is_empty() {
                    String::new()
                } else {
                    format!("; known keys: {}", known_hint.join(", "))
                };
                let guess = closest(k, known_hint).map(|g| format!(" (did you mean '{g}'?)")).unwrap_or_default();
                return Err(self.error(k, format!("unknown key '{k}'{guess}{hint}")));
            }
        }
        Ok(())
    }
}
