//! metabezier-spec: the grammar layer of metabezier's TOML files, shared by
//! the campaign specs (`metabezier-campaign`) and the chapter-6 implant spec
//! (`metabezier-implant`). A [`Parser`] holds a file's path and text; its
//! primitives (fields, tables, strings, numbers, known keys) turn a TOML
//! value into a Rust one or into a [`SpecError`] that names the file, line,
//! column and field, says what was expected and lists the valid choices
//! ([`choices_hint`], Damerau 1964). What a section means is its reader's
//! business, in the crate that owns the section.
//!
//! The TOML is read by the `toml` crate's span-keeping document parser
//! (`toml::de::DeTable`), so every value keeps its byte range.
#![warn(missing_docs)]

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

use metabezier_core::optim::{quoted_list, Raw};
use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// A TOML table with the spans of its keys and values.
pub type Table<'i> = DeTable<'i>;
/// A TOML value with its byte range in the text.
pub type Value<'i> = Spanned<DeValue<'i>>;

/// A spec that failed to load, located in its file.
#[derive(Clone, Debug, PartialEq)]
pub struct SpecError {
    /// The spec file.
    pub path: PathBuf,
    /// 1-based line of the offending text (0 when the file could not be read).
    pub line: usize,
    /// 1-based column, in characters.
    pub column: usize,
    /// The field, as a path such as `algorithm[2].hmcr`.
    pub field: String,
    /// What is wrong and what was expected.
    pub message: String,
}

impl fmt::Display for SpecError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "{}: {}", self.path.display(), self.message)
        } else if self.field.is_empty() {
            write!(
                f,
                "{}:{}:{}: {}",
                self.path.display(),
                self.line,
                self.column,
                self.message
            )
        } else {
            write!(
                f,
                "{}:{}:{}: {}: {}",
                self.path.display(),
                self.line,
                self.column,
                self.field,
                self.message
            )
        }
    }
}

impl std::error::Error for SpecError {}

impl SpecError {
    /// The spec file at `path` could not be read.
    pub fn unreadable(path: &Path, e: &std::io::Error) -> SpecError {
        SpecError {
            path: path.to_owned(),
            line: 0,
            column: 0,
            field: String::new(),
            message: format!("cannot read the spec: {e}"),
        }
    }

    /// Reads the text of the spec (or template) at `path`, refusing a file
    /// over [`metabezier_files::MAX_TEXT_BYTES`] before reading more of it.
    pub fn read(path: &Path) -> Result<String, SpecError> {
        metabezier_files::read_text_limited(path, metabezier_files::MAX_TEXT_BYTES, "a spec")
            .map_err(|e| SpecError::unreadable(path, &e))
    }
}

/// A TOML file's reader: its path and text, for errors located by line
/// and column. The primitives below serve every section reader; a reader
/// of a kind of file wraps it (and reaches the primitives through `Deref`).
#[derive(Clone, Copy, Debug)]
pub struct Parser<'a> {
    /// The file, as errors name it.
    pub path: &'a Path,
    /// Its text.
    pub text: &'a str,
}

/// The TOML type of `v` as an error names it ("string", "integer", …).
pub fn type_name(v: &DeValue<'_>) -> &'static str {
    match v {
        DeValue::String(_) => "string",
        DeValue::Integer(_) => "integer",
        DeValue::Float(_) => "float",
        DeValue::Boolean(_) => "boolean",
        DeValue::Datetime(_) => "datetime",
        DeValue::Array(_) => "array",
        DeValue::Table(_) => "table",
    }
}

/// `v` as an optimiser parameter's raw value ([`Raw`]), the type named
/// when it is none of integer, float or string.
pub fn raw(v: &DeValue<'_>) -> Raw {
    match v {
        DeValue::Integer(i) => match i64::from_str_radix(i.as_str(), i.radix()) {
            Ok(n) => Raw::Int(n),
            Err(_) => Raw::Other("integer out of range"),
        },
        DeValue::Float(x) => match x.as_str().parse::<f64>() {
            Ok(f) => Raw::Float(f),
            Err(_) => Raw::Other("float"),
        },
        DeValue::String(s) => Raw::Text(s.to_string()),
        other => Raw::Other(type_name(other)),
    }
}

/// The closest name within edit distance 2, for "did you mean" hints. The
/// distance is Damerau–Levenshtein's in its optimal-string-alignment form
/// (Damerau 1964): insertions, deletions, substitutions and transpositions
/// of two adjacent characters each cost 1, so `msh` is one edit from `mhs`.
fn suggest<'n>(word: &str, names: &[&'n str]) -> Option<&'n str> {
    fn distance(a: &str, b: &str) -> usize {
        let a: Vec<char> = a.chars().collect();
        let b: Vec<char> = b.chars().collect();
        // d[i][j]: distance between a[..i] and b[..j].
        let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
        for (i, row) in d.iter_mut().enumerate() {
            row[0] = i;
        }
        for (j, cell) in d[0].iter_mut().enumerate() {
            *cell = j;
        }
        for i in 1..=a.len() {
            for j in 1..=b.len() {
                let cost = usize::from(a[i - 1] != b[j - 1]);
                let mut best = (d[i - 1][j] + 1)
                    .min(d[i][j - 1] + 1)
                    .min(d[i - 1][j - 1] + cost);
                if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                    best = best.min(d[i - 2][j - 2] + 1);
                }
                d[i][j] = best;
            }
        }
        d[a.len()][b.len()]
    }
    names
        .iter()
        .map(|n| (distance(word, n), *n))
        .filter(|(d, _)| *d <= 2)
        .min_by_key(|(d, _)| *d)
        .map(|(_, n)| n)
}

/// "did you mean …? Valid choices: …" for `word` among `names`, or the
/// valid choices alone when no name is within two edits.
pub fn choices_hint(word: &str, names: &[&str]) -> String {
    match suggest(word, names) {
        Some(s) => format!(
            "did you mean \"{s}\"? Valid choices: {}",
            quoted_list(names)
        ),
        None => format!("valid choices: {}", quoted_list(names)),
    }
}

impl<'a> Parser<'a> {
    /// The error at byte range `span` of the text, located by line and
    /// column (characters), naming `field`.
    pub fn error(&self, span: Range<usize>, field: &str, message: String) -> SpecError {
        let start = span.start.min(self.text.len());
        let before = &self.text[..start];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = self.text[line_start..start].chars().count() + 1;
        SpecError {
            path: self.path.to_owned(),
            line,
            column,
            field: field.to_owned(),
            message,
        }
    }

    /// The text as a TOML document, or the located TOML error; a
    /// duplicate key is named (the span of the error is the second one).
    pub fn toml(&self) -> Result<Spanned<DeTable<'a>>, SpecError> {
        DeTable::parse(self.text).map_err(|e| {
            let span = e.span().unwrap_or(0..0);
            let mut msg = e.message().trim().to_string();
            if msg.starts_with("duplicate key") {
                let key = self
                    .text
                    .get(span.clone())
                    .map(|k| k.trim().trim_matches(['[', ']']).trim())
                    .filter(|k| !k.is_empty() && k.chars().count() <= 80);
                if let Some(key) = key {
                    msg = format!("duplicate key {key}: a key is set once in its table");
                }
            }
            self.error(span, "", format!("invalid TOML: {msg}"))
        })
    }

    /// The value of `key` in `table`, if present.
    pub fn get<'t, 'i>(&self, table: &'t Table<'i>, key: &str) -> Option<&'t Value<'i>> {
        table
            .iter()
            .find(|(k, _)| k.get_ref() == key)
            .map(|(_, v)| v)
    }

    /// The value of the required `key` of `[section]`, or the error at
    /// `span` (the section's) that names it as missing.
    pub fn required<'t, 'i>(
        &self,
        table: &'t Table<'i>,
        section: &str,
        key: &str,
        span: Range<usize>,
    ) -> Result<&'t Value<'i>, SpecError> {
        self.get(table, key).ok_or_else(|| {
            self.error(
                span,
                &format!("{section}.{key}"),
                format!("missing required field \"{key}\" in [{section}]"),
            )
        })
    }

    /// Refuses a key of `table` not in `allowed`, with a "did you mean"
    /// hint and the valid choices.
    pub fn check_keys(
        &self,
        table: &Table<'_>,
        section: &str,
        allowed: &[&str],
    ) -> Result<(), SpecError> {
        for (k, _) in table.iter() {
            let key: &str = k.get_ref();
            if !allowed.contains(&key) {
                return Err(self.error(
                    k.span(),
                    &format!("{section}.{key}"),
                    format!("unknown field; {}", choices_hint(key, allowed)),
                ));
            }
        }
        Ok(())
    }

    /// `v` as a table, or the error that names the type found.
    pub fn table<'t, 'i>(&self, v: &'t Value<'i>, field: &str) -> Result<&'t Table<'i>, SpecError> {
        match v.get_ref() {
            DeValue::Table(t) => Ok(t),
            other => Err(self.error(
                v.span(),
                field,
                format!("expected a table, found a {}", type_name(other)),
            )),
        }
    }

    /// `v` as a string, or the error that names the type found.
    pub fn string(&self, v: &Value<'_>, field: &str) -> Result<String, SpecError> {
        match v.get_ref() {
            DeValue::String(s) => Ok(s.to_string()),
            other => Err(self.error(
                v.span(),
                field,
                format!("expected a string, found a {}", type_name(other)),
            )),
        }
    }

    /// `v` as an integer in `min..=max`, or the error that states the range.
    pub fn integer(
        &self,
        v: &Value<'_>,
        field: &str,
        min: u64,
        max: u64,
    ) -> Result<u64, SpecError> {
        let expected = if max >= i64::MAX as u64 {
            format!("an integer ≥ {min}")
        } else {
            format!("an integer in {min}..={max}")
        };
        match raw(v.get_ref()) {
            Raw::Int(n) if n >= 0 && (n as u64) >= min && (n as u64) <= max => Ok(n as u64),
            r => Err(self.error(
                v.span(),
                field,
                format!("expected {expected}, found {}", r.found_for_integer()),
            )),
        }
    }

    /// `v` as a real number (an integer is taken as a real), or the error.
    pub fn real(&self, v: &Value<'_>, field: &str) -> Result<f64, SpecError> {
        match raw(v.get_ref()) {
            Raw::Int(n) => Ok(n as f64),
            Raw::Float(x) => Ok(x),
            r => Err(self.error(
                v.span(),
                field,
                format!("expected a real number, found {r}"),
            )),
        }
    }

    /// The elements of a value that may be a single item or a list.
    pub fn one_or_many<'t, 'i>(
        &self,
        v: &'t Value<'i>,
        field: &str,
    ) -> Result<Vec<&'t Value<'i>>, SpecError> {
        match v.get_ref() {
            DeValue::Array(items) => {
                if items.is_empty() {
                    return Err(self.error(
                        v.span(),
                        field,
                        "expected a value or a non-empty list, found an empty list".into(),
                    ));
                }
                Ok(items.iter().collect())
            }
            _ => Ok(vec![v]),
        }
    }

    /// The `[[key]]` tables of `root` (at least one), or the error at
    /// `span` (the document's).
    pub fn array_of_tables<'t, 'i>(
        &self,
        root: &'t Table<'i>,
        key: &str,
        span: Range<usize>,
    ) -> Result<Vec<&'t Value<'i>>, SpecError> {
        let v = self.get(root, key).ok_or_else(|| {
            self.error(
                span,
                key,
                format!("missing [[{key}]] entries; the spec needs at least one"),
            )
        })?;
        match v.get_ref() {
            DeValue::Array(items) if !items.is_empty() => Ok(items.iter().collect()),
            other => Err(self.error(
                v.span(),
                key,
                format!(
                    "expected one or more [[{key}]] tables, found a {}",
                    type_name(other)
                ),
            )),
        }
    }
}
